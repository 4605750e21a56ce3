#include "krl/diff_path.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "redpost/kinematics/kuka_abc.hpp"

namespace redpost::krl {

namespace {

constexpr int kMaxRings = 3;  // the search goes this many cells out before it gives up

bool finite3(const std::array<double, 3>& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

Eigen::Vector3d vec(const std::array<double, 3>& v) {
  return {v[0], v[1], v[2]};
}

}  // namespace

std::size_t PathIndex::CellHash::operator()(const Cell& c) const {
  std::uint64_t h = 1469598103934665603ULL;
  for (std::int64_t v : c)
    h = (h ^ static_cast<std::uint64_t>(v)) * 1099511628211ULL;
  return static_cast<std::size_t>(h);
}

PathIndex::Cell PathIndex::cell_of(const std::array<double, 3>& p) const {
  return {static_cast<std::int64_t>(std::floor(p[0] / h_)),
          static_cast<std::int64_t>(std::floor(p[1] / h_)),
          static_cast<std::int64_t>(std::floor(p[2] / h_))};
}

// A segment goes into the cells of points along it every h/2, so that every point of it is
// within h/4 of a point that was put in a cell.
void PathIndex::insert_segment(std::uint32_t i) {
  const Eigen::Vector3d a = vec(points_[i].xyz);
  const Eigen::Vector3d b =
      i + 1 < points_.size() && !points_[i + 1].starts_piece ? vec(points_[i + 1].xyz) : a;
  const double length = (b - a).norm();
  const int steps = static_cast<int>(std::ceil(length / (0.5 * h_)));
  Cell last{std::numeric_limits<std::int64_t>::min(), 0, 0};
  for (int k = 0; k <= steps; ++k) {
    const Eigen::Vector3d p = steps == 0 ? a : a + (b - a) * (static_cast<double>(k) / steps);
    const Cell c = cell_of({p.x(), p.y(), p.z()});
    if (c == last)
      continue;
    std::vector<std::uint32_t>& v = grid_[c];
    if (v.empty() || v.back() != i)
      v.push_back(i);
    last = c;
  }
}

PathIndex::PathIndex(std::vector<PathPoint> points, double cell_mm)
    : points_(std::move(points)), h_(std::max(cell_mm, 1e-3)) {
  for (std::uint32_t i = 0; i < points_.size(); ++i)
    if (finite3(points_[i].xyz))
      insert_segment(i);
}

PathIndex::Nearest PathIndex::nearest(const PathPoint& q) const {
  Nearest best;
  best.distance_mm = std::numeric_limits<double>::infinity();
  best.orientation_deg = std::numeric_limits<double>::quiet_NaN();
  if (points_.empty() || !finite3(q.xyz))
    return best;
  const Eigen::Vector3d x = vec(q.xyz);
  const Cell c0 = cell_of(q.xyz);
  std::uint32_t best_segment = 0;
  double best_t = 0.0;
  for (int r = 0; r <= kMaxRings; ++r) {
    // The shell of cells at Chebyshev distance r from the query's cell.
    for (std::int64_t dx = -r; dx <= r; ++dx) {
      for (std::int64_t dy = -r; dy <= r; ++dy) {
        for (std::int64_t dz = -r; dz <= r; ++dz) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r)
            continue;
          const auto it = grid_.find({c0[0] + dx, c0[1] + dy, c0[2] + dz});
          if (it == grid_.end())
            continue;
          for (std::uint32_t i : it->second) {
            const Eigen::Vector3d a = vec(points_[i].xyz);
            const bool segment = i + 1 < points_.size() && !points_[i + 1].starts_piece;
            const Eigen::Vector3d b = segment ? vec(points_[i + 1].xyz) : a;
            const Eigen::Vector3d ab = b - a;
            const double len2 = ab.squaredNorm();
            const double t = len2 > 0.0 ? std::clamp((x - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
            const double d = (a + t * ab - x).norm();
            if (d < best.distance_mm) {
              best.distance_mm = d;
              best_segment = i;
              best_t = t;
            }
          }
        }
      }
    }
    // Cells further out hold only points at least r h from the query's cell, and segment
    // points within h/4 of them: nothing there is nearer than r h - h/4.
    if (best.distance_mm <= r * h_ - 0.25 * h_)
      break;
    if (r == kMaxRings) {
      best.exact = std::isfinite(best.distance_mm) && best.distance_mm <= r * h_ - 0.25 * h_;
      if (!best.exact)
        best.distance_mm = std::min(best.distance_mm, r * h_ - 0.25 * h_);
      return best;
    }
  }
  // The orientation of the path at the nearest point: the segment's end orientations, slerped.
  const PathPoint& a = points_[best_segment];
  const bool segment = best_segment + 1 < points_.size() && !points_[best_segment + 1].starts_piece;
  const PathPoint& b = segment ? points_[best_segment + 1] : a;
  if (finite3(q.abc) && finite3(a.abc) && finite3(b.abc)) {
    const Eigen::Quaterniond qa(rotation_from_abc({a.abc[0], a.abc[1], a.abc[2]}));
    const Eigen::Quaterniond qb(rotation_from_abc({b.abc[0], b.abc[1], b.abc[2]}));
    const Eigen::Quaterniond qq(rotation_from_abc({q.abc[0], q.abc[1], q.abc[2]}));
    const Eigen::Quaterniond path = qa.slerp(best_t, qb);
    const double angle = path.angularDistance(qq) * 180.0 / 3.14159265358979323846;
    best.orientation_deg = angle < 1e-9 ? 0.0 : angle;
  }
  return best;
}

}  // namespace redpost::krl
