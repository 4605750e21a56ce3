// The state of a ClExpander (redpost/cl/expander.hpp), shared by its sources: expander.cpp (the
// dispatch, straight moves, arcs, MSYS, text) and expander_curves.cpp (drilling cycles and NURBS).
//
// Internal to core (core/src/cl/); not installed.
#pragma once

#include <cstddef>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cl/arc_chords.hpp"
#include "cl/nurbs_curve.hpp"
#include "redpost/cl/expander.hpp"

namespace redpost {

struct ClExpander::Impl {
  using Vector3d = Eigen::Vector3d;

  // Events per refill from an arc, NURBS or hole generator.
  static constexpr std::size_t kBatch = 64;

  enum class Generator { none, arc, nurbs, hole };

  // The drilling cycle in force (lengths in mm along the tool axis from the hole's point).
  struct DrillCycle {
    bool defined = false;
    bool active = false;
    // The tool changed (or a new operation began) while the cycle was on and no cycle off came:
    // whether the motions after it are holes or moves is not said, so motion is refused.
    bool interrupted = false;
    int interrupted_line = 0;
    int line = 0;
    std::string name;  // "CYCLE/DRILL", for messages
    bool deep = false;
    double depth_mm = 0.0;
    double clearance_mm = 0.0;
    double retract_mm = 0.0;
    double feed_mm_per_min = 0.0;
    double first_peck_mm = 0.0;
    double next_peck_mm = 0.0;
    double dwell_s = 0.0;
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

  Impl(std::string source_name, const ClExpanderOptions& options, Warn warn_fn);

  // ---- expander.cpp --------------------------------------------------------------------------
  [[noreturn]] void fail(int line, const std::string& message) const;
  void warn(const std::string& key, int line, const std::string& message);
  ClEvent& emit(const ClEvent& e);
  ClEvent& emit_kind(ClEventKind kind, int line);
  Vector3d in_frame_point(const Vector3d& p) const;
  Vector3d in_frame_vector(const Vector3d& v) const;
  static const char* word_of(const ClEvent& e);
  void on_move(const ClEvent& e);
  void on_arc(const ClEvent& e);
  void run_arc();
  void on_msys(const ClEvent& e);
  void on_text(const ClEvent& e);
  void on_cutcom(const ClEvent& e);

  // ---- expander_curves.cpp -------------------------------------------------------------------
  void check_cycle_not_interrupted(const ClEvent& e) const;
  void interrupt_cycle(int line);
  void on_cycle(const ClEvent& e);
  void on_hole(const ClEvent& e, const Vector3d& p, const Vector3d& axis);
  double peck_depth(long k) const;
  void hole_move(double above_mm, bool rapid);
  void run_hole();
  [[noreturn]] void fail_nurbs(const std::string& message) const;
  void on_nurbs(const ClEvent& e);
  void check_knot_runs() const;
  void run_nurbs();

  std::string source;
  ClExpanderOptions opt;
  Warn warn_fn;

  // ---- output --------------------------------------------------------------------------------
  std::vector<ClEvent> out;
  std::size_t head = 0;

  // ---- state, in the frame the events go out in ----------------------------------------------
  bool pos_known = false;
  Vector3d pos = Vector3d::Zero();
  Vector3d axis = Vector3d::UnitZ();  // the last motion's tool axis
  bool feed_known = false;
  double feed_mm_per_min = 0.0;  // the last feed given (not the cycles' own)
  DrillCycle cycle;
  // MSYS: the first one (all must agree with it under MsysMode::ignore) and, under apply, the
  // transform from the current MCS into NX's absolute frame.
  int msys_line = 0;
  Eigen::Matrix3d msys_R = Eigen::Matrix3d::Identity();
  Vector3d msys_origin = Vector3d::Zero();
  bool frame_applied = false;
  Eigen::Matrix3d frame_R = Eigen::Matrix3d::Identity();
  Vector3d frame_origin = Vector3d::Zero();
  std::set<std::string> warned;  // keys of warnings given once
  int text_warnings = 0;         // operator-text warnings given (each names its line, up to a cap)

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
  HolePhase hole_phase = HolePhase::done;
  Vector3d hole_point = Vector3d::Zero();
  long hole_pecks = 1;
  long hole_peck = 0;
};

}  // namespace redpost
