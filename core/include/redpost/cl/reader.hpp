// A streaming reader for ISO APT/CLDATA and the NX CLSF dialect (docs/cl-format.md).
//
// It reads one record at a time from a std::istream (never the whole file), joins `$`
// continuation lines, and turns each record into the toolpath events it says (cl/event.hpp):
// a drilling cycle and its holes, a NURBS with its knots and control points, NX's MSYS, operator
// text. With ClReaderOptions::toolpath_events these are what next() gives, for a post session to
// expand (redpost convert); else they go through a ClExpander here and come out plain: arcs and
// NURBS as linear moves within the chordal tolerance, drilling cycles as the moves they stand
// for. Malformed records throw Error(bad_input) with "file:line:column: message"; what the
// expander refuses, with "file:line: message".
#pragma once

#include <cstddef>
#include <deque>
#include <istream>
#include <memory>
#include <string>

#include "redpost/cl/event.hpp"
#include "redpost/cl/expander.hpp"

namespace redpost {

// Which CAM system's conventions a file follows where they differ (docs/cl-format.md).
enum class ClDialect {
  automatic,  // NX CLSF from the first TOOL PATH/, TLDATA/, MSYS/, END-OF-PATH or PAINT record,
              // APT before and without one
  apt,        // ISO APT, SolidWorks CAM: a CIRCLE axis gives the direction by the right-hand rule
  nx_clsf,    // Siemens NX CLSF: the CIRCLE axis is written "assuming a clockwise direction"
};

struct ClReaderOptions {
  double chordal_tolerance_mm = 0.01;  // arcs and NURBS are split so that no chord strays further
  std::size_t max_line_bytes = 1u << 20;  // a longer physical line is refused with a message
  bool keep_comments = false;             // $$ comments become comment events (PPRINT always does)
  ClDialect dialect = ClDialect::automatic;
  // How far a point that must lie on a curve may miss it: an arc's end (the GOTO) and its
  // circle, a NURBS's first control point and the current position. CL files print 4 to 6
  // decimals, so their own rounding stays well inside 5 micrometres.
  double point_match_tolerance_mm = 0.005;
  // SELECT/TOOL,n is a preselect (the next tool to fetch) in SolidWorks CAM and NX output; set
  // this for a dialect in which SELECT/TOOL loads the tool.
  bool select_tool_loads = false;
  MsysMode msys = MsysMode::ignore;
  // CIRCLE + GOTO as one ClEventKind::arc instead of its chords (the post session chords it, or
  // writes a CIRC).
  bool arcs_as_events = false;
  // The toolpath events as the file gives them, unexpanded, for a post session, which expands
  // them with its own ClExpander (and its own MSYS mode: `msys` is not used then); arcs come
  // whole. The same toolpath from NX's postprocessor then goes through the same expansion.
  bool toolpath_events = false;
};

class ClReader {
 public:
  ClReader(std::istream& in, std::string source_name, ClReaderOptions options = {});
  ~ClReader();
  ClReader(const ClReader&) = delete;
  ClReader& operator=(const ClReader&) = delete;

  // The next event, or false at the end of the stream. Throws Error on malformed input; after
  // an Error the reader is spent and next() returns false.
  bool next(ClEvent& event);

  // Warnings collected so far ("file:line: unknown word CSI_SET_FLUTE_LENGTH ignored"), one per
  // distinct unknown word, and one per kind of ignored instruction (CUTCOM, DWELL, ...).
  const std::deque<std::string>& warnings() const;

  const std::string& source_name() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace redpost
