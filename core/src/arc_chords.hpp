// A circular or helical arc about an axis, split into chords whose sagitta stays within a
// tolerance, one chord end at a time.
//
// The arc starts at S and turns by `sweep` about the unit axis n through the centre C, by the
// right-hand rule. With u the unit radial direction of S and v = n x u, the point at fraction
// f in [0, 1] is
//
//   P(f) = C + h(f) n + r(f) (cos(f sweep) u + sin(f sweep) v)
//
// where h (height along n) and r (radius) go linearly from the start's to the end's values:
// r0 == r1 up to the CL file's rounding, and h0 != h1 is a helix. A chord spanning the angle
// phi strays from the circle by its sagitta r (1 - cos(phi / 2)) = 2 r sin^2(phi / 4), so
// phi_max = 4 asin(sqrt(tol / (2 r))) keeps every chord within tol (the axial part is linear in
// both the helix and the chord, so it adds nothing).
//
// Internal to the CL reader (cl_reader.cpp); not installed.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

namespace redpost::detail {

// Number of chords for an arc of `sweep_rad` and radius `radius_mm` within `tolerance_mm`;
// at most a quarter turn per chord, so that a coarse tolerance still draws a circle.
inline double arc_chord_count(double sweep_rad, double radius_mm, double tolerance_mm) {
  constexpr double kQuarterTurn = 1.5707963267948966;
  double max_angle = kQuarterTurn;
  if (tolerance_mm < 2.0 * radius_mm)
    max_angle = std::min(max_angle, 4.0 * std::asin(std::sqrt(tolerance_mm / (2.0 * radius_mm))));
  return std::max(1.0, std::ceil(sweep_rad / max_angle));
}

struct ArcChords {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // unit; travel by the right-hand rule
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();     // unit radial direction of the start
  Eigen::Vector3d v = Eigen::Vector3d::UnitY();     // axis x u
  Eigen::Vector3d end = Eigen::Vector3d::Zero();    // exact end point (the GOTO)
  double r0 = 0.0, r1 = 0.0;                        // radius at start and end, mm
  double h0 = 0.0, h1 = 0.0;                        // height along the axis at start and end
  double sweep_rad = 0.0;
  long chords = 1;

  // End of chord k (1..chords); the last one is `end` exactly.
  Eigen::Vector3d point(long k) const {
    if (k >= chords)
      return end;
    const double f = static_cast<double>(k) / static_cast<double>(chords);
    const double phi = f * sweep_rad;
    const double r = r0 + (r1 - r0) * f;
    const double h = h0 + (h1 - h0) * f;
    return centre + h * axis + r * (std::cos(phi) * u + std::sin(phi) * v);
  }
};

}  // namespace redpost::detail
