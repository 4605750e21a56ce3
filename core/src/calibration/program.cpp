// The KRL program of a calibration plan (docs/calibration.md, "On the shop floor").
#include "redpost/calibration/program.hpp"

#include <cmath>

#include <fmt/format.h>

#include "redpost/io/error.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "redpost/krl/writer.hpp"

namespace redpost {

namespace {

std::string external_text(const Cell& cell, const std::vector<int>& ext, const JointVector& q) {
  std::string s;
  for (size_t k = 0; k < ext.size(); ++k) {
    const Joint& j = cell.joint(ext[k]);
    const std::string unit = j.type == JointType::prismatic ? "mm" : "deg";
    const double v = j.type == JointType::prismatic ? q[ext[k]] : rad_to_deg(q[ext[k]]);
    s += fmt::format("{}{} {:.3f} {}", k ? ", " : "", j.name, v, unit);
  }
  return s;
}

}  // namespace

std::vector<std::string> write_calibration_program(const Cell& nominal,
                                                   const std::vector<CalibrationPoint>& points,
                                                   const KrlTemplateSet& templates,
                                                   const CalibrationProgramOptions& options) {
  if (points.empty())
    throw Error(ErrorCode::bad_input, "calibration program: the plan has no points");
  if (!(options.dwell_s >= 0.0) || !std::isfinite(options.dwell_s))
    throw Error(ErrorCode::bad_input, "calibration program: the dwell time must be >= 0 s");
  if (!(options.retract_mm >= 0.0) || !std::isfinite(options.retract_mm))
    throw Error(ErrorCode::bad_input, "calibration program: the retract distance must be >= 0");
  const std::vector<int> ext =
      options.external_joints.empty() ? external_joint_indices(nominal) : options.external_joints;
  const ArmStatusModel arm = make_arm_status_model(nominal);

  KrlProgramInfo info;
  info.name = options.name;
  info.output_dir = options.output_dir;
  info.base = options.base;
  info.tool = options.tool;
  info.cl_line_every = 0;
  info.header_comment = options.header_comment;
  KrlWriter writer(templates, info);

  auto emit = [&](const JointVector& q) {
    // Never write a posture outside the limits: the plan's solver guarantees it, this makes sure.
    if (!within_limits(nominal, q))
      throw Error(ErrorCode::internal,
                  "calibration program: a posture outside the joint limits reached the writer");
    KrlMotion m;
    m.kind = KrlMotionKind::ptp_axes;
    m.axes = to_controller_axes(nominal, q);
    m.T_base_tcp = tcp_pose(nominal, q);
    m.status_turn = status_turn(nominal, arm, q);
    writer.motion(m);
  };
  // The pose backed off from a point along its beam (the beam is -z of the TCP), with the
  // external axes of the point held. Near the edge of the workspace the full distance may be out
  // of reach: half and a quarter of it are tried before giving up.
  auto backed_off = [&](const CalibrationPoint& pt, const char* what, size_t index) {
    std::vector<double> values;
    for (int j : ext)
      values.push_back(pt.q[j]);
    std::string last_error;
    for (double fraction : {1.0, 0.5, 0.25}) {
      Isometry T = pt.T_B_commanded;
      T.translation() += fraction * options.retract_mm * T.linear().col(2);
      try {
        return joints_for_commanded_frame(nominal, ext, values, T, options.perturbed_starts,
                                          options.seed);
      } catch (const Error& e) {
        if (e.code() != ErrorCode::unreachable)
          throw;
        last_error = e.message();
      }
    }
    throw Error(ErrorCode::unreachable,
                fmt::format("calibration program: the {} of point {} ({} mm back along the beam, "
                            "or a half or a quarter of it): {}; use a smaller --retract",
                            what, index + 1, options.retract_mm, last_error));
  };

  writer.comment(fmt::format(
      "Calibration plan: {} points. At each point the laser reading goes into the row of the "
      "same point number in readings_template.csv.",
      points.size()));
  const std::string pause =
      options.dwell_s > 0.0 ? fmt::format("WAIT SEC {:.2f}", options.dwell_s) : "HALT";
  for (size_t i = 0; i < points.size(); ++i) {
    const CalibrationPoint& pt = points[i];
    const bool new_group = i == 0 || pt.configuration != points[i - 1].configuration ||
                           pt.plane != points[i - 1].plane;
    if (new_group) {
      if (i > 0 && options.retract_mm > 0.0)
        emit(backed_off(points[i - 1], "retract", i - 1));
      writer.comment(fmt::format("plane {}, configuration {} ({})", to_string(pt.plane),
                                 pt.configuration + 1, external_text(nominal, ext, pt.q)));
      if (options.retract_mm > 0.0)
        emit(backed_off(pt, "approach", i));
    }
    writer.comment(
        fmt::format("point {} of {}: plane {}", i + 1, points.size(), to_string(pt.plane)));
    emit(pt.q);
    writer.literal(pause);
  }
  if (options.retract_mm > 0.0)
    emit(backed_off(points.back(), "retract", points.size() - 1));
  return writer.finish();
}

}  // namespace redpost
