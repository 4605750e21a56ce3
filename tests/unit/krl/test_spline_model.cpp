// The model of a SPLINE block's path (redpost/krl/spline_model.hpp) against closed forms, a
// finite difference and a brute-force sampling of its bound; and the writer's SPL knots.
#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "catch_compat.hpp"
#include "redpost/krl/spline_model.hpp"

using namespace redpost;

namespace {

// Distance from p to the segment a-b.
double to_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = b - a;
  const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * d)).norm();
}

// The largest distance of the segment's curve from its chord, sampled; and whether it advances
// along the chord all the way.
double chord_deviation(const SplineSegment& s, bool& monotone) {
  const Eigen::Vector3d d = (s.p1 - s.p0).normalized();
  double worst = 0.0, last = -1e300;
  monotone = true;
  for (int k = 0; k <= 2000; ++k) {
    const Eigen::Vector3d p = s.at(k / 2000.0);
    worst = std::max(worst, to_segment(s.p0, s.p1, p));
    const double along = (p - s.p0).dot(d);
    monotone = monotone && along >= last - 1e-12;
    last = along;
  }
  return worst;
}

}  // namespace

TEST_CASE("spline model: Bessel's tangent on a circle is the circle's") {
  // Three points of a circle, equally spaced: the parabola's tangent at the middle one is the
  // circle's there (symmetry), whatever the radius and spacing.
  for (double r : {0.5, 20.0, 3000.0}) {
    for (double step : {0.01, 0.2, 0.5}) {
      const Eigen::Vector3d a(r * std::cos(-step), r * std::sin(-step), 1.0);
      const Eigen::Vector3d b(r, 0.0, 1.0);
      const Eigen::Vector3d c(r * std::cos(step), r * std::sin(step), 1.0);
      const Eigen::Vector3d t = bessel_tangent(a, b, c);
      CHECK((t - Eigen::Vector3d::UnitY()).norm() < 1e-12);
    }
  }
  // Collinear points: the line's direction; a repeated point: no tangent.
  CHECK((bessel_tangent({0, 0, 0}, {1, 0, 0}, {5, 0, 0}) - Eigen::Vector3d::UnitX()).norm() <
        1e-15);
  CHECK(bessel_tangent({0, 0, 0}, {0, 0, 0}, {1, 0, 0}).isZero());
}

TEST_CASE("spline model: a segment interpolates its ends with the tangents given") {
  const Eigen::Vector3d p0(1, 2, 3), p1(4, 2, 5);
  const Eigen::Vector3d t0 = Eigen::Vector3d(1, 0.3, 0.1).normalized();
  const Eigen::Vector3d t1 = Eigen::Vector3d(1, -0.2, 0.4).normalized();
  const SplineSegment s = spline_segment(p0, t0, p1, t1);
  CHECK((s.at(0.0) - p0).norm() < 1e-15);
  CHECK((s.at(1.0) - p1).norm() < 1e-14);
  // The derivative by central differences at the ends' neighbourhood: the chord's length times
  // the unit tangent.
  const double h = 1e-6, length = (p1 - p0).norm();
  const Eigen::Vector3d d0 = (s.at(h) - s.at(0.0)) / h, d1 = (s.at(1.0) - s.at(1.0 - h)) / h;
  CHECK((d0 - length * t0).norm() < 1e-5);
  CHECK((d1 - length * t1).norm() < 1e-5);
  // Both ends corners: the straight SLIN.
  const SplineSegment line =
      spline_segment(p0, Eigen::Vector3d::Zero(), p1, Eigen::Vector3d::Zero());
  for (double u : {0.1, 0.37, 0.8})
    CHECK(to_segment(p0, p1, line.at(u)) < 1e-12);
}

TEST_CASE("spline model: a smooth knot keeps both its segments within the tolerance") {
  // Seeded random knots: whenever smooth_knot accepts b between a and c, each segment through b
  // stays within the tolerance of its chord with any accepted tangent at its other end (or a
  // corner there), sampled; and it advances along its chord.
  std::mt19937_64 rng(30);
  std::uniform_real_distribution<double> len(0.05, 5.0), turn(-0.25, 0.25), unit(-1.0, 1.0);
  const double tol = 0.009;
  int accepted = 0, refused = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const Eigen::Vector3d b(unit(rng), unit(rng), unit(rng));
    const Eigen::Vector3d dir = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    const Eigen::Vector3d axis = dir.unitOrthogonal();
    const double scale = trial % 2 ? 0.05 : 1.0;  // small turns and large ones
    const Eigen::Vector3d a = b - len(rng) * (Eigen::AngleAxisd(scale * turn(rng), axis) * dir);
    const Eigen::Vector3d c =
        b + len(rng) * (Eigen::AngleAxisd(scale * turn(rng), axis.cross(dir)) * dir);
    if (!smooth_knot(a, b, c, tol)) {
      ++refused;
      continue;
    }
    ++accepted;
    const Eigen::Vector3d t = bessel_tangent(a, b, c);
    // The other end's tangent: a corner, or the worst a smooth knot there may have, the tangent
    // across its chord at the bound (the chord turned by the largest angle it allows).
    for (int other = 0; other < 3; ++other) {
      for (const bool before : {true, false}) {
        const Eigen::Vector3d p0 = before ? a : b, p1 = before ? b : c;
        const Eigen::Vector3d chord = p1 - p0;
        Eigen::Vector3d far = Eigen::Vector3d::Zero();
        if (other > 0) {
          const double budget = 0.5 * tol * 27.0 / 4.0 / chord.norm();
          const double angle = std::asin(std::min(1.0, budget)) * (other == 1 ? 1.0 : -1.0);
          far = Eigen::AngleAxisd(angle, chord.unitOrthogonal()) * chord.normalized();
        }
        const SplineSegment s =
            before ? spline_segment(p0, far, p1, t) : spline_segment(p0, t, p1, far);
        bool monotone = false;
        const double dev = chord_deviation(s, monotone);
        CHECK(dev <= tol * (1.0 + 1e-9));
        CHECK(monotone);
      }
    }
  }
  // Both outcomes are exercised.
  CHECK(accepted > 500);
  CHECK(refused > 500);
}

TEST_CASE("spline model: corners, very unequal segments and repeated points are not smooth") {
  const double tol = 0.01;
  // A right angle.
  CHECK_FALSE(smooth_knot({0, 0, 0}, {10, 0, 0}, {10, 10, 0}, tol));
  // Nearly straight but 5:1 in length.
  CHECK_FALSE(smooth_knot({0, 0, 0}, {10, 0, 0}, {12, 0.0001, 0}, tol));
  // A point given twice, and a turn on the spot.
  CHECK_FALSE(smooth_knot({0, 0, 0}, {0, 0, 0}, {1, 0, 0}, tol));
  CHECK_FALSE(smooth_knot({0, 0, 0}, {1, 0, 0}, {1, 0, 0}, tol));
  // No tolerance: nothing is smooth.
  CHECK_FALSE(smooth_knot({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, 0.0));
  // Dense points of a 50 mm circle, 1 mm apart (sagitta 2.5 um): smooth.
  const double r = 50.0, s = 1.0 / r;
  CHECK(smooth_knot({r * std::cos(-s), r * std::sin(-s), 0}, {r, 0, 0},
                    {r * std::cos(s), r * std::sin(s), 0}, tol));
}
