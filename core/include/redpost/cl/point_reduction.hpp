// Tolerance-bounded point reduction (docs/timing.md, "Point reduction"): consecutive CL points
// merged into one straight move where that move stays within a tolerance of every point it
// drops, so that a program of dense CAM points runs at its feed on a controller that plans on
// an interpolation cycle (a KR C4: 12 ms, 2 mm at 10 m/min).
//
// The tool axis of a point is judged against the great circle within half of
// `axis_tolerance_deg`; the session proves that the controller's turn of the whole frame keeps
// the axis within the other half of the great circle (or writes the tracked steps).
//
// A stage of plain events (cl/event.hpp) between the ClExpander and the tracker. It only drops
// cutting GOTOs and a NURBS's chord points (already within the chordal tolerance of the curve,
// so the sum of both tolerances bounds the distance to the curve): a dropped point p lies within
// `tolerance_mm` of the merged line a-b, and its tool axis within `axis_tolerance_deg` of the
// merged move's axis where the tool passes p (the great circle from a's axis to b's at the fraction
// of the line nearest p, as the tracker steps a move). The distance to a line is convex, so the
// polyline through the dropped points stays within the tolerance too. It merges only within one
// feed, operation and tool: every event but a move (or a FEDRAT that repeats the feed in force)
// ends a run, and a rapid, a cycle's move, an arc, the first move after a tool change or an MSYS,
// and the move after each of these are kept as they are. Memory is bounded (`max_points`), whatever
// the length of the file.
//
// With `arcs` (a template set with CIRC), a run that no one line covers but that lies on a circle
// becomes one arc event (origin fitted_arc) instead: every point within half the tolerance of
// the circle through the run's start, middle and end, in order along it, each chord of the CL
// polyline within that half too, every tool axis the start's within half the angular tolerance,
// at least kMinArcPoints points and at most kMaxArcSweepRad of turn. The other half of the
// tolerance is for the session: the circle the controller draws through the printed points, or
// the chords it writes where the CIRC cannot be proven.
#pragma once

#include <cstddef>
#include <deque>
#include <limits>
#include <string>
#include <vector>

#include "redpost/cl/event.hpp"

namespace redpost {

struct PointReductionOptions {
  double tolerance_mm = 0.0;        // 0: off, every event passes unchanged
  double axis_tolerance_deg = 0.1;  // of the tool axis
  int max_points = 100;             // CL points one merged move may cover at most
  bool arcs = false;                // runs on a circle become arcs (a writer with CIRC)
};

// An arc covers at least this many CL points (so that two of them check the circle its start,
// middle and end define), and turns by at most this much (a CIRC near a full turn is ill-defined
// by its three points).
inline constexpr int kMinArcPoints = 4;
inline constexpr double kMaxArcSweepRad = 1.5 * 3.14159265358979323846;
// Radii an arc may have (mm): below, a corner; above, a line within any tolerance.
inline constexpr double kMinArcRadiusMm = 0.1;
inline constexpr double kMaxArcRadiusMm = 1e5;

// The tightest and loosest tolerances accepted (mm, deg): below 1 um the reduction can only
// drop collinear points; above 1 mm (or 5 deg) it would cut another part.
inline constexpr double kMinFitToleranceMm = 1e-3;
inline constexpr double kMaxFitToleranceMm = 1.0;
inline constexpr double kMinFitAngleToleranceDeg = 1e-3;
inline constexpr double kMaxFitAngleToleranceDeg = 5.0;

// "" when the options are valid (tolerance_mm 0, or within the bounds above), else what is wrong,
// naming --fit-tol and --fit-ang-tol.
std::string point_reduction_problem(const PointReductionOptions& options);

// How far the straight move from a (tool axis a_axis) to b (b_axis) misses the point p with its
// tool axis p_axis: the distance from p to the segment, and the angle between p_axis and the
// move's axis at the segment's point nearest p. Unit axes.
struct LinDeviation {
  double distance_mm = 0.0;
  double axis_rad = 0.0;
};
LinDeviation lin_deviation(const Eigen::Vector3d& a, const Eigen::Vector3d& a_axis,
                           const Eigen::Vector3d& b, const Eigen::Vector3d& b_axis,
                           const Eigen::Vector3d& p, const Eigen::Vector3d& p_axis);

// Pull-based like the ClExpander: push() one plain event, then next() until it returns false;
// finish() at the end of the toolpath gives the last run. A merged move is the run's last point
// with `first_line` set to the line of the first point it covers.
class PointReducer {
 public:
  explicit PointReducer(const PointReductionOptions& options);

  void push(const ClEvent& e);
  bool next(ClEvent& e);
  void finish();

  bool enabled() const { return o_.tolerance_mm > 0.0; }
  // The reduction judges a dropped point's tool axis against the great circle of the merged
  // move within half the angular tolerance; the other half is what the controller's own turn of
  // the frame may add (the session proves it, post/timing.cpp), so the sum stays within it.
  double controller_axis_budget_rad() const { return axis_tolerance_rad_; }
  // A fitted arc's points are within half the tolerance of its circle; the other half is the
  // session's, for the controller's circle or the chords it writes instead.
  double arc_tolerance_mm() const { return 0.5 * o_.tolerance_mm; }
  long moves_in() const { return moves_in_; }    // cutting GOTOs that could be merged
  long moves_out() const { return moves_out_; }  // ... and the moves written for them
  long arcs_out() const { return arcs_out_; }    // ... of which arcs

 private:
  void add_point(const ClEvent& e);
  void extend(const ClEvent& e);
  bool covers(const ClEvent& end) const;  // the line anchor -> end covers every point of the run
  // The circle anchor -> middle -> end covers every point of the run and `end` (the class
  // comment's rules); fills the arc event's centre and axis.
  bool fits_arc(const ClEvent& end, Eigen::Vector3d& centre, Eigen::Vector3d& normal) const;
  void flush();
  void flush_arc();
  void replay_as_lines();       // an arc that never had its points: the run as lines after all
  void pass(const ClEvent& e);  // out at once, after the run

  PointReductionOptions o_;
  double axis_tolerance_rad_ = 0.0;
  double sin_axis_tolerance_ = 0.0;  // its sine, once (covers() and fits_arc() compare with it)
  std::vector<ClEvent> run_;  // the points since the anchor; the last is the merged move's end
  // The same points' positions and unit tool axes, packed: covers() reads them for every point
  // of the run at every point added.
  struct RunPoint {
    Eigen::Vector3d p_mm;
    Eigen::Vector3d axis;
  };
  std::vector<RunPoint> run_points_;
  // covers()'s scratch: the tool axis's turn at each point's place along the line (rad), and its
  // sine and cosine (taken together for the run).
  mutable std::vector<double> turns_, sin_phi_, cos_phi_;
  void run_push(const ClEvent& e);
  void run_clear();
  std::deque<ClEvent> out_;
  bool anchored_ = false;  // the tool's position is known (not at the start, or after a tool
                           // change or an MSYS: the next move is an approach)
  Eigen::Vector3d anchor_p_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d anchor_axis_ = Eigen::Vector3d::UnitZ();
  bool next_rapid_ = false;
  bool keep_next_ = false;  // the next move is kept (after a rapid, an approach, a cycle's move)
  double feed_ = std::numeric_limits<double>::quiet_NaN();
  long moves_in_ = 0, moves_out_ = 0, arcs_out_ = 0;
  // The run is an arc (no line covers it): proven once it has kMinArcPoints points.
  bool arc_ = false;
  Eigen::Vector3d arc_centre_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d arc_normal_ = Eigen::Vector3d::UnitZ();
  std::vector<ClEvent> replay_;  // replay_as_lines' scratch
};

}  // namespace redpost
