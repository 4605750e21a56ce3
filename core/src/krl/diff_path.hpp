// Comparing two Cartesian paths as curves (`redpost diff`, docs/krl-diff.md): the distance from
// a point of one program to the polyline of the other, and the orientation there, interpolated
// along the nearest segment. Programs that trace one path with other points (another chordal
// tolerance, a CIRC against its chords) are then close, where pairing their points one by one
// would put them hundreds of millimetres apart.
//
// Internal to redpost::core; not installed.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace redpost::krl {

struct PathPoint {
  std::array<double, 3> xyz{};
  std::array<double, 3> abc{};  // KUKA A, B, C (deg); NaN: not known
  bool starts_piece = false;    // no segment from the point before (a PTP between, say)
};

class PathIndex {
 public:
  // The polyline through `points`, in a uniform grid of cells of at least `cell_mm`.
  explicit PathIndex(std::vector<PathPoint> points, double cell_mm = 1.0);

  struct Nearest {
    double distance_mm = 0.0;      // to the nearest segment (or point)
    bool exact = true;             // false: nothing within the search, distance_mm is a lower bound
    double orientation_deg = 0.0;  // against the path's orientation there; NaN: not known
  };
  Nearest nearest(const PathPoint& q) const;
  bool empty() const { return points_.empty(); }

 private:
  using Cell = std::array<std::int64_t, 3>;
  struct CellHash {
    std::size_t operator()(const Cell& c) const;
  };
  Cell cell_of(const std::array<double, 3>& p) const;
  void insert_segment(std::uint32_t i);

  std::vector<PathPoint> points_;
  double h_ = 1.0;
  std::unordered_map<Cell, std::vector<std::uint32_t>, CellHash> grid_;  // cell -> segment starts
};

}  // namespace redpost::krl
