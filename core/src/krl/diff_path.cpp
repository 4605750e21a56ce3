// The other program's path as a sliding window of segments in a grid (krl/diff_path.hpp).
#include "krl/diff_path.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "redpost/kinematics/kuka_abc.hpp"

namespace redpost::krl {

namespace {

constexpr int kMaxRings = 3;  // the search goes this many cells out before it gives up
// The cells of the outermost shell searched: 7^3 - 5^3.
constexpr std::size_t kShellCells = 218;

bool finite3(const std::array<double, 3>& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

Eigen::Vector3d vec(const std::array<double, 3>& v) {
  return {v[0], v[1], v[2]};
}

}  // namespace

std::size_t PathWindow::CellHash::operator()(const Cell& c) const {
  std::uint64_t h = 1469598103934665603ULL;
  for (std::int64_t v : c)
    h = (h ^ static_cast<std::uint64_t>(v)) * 1099511628211ULL;
  return static_cast<std::size_t>(h);
}

PathWindow::PathWindow(double cell_mm) : h_(std::max(cell_mm, 1e-3)) {}

void PathWindow::set_cell(double cell_mm) {
  h_ = std::max(cell_mm, 1e-3);
  rebuild();
}

PathWindow::Cell PathWindow::cell_of(const std::array<double, 3>& p) const {
  return {static_cast<std::int64_t>(std::floor(p[0] / h_)),
          static_cast<std::int64_t>(std::floor(p[1] / h_)),
          static_cast<std::int64_t>(std::floor(p[2] / h_))};
}

bool PathWindow::has_segment(std::uint64_t id) const {
  const std::uint64_t next = id + 1;
  return next < first_id_ + points_.size() && !point(next).starts_piece;
}

// A segment goes into the cells of points along it every h/2, so that every point of it is
// within h/4 of a point that was put in a cell. A point is put in alone when it arrives and with
// its segment when the next point does.
template <class Visit>
void PathWindow::for_each_cell(std::uint64_t id, bool segment, Visit&& visit) const {
  const Eigen::Vector3d a = vec(point(id).xyz);
  const Eigen::Vector3d b = segment ? vec(point(id + 1).xyz) : a;
  const double length = (b - a).norm();
  const int steps = static_cast<int>(std::ceil(length / (0.5 * h_)));
  Cell last{std::numeric_limits<std::int64_t>::min(), 0, 0};
  for (int k = 0; k <= steps; ++k) {
    const Eigen::Vector3d p = steps == 0 ? a : a + (b - a) * (static_cast<double>(k) / steps);
    const Cell c = cell_of({p.x(), p.y(), p.z()});
    if (c != last)
      visit(c);
    last = c;
  }
}

bool PathWindow::same_segment(std::uint64_t a, std::uint64_t b) const {
  const PathPoint& a0 = point(a);
  const PathPoint& a1 = has_segment(a) ? point(a + 1) : a0;
  const PathPoint& b0 = point(b);
  const PathPoint& b1 = has_segment(b) ? point(b + 1) : b0;
  const auto same = [](const PathPoint& x, const PathPoint& y) {
    // NaN orientations (not known) compare unequal: such entries are never merged.
    return x.xyz == y.xyz && x.abc == y.abc;
  };
  return (same(a0, b0) && same(a1, b1)) || (same(a0, b1) && same(a1, b0));
}

// An entry that stands for the same segment as one of the cell's last kDedupDepth replaces it:
// the older id leaves the list and the newer goes to its end, so that the ids stay ascending and
// the place stays in the grid until its newest segment leaves the window. A point put in alone
// becomes its segment when the next point comes; the segment holds the point, so nothing that
// the older entry stood for is lost.
void PathWindow::insert(std::uint64_t id, bool segment) {
  for_each_cell(id, segment, [&](const Cell& c) {
    CellIds& cell = grid_[c];
    std::vector<std::uint64_t>& v = cell.ids;
    if (cell.live() > 0 && v.back() == id)
      return;
    const std::size_t stop = v.size() - std::min<std::size_t>(cell.live(), kDedupDepth);
    for (std::size_t k = v.size(); k-- > stop;) {
      if (same_segment(v[k], id)) {
        v.erase(v.begin() + static_cast<std::ptrdiff_t>(k));
        break;
      }
    }
    v.push_back(id);
  });
}

// The oldest point leaves: ids go into a cell in ascending order, so it is the cell's first
// (unless a newer entry replaced it, then it is there no more).
void PathWindow::remove(std::uint64_t id, bool segment) {
  for_each_cell(id, segment, [&](const Cell& c) {
    const auto it = grid_.find(c);
    if (it == grid_.end())
      return;
    CellIds& cell = it->second;
    if (cell.live() == 0 || cell.ids[cell.head] != id)
      return;
    ++cell.head;
    if (cell.live() == 0) {
      grid_.erase(it);
    } else if (2 * cell.head > cell.ids.size()) {
      cell.ids.erase(cell.ids.begin(), cell.ids.begin() + static_cast<std::ptrdiff_t>(cell.head));
      cell.head = 0;
    }
  });
}

void PathWindow::push(const PathPoint& p) {
  if (!finite3(p.xyz))
    return;
  points_.push_back(p);
  const std::uint64_t id = first_id_ + points_.size() - 1;
  if (id > first_id_ && has_segment(id - 1))
    insert(id - 1, true);
  insert(id, false);
}

void PathWindow::drop_before(std::uint64_t seq) {
  // The newest point stays: the next one's segment starts there.
  while (points_.size() > 1 && points_.front().seq < seq) {
    remove(first_id_, false);
    if (has_segment(first_id_))
      remove(first_id_, true);
    points_.pop_front();
    ++first_id_;
  }
}

void PathWindow::rebuild() {
  grid_.clear();
  for (std::uint64_t id = first_id_; id < first_id_ + points_.size(); ++id) {
    insert(id, false);
    if (has_segment(id))
      insert(id, true);
  }
}

PathWindow::Nearest PathWindow::nearest(const PathPoint& q, double enough_mm) const {
  Nearest best;
  best.distance_mm = std::numeric_limits<double>::infinity();
  best.orientation_deg = std::numeric_limits<double>::quiet_NaN();
  if (points_.empty() || !finite3(q.xyz))
    return best;
  const Eigen::Vector3d x = vec(q.xyz);
  const Cell c0 = cell_of(q.xyz);
  std::uint64_t best_id = first_id_;
  double best_t = 0.0;
  // A segment this near ends the search: none can be nearer by more.
  const double enough = std::max(enough_mm, kOnPathMm);
  bool done = false;
  std::size_t examined = 0;
  // One cell's segments, from the entry of the query's own motion number outwards: a program
  // compared with itself, or with one that differs here and there, meets its partner first.
  const auto scan = [&](const CellIds& cell) {
    const auto first = cell.ids.begin() + static_cast<std::ptrdiff_t>(cell.head);
    const auto mid =
        std::lower_bound(first, cell.ids.end(), q.seq,
                         [&](std::uint64_t id, std::uint64_t seq) { return point(id).seq < seq; });
    auto up = mid, down = mid;
    while (!done && (up != cell.ids.end() || down != first)) {
      if (examined++ == kMaxExamined) {
        best.capped = done = true;
        break;
      }
      const bool take_up = up != cell.ids.end() && (down == first || up - mid <= mid - down);
      const std::uint64_t id = take_up ? *up++ : *--down;
      const Eigen::Vector3d a = vec(point(id).xyz);
      const Eigen::Vector3d b = has_segment(id) ? vec(point(id + 1).xyz) : a;
      const Eigen::Vector3d ab = b - a;
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0.0 ? std::clamp((x - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      const double d = (a + t * ab - x).norm();
      if (d < best.distance_mm) {
        best.distance_mm = d;
        best_id = id;
        best_t = t;
        done = d <= enough;
      }
    }
  };
  // The distance from the query to a cell's box.
  const auto box_distance = [&](const Cell& c) {
    double d2 = 0.0;
    for (std::size_t i = 0; i < 3; ++i) {
      const double lo = static_cast<double>(c[i]) * h_, hi = lo + h_;
      const double out = std::max(
          {0.0, lo - x[static_cast<Eigen::Index>(i)], x[static_cast<Eigen::Index>(i)] - hi});
      d2 += out * out;
    }
    return std::sqrt(d2);
  };
  // A segment has a point put in a cell every h/2 along it, so each of its points is within h/4
  // of a cell it is in: a cell whose box is d away holds nothing nearer than d - h/4.
  std::array<std::pair<double, const CellIds*>, kShellCells> shell;
  // How far the query lies inside its own cell: to the nearest of its faces.
  double inside = 0.5 * h_;
  for (std::size_t i = 0; i < 3; ++i) {
    const double lo = x[static_cast<Eigen::Index>(i)] - static_cast<double>(c0[i]) * h_;
    inside = std::min({inside, lo, h_ - lo});
  }
  inside = std::max(inside, 0.0);
  for (int r = 0; r <= kMaxRings && !done; ++r) {
    // The shell of cells at Chebyshev distance r from the query's cell, nearest box first.
    std::size_t n = 0;
    for (std::int64_t dx = -r; dx <= r; ++dx) {
      for (std::int64_t dy = -r; dy <= r; ++dy) {
        for (std::int64_t dz = -r; dz <= r; ++dz) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r)
            continue;
          const Cell c{c0[0] + dx, c0[1] + dy, c0[2] + dz};
          const auto it = grid_.find(c);
          if (it != grid_.end())
            shell[n++] = {box_distance(c), &it->second};
        }
      }
    }
    std::sort(shell.begin(), shell.begin() + static_cast<std::ptrdiff_t>(n),
              [](const auto& u, const auto& v) { return u.first < v.first; });
    for (std::size_t k = 0; k < n && !done; ++k) {
      if (shell[k].first - 0.25 * h_ >= best.distance_mm)
        break;
      scan(*shell[k].second);
    }
    // Cells further out are at least r h + `inside` from the query (the nearest face of the
    // block of rings 0..r).
    const double reach = r * h_ + inside - 0.25 * h_;
    if (done || best.distance_mm <= reach)
      break;
    if (r == kMaxRings) {
      best.exact = std::isfinite(best.distance_mm) && best.distance_mm <= reach;
      if (!best.exact)
        best.distance_mm = std::min(best.distance_mm, reach);
      best.examined = examined;
      return best;
    }
  }
  best.examined = examined;
  // The orientation of the path at the nearest point: the segment's end orientations, slerped.
  const PathPoint& a = point(best_id);
  const PathPoint& b = has_segment(best_id) ? point(best_id + 1) : a;
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
