// A streaming reader for ISO APT/CLDATA and the NX CLSF dialect (docs/cl-format.md).
//
// It reads one record at a time from a std::istream (never the whole file), joins `$`
// continuation lines, and turns each record into zero or more ClEvents: arcs and NURBS come out
// as linear moves within the chordal tolerance, drilling cycles as the moves they stand for.
// Malformed records throw Error(bad_input) with "file:line:column: message".
#pragma once

#include <cstddef>
#include <deque>
#include <istream>
#include <memory>
#include <string>

#include "redpost/cl/event.hpp"

namespace redpost {

// Which CAM system's conventions a file follows where they differ (docs/cl-format.md).
enum class ClDialect {
  automatic,  // NX CLSF from the first TOOL PATH/, TLDATA/, MSYS/, END-OF-PATH or PAINT record,
              // APT before and without one
  apt,        // ISO APT, SolidWorks CAM: a CIRCLE axis gives the direction by the right-hand rule
  nx_clsf,    // Siemens NX CLSF: the CIRCLE axis is written "assuming a clockwise direction"
};

// What NX's MSYS record means for the CL data after it (docs/cl-format.md, "MSYS").
enum class MsysMode {
  ignore,  // the data stay in NX's machine coordinate system (MCS), the workpiece frame; every
           // MSYS of the file must then be the same
  apply,   // points and vectors are turned into NX's absolute frame: p_abs = origin + R p_mcs
};

// The finest chordal tolerance accepted: 0.1 um, far below what an arm repeats to (some 20 um),
// and the most chords one arc or NURBS may become. Beyond them a typo in the tolerance would
// write gigabytes of KRL, or run for ever.
inline constexpr double kMinChordalToleranceMm = 1e-4;
inline constexpr long kMaxCurveChords = 1'000'000;

// "" when `tolerance_mm` is a finite number of at least kMinChordalToleranceMm, else what is
// wrong, naming --chordal-tol.
std::string chordal_tolerance_problem(double tolerance_mm);

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
