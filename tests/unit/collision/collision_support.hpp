// Shared helpers of the collision tests: independent distances (closed forms, brute force over
// triangles) and a skeleton of capsules along a cell's DH links.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "redpost/collision/body.hpp"
#include "redpost/kinematics/cell.hpp"

namespace redpost::test {

// Closest point of the segment [a, b] to p.
inline Eigen::Vector3d closest_on_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = b - a;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return a + t * d;
}

// Distance from p to the triangle (a, b, c) (Ericson, Real-Time Collision Detection 5.1.5).
inline double point_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  if (n.norm() > 1e-12) {
    const Eigen::Vector3d nn = n.normalized();
    const Eigen::Vector3d q = p - nn.dot(p - a) * nn;
    // Inside the triangle (same side of every edge)?
    const bool in = (b - a).cross(q - a).dot(n) >= 0.0 && (c - b).cross(q - b).dot(n) >= 0.0 &&
                    (a - c).cross(q - c).dot(n) >= 0.0;
    if (in)
      return (p - q).norm();
  }
  return std::min({(p - closest_on_segment(a, b, p)).norm(),
                   (p - closest_on_segment(b, c, p)).norm(),
                   (p - closest_on_segment(c, a, p)).norm()});
}

// The minimum over t in [0, 1] of a convex function (golden section, to 1e-10).
template <class F>
double convex_min(F f) {
  double lo = 0.0, hi = 1.0;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < 200 && hi - lo > 1e-12; ++i) {
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - g * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + g * (hi - lo);
      f2 = f(x2);
    }
  }
  return std::min({f(0.0), f(1.0), f1, f2});
}

// Distance from a point (in {B}) to a convex primitive placed at T (0 inside).
inline double point_to_shape(const Eigen::Vector3d& p_B, const Shape& s,
                             const Isometry& T_B_shape) {
  const Eigen::Vector3d p = T_B_shape.inverse() * p_B;
  switch (s.kind) {
    case ShapeKind::sphere:
      return std::max(0.0, p.norm() - s.radius_mm);
    case ShapeKind::capsule: {
      const Eigen::Vector3d a(0, 0, -0.5 * s.length_mm), b(0, 0, 0.5 * s.length_mm);
      return std::max(0.0, (p - closest_on_segment(a, b, p)).norm() - s.radius_mm);
    }
    case ShapeKind::cylinder: {
      const double radial = std::max(0.0, std::hypot(p.x(), p.y()) - s.radius_mm);
      const double axial = std::max(0.0, std::fabs(p.z()) - 0.5 * s.length_mm);
      return std::hypot(radial, axial);
    }
    case ShapeKind::box: {
      const Eigen::Vector3d h = 0.5 * s.size_mm;
      const Eigen::Vector3d d = (p.cwiseAbs() - h).cwiseMax(0.0);
      return d.norm();
    }
    case ShapeKind::mesh:
      break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// Every pair among the first `count` bodies: the skeleton's links overlap where they meet, so
// their own pairs are allowed to touch.
inline std::vector<std::pair<int, int>> all_pairs(int count) {
  std::vector<std::pair<int, int>> out;
  for (int a = 0; a < count; ++a) {
    for (int b = a + 1; b < count; ++b)
      out.emplace_back(a, b);
  }
  return out;
}

// Capsules along a cell's DH links (each link from the previous frame's origin along its z by
// d, then along x by a): a skeleton of bodies, one per physical joint, made without the cell's
// own bodies, for tests that need an arm of some thickness.
inline std::vector<Body> skeleton_bodies(const Cell& cell, double radius_mm) {
  std::vector<Body> out;
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    if (j.type == JointType::virtual_spin || j.convention != DhConvention::standard)
      break;
    const double d = j.type == JointType::prismatic ? 0.0 : j.d_mm;
    // Frame i-1's origin and the foot of the common normal, in frame i: frame i is frame i-1
    // times Rz(theta) Tz(d) Tx(a) Rx(alpha), so both are (Tx(a) Rx(alpha))^-1 applied to
    // (0, 0, -d) and to the origin.
    Isometry fwd = Isometry::Identity();
    fwd.translation() = Eigen::Vector3d(j.a_mm, 0.0, 0.0);
    fwd.linear() = Eigen::AngleAxisd(j.alpha_rad, Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Isometry back = fwd.inverse();
    const Eigen::Vector3d foot = back * Eigen::Vector3d::Zero();
    const Eigen::Vector3d origin_before = back * Eigen::Vector3d(0.0, 0.0, -d);
    Body b;
    b.name = "skeleton_" + j.name;
    b.frame = i;
    for (const auto& [p1, p2] : {std::make_pair(origin_before, foot),
                                 std::make_pair(foot, Eigen::Vector3d(Eigen::Vector3d::Zero()))}) {
      Shape s;
      s.kind = ShapeKind::capsule;
      s.radius_mm = radius_mm;
      s.length_mm = (p2 - p1).norm();
      const Eigen::Vector3d z =
          s.length_mm > 1e-9 ? Eigen::Vector3d((p2 - p1) / s.length_mm) : Eigen::Vector3d::UnitZ();
      s.T_frame_shape.linear() =
          Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), z).toRotationMatrix();
      s.T_frame_shape.translation() = 0.5 * (p1 + p2);
      b.shapes.push_back(s);
    }
    out.push_back(b);
  }
  return out;
}

}  // namespace redpost::test
