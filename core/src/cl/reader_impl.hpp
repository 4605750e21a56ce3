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
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "cl/arc_chords.hpp"
#include "cl/nurbs_curve.hpp"
#include "cl/record.hpp"
#include "redpost/cl/event.hpp"
#include "redpost/cl/reader.hpp"

namespace redpost {

struct ClReader::Impl : detail::ClRecordReader {
  // Events per refill from an arc, NURBS or cycle generator.
  static constexpr std::size_t kBatch = 64;

  enum class Generator { none, arc, nurbs, hole };

  // A drilling cycle as CYCLE/ defined it (lengths in mm, along the tool axis from the hole point).
  struct DrillCycle {
    bool defined = false;
    bool active = false;
    // The tool changed (or a new NX operation began) while the cycle was on and no CYCLE/OFF
    // came: whether the GOTOs after it are holes or moves is not written, so motion is refused.
    bool interrupted = false;
    int interrupted_line = 0;
    bool deep = false;  // pecking: full retract to the clearance between pecks
    int line = 0;
    double depth_mm = 0.0;      // FEDTO: bottom of the hole below the GOTO point
    double clearance_mm = 0.0;  // RAPTO: rapids stop this far above the point (or a peck bottom)
    double retract_mm = 0.0;    // RTRCTO (or RAPTO): where the tool goes after the hole
    double feed_mm_per_min = 0.0;
    double first_peck_mm = 0.0;
    double next_peck_mm = 0.0;
    double dwell_s = 0.0;  // DWELL at the hole bottom
  };

  enum class HolePhase {
    travel,
    approach,
    feed_on,
    reenter,
    cut,
    peck_out,
    dwell,
    feed_off,
    retract,
    done
  };

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
  void warn_text(const char* kind, const std::string& message);
  void run_generator();

  // ---- motion.cpp: events, GOTO, FROM, GODLTA, RAPID, TLAXIS ---------------------------------
  ClEvent& push(ClEventKind kind, int line_no);
  void push_move(const Vector3d& p, const Vector3d& tool_axis, MoveOrigin origin, bool rapid,
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
  void start_arc(const Vector3d& end, const Vector3d& tool_axis);
  void run_arc();

  // ---- nurbs.cpp: NURBS, KNOT, CNTRL ---------------------------------------------------------
  void on_nurbs();
  void on_knot();
  void on_cntrl();
  [[noreturn]] void fail_nurbs(const std::string& message) const;
  void finish_nurbs();
  void check_knot_runs() const;
  void run_nurbs();

  // ---- cycles.cpp: CYCLE and its holes -------------------------------------------------------
  void on_cycle();
  void read_cycle_parameters(std::size_t i, bool deep);
  void interrupt_cycle();
  void check_cycle_not_interrupted() const;
  void start_hole(const Vector3d& p);
  double peck_depth(long k) const;
  void hole_move(double above_mm, bool rapid);
  void run_hole();

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
  Vector3d in_frame_point(const Vector3d& p) const;
  Vector3d in_frame_vector(const Vector3d& v) const;
  void on_csys();
  void on_trntyp();
  void on_cutcom();

  // ---- input ---------------------------------------------------------------------------------
  ClReaderOptions opt;
  bool record_pending = false;  // parsed, to be handled once the NURBS before it is out

  // ---- output --------------------------------------------------------------------------------
  std::vector<ClEvent> queue;
  std::size_t head = 0;
  bool finished = false;
  std::deque<std::string> warnings;
  std::set<std::string> warned;                      // keys of warnings already given
  std::set<std::string, std::less<>> unknown_words;  // unknown major words already reported
  int text_warnings = 0;  // INSERT and PPRINT warnings given (each names its line, up to a cap)

  // ---- machine state (unit_mm is in ClRecordReader) ------------------------------------------
  bool nx;                   // NX CLSF conventions (see ClDialect)
  bool units_given = false;  // a UNITS record was read
  bool multax = false;
  bool axis_known = false;  // a TLAXIS or a GOTO with i,j,k was seen
  Vector3d axis = Vector3d::UnitZ();
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
  // MSYS: the first one (all must agree with it under MsysMode::ignore) and, under apply, the
  // transform from the current MCS into NX's absolute frame.
  int msys_line = 0;
  Eigen::Matrix3d msys_R = Eigen::Matrix3d::Identity();
  Vector3d msys_origin = Vector3d::Zero();
  bool frame_applied = false;
  Eigen::Matrix3d frame_R = Eigen::Matrix3d::Identity();
  Vector3d frame_origin = Vector3d::Zero();
  double tool_diameter_mm = 0.0;
  double tool_length_mm = 0.0;
  std::string tool_name;

  // ---- CIRCLE waiting for its GOTO -----------------------------------------------------------
  bool arc_pending = false;
  int arc_line = 0;
  Vector3d arc_centre = Vector3d::Zero();
  Vector3d arc_axis = Vector3d::UnitZ();  // travel by the right-hand rule (NX sign undone)
  bool arc_has_radius = false;
  double arc_radius_mm = 0.0;
  std::size_t arc_radius_offset = 0;

  // ---- NURBS being collected -----------------------------------------------------------------
  bool collecting_nurbs = false;
  int nurbs_line = 0;
  std::vector<double> nurbs_knots;                     // as written
  std::vector<detail::HomogeneousPoint> nurbs_points;  // as written

  // ---- generators ----------------------------------------------------------------------------
  Generator generator = Generator::none;
  int gen_line = 0;
  bool gen_rapid = false;
  Vector3d gen_axis = Vector3d::UnitZ();
  detail::ArcChords arc;
  long arc_done = 0;
  Vector3d arc_end_axis = Vector3d::UnitZ();
  detail::NurbsCurve curve;
  detail::NurbsChords curve_chords;
  long curve_chord_count = 0;  // chords given out for the current NURBS (kMaxCurveChords)
  DrillCycle cycle;
  HolePhase hole_phase = HolePhase::done;
  Vector3d hole_point = Vector3d::Zero();
  long hole_pecks = 1;
  long hole_peck = 0;
};

}  // namespace redpost
