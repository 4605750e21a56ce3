// Comparing two KRL programs motion by motion (`redpost diff`, docs/krl-diff.md).
//
// The motions of both programs (read with read_krl_program, so split programs are followed
// through their calls, and streamed: a window of each is held, never a whole program) are
// aligned, then each aligned pair is compared: position (mm,
// Euclidean), orientation (the angle of R_A^T R_B, so equivalent A, B, C forms compare equal),
// arm axes A1..A6 and external axes E1..E6 (absolute difference), Status and Turn (exact, where
// both have them) and the motion keyword. Motions of one side that have no partner are
// insertions (only in B) or removals (only in A).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "redpost/krl/reader.hpp"

namespace redpost {

struct KrlDiffOptions {
  double pos_tol_mm = 0.001;   // a deviation counts when it is strictly larger than the tolerance
  double ang_tol_deg = 0.001;  // orientation
  double axis_tol = 0.001;     // A1..A6, E1..E6 in controller units (deg or mm)
  double vel_tol_m_per_s = 1e-6;  // $VEL.CP (the writer prints 6 decimals)
  // The Cartesian paths compared as curves: the largest distance from a point of either
  // program to the other's polyline must not exceed this (mm).
  double path_tol_mm = 0.001;
  // true: positions and orientations of Cartesian motions are compared only as curves (the
  // path quantities), and motions of one side whose point lies on the other's path are not
  // insertions or removals: programs that trace the same path with other points (another
  // chordal tolerance, CIRC against chords) compare equal within path_tol_mm.
  bool as_curves = false;
  size_t max_shown = 20;  // differences kept in KrlDiffResult::differences
  // Motions of each program held at once: the alignment looks this far ahead, and each point is
  // measured against the other program's path from a quarter of it behind to what is read ahead.
  // Memory is bounded by it (about 0.6 KB a motion), not by the programs' length.
  size_t window = 20000;
};

// The quantities compared, in report order.
enum class KrlQuantity : int {
  position,
  orientation,
  aux_position,  // CIRC auxiliary point
  A1,
  A2,
  A3,
  A4,
  A5,
  A6,
  E1,
  E2,
  E3,
  E4,
  E5,
  E6,
  status,
  turn,
  keyword,
  target_kind,       // Cartesian target on one side, axis target on the other
  vel_cp,            // $VEL.CP in force (m/s)
  apo_cdis,          // $APO.CDIS in force (mm)
  ptp_velocity,      // BAS (#VEL_PTP, n) in force (%)
  tool,              // $TOOL in force (exact, as written)
  base,              // $BASE in force (exact, as written)
  path,              // distance of a point to the other program's polyline (mm), both ways
  path_orientation,  // orientation against the other path's, interpolated there (deg)
  count_
};
// The quantities said once per program, as a summary, rather than at every motion: a changed
// template or setting changes them at hundreds of motions at once.
bool krl_quantity_is_summarised(KrlQuantity q);
inline constexpr int kKrlQuantityCount = static_cast<int>(KrlQuantity::count_);
const char* krl_quantity_name(KrlQuantity q);  // "position", "A1", "status", ...
const char* krl_quantity_unit(KrlQuantity q);  // "mm", "deg", "" (exact quantities)

struct KrlDeviation {
  KrlQuantity quantity = KrlQuantity::position;
  double value = 0.0;  // mm, deg or axis units; 1 for an exact quantity that differs
  std::string detail;  // "A 'B110' B 'B010'" for exact quantities, else ""
};

struct KrlDifference {
  enum class Kind { changed, inserted, removed };
  Kind kind = Kind::changed;
  // Where on each side. For `inserted` only B is set, for `removed` only A; `count` motions
  // from there on (a run of consecutive insertions or removals is one difference).
  std::string file_a, file_b;
  int line_a = 0, line_b = 0;
  int last_line_a = 0, last_line_b = 0;  // last motion of the run (same file assumed)
  size_t count = 1;
  std::string keyword_a, keyword_b;
  std::vector<KrlDeviation> deviations;  // `changed`: the quantities over tolerance
};

// A program-wide difference: a summarised quantity over tolerance at `count` aligned pairs,
// the first of them given with its values (`detail`, "A LIN, B SLIN").
struct KrlSummaryDifference {
  KrlQuantity quantity = KrlQuantity::keyword;
  size_t count = 0;
  std::string file_a, file_b;
  int line_a = 0, line_b = 0;
  std::string detail;
};

struct KrlQuantityStats {
  size_t compared = 0;
  size_t over_tolerance = 0;
  double max = 0.0;
  double sum = 0.0;
  double mean() const { return compared == 0 ? 0.0 : sum / static_cast<double>(compared); }
};

struct KrlDiffResult {
  bool equal = true;
  size_t motions_a = 0, motions_b = 0;
  size_t compared = 0;          // aligned pairs compared
  size_t changed = 0;           // pairs with at least one quantity over tolerance
  size_t inserted = 0;          // motions only in B
  size_t removed = 0;           // motions only in A
  size_t difference_count = 0;  // all differences (changed pairs + insertion/removal runs)
  bool aligned_by_cl_line = false;
  std::vector<KrlDifference> differences;       // the first max_shown, in program order
  std::vector<KrlSummaryDifference> summaries;  // one per summarised quantity that differs
  // The Cartesian paths as curves: the largest distance from a point of one program to the
  // other's polyline (mm), and where (the point's file and line). exact false: farther than
  // the search went, `path_distance_mm` is then a lower bound.
  double path_distance_mm = 0.0;
  std::string path_file;
  int path_line = 0;
  bool path_exact = true;
  // Points whose distance is an upper bound: near them the other path held more segments that
  // are not duplicates than the search examines (krl/diff_path.hpp, PathWindow::kMaxExamined).
  size_t path_capped = 0;
  // Segments the path searches examined in all (the work per point is bounded: at most 256).
  size_t path_examined = 0;
  std::array<KrlQuantityStats, kKrlQuantityCount> statistics{};
  // The alignment's window (KrlDiffOptions::window), and the regions where no motion had a
  // partner within it: their first halves were paired in order. The first such region's place.
  size_t window = 0;
  size_t unaligned_regions = 0;
  std::string unaligned_file_a, unaligned_file_b;
  int unaligned_line_a = 0, unaligned_line_b = 0;
  // The alignment's work budget ran out somewhere: the rest of that region was paired in order.
  bool budget_exhausted = false;
  // Directory comparison: programs found on one side only ("only in A: FOO.src").
  std::vector<std::string> unmatched;
};

// Compares two programs already read (as diff_krl_paths compares them from their files).
KrlDiffResult diff_krl_programs(const KrlProgram& a, const KrlProgram& b,
                                const KrlDiffOptions& options);

// Compares two .src files, or two directories (their main programs matched by file name,
// case-insensitively). Both programs are read side by side, on threads of their own. Throws
// Error (io, bad_input) as read_krl_program does.
KrlDiffResult diff_krl_paths(const std::string& path_a, const std::string& path_b,
                             const KrlDiffOptions& options);

// The main programs of a directory: every .src that no other .src in it calls, sorted by name.
std::vector<std::string> krl_main_programs(const std::string& directory);

// The report as text (first differences, then statistics) and as JSON.
std::string format_krl_diff_text(const KrlDiffResult& result, const KrlDiffOptions& options);
std::string format_krl_diff_json(const KrlDiffResult& result, const KrlDiffOptions& options);

}  // namespace redpost
