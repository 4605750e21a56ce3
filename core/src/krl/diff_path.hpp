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
  };
  Nearest nearest(const PathPoint& q) const;
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

  std::deque<PathPoint> points_;
  std::uint64_t first_id_ = 0;  // id of points_.front(); ids count every point pushed
  double h_ = 1.0;
  // cell -> ids of the points whose segment (or the point alone) passes through it, ascending.
  std::unordered_map<Cell, std::vector<std::uint64_t>, CellHash> grid_;
};

}  // namespace redpost::krl
