// Events of a CL (cutter location) stream: the one event model of every front end (the APT/CLSF
// reader, NX's postprocessor through the Tcl handlers, C hosts) and of the post session.
//
// Two layers. The front ends give the *toolpath events* (all kinds below): a drilling cycle and
// its holes, a NURBS, NX's MSYS, operator text, cutter compensation, as the CL file or NX says
// them. ClExpander (cl/expander.hpp) turns them into the *plain events* a post session tracks
// (moves, arcs, feeds, dwells, comments, literals, ...), the same way for every front end, so
// that the same toolpath gives the same program whichever way it came in.
//
// Positions are in mm in the CL frame (the workpiece frame: NX's MCS, or under MsysMode::apply
// NX's absolute frame once expanded); the reader has already converted inches.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "redpost/kinematics/types.hpp"

namespace redpost {

enum class ClEventKind {
  part_name,        // PARTNO: text
  tool_change,      // LOADTL, LOAD/TOOL, SELECT/TOOL (when it loads), with CUTTER/TLDATA data
  spindle,          // SPINDL: value = rpm (0 = off), direction
  feed,             // FEDRAT: value = mm/min (MMPR converted with the spindle speed)
  rapid,            // RAPID: the next move is a rapid traverse
  move,             // GOTO, GODLTA, FROM, and the pieces of arcs, NURBS and cycles
  coolant,          // COOLNT: flag = on/off, text = mode (FLOOD, MIST, ...)
  operation_start,  // TOOL PATH/ (NX) or the first motion after a new operation: text = name
  operation_end,    // END-OF-PATH
  comment,          // PPRINT, INSERT free text, $$ comments the user wants kept: text
  literal,          // INSERT/KRL: statement: KRL code passed to the program (checked there)
  dwell,            // a drilling cycle's DWELL at the hole bottom: value = seconds
  arc,              // CIRCLE + GOTO as one event (ClReaderOptions::arcs_as_events): p_mm the end,
                    // tool_axis the end's, arc_centre_mm, arc_axis (right-hand rule), value the
                    // radius (0: from the start)
  machine_frame,    // NX MSYS as expanded: p_mm = origin, tool_axis = the MCS z axis, both in NX's
                    // absolute frame; flag = the CL data after it are turned into that frame
  unknown_word,     // a major word the reader does not know: text = the word (first time only)
  end_of_program,   // FINI / END

  // Toolpath events, expanded by ClExpander into the plain ones above.
  cycle,          // CYCLE/DRILL..., NX's MOM_drill*: `cycle` defined and switched on; text = its
                  // name for messages ("CYCLE/DRILL")
  cycle_on,       // CYCLE/ON: the last cycle defined on again
  cycle_off,      // CYCLE/OFF, NX's MOM_cycle_off
  hole,           // NX's MOM_drill_move: a hole of the active cycle at p_mm (its top), tool_axis
                  // (a plain move's GOTO while a cycle is on is a hole too, as in APT)
  nurbs,          // NURBS/ with its KNOT/ and CNTRL/, NX's MOM_nurbs_move: from the current point
                  // through `nurbs_knots` and `nurbs_points` as given (docs/cl-format.md)
  msys,           // NX's MSYS / MOM_msys as given: p_mm = origin, msys_x and msys_y the MCS's X
                  // and Y axes in NX's absolute frame
  operator_text,  // INSERT, PPRINT, NX's MOM_insert / MOM_pprint / MOM_operator_message: text, as
                  // `text_kind` says; only INSERT's "KRL: statement" passes code through
  cutcom,         // CUTCOM/, NX's MOM_cutcom_on/off: flag on, text = LEFT, RIGHT or ON
};

enum class SpindleDirection { clockwise, counter_clockwise, off };

// Where a move came from. A goto_point while a drilling cycle is on is a hole of it; a FROM or
// a GODLTA (delta) there is refused.
// fitted_arc: an arc event the point reduction made of CL points that lie on a circle
// (cl/point_reduction.hpp); its chords keep half the reduction's tolerance.
enum class MoveOrigin { goto_point, from_point, arc, nurbs, cycle, delta, fitted_arc };

// The longest dwell accepted (s): a longer one is a typo (a value in milliseconds, or
// revolutions), and the spindle would run for minutes at the hole's bottom.
inline constexpr double kMaxDwellSeconds = 600.0;

// The fastest spindle accepted (rpm): milling spindles run to about 60 000 rpm; a larger value
// is a typo (a surface speed, or a unit slip), and it is written into the program.
inline constexpr double kMaxSpindleRpm = 100000.0;

// What operator text is (ClEventKind::operator_text).
enum class TextKind { insert, pprint, message };

// A drilling cycle as its definition gives it (CYCLE/DRILL..., NX's MOM_drill*). Lengths in mm
// along the tool axis from the hole's point (its top); NaN where the definition gives none.
struct ClCycle {
  bool deep = false;  // pecking: a full retract to the clearance between pecks
  double depth_mm = std::numeric_limits<double>::quiet_NaN();         // FEDTO: below the point
  double clearance_mm = std::numeric_limits<double>::quiet_NaN();     // RAPTO: above it
  double retract_mm = std::numeric_limits<double>::quiet_NaN();       // RTRCTO; NaN: RAPTO's
  double feed_mm_per_min = std::numeric_limits<double>::quiet_NaN();  // NaN: the feed in force
  double dwell_s = 0.0;                                               // at the hole's bottom
  double first_peck_mm = std::numeric_limits<double>::quiet_NaN();    // 1STPECK
  double next_peck_mm = std::numeric_limits<double>::quiet_NaN();     // SUBPECK; NaN: 1STPECK's
};

// A NURBS control point as given: cartesian, with its weight.
struct ClNurbsPoint {
  double x = 0.0, y = 0.0, z = 0.0, w = 1.0;
};

struct ClEvent {
  ClEventKind kind = ClEventKind::move;
  int line = 0;  // 1-based line of the record in the CL file (first line of a continued record)
  // A move that stands for several CL points (cl/point_reduction.hpp): the line of the first
  // point it covers; 0: only its own.
  int first_line = 0;

  // move
  Eigen::Vector3d p_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d tool_axis = Eigen::Vector3d::UnitZ();  // unit, from tip towards spindle
  MoveOrigin origin = MoveOrigin::goto_point;
  bool rapid = false;  // this move is a rapid traverse (RAPID applied to it)
  // A drilling cycle's clearance (RAPTO) for its moves: the plane through clearance_p_mm normal
  // to tool_axis. Below it the tool may be inside the part, so a rapid must follow its straight
  // line there (docs/convert.md, "Rapids").
  bool has_clearance = false;
  Eigen::Vector3d clearance_p_mm = Eigen::Vector3d::Zero();

  // arc
  Eigen::Vector3d arc_centre_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d arc_axis = Eigen::Vector3d::UnitZ();

  // tool_change
  int tool_number = 0;
  double tool_diameter_mm = 0.0;
  double tool_length_mm = 0.0;

  // spindle, feed
  double value = 0.0;
  SpindleDirection direction = SpindleDirection::off;

  // coolant, cutcom
  bool flag = false;

  // part_name, tool name, operation names, comments, literals, unknown words, operator text
  std::string text;
  TextKind text_kind = TextKind::insert;

  // cycle
  ClCycle cycle;

  // nurbs: the knots and control points as written (empty for every other kind)
  std::vector<double> nurbs_knots;
  std::vector<ClNurbsPoint> nurbs_points;

  // msys
  Eigen::Vector3d msys_x = Eigen::Vector3d::UnitX();
  Eigen::Vector3d msys_y = Eigen::Vector3d::UnitY();
};

}  // namespace redpost
