// Writing a KRL program (.src/.dat), streaming, through a template set.
//
// Statements go to temporary files as they come, so memory does not grow with the program;
// finish() writes the main program and renames every file to its final name only when the
// whole program is complete. A writer destroyed without finish() removes its temporary files:
// a failed run leaves nothing that looks finished. Output is byte-identical for identical input:
// fixed decimals, '.' as decimal separator whatever the locale, no time stamps unless asked.
// Every line ends with CRLF, as on the (Windows-based) controller.
//
// The program's first motion is always written as a PTP to its full E6AXIS (whatever its kind),
// so that the controller's BCO run is a defined joint move: the set's bco_ptp, which says so and
// slows it (docs/krl-templates.md, "The start"), else ptp_axes. A program is split into parts when
// a .src would grow beyond max_file_bytes (by default 512 KiB: a KR C4 holds about 4 MB in all), or
// every motions_per_file motions: it is then NAME.src, which calls NAME_P001() ... in order; each
// part has its own .dat and starts by restating the tool, spindle and coolant and a PTP E6AXIS
// to where the previous part ended, so that it also runs alone. A part ends out of the material
// where it can: once it holds three quarters of its budget, after the next rapid or approach
// (KrlMotion::in_air).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "redpost/krl/template.hpp"

namespace redpost {

// The default byte budget of one .src: a KR C4 holds about 4 MB of programs in all (KSS 8.3),
// the system's and the cell's own among them, so a part stays well under 1 MB
// (docs/krl-templates.md, "Splitting").
inline constexpr long kDefaultMaxFileBytes = 512L * 1024;

struct KrlProgramInfo {
  std::string name;                   // KRL identifier, at most 24 characters (checked)
  std::string output_dir;             // must exist and be writable (checked at construction)
  std::string base = "BASE_DATA[1]";  // right-hand side of $BASE = (the offset base if coupled)
  std::string tool = "TOOL_DATA[1]";  // right-hand side of $TOOL = until a tool_change()
  // The numbers of that tool ({tool_data}: $ACT_TOOL; 0 where `tool` is not a TOOL_DATA entry,
  // and a set that writes the number is then refused, docs/krl-templates.md, "Base and tool")
  // and of its load data ({load_data}: $LOAD = LOAD_DATA[n]; 0: tool_data, as KUKA's
  // BAS (#TOOL, n) pairs them), until a tool_change().
  int tool_data = 1;
  int load_data = 0;
  double apo_mm = 0.5;       // $APO.CDIS
  int motions_per_file = 0;  // 0: split by bytes only
  // A .src is never larger than this (bytes); 0: the template set's <limits max-bytes>, or
  // kDefaultMaxFileBytes. At least 16 KiB.
  long max_file_bytes = 0;
  int cl_line_every = 50;      // a comment with the CL line every N motions (0: never)
  std::string header_comment;  // e.g. "redpost 0.1.0, cell andres2011_kr15_track_table"
  // The base turns with a mathematically coupled kinematic (a turntable): $BASE comes from the
  // template's base_coupled statement with {machine} (MACHINE_DEF index) and {ex_axes}.
  bool base_coupled = false;
  int machine_def = 2;  // {machine}: KSS 8's MACHINE_DEF index
  int ex_ax_data = 1;   // {ex_ax_data}: KSS 5's EX_AX_DATA index
  // The BASE_DATA index ({base_data}) of `base` ($ACT_BASE, KSS 5's BAS); 0 where `base` is no
  // BASE_DATA entry, and a set that writes the number is then refused.
  int base_data = 1;
  int ex_axes = 0;
  // The cell's tool change routine ({routine} in tool_change); empty: tool_change_manual.
  std::string tool_change_routine;
  // In a spline set with a spline_spl statement: how far (mm) the model of the controller's
  // spline (krl/spline_model.hpp) may leave each segment's chord where the block passes a point
  // smoothly as SPL. 0: every feed move an SLIN, and every point of a block passed as written.
  double spline_tolerance_mm = 0.0;
  // With SPL and the per-segment speed statements: an SLIN segment with a corner at both ends
  // that would last less than this (s) at its speed is written with the speed at which it lasts
  // one (WITH $VEL.CP), its length taken short by what the printed decimals may take off both
  // ends (take_rate_segment says which). 0: never.
  double interpolation_cycle_s = 0.0;
};

// A tool change as the program writes it (docs/tools.md).
struct KrlToolChange {
  int number = 0;     // the CL tool number
  std::string name;   // the CL tool's name (a comment)
  int tool_data = 1;  // TOOL_DATA index
  int load_data = 0;  // LOAD_DATA index ($LOAD); 0: tool_data
  std::string tool;   // right-hand side of $TOOL =, e.g. "TOOL_DATA[16]"
};

enum class KrlMotionKind {
  ptp_axes,  // PTP to a full E6AXIS (the first motion, approaches)
  rapid,     // a rapid traverse (the template decides PTP E6AXIS, or Cartesian PTP with S/T)
  lin,       // a feed move: LIN (or SLIN in a spline block) to an E6POS
};

struct KrlMotion {
  KrlMotionKind kind = KrlMotionKind::lin;
  AxisValues axes;         // A1..A6, E1..E6 (deg, mm); NaN for axes the cell does not have
  Isometry T_base_tcp;     // the physical TCP in $BASE (mm), for Cartesian motions
  StatusTurn status_turn;  // for Cartesian PTP
  int cl_line = 0;         // the CL record it came from (0: none)
  // A rapid traverse or an approach: it ends out of the material, so a part of a split program
  // may end after it (docs/krl-templates.md, "Splitting"). (It may start in the cut: a drill's
  // rapid retract from the hole's bottom.)
  bool in_air = false;
};

// Where a split program's parts end (KrlWriter::split()).
struct KrlSplitReport {
  int parts = 0;           // 0: one file, not split
  long program_bytes = 0;  // every .src and .dat of the program (after prepare())
  // Part boundaries that the byte budget forced where the tool may be in the material (no
  // rapid or approach within the budget's last quarter): how many, and the CL lines of the
  // first ones.
  long mid_cut = 0;
  std::vector<int> mid_cut_lines;
  // Of those, the parts that continue the cut without a stop (the set's continued_src); the
  // others start with an exact-stop PTP.
  long continued = 0;
};

// "" when `name` can name a KRL program (a letter, then letters, digits and '_', at most 24
// characters, no keyword), else what is wrong ("is a KRL keyword"): for a host that checks a
// name before long work that ends in writing the program.
std::string krl_program_name_problem(std::string_view name);

class KrlWriter {
 public:
  // Throws Error(io) if the output directory is missing or not writable, Error(bad_input) if
  // the name is not a valid KRL identifier of at most 24 characters.
  KrlWriter(const KrlTemplateSet& templates, const KrlProgramInfo& info);
  ~KrlWriter();  // removes temporary files unless finish() succeeded
  KrlWriter(const KrlWriter&) = delete;
  KrlWriter& operator=(const KrlWriter&) = delete;

  // Throws Error(internal) if the template needs a value that is NaN (an arm axis, or the pose)
  // or if the set of external axes (non-NaN E entries) differs from the first motion's, and
  // Error(bad_input) for a feed move before any velocity(): a LIN at the controller's default
  // speed is never written.
  void motion(const KrlMotion& m);
  void velocity(double vel_m_per_s);  // emitted before the next feed move when it changed
  // A circular motion from the last motion through aux to end (both KrlMotionKind::lin), as
  // one CIRC; the set must have a circ statement (has_circ()). The caller proves it safe.
  void circ(const KrlMotion& aux, const KrlMotion& end);
  bool has_circ() const;
  // The feed move last given starts at a point the spline block passes smoothly (an SPL knot:
  // no corner there for the time model). False in sets without SPL.
  bool joined_smoothly() const;
  // A spline set with spline_spl and a spline tolerance: feed moves may be written as SPL.
  bool has_spl() const;
  // Whether motion `index` (1, 2, ... in the order given) was written at the motion rate
  // (KrlProgramInfo::interpolation_cycle_s), and at which $VEL.CP (m/s). Asked in order: the
  // answers for earlier motions are dropped. Known once the motion after it was given, or its
  // block ended.
  bool take_rate_segment(long index, double& vel_m_per_s);
  // Ends an open SPLINE block now (its last segment is written).
  void end_block();
  // The tool change statement (the cell's routine, or tool_change_manual), then tool_select.
  void tool_change(const KrlToolChange& change);
  void dwell(double seconds);                // the set's dwell statement (WAIT SEC)
  void spindle(double rpm, bool clockwise);  // rpm 0: off
  void coolant(bool on, const std::string& mode);
  void comment(const std::string& text);  // sanitised: no line breaks, ';' prefixed by template
  void literal(const std::string& text);  // verbatim (one line)

  // Completes every file of the program (the main program of a split one too) and flushes it
  // to the disk, without renaming anything yet: a full disk shows here, and the host may write
  // its own files (a report) before the program replaces an old one. No statement may follow.
  void prepare();
  // prepare() if not done, then renames all files as one swap (the main .src last; an old
  // program is kept whole if the swap fails); returns the final .src paths written, the main
  // program first, then the parts in order.
  std::vector<std::string> finish();

  int motions() const;
  // The parts and where they end; program_bytes once prepare() ran.
  const KrlSplitReport& split() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace redpost
