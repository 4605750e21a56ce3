// A post session's deflection (PostSession::Impl, post/session_impl.hpp; docs/deflection.md):
// the cutting force of each cutting move (Tlusty-MacNeil, Caro 2014 eqs. 3.1-3.4) from the CL
// file's tool, spindle and feed and the cutting conditions, the tool's deflection at the posture
// the program uses (eq. 4.1), and under compensate the target moved against it until the
// deflected tool lands on the CL point: a fixed point, since the posture changes with the target.
#include <cmath>

#include "post/session_impl.hpp"
#include "redpost/io/error.hpp"

namespace redpost {

namespace {

// The fixed point is met when one more iteration would move the target by less than a fifth of
// the 0.001 mm the E6POS is written to, and the tool axis by an angle that moves the contact
// 20 mm up the flank by as much. The corrections (Tracker::correct) take no self-motion, so the
// posture moves by the target's change alone and the map contracts by ~1e-3 per iteration.
constexpr double kFixedPointMm = 2e-4;
constexpr double kFixedPointRad = 1e-5;
// The map is a contraction by about |dK_X^-1/dq| |dq/dX| |w|, 1e-3 for milling forces: two
// iterations meet the tolerance. Eight that do not mean the arm is near buckling or a
// singularity, where the linear model is no guide.
constexpr int kMaxFixedPointIterations = 8;

// The target whose deflected tool lands on `cam`: the TCP moved back by the deflection, the tool
// axis turned back by its rotation (to first order, as the model is).
TcpTarget against(const TcpTarget& cam, const ToolDeflection& d) {
  return TcpTarget::axis(cam.p_B_mm - d.translation_mm, cam.z_B - d.rotation_rad.cross(cam.z_B));
}

}  // namespace

// Checked when the session opens: the cell must have the six joint stiffnesses.
void PostSession::Impl::check_deflection_inputs() const {
  if (!deflection_on())
    return;
  try {
    compliant_joints(cell);
  } catch (const Error& e) {
    throw Error(ErrorCode::bad_input,
                "the deflection prediction and compensation need the arm's joint stiffness: " +
                    e.message());
  }
}

ToolDeflection PostSession::Impl::deflection_at(const JointVector& q, const CuttingLoad& load) {
  forward_kinematics(*active_cell, q, deflection_data, false);
  return tool_deflection(*active_cell, deflection_data, load);
}

bool PostSession::Impl::load_for_move(const TcpTarget& cam, const Eigen::Vector3d& p_mm,
                                      int cl_line, CuttingLoad& load) {
  if (spindle_state == Spindle::off)
    return false;  // a move at feed with the spindle stopped cuts nothing
  const CuttingConditions& cc = o.cutting.for_operation(operation_name);
  if (!std::isfinite(cc.diameter_mm) && !(tool_diameter_mm > 0.0)) {
    throw Error(ErrorCode::bad_input,
                tool_number < 0
                    ? "the cutting force needs the tool's diameter, and no tool was loaded "
                      "(LOADTL, LOAD/TOOL) before this cutting move: a CUTTER or TLDATA alone "
                      "loads none. Load the tool in the CL file, or give diameter in the cutting "
                      "file (--cutting, docs/deflection.md)"
                    : "the cutting force needs the tool's diameter, and the CL file gives none "
                      "for the tool in use (CUTTER, TLDATA before its LOADTL): give diameter in "
                      "the cutting file (--cutting, docs/deflection.md)",
                SourceLocation{o.source_name, cl_line, 0});
  }
  MillingConditions mc;
  try {
    mc = milling_conditions(cc, tool_diameter_mm, spindle_rpm, spindle_cw, feed_mm_per_min);
  } catch (const Error& e) {
    std::string where;
    if (!o.cutting.source_file.empty()) {
      where =
          cc.source_line > 0
              ? fmt::format(" (cutting conditions: {}:{})", o.cutting.source_file, cc.source_line)
              : " (cutting conditions: the defaults of " + o.cutting.source_file + ")";
    }
    throw Error(ErrorCode::bad_input, e.message() + where,
                SourceLocation{o.source_name, cl_line, 0});
  }
  const Eigen::Vector3d feed_B = o.T_B_part.linear() * (p_mm - last_cl_point);
  return cutting_load(mc, cam.z_B, feed_B, load);
}

TcpTarget PostSession::Impl::track_cut(const TcpTarget& cam, const Eigen::Vector3d& p_mm,
                                       int cl_line) {
  CuttingLoad load;
  if (!load_for_move(cam, p_mm, cl_line, load)) {
    ++summary.unloaded_moves;
    track_line(cam, cl_line, false);
    return cam;
  }
  MotionDeflection md;
  md.force_N = load.force_N;
  TcpTarget target = cam;
  ToolDeflection d;
  if (o.deflection == DeflectionMode::compensate) {
    // Warm start: the deflection at the posture the move starts from, under this move's load.
    target = against(cam, deflection_at(tracker.q(), load));
    compensating = true;
    track_line(target, cl_line, false);
    int iterations = 1;
    for (;; ++iterations) {
      d = deflection_at(tracker.q(), load);
      const TcpTarget next = against(cam, d);
      const double moved_mm = (next.p_B_mm - target.p_B_mm).norm();
      const double turned_rad = (next.z_B - target.z_B).norm();
      if (moved_mm <= kFixedPointMm && turned_rad <= kFixedPointRad)
        break;
      if (iterations >= kMaxFixedPointIterations) {
        compensating = false;
        throw Error(ErrorCode::unreachable,
                    fmt::format("the deflection compensation does not settle: after {} "
                                "iterations the target still moves by {:.4f} mm and {:.2e} rad "
                                "per iteration (the arm is near a singularity or the load is "
                                "too large for the linear model). Move the part (--placement), "
                                "lighten the cut (ae, ap in --cutting), or convert without "
                                "--compensate",
                                iterations, moved_mm, turned_rad),
                    SourceLocation{o.source_name, cl_line, 0});
      }
      const PoseResult r = tracker.correct(next);
      if (r.status != PoseStatus::converged)
        fail(r, cl_line, "cutting move, its target moved against the arm's deflection");
      record(r, cl_line, false);
      if (!line_steps.empty())
        line_steps.back() = r.q;
      target = next;
    }
    compensating = false;
    md.iterations = iterations;
    summary.compensation_iterations += iterations - 1;
    summary.max_compensation_iterations = std::max(summary.max_compensation_iterations, iterations);
    md.compensation_mm = (target.p_B_mm - cam.p_B_mm).norm();
  } else {
    track_line(cam, cl_line, false);
    d = deflection_at(tracker.q(), load);
  }
  // The model's error at the posture tracked: where the deflected tool ends, against the CL point.
  const Eigen::Vector3d error_B =
      tracker.tcp_pose_at_q().translation() + d.translation_mm - cam.p_B_mm;
  const Eigen::Matrix3d R_part_B = o.T_B_part.linear().transpose();
  md.translation_mm = R_part_B * d.translation_mm;
  md.rotation_rad = R_part_B * d.rotation_rad;
  md.normal_mm = d.normal_mm;
  md.residual_mm = error_B.norm();
  md.residual_normal_mm = error_B.dot(load.n_material_B);
  move_deflection = md;
  note_deflection(md, cl_line);
  return target;
}

void PostSession::Impl::note_deflection(const MotionDeflection& d, int cl_line) {
  if (summary.deflection.empty() || stats_serial != operation_serial) {
    summary.deflection.emplace_back();
    summary.deflection.back().operation = operation_name;
    summary.deflection.back().first_line = cl_line;
    stats_serial = operation_serial;
  }
  DeflectionStats& s = summary.deflection.back();
  // rms_* hold the sums of squares until prepare() turns them into RMS values.
  const double n = std::fabs(d.normal_mm), after = std::fabs(d.residual_normal_mm);
  const double tol = o.deflection_tolerance_mm;
  ++s.motions;
  s.last_line = cl_line;
  s.max_mm = std::max(s.max_mm, d.translation_mm.norm());
  s.rms_mm += d.translation_mm.squaredNorm();
  if (n > s.max_normal_mm) {
    s.max_normal_mm = n;
    s.max_normal_line = cl_line;
  }
  s.rms_normal_mm += n * n;
  s.max_rotation_rad = std::max(s.max_rotation_rad, d.rotation_rad.norm());
  s.max_force_N = std::max(s.max_force_N, d.force_N);
  s.over_tolerance += n > tol;
  s.max_residual_mm = std::max(s.max_residual_mm, d.residual_mm);
  s.max_residual_normal_mm = std::max(s.max_residual_normal_mm, after);
  s.over_tolerance_after += after > tol;
  s.max_compensation_mm = std::max(s.max_compensation_mm, d.compensation_mm);
}

}  // namespace redpost
