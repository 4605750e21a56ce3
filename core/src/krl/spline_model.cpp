// The model of a SPLINE block's path (redpost/krl/spline_model.hpp).
#include "redpost/krl/spline_model.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace redpost {

namespace {

// The largest magnitude of the Hermite basis functions h10 and h11 on [0, 1] (at 1/3, 2/3).
constexpr double kHermitePeak = 4.0 / 27.0;

}  // namespace

Eigen::Vector3d bessel_tangent(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               const Eigen::Vector3d& c) {
  const Eigen::Vector3d d1 = b - a, d2 = c - b;
  const double l1 = d1.norm(), l2 = d2.norm();
  if (!(l1 > 0.0) || !(l2 > 0.0))
    return Eigen::Vector3d::Zero();
  // The derivative at b of the parabola through a (at -l1), b (at 0) and c (at l2).
  const Eigen::Vector3d t = (l2 / (l1 + l2)) * (d1 / l1) + (l1 / (l1 + l2)) * (d2 / l2);
  const double n = t.norm();
  return n > 0.0 ? Eigen::Vector3d(t / n) : Eigen::Vector3d::Zero();
}

bool smooth_knot(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                 double tolerance_mm) {
  if (!(tolerance_mm > 0.0))
    return false;
  const Eigen::Vector3d d1 = b - a, d2 = c - b;
  const double l1 = d1.norm(), l2 = d2.norm();
  if (!(l1 >= kMinSplineSegmentMm) || !(l2 >= kMinSplineSegmentMm))
    return false;
  if (std::max(l1, l2) > kMaxSplineLengthRatio * std::min(l1, l2))
    return false;
  const double kink = std::atan2(d1.cross(d2).norm(), d1.dot(d2));
  if (!(kink <= kMaxSplineKinkRad))
    return false;
  const Eigen::Vector3d t = bessel_tangent(a, b, c);
  // Each segment's tangent at b is t times its chord's length; its part across the chord.
  const double across1 = l1 * t.cross(d1 / l1).norm();
  const double across2 = l2 * t.cross(d2 / l2).norm();
  const double budget = 0.5 * tolerance_mm / kHermitePeak;
  return across1 <= budget && across2 <= budget;
}

Eigen::Vector3d SplineSegment::at(double u) const {
  const double u2 = u * u, u3 = u2 * u;
  const double h00 = 2.0 * u3 - 3.0 * u2 + 1.0, h10 = u3 - 2.0 * u2 + u;
  const double h01 = -2.0 * u3 + 3.0 * u2, h11 = u3 - u2;
  return h00 * p0 + h10 * m0 + h01 * p1 + h11 * m1;
}

SplineSegment spline_segment(const Eigen::Vector3d& p0, const Eigen::Vector3d& t0,
                             const Eigen::Vector3d& p1, const Eigen::Vector3d& t1) {
  SplineSegment s;
  s.p0 = p0;
  s.p1 = p1;
  const Eigen::Vector3d chord = p1 - p0;
  const double length = chord.norm();
  s.m0 = t0.isZero() ? chord : Eigen::Vector3d(length * t0);
  s.m1 = t1.isZero() ? chord : Eigen::Vector3d(length * t1);
  return s;
}

}  // namespace redpost
