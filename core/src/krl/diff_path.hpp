// Comparing two Cartesian paths as curves (`redpost diff`, docs/krl-diff.md): the distance from
// a point of one program to the polyline of the other, and the orientation there, interpolated
// along the nearest segment. Programs that trace one path with other points (another chordal
// tolerance, a CIRC against its chords) are then close, where pairing their points one by one
// would put them hundreds of millimetres apart.
//
// The polyline is a sliding window of the other program: points are pushed as they are read and
// dropped once the comparison has passed them, so that memory is bounded by the window, not by
// the program's length.
//
// Internal to redpost::core; not installed.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <unordered_map>
#include <vector>

namespace redpost::krl {

struct PathPoint {
  std::array<double, 3> xyz{};
  std::array<double, 3> abc{};  // KUKA A, B, C (deg); NaN: not known
  bool starts_piece = false;    // no segment from the point before (a PTP between, say)
  std::uint64_t seq = 0;        // the motion it is the target of, in its program
};

class PathWindow {
 public:
  // Segments are put in a uniform grid of cells of at least `cell_mm`: the typical segment's
  // length, so that a query looks at a few cells.
  explicit PathWindow(double cell_mm = 1.0);
  void set_cell(double cell_mm);  // before the first point

  void push(const PathPoint& p);
  // Drops the points of motions before `seq` (the window's back edge has passed them).
  void drop_before(std::uint64_t seq);

  struct Nearest {
    double distance_mm = 0.0;      // to the nearest segment (or point)
    bool exact = true;             // false: nothing within the search, distance_mm is a lower bound
    double orientation_deg = 0.0;  // against the path's orientation there; NaN: not known
    // The search met more than kMaxExamined segments that are not duplicates near the query (a
    // cloud of points, a path that revisits one place with small changes) and stopped there:
    // distance_mm is the least over those it examined, an upper bound.
    bool capped = false;
    std::size_t examined = 0;  // segments the search looked at (the work it did)
  };
  // The work is bounded whatever the path's shape (issue 48): a segment equal to one of the last
  // kDedupDepth in a cell replaces it there (a path that stands at one point, or goes back and
  // forth over itself, leaves one entry per place, not one per pass), the search ends at the
  // first segment within kOnPathMm of the query (a program diffed against itself, or against one
  // that retraces it, finds it in the first cell), and it examines at most kMaxExamined segments
  // (Nearest::capped).
  static constexpr int kDedupDepth = 4;
  static constexpr double kOnPathMm = 1e-9;
  static constexpr std::size_t kMaxExamined = 256;
  // enough_mm: a segment this near ends the search (at least kOnPathMm); the distance is then
  // at most that, not the least.
  Nearest nearest(const PathPoint& q, double enough_mm = 0.0) const;
  bool empty() const { return points_.empty(); }
  std::size_t size() const { return points_.size(); }

 private:
  using Cell = std::array<std::int64_t, 3>;
  struct CellHash {
    std::size_t operator()(const Cell& c) const;
  };
  Cell cell_of(const std::array<double, 3>& p) const;
  const PathPoint& point(std::uint64_t id) const { return points_[id - first_id_]; }
  bool has_segment(std::uint64_t id) const;  // a segment from point id to the next
  template <class Visit>
  void for_each_cell(std::uint64_t id, bool segment, Visit&& visit) const;
  void insert(std::uint64_t id, bool segment);
  void remove(std::uint64_t id, bool segment);
  void rebuild();
  // Whether the entries a and b stand for the same segment (or point), ends and orientations
  // equal, either way round.
  bool same_segment(std::uint64_t a, std::uint64_t b) const;

  // The ids of the points whose segment (or the point alone) passes through a cell, ascending;
  // those before `head` have left (erasing at the front of a long vector cost its length).
  struct CellIds {
    std::vector<std::uint64_t> ids;
    std::size_t head = 0;
    std::size_t live() const { return ids.size() - head; }
  };

  std::deque<PathPoint> points_;
  std::uint64_t first_id_ = 0;  // id of points_.front(); ids count every point pushed
  double h_ = 1.0;
  std::unordered_map<Cell, CellIds, CellHash> grid_;
};

}  // namespace redpost::krl
