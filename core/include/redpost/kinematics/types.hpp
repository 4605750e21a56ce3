// Fixed-capacity Eigen types shared by the kinematics.
//
// A cell has at most kMaxJoints joints. Every per-pose quantity uses storage of that fixed
// capacity, so nothing on the per-pose path touches the heap (Eigen keeps the buffer inline and
// only the run-time size varies).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace redpost {

inline constexpr int kMaxJoints = 16;

// Joint values in DH units: rad for revolute and virtual joints, mm for prismatic ones.
using JointVector = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxJoints, 1>;

// A 6 x n Jacobian, rows [omega; v] (rad/s and mm/s per unit joint rate), as Andres eq. 14.
using Jacobian = Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::ColMajor, 6, kMaxJoints>;

using Vector6d = Eigen::Matrix<double, 6, 1>;

// Rigid transforms. Translations are in mm.
using Isometry = Eigen::Isometry3d;

inline constexpr double kPi = 3.141592653589793238462643383279502884;
inline constexpr double deg_to_rad(double deg) {
  return deg * (kPi / 180.0);
}
inline constexpr double rad_to_deg(double rad) {
  return rad * (180.0 / kPi);
}

}  // namespace redpost
