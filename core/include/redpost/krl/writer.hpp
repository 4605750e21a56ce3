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
// so that the controller's BCO run is a defined joint move. With motions_per_file > 0 the
// program is NAME.src, which calls NAME_P001() ... in order; each part holds that many motions,
// has its own .dat, and starts by restating the last tool change, spindle and coolant statements
// and a PTP E6AXIS to where the previous part ended, so that it also runs alone.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "redpost/krl/template.hpp"

namespace redpost {

struct KrlProgramInfo {
  std::string name;                   // KRL identifier, at most 24 characters (checked)
  std::string output_dir;             // must exist and be writable (checked at construction)
  std::string base = "BASE_DATA[1]";  // right-hand side of $BASE =
  std::string tool = "TOOL_DATA[1]";  // right-hand side of $TOOL =
  double apo_mm = 0.5;                // $APO.CDIS
  int motions_per_file = 0;           // 0: no splitting
  int cl_line_every = 50;             // a comment with the CL line every N motions (0: never)
  std::string header_comment;         // e.g. "redpost 0.1.0, cell andres2011_kr15_track_table"
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
};

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
  void tool_change(int number, const std::string& name);
  void spindle(double rpm, bool clockwise);  // rpm 0: off
  void coolant(bool on, const std::string& mode);
  void comment(const std::string& text);  // sanitised: no line breaks, ';' prefixed by template
  void literal(const std::string& text);  // verbatim (one line)

  // Completes the program and renames all files (the main .src last); returns the final .src
  // paths written, the main program first, then the parts in order.
  std::vector<std::string> finish();

  int motions() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace redpost
