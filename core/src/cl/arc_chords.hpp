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
// Internal to core (the CL reader's CIRCLE and PostSession::circular_move); not installed.
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>

#include <Eigen/Core>

#include "redpost/cl/expander.hpp"

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
  double tolerance_mm = 0.0;  // the chordal tolerance the chords keep (and a CIRC of it must)

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

// The part of `arc` from fraction f0 to f1 of its sweep, as an arc of its own with `chords`
// chords (at least 1); its end is `arc.end` exactly where f1 is 1. A full turn has no circle
// through its start, middle and end (two of them coincide): the session writes it as two halves.
inline ArcChords arc_piece(const ArcChords& arc, double f0, double f1, long chords) {
  ArcChords piece = arc;
  const double phi0 = f0 * arc.sweep_rad;
  piece.u = std::cos(phi0) * arc.u + std::sin(phi0) * arc.v;
  piece.v = arc.axis.cross(piece.u);
  piece.r0 = arc.r0 + (arc.r1 - arc.r0) * f0;
  piece.r1 = arc.r0 + (arc.r1 - arc.r0) * f1;
  piece.h0 = arc.h0 + (arc.h1 - arc.h0) * f0;
  piece.h1 = arc.h0 + (arc.h1 - arc.h0) * f1;
  piece.sweep_rad = (f1 - f0) * arc.sweep_rad;
  piece.chords = std::max(1L, chords);
  if (f1 < 1.0) {
    const double phi1 = f1 * arc.sweep_rad;
    piece.end = arc.centre + piece.h1 * arc.axis +
                piece.r1 * (std::cos(phi1) * arc.u + std::sin(phi1) * arc.v);
  }
  return piece;
}

// What is wrong with an arc, so that each caller can point at the right place (the CIRCLE
// record, or the GOTO that ends the arc).
enum class ArcProblem {
  none,
  start_on_axis,     // the start point lies on the axis: no radius, no direction
  start_off_radius,  // the start is not at the given radius
  end_off_circle,    // the end point is not on the start's circle
  too_many_chords,   // the tolerance asks for more than kMaxArcChords chords
};

struct ArcBuild {
  ArcChords arc;
  ArcProblem problem = ArcProblem::none;
  std::string message;  // what is wrong, without a location; empty when problem == none
};

// How the caller names things in messages, so that both callers share one geometry and one
// wording: "CIRCLE gives the radius 12 mm", "not on the circle of the CIRCLE at line 3".
struct ArcWording {
  std::string radius_from = "CIRCLE";  // who gave the radius
  std::string circle = "the circle";   // the circle the end point must lie on
};

inline std::string arc_format_mm(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6);
  return std::string(buf, r.ptr);
}

// A count of chords: whole below 1e15, else in exponent form.
inline std::string arc_format_count(double n) {
  return n < 1e15 ? std::to_string(static_cast<long long>(n)) : arc_format_mm(n);
}

// The chords of the arc from `start` to `end` about the unit `axis` through `centre`, turning by
// the right-hand rule. `radius_mm` > 0 is checked against the start's distance from the axis
// (0: none given). Both ends must lie on one circle within `point_tolerance_mm`; an end back at
// the start's direction is a full turn (APT's way to write a circle). The chords stay within
// `chordal_tolerance_mm` of the arc.
inline ArcBuild make_arc_chords(const Eigen::Vector3d& start, const Eigen::Vector3d& centre,
                                const Eigen::Vector3d& axis, double radius_mm,
                                const Eigen::Vector3d& end, double point_tolerance_mm,
                                double chordal_tolerance_mm, const ArcWording& wording = {}) {
  constexpr double kTwoPi = 6.283185307179586;
  ArcBuild b;
  const Eigen::Vector3d& n = axis;
  const Eigen::Vector3d rs = start - centre;
  const Eigen::Vector3d re = end - centre;
  const double h0 = rs.dot(n);
  const double h1 = re.dot(n);
  const Eigen::Vector3d us = rs - h0 * n;
  const Eigen::Vector3d ue = re - h1 * n;
  const double r0 = us.norm();
  const double r1 = ue.norm();
  const double tol = point_tolerance_mm;
  if (!(r0 > 1e-9)) {
    b.problem = ArcProblem::start_on_axis;
    b.message = "the arc's start point lies on the circle's axis (radius 0)";
    return b;
  }
  if (radius_mm > 0.0 && std::fabs(radius_mm - r0) > tol) {
    b.problem = ArcProblem::start_off_radius;
    b.message = "the arc starts " + arc_format_mm(r0) + " mm from the circle's axis, but " +
                wording.radius_from + " gives the radius " + arc_format_mm(radius_mm) +
                " mm (tolerance " + arc_format_mm(tol) + " mm)";
    return b;
  }
  if (std::fabs(r1 - r0) > tol) {
    b.problem = ArcProblem::end_off_circle;
    b.message = "the arc's end point is not on " + wording.circle + ": it lies " +
                arc_format_mm(r1) + " mm from the axis, the radius is " + arc_format_mm(r0) +
                " mm (tolerance " + arc_format_mm(tol) + " mm)";
    return b;
  }
  double sweep = kTwoPi;
  if ((ue / r1 - us / r0).norm() > 1e-12) {
    sweep = std::atan2(n.dot(us.cross(ue)), us.dot(ue));
    if (sweep <= 0.0)
      sweep += kTwoPi;
  }
  const double chords = arc_chord_count(sweep, std::max(r0, r1), chordal_tolerance_mm);
  if (chords > static_cast<double>(kMaxCurveChords)) {
    b.problem = ArcProblem::too_many_chords;
    b.message = "this arc needs " + arc_format_count(chords) + " chords, more than the " +
                arc_format_count(static_cast<double>(kMaxCurveChords)) +
                " a curve may have, at a chordal tolerance of " +
                arc_format_mm(chordal_tolerance_mm) + " mm: raise --chordal-tol";
    return b;
  }
  ArcChords& arc = b.arc;
  arc.centre = centre;
  arc.axis = n;
  arc.u = us / r0;
  arc.v = n.cross(arc.u);
  arc.end = end;
  arc.r0 = r0;
  arc.r1 = r1;
  arc.h0 = h0;
  arc.h1 = h1;
  arc.sweep_rad = sweep;
  arc.chords = static_cast<long>(chords);
  arc.tolerance_mm = chordal_tolerance_mm;
  return b;
}

}  // namespace redpost::detail
