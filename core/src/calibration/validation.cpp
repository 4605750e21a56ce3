// The validation of a calibration (validation.hpp; Andres et al. 2011 Section 3.3): the random
// validation plan and the statistics of what the nominal and calibrated models leave.
// docs/calibration.md.
#include "redpost/calibration/validation.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "calibration/fail.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"

namespace redpost {

namespace {

using detail::fail_bad_input;

}  // namespace

std::vector<CalibrationPoint> plan_validation(const Cell& nominal,
                                              const ValidationPlanOptions& options) {
  if (options.points < 1)
    fail_bad_input("validation plan: at least one point is needed");
  const std::vector<int> ext =
      options.external_joints.empty() ? external_joint_indices(nominal) : options.external_joints;
  std::vector<std::pair<double, double>> ranges = options.ranges;
  if (ranges.empty()) {
    for (int j : ext) {
      const Joint& jt = nominal.joint(j);
      // The paper's section 3.3: theta_M in [0, pi], d_L in [0, 1000] mm.
      if (jt.type == JointType::prismatic)
        ranges.emplace_back(0.0, 1000.0);
      else
        ranges.emplace_back(0.0, kPi);
    }
  }
  if (ranges.size() != ext.size())
    fail_bad_input("validation plan: " + std::to_string(ranges.size()) + " ranges for " +
                   std::to_string(ext.size()) + " external joints");
  for (size_t k = 0; k < ext.size(); ++k) {
    const Joint& jt = nominal.joint(ext[k]);
    ranges[k].first = std::max(ranges[k].first, jt.lower);
    ranges[k].second = std::min(ranges[k].second, jt.upper);
    if (!(ranges[k].first <= ranges[k].second))
      fail_bad_input("validation plan: the range of joint '" + jt.name +
                     "' lies outside its limits");
  }
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto& off = options.model.plane_offset_mm;
  const double w = options.half_width_mm;
  std::vector<CalibrationPoint> points;
  points.reserve(static_cast<size_t>(options.points));
  for (int i = 0; i < options.points; ++i) {
    std::vector<double> config(ext.size());
    for (size_t k = 0; k < ext.size(); ++k)
      config[k] = ranges[k].first + (ranges[k].second - ranges[k].first) * unit(rng);
    const double u = -w + 2.0 * w * unit(rng);
    const double v = unit(rng);
    Eigen::Vector3d p;
    if (options.plane == PlaneAxis::x)
      p = {off[0], u, options.z_min_mm + (options.z_max_mm - options.z_min_mm) * v};
    else if (options.plane == PlaneAxis::y)
      p = {u, off[1], options.z_min_mm + (options.z_max_mm - options.z_min_mm) * v};
    else
      p = {u, -w + 2.0 * w * v, off[2]};
    CalibrationPoint pt;
    pt.plane = options.plane;
    pt.configuration = i;
    pt.T_B_commanded = commanded_frame(options.plane, p, options.stand_off_mm);
    try {
      pt.q = joints_for_commanded_frame(nominal, ext, config, pt.T_B_commanded,
                                        options.perturbed_starts, options.seed);
    } catch (const Error& e) {
      throw Error(e.code(), "validation plan: point " + std::to_string(i + 1) + ": " + e.message());
    }
    pt.reading_mm = options.stand_off_mm;
    points.push_back(pt);
  }
  return points;
}

DistanceStatistics distance_statistics(const Eigen::VectorXd& d) {
  DistanceStatistics st;
  st.count = static_cast<int>(d.size());
  if (d.size() == 0)
    return st;
  const double n = static_cast<double>(d.size());
  st.mean_mm = d.mean();
  st.rms_mm = std::sqrt(d.squaredNorm() / n);
  st.std_mm = d.size() > 1 ? std::sqrt((d.array() - st.mean_mm).square().sum() / (n - 1.0)) : 0.0;
  st.max_abs_mm = d.cwiseAbs().maxCoeff();
  return st;
}

ValidationResult validate_calibration(const Cell& nominal, const Cell& calibrated,
                                      const std::vector<CalibrationPoint>& points,
                                      const MeasurementModel& model) {
  ValidationResult v;
  const auto n = static_cast<Eigen::Index>(points.size());
  v.before_mm.resize(n);
  v.after_mm.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const CalibrationPoint& pt = points[static_cast<size_t>(i)];
    v.before_mm[i] = pt.reading_mm - laser_reading(tcp_pose(nominal, pt.q), pt.plane, model);
    v.after_mm[i] = pt.reading_mm - laser_reading(tcp_pose(calibrated, pt.q), pt.plane, model);
  }
  v.before = distance_statistics(v.before_mm);
  v.after = distance_statistics(v.after_mm);
  return v;
}

}  // namespace redpost
