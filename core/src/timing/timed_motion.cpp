// Motions as the time model sees them (timing/timed_motion.hpp).
#include "redpost/timing/timed_motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace redpost {

double rotation_angle(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b) {
  const double c = std::clamp(0.5 * ((R_a.transpose() * R_b).trace() - 1.0), -1.0, 1.0);
  return std::acos(c);
}

TimedMotion cp_motion(const Cell& cell, const JointVector& q0, const Isometry& T_B_tcp0,
                      const JointVector& q1, const Isometry& T_B_tcp1, double length_mm,
                      double asked_mm_s, double orientation_velocity_rad_s, double blend_mm) {
  TimedMotion t;
  t.kind = TimedMotion::Kind::cp;
  t.asked_mm_s = asked_mm_s;
  t.command_mm_s = asked_mm_s;
  const double turn = rotation_angle(T_B_tcp0.linear(), T_B_tcp1.linear());
  const double turn_mm = turn * asked_mm_s / orientation_velocity_rad_s;
  t.length_mm = length_mm > 1e-6 ? length_mm : turn_mm;
  t.tcp_length_mm = length_mm;
  if (length_mm > 1e-6 && turn > 0.0)
    t.orientation_cap_mm_s = length_mm * orientation_velocity_rad_s / turn;
  const int n = cell.size();
  t.chord_rate.setZero(n);
  t.peak_rate.setZero(n);
  if (t.length_mm > 0.0) {
    t.chord_rate = (q1 - q0) / t.length_mm;
    t.peak_rate = t.chord_rate.cwiseAbs();
  }
  if (length_mm > 1e-6)
    t.tangent = (T_B_tcp1.translation() - T_B_tcp0.translation()) / length_mm;
  t.exit_tangent = t.tangent;
  t.entry_rate = t.chord_rate;
  t.exit_rate = t.chord_rate;
  t.blend_mm = blend_mm;
  return t;
}

TimedMotion synchronous_ptp(const Cell& cell, const JointVector& q0, const JointVector& q1,
                            const ControllerTiming& controller) {
  TimedMotion t;
  t.kind = TimedMotion::Kind::ptp;
  t.asked_mm_s = std::numeric_limits<double>::quiet_NaN();
  t.command_mm_s = std::numeric_limits<double>::quiet_NaN();
  t.chord_rate = q1 - q0;
  t.peak_rate.setZero(cell.size());
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    if (!j.has_speed())
      continue;
    const double s = PathTimer::stop_to_stop_s(
        t.chord_rate[i], controller.ptp_velocity_fraction * j.max_velocity,
        controller.ptp_acceleration_fraction * j.max_acceleration);
    if (s > t.ptp_time_s) {
      t.ptp_time_s = s;
      t.ptp_joint = i;
    }
  }
  return t;
}

}  // namespace redpost
