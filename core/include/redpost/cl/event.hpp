// Events of a CL (cutter location) stream, as the APT/CLSF reader produces them and as every
// front end (CL file, NX event handlers, C hosts) feeds them to a post session.
//
// Positions are in mm in the CL file's coordinate system (the workpiece frame); the reader has
// already converted inches, linearised arcs and NURBS, and expanded drilling cycles into moves.
#pragma once

#include <string>

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
  machine_frame,    // NX MSYS: p_mm = origin, tool_axis = the MCS z axis, both in NX's absolute
                    // frame; flag = the CL data after it are turned into that frame (--msys apply)
  unknown_word,     // a major word the reader does not know: text = the word (first time only)
  end_of_program,   // FINI / END
};

enum class SpindleDirection { clockwise, counter_clockwise, off };

// Where a move came from, for the CL line comments and the joints CSV.
enum class MoveOrigin { goto_point, from_point, arc, nurbs, cycle };

struct ClEvent {
  ClEventKind kind = ClEventKind::move;
  int line = 0;  // 1-based line of the record in the CL file (first line of a continued record)

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

  // coolant
  bool flag = false;

  // part_name, tool name, operation names, comments, literals, unknown words
  std::string text;
};

}  // namespace redpost
