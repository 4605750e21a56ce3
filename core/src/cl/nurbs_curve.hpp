// A NURBS curve for the CL reader: evaluation by de Boor's algorithm and linearisation into
// chords within a tolerance, one chord end at a time (a long spline never becomes a big array).
//
//   C(t) = sum_i N_i,p(t) w_i P_i / sum_i N_i,p(t) w_i
//
// with n control points P_i, weights w_i > 0, degree p = order - 1 and a clamped knot vector
// U of n + order values (U[0..p] equal, U[n..n+p] equal), so that C(U[p]) = P_0 and
// C(U[n]) = P_{n-1}. de Boor's algorithm blends the homogeneous points (w x, w y, w z, w) of
// the span U[k] <= t < U[k+1] in p affine rounds and divides by w at the end (Piegl & Tiller,
// "The NURBS Book", algorithms A2.1 and A4.1).
//
// Internal to the CL reader (cl/nurbs.cpp); not installed.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace redpost::detail {

inline constexpr int kMaxNurbsOrder = 10;  // degree 9; NX writes cubics (order 4)

struct HomogeneousPoint {
  double wx = 0.0, wy = 0.0, wz = 0.0, w = 1.0;
};

struct NurbsCurve {
  int order = 0;                         // degree + 1
  std::vector<double> knots;             // the full clamped knot vector: points.size() + order
  std::vector<HomogeneousPoint> points;  // (w x, w y, w z, w), in mm

  int degree() const { return order - 1; }
  double t_begin() const { return knots[static_cast<std::size_t>(degree())]; }
  double t_end() const { return knots[points.size()]; }

  // The index k of the span U[k] <= t < U[k+1] that holds t (the last non-empty span for
  // t = t_end()).
  std::size_t span(double t) const {
    const std::size_t p = static_cast<std::size_t>(degree());
    const std::size_t n = points.size();
    // First knot in U[p+1 .. n] greater than t; the span starts one before it.
    const auto it = std::upper_bound(knots.begin() + static_cast<std::ptrdiff_t>(p) + 1,
                                     knots.begin() + static_cast<std::ptrdiff_t>(n), t);
    std::size_t k = static_cast<std::size_t>(it - knots.begin()) - 1;
    while (k > p && knots[k] == knots[k + 1])  // t = t_end(): step back over empty spans
      --k;
    return k;
  }

  Eigen::Vector3d at(double t) const {
    const int p = degree();
    const std::size_t k = span(t);
    std::array<HomogeneousPoint, kMaxNurbsOrder> d;
    for (int j = 0; j <= p; ++j)
      d[static_cast<std::size_t>(j)] = points[k - static_cast<std::size_t>(p - j)];
    for (int r = 1; r <= p; ++r) {
      for (int j = p; j >= r; --j) {
        const std::size_t i = k - static_cast<std::size_t>(p - j);
        const double lo = knots[i];
        const double hi = knots[i + static_cast<std::size_t>(p - r + 1)];
        const double a = (t - lo) / (hi - lo);  // hi > lo: interior multiplicity <= degree
        HomogeneousPoint& q = d[static_cast<std::size_t>(j)];
        const HomogeneousPoint& q0 = d[static_cast<std::size_t>(j - 1)];
        q.wx = (1.0 - a) * q0.wx + a * q.wx;
        q.wy = (1.0 - a) * q0.wy + a * q.wy;
        q.wz = (1.0 - a) * q0.wz + a * q.wz;
        q.w = (1.0 - a) * q0.w + a * q.w;
      }
    }
    const HomogeneousPoint& c = d[static_cast<std::size_t>(p)];
    return Eigen::Vector3d(c.wx / c.w, c.wy / c.w, c.wz / c.w);
  }

  Eigen::Vector3d cartesian(std::size_t i) const {
    const HomogeneousPoint& c = points[i];
    return Eigen::Vector3d(c.wx / c.w, c.wy / c.w, c.wz / c.w);
  }
};

// Distance from q to the segment [a, b].
inline double distance_to_segment(const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double len2 = d.squaredNorm();
  if (len2 <= 0.0)
    return (q - a).norm();
  const double u = std::clamp((q - a).dot(d) / len2, 0.0, 1.0);
  return (q - (a + u * d)).norm();
}

// Chords of a NURBS curve, each knot span split in halves until the curve at a quarter, half
// and three quarters of a piece lies within 0.8 x tolerance of its chord. The 0.8 leaves room
// for the true maximum deviation falling between the samples (for an arc-like piece whose
// deepest point sits 10 % off the middle the sampled deviation is 96 % of the true one).
class NurbsChords {
 public:
  // Starts at C(t_begin()), which the caller has already emitted.
  void start(const NurbsCurve& curve, double tolerance_mm) {
    curve_ = &curve;
    tolerance_mm_ = tolerance_mm;
    span_ = static_cast<std::size_t>(curve.degree());
    stack_.clear();
    last_ = curve.cartesian(0);
  }

  // The next chord end, false after the last one (which is exactly the last control point).
  bool next(Eigen::Vector3d& p) {
    const NurbsCurve& c = *curve_;
    const std::size_t n = c.points.size();
    for (;;) {
      if (stack_.empty()) {
        while (span_ < n && !(c.knots[span_] < c.knots[span_ + 1]))
          ++span_;
        if (span_ >= n)
          return false;
        stack_.push_back({c.knots[span_], c.knots[span_ + 1], 0});
        ++span_;
      }
      const Piece piece = stack_.back();
      const bool at_end = piece.t1 >= c.t_end();
      const Eigen::Vector3d end = at_end ? c.cartesian(n - 1) : c.at(piece.t1);
      if (piece.depth < kMaxDepth && !flat(piece, end)) {
        const double mid = 0.5 * (piece.t0 + piece.t1);
        stack_.back() = {mid, piece.t1, piece.depth + 1};
        stack_.push_back({piece.t0, mid, piece.depth + 1});
        continue;
      }
      stack_.pop_back();
      last_ = end;
      p = end;
      return true;
    }
  }

 private:
  struct Piece {
    double t0, t1;
    int depth;
  };
  static constexpr int kMaxDepth = 40;  // a piece of 1e-12 of a span is flat for any purpose

  bool flat(const Piece& piece, const Eigen::Vector3d& end) const {
    const double limit = 0.8 * tolerance_mm_;
    for (double f : {0.25, 0.5, 0.75}) {
      const Eigen::Vector3d q = curve_->at(piece.t0 + f * (piece.t1 - piece.t0));
      if (distance_to_segment(q, last_, end) > limit)
        return false;
    }
    return true;
  }

  const NurbsCurve* curve_ = nullptr;
  double tolerance_mm_ = 0.01;
  std::size_t span_ = 0;
  std::vector<Piece> stack_;
  Eigen::Vector3d last_ = Eigen::Vector3d::Zero();
};

}  // namespace redpost::detail
