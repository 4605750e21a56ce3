// The front door of the CL event model (cl/event.hpp): the toolpath events a front end gives, in;
// the plain events a post session tracks, out.
//
// Every front end goes through one ClExpander: the CL reader (inside ClReader, or in the post
// session when the reader gives toolpath events), and NX's postprocessor through the C ABI's
// calls. It owns what the toolpath's meaning depends on beyond one record:
// - drilling cycles: a cycle's definition, its holes (a GOTO while it is on, NX's
//   MOM_drill_move) expanded into the rapid, feed, peck, dwell and retract moves of each hole,
//   the feed restored after it, and a cycle left on across a tool change refused;
// - NURBS: the knot vector completed (both forms of docs/cl-format.md, "NURBS") from the current
//   point and split into chords within the chordal tolerance;
// - NX's MSYS: checked (one MCS under MsysMode::ignore) or applied to every point and vector after
//   it (MsysMode::apply);
// - operator text (INSERT, PPRINT, NX's Insert and operator messages) as comments, and only
//   INSERT's "KRL: statement" as code; cutter compensation, which KRL does not have, with a
//   warning;
// - arcs, passed on whole (the session writes a CIRC or its chords) or, for hosts that read
//   plain moves, as their chords.
//
// Pull-based, so that an arc or a NURBS of a million chords never becomes a list: push() one
// event, then next() until it returns false. Errors throw Error(bad_input) at the event's line;
// warnings go to the callback, each with "source:line: ".
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "redpost/cl/event.hpp"

namespace redpost {

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

struct ClExpanderOptions {
  double chordal_tolerance_mm = 0.01;  // NURBS (and arcs with chord_arcs) within it
  // How far a point that must lie on a curve may miss it: an arc's end and its circle, a NURBS's
  // first control point and the current position.
  double point_match_tolerance_mm = 0.005;
  MsysMode msys = MsysMode::ignore;
  // Arcs out as the moves of their chords (for hosts that read plain moves) instead of whole.
  bool chord_arcs = false;
};

class ClExpander {
 public:
  using Warn = std::function<void(const std::string& message)>;

  // `source_name` names the input in messages ("part.apt:12: ..."); `warn` takes each warning.
  ClExpander(std::string source_name, const ClExpanderOptions& options, Warn warn);
  ~ClExpander();
  ClExpander(const ClExpander&) = delete;
  ClExpander& operator=(const ClExpander&) = delete;

  // One toolpath event. The plain events it stands for come out of next(); push() may only
  // follow once next() has returned false. Throws Error(bad_input) at e.line.
  void push(const ClEvent& e);
  // The next plain event of the last push(), false when there is none left. Throws Error for a
  // curve that turns out to need too many chords.
  bool next(ClEvent& out);

  // A drilling cycle is on (its holes are expanded).
  bool cycle_active() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace redpost
