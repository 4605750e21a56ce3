// A model of the path a KR C4 draws through a SPLINE block of SLIN and SPL segments
// (docs/krl-templates.md, "SPL segments"), and the rule by which the writer passes a point of
// the block smoothly.
//
// KUKA does not publish its SPL interpolation (the controller estimates a point's derivatives
// from its neighbours). The model here is ours, to be verified on KUKA.OfficeLite: each segment
// is a cubic Hermite curve from its start to its end point; at a point the block passes
// smoothly (an SPL knot) the tangent is Bessel's (the parabola through the point and its two
// neighbours, parameterised by chord length), and at a point where the block starts or ends
// (a corner: the block is ended there and blended into the next with $APO.CDIS) the segment
// leaves or arrives along its own chord. A segment with no smooth end is a straight SLIN.
//
// The bound that makes a knot smooth: the Hermite segment's distance from its chord is the sum
// of its end tangents' components across the chord times the basis functions h10 and h11,
// whose magnitudes peak at 4/27; so a segment is within `tolerance_mm` of its chord when each
// of its ends adds at most half of it, (4/27) |lateral| <= tolerance / 2. The tangents' along
// components stay within the chord's length, so the curve advances monotonically along the
// chord and the distance holds both ways (every chord point is as close to the curve).
#pragma once

#include <Eigen/Core>

namespace redpost {

// A point is passed smoothly only where the path turns by at most this much there, and its two
// segments' lengths are within this ratio of each other (KUKA's estimate of the derivatives is
// its own: the model should not be stretched where two models could differ much).
inline constexpr double kMaxSplineKinkRad = 30.0 * 3.14159265358979323846 / 180.0;
inline constexpr double kMaxSplineLengthRatio = 4.0;
// Segments shorter than this (mm) are a turn on the spot: never part of a smooth knot.
inline constexpr double kMinSplineSegmentMm = 1e-3;

// The unit tangent at b of the parabola through a, b and c with chord-length parameters.
Eigen::Vector3d bessel_tangent(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               const Eigen::Vector3d& c);

// Whether a block may pass b smoothly between a and c, its segments each within
// `tolerance_mm` of their chords whatever their other ends (the class comment's bound).
bool smooth_knot(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                 double tolerance_mm);

// One segment of the model: p(u) = h00 p0 + h10 m0 + h01 p1 + h11 m1, u in [0, 1].
struct SplineSegment {
  Eigen::Vector3d p0 = Eigen::Vector3d::Zero(), m0 = Eigen::Vector3d::Zero();
  Eigen::Vector3d p1 = Eigen::Vector3d::Zero(), m1 = Eigen::Vector3d::Zero();
  Eigen::Vector3d at(double u) const;
};

// The segment from p0 to p1: t0 and t1 are the unit tangents at smooth knots, or zero at a
// corner (the segment leaves or arrives along its chord). Tangents are scaled by the chord.
SplineSegment spline_segment(const Eigen::Vector3d& p0, const Eigen::Vector3d& t0,
                             const Eigen::Vector3d& p1, const Eigen::Vector3d& t1);

}  // namespace redpost
