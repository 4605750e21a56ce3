// The tool axis between two poses: turned along the great circle from one to the other, as the
// tracker steps a move (post/motion.cpp) and as the point reduction judges a merged LIN
// (cl/point_reduction.hpp).
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace redpost {

// The unit axis at the fraction t of the great circle from a to b (unit vectors); for opposite
// axes the circle is one of many.
inline Eigen::Vector3d slerp_axis(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t) {
  const Eigen::Quaterniond turn = Eigen::Quaterniond::FromTwoVectors(a, b);
  return (Eigen::Quaterniond::Identity().slerp(t, turn) * a).normalized();
}

// The angle between two directions (rad), accurate for small angles too (acos is not).
inline double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace redpost
