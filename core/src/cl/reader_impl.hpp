// The CL reader's state and record handlers (ClReader::Impl), declared once for the files that
// define them: reader.cpp (driving and dispatch), motion.cpp (the event queue, GOTO, FROM,
// GODLTA, RAPID, TLAXIS), arcs.cpp (CIRCLE), nurbs.cpp (NURBS), cycles.cpp (CYCLE) and
// settings.cpp (the records that only set machine state). The input and the current record are
// in the base, ClRecordReader (cl/record.hpp).
//
// Internal to the CL reader (core/src/cl/); not installed.
#pragma once

#include <cstddef>
#include <deque>
#include <functional>
#include <istream>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "cl/arc_chords.hpp"
#include "cl/record.hpp"
#include "redpost/cl/event.hpp"
#include "redpost/cl/expander.hpp"
#include "redpost/cl/reader.hpp"

namespace redpost {

struct ClReader::Impl : detail::ClRecordReader {
  Impl(std::istream& in, std::string source_name, ClReaderOptions options);

  // ---- reader.cpp: driving, dispatch, warnings -----------------------------------------------
  void warn_once(const std::string& key, int line_no, const std::string& message);
  bool read_record();
  void step();
  void finish_input();
  void handle_record();
  void emit_comments();
  void dispatch();
  void on_unknown();
  void on_operator_text(bool insert);

  // ---- motion.cpp: events, GOTO, FROM, GODLTA, RAPID, TLAXIS ---------------------------------
  ClEvent& push(ClEventKind kind, int line_no);
  ClEvent& push_move(const Vector3d& p, const Vector3d& tool_axis, MoveOrigin origin, bool rapid,
                     int line_no);
  void push_feed(double mm_per_min, int line_no);
  void push_text(ClEventKind kind, std::string_view text);
  bool take_rapid();
  const Vector3d& current_axis() const;
  void on_goto(MoveOrigin origin);
  void on_godlta();
  void on_rapid();
  void on_tlaxis();

  // ---- arcs.cpp: CIRCLE ----------------------------------------------------------------------
  void on_circle();
  void check_arc_not_interrupted() const;
  void start_arc(const Vector3d& end);

  // ---- nurbs.cpp: NURBS, KNOT, CNTRL ---------------------------------------------------------
  void on_nurbs();
  void on_knot();
  void on_cntrl();
  void finish_nurbs();

  // ---- cycles.cpp: CYCLE ---------------------------------------------------------------------
  void on_cycle();
  void read_cycle_parameters(std::size_t i, bool deep);

  // ---- settings.cpp: feed, spindle, coolant, tools, units, coordinate systems ----------------
  double feed_value(const Field& value, std::string_view unit) const;
  void on_fedrat();
  void on_spindl();
  void on_coolnt();
  void push_tool_change(int number_);
  void read_tool_couplets(std::size_t i);
  void on_loadtl();
  void on_load_or_select(bool load);
  void on_cutter();
  void on_tldata();
  void on_tool_path();
  void on_units();
  void on_multax();
  void on_msys();
  void on_csys();
  void on_trntyp();
  void on_cutcom();

  // ---- input ---------------------------------------------------------------------------------
  ClReaderOptions opt;
  bool record_pending = false;  // parsed, to be handled once the NURBS before it is out

  // ---- output --------------------------------------------------------------------------------
  // The toolpath events of the records read; without opt.toolpath_events, each is expanded by
  // `expander` into the plain events next() gives.
  std::vector<ClEvent> queue;
  std::size_t head = 0;
  std::unique_ptr<ClExpander> expander;
  bool finished = false;
  std::deque<std::string> warnings;
  std::set<std::string> warned;                      // keys of warnings already given
  std::set<std::string, std::less<>> unknown_words;  // unknown major words already reported

  // ---- machine state (unit_mm is in ClRecordReader), in the file's own frame ------------------
  bool nx;                   // NX CLSF conventions (see ClDialect)
  bool units_given = false;  // a UNITS record was read
  bool multax = false;
  bool axis_known = false;  // a TLAXIS or a GOTO with i,j,k was seen
  Vector3d axis = Vector3d::UnitZ();
  // Where the tool is, for the records checked against it (an arc's start); the expander keeps
  // its own, exact one.
  bool pos_known = false;
  Vector3d pos = Vector3d::Zero();
  bool rapid_next = false;
  bool feed_known = false;
  bool feed_per_rev = false;
  double feed_mm_per_rev = 0.0;
  double feed_mm_per_min = 0.0;
  double spindle_rpm = 0.0;       // 0 while stopped
  double last_spindle_rpm = 0.0;  // for SPINDL/ON
  SpindleDirection last_direction = SpindleDirection::clockwise;
  double tool_diameter_mm = 0.0;
  double tool_length_mm = 0.0;
  std::string tool_name;
  // A drilling cycle seen as on, and where its holes leave the tool (above the hole point):
  // only so that `pos` follows the holes (ClExpander expands and checks them).
  bool cycle_on = false;
  bool cycle_defined = false;
  double cycle_retract_mm = 0.0;

  // ---- CIRCLE waiting for its GOTO -----------------------------------------------------------
  bool arc_pending = false;
  int arc_line = 0;
  Vector3d arc_centre = Vector3d::Zero();
  Vector3d arc_axis = Vector3d::UnitZ();  // travel by the right-hand rule (NX sign undone)
  bool arc_has_radius = false;
  double arc_radius_mm = 0.0;

  // ---- NURBS being collected -----------------------------------------------------------------
  bool collecting_nurbs = false;
  int nurbs_line = 0;
  bool nurbs_rapid = false;
  std::vector<double> nurbs_knots;         // as written
  std::vector<ClNurbsPoint> nurbs_points;  // as written (mm)
};

}  // namespace redpost
