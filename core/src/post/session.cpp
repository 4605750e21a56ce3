// A postprocessing session (redpost/post/session.hpp): construction, the public calls and the
// dispatch of CL events, the joints log, and finish(). The moves are in motion.cpp, the tool
// changes in tools.cpp (post/session_impl.hpp).
#include "redpost/post/session.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>

#include "post/session_impl.hpp"
#include "redpost/io/error.hpp"
#include "redpost/krl/check.hpp"
#include "redpost/krl/statement.hpp"

namespace redpost {

namespace {

// In a spline set with SPL, the share of the fit tolerance left to the lines the point
// reduction merges (only nearly straight runs: a curve is better drawn by the spline through its
// points); the rest is the SPL segments' (krl/spline_model.hpp).
constexpr double kSplineLineShare = 0.1;

// What of --fit-tol (mm) the written path may take: the printed decimals move each written
// point by up to sqrt(3)/2 of their last place, and every CL point must stay within --fit-tol of
// the path the program prints (issue 30), not only of the one the session computed. A set that
// prints too few decimals for the tolerance keeps a tenth of it.
double path_budget_mm(double fit_tolerance_mm, int position_decimals) {
  const double printing_mm = 0.5 * std::sqrt(3.0) * std::pow(10.0, -position_decimals);
  return std::max(fit_tolerance_mm - printing_mm, 0.1 * fit_tolerance_mm);
}

// The same for --fit-ang-tol (deg): each of A, B and C moves by up to half its last place.
double axis_budget_deg(double fit_angle_tolerance_deg, const KrlTemplateSet& t) {
  const double printing_deg = 1.5 * std::pow(10.0, -t.angle_decimals);
  return std::max(fit_angle_tolerance_deg - printing_deg, 0.1 * fit_angle_tolerance_deg);
}

// n where `expr` is `array`[n] (blanks allowed around the parts), else 0: the number the
// controller's $ACT_TOOL / $ACT_BASE give an entry of TOOL_DATA / BASE_DATA.
int data_entry(std::string_view expr, std::string_view array) {
  const auto blank = [](char ch) { return ch == ' ' || ch == '\t'; };
  const auto skip = [&](std::size_t& i) {
    while (i < expr.size() && blank(expr[i]))
      ++i;
  };
  std::size_t i = 0;
  skip(i);
  if (expr.size() - i < array.size())
    return 0;
  for (std::size_t k = 0; k < array.size(); ++k) {
    if (std::toupper(static_cast<unsigned char>(expr[i + k])) != array[k])
      return 0;
  }
  i += array.size();
  skip(i);
  if (i >= expr.size() || expr[i++] != '[')
    return 0;
  skip(i);
  int n = 0;
  const auto [end, ec] = std::from_chars(expr.data() + i, expr.data() + expr.size(), n);
  if (ec != std::errc() || n < 1)
    return 0;
  i = static_cast<std::size_t>(end - expr.data());
  skip(i);
  if (i >= expr.size() || expr[i++] != ']')
    return 0;
  skip(i);
  return i == expr.size() ? n : 0;
}

// The writer's program settings that come from the cell: how $BASE is set (a turntable as a
// mathematically coupled kinematic), the number of external axes, the tool change routine, the
// numbers of the base, the tool and its load.
KrlProgramInfo program_for(const Cell& cell, const PostOptions& o, const KrlTemplateSet& t) {
  KrlProgramInfo info = o.program;
  // SPL knots in a spline set get most of the fit tolerance; the lines merged before them the
  // rest (reduction_for), so that a dropped point is within the sum of the written curve. The
  // motion rate in a spline set goes with the reduction, as in the others (timing.cpp). A bad
  // tolerance is refused by the session, in --fit-tol's words, not by the writer.
  const double tolerance_mm = o.reduction.tolerance_mm;
  if (std::isfinite(tolerance_mm) && tolerance_mm > 0.0) {
    info.spline_tolerance_mm =
        (1.0 - kSplineLineShare) * path_budget_mm(tolerance_mm, t.position_decimals);
    info.interpolation_cycle_s = t.timing.interpolation_cycle_ms / 1000.0;
  }
  const ControllerSettings& c = cell.controller;
  if (c.coupled_base_joint >= 0) {
    info.base_coupled = true;
    info.machine_def = c.machine_def;
    info.ex_ax_data = c.ex_ax_data;
  }
  int external = 0;
  for (int i = 0; i < cell.size(); ++i)
    external += cell.joint(i).axis.kind == AxisKind::external;
  info.ex_axes = external;
  info.tool_change_routine = c.tool_change_routine;
  info.base_data = data_entry(info.base, "BASE_DATA");
  info.tool_data = data_entry(info.tool, "TOOL_DATA");
  info.load_data = c.load_data;  // 0: the tool's own number
  return info;
}

// The front door's settings from the session's.
ClExpanderOptions expander_options(const PostOptions& o) {
  ClExpanderOptions e;
  e.chordal_tolerance_mm = o.chordal_tolerance_mm;
  e.point_match_tolerance_mm = o.arc_point_tolerance_mm;
  e.msys = o.msys;
  e.chord_arcs = false;  // the session writes a CIRC or its chords (motion.cpp)
  return e;
}

}  // namespace

// The reduction fits arcs where the writer may write a CIRC (each one proven there, circ.cpp):
// a set with CIRC, and no deflection model (which gives every chord its own load and target).
PointReductionOptions session_reduction(const PostOptions& o, const KrlWriter& writer,
                                        const KrlTemplateSet& t) {
  PointReductionOptions r = o.reduction;
  r.arcs = writer.has_circ() && o.deflection == DeflectionMode::off;
  if (point_reduction_problem(r).empty() && r.tolerance_mm > 0.0) {
    r.tolerance_mm = path_budget_mm(r.tolerance_mm, t.position_decimals);
    r.axis_tolerance_deg = axis_budget_deg(r.axis_tolerance_deg, t);
  }
  if (writer.has_spl())
    r.tolerance_mm *= kSplineLineShare;
  return r;
}

double PostSession::Impl::cl_arc_tolerance_mm() const {
  return reducer.enabled() ? path_budget_mm(o.chordal_tolerance_mm, templates_position_decimals)
                           : o.chordal_tolerance_mm;
}

PostSession::Impl::Impl(const Cell& c, const KrlTemplateSet& templates, const PostOptions& options)
    : cell(c),
      o(options),
      active_cell(&c),
      tracker(c, options.tracker),
      writer(templates, program_for(c, options, templates)),
      arm(make_arm_status_model(c)),
      spin_last(last_pure_spin(c)),
      templates_position_decimals(templates.position_decimals),
      program_memory_bytes(templates.program_memory_bytes),
      front(options.source_name, expander_options(options),
            [this](const std::string& w) {
              // Run apart (PostSession::front): among the items, taken in order.
              if (front_sink) {
                front_sink->push_back(PostSession::FrontItem{ClEvent{}, w, true});
                return;
              }
              // Under the pipeline the summary is the tracking thread's: the warning waits for
              // the next batch, or for the tracking to catch up (take_front_warnings).
              (stage ? front_warnings : summary.warnings).push_back(w);
            }),
      reducer(session_reduction(options, writer, templates)) {
  if (const std::string why = point_reduction_problem(o.reduction); !why.empty())
    throw Error(ErrorCode::bad_input, why);
  if (!std::isfinite(o.rapid_velocity_m_per_s) || !(o.rapid_velocity_m_per_s > 0.0) ||
      o.rapid_velocity_m_per_s > 2.0) {
    throw Error(ErrorCode::bad_input,
                fmt::format("the rapid velocity must be > 0 and at most 2 m/s, got {}",
                            o.rapid_velocity_m_per_s));
  }
  if (!std::isnan(o.clearance_z_mm) && !std::isfinite(o.clearance_z_mm)) {
    throw Error(ErrorCode::bad_input, "the clearance height must be a finite number of mm");
  }
  if (!std::isfinite(o.deflection_tolerance_mm) || !(o.deflection_tolerance_mm > 0.0)) {
    throw Error(ErrorCode::bad_input,
                fmt::format("the deflection tolerance must be a finite number of mm above 0, "
                            "got {}",
                            o.deflection_tolerance_mm));
  }
  check_deflection_inputs();
  summary.deflection_mode = o.deflection;
  summary.deflection_tolerance_mm = o.deflection_tolerance_mm;
  summary.joints.assign(static_cast<size_t>(c.size()), JointRange{});
  for (JointRange& r : summary.joints) {
    r.lowest = r.margin_lower = r.margin_upper = std::numeric_limits<double>::infinity();
    r.highest = -std::numeric_limits<double>::infinity();
  }
  if (!o.joints_csv_path.empty()) {
    csv = std::make_unique<PendingFile>(o.joints_csv_path);
    line.clear();
    fmt::format_to(std::back_inserter(line), "pose,cl_line,time_s");
    for (int i = 0; i < c.size(); ++i)
      fmt::format_to(std::back_inserter(line), ",{}", c.joint(i).name);
    for (int i = 0; i < c.size(); ++i) {
      if (c.joint(i).axis.mapped()) {
        fmt::format_to(std::back_inserter(line), ",{}", axis_name(c.joint(i).axis));
      }
    }
    // With the deflection model, each motion's predicted deflection (docs/deflection.md).
    if (o.deflection != DeflectionMode::off) {
      fmt::format_to(std::back_inserter(line),
                     ",deflection_x_mm,deflection_y_mm,deflection_z_mm,deflection_normal_mm,"
                     "cutting_force_N,compensation_mm,residual_mm");
    }
    // With the point reduction, the first CL line each motion covers (cl_line is the last).
    if (reducer.enabled())
      fmt::format_to(std::back_inserter(line), ",cl_first_line");
    // With the collision check, each motion's least clearance (docs/collision.md).
    if (o.collision.check)
      fmt::format_to(std::back_inserter(line), ",clearance_mm");
    line.push_back('\n');
    csv->write(line);
  }
  // A SPLINE block's segments stray from their chords by at most the writer's tolerance at the
  // TCP (krl/spline_model.hpp); the arm's bodies are given twenty times that (docs/collision.md).
  spline_allowance_mm =
      templates.spline ? 20.0 * program_for(c, o, templates).spline_tolerance_mm : 0.0;
  start_collision();
  start_timing(templates);
}

PostSession::PostSession(const Cell& cell, const KrlTemplateSet& templates,
                         const PostOptions& options)
    : impl_(std::make_unique<Impl>(cell, templates, options)) {}

PostSession::~PostSession() = default;

namespace {
// True on a thread while it tracks the calls a plan released (the session's own thread in
// serial, the DispatchStage's thread in the pipeline): those calls are not deferred again.
thread_local bool t_dispatching = false;

struct DispatchingScope {
  DispatchingScope() { t_dispatching = true; }
  ~DispatchingScope() { t_dispatching = false; }
  DispatchingScope(const DispatchingScope&) = delete;
  DispatchingScope& operator=(const DispatchingScope&) = delete;
};
}  // namespace

bool PostSession::defer(const ClEvent& e) {
  Impl& m = *impl_;
  if (!m.planning() || t_dispatching)
    return false;
  // A bad motion is refused by the call that brings it, as without the plan.
  if (e.kind == ClEventKind::move || e.kind == ClEventKind::arc) {
    const SourceLocation at{m.o.source_name, e.line, 0};
    if (!e.p_mm.allFinite() || !e.tool_axis.allFinite() ||
        (e.kind == ClEventKind::arc &&
         (!e.arc_centre_mm.allFinite() || !e.arc_axis.allFinite() || !std::isfinite(e.value)))) {
      throw Error(ErrorCode::bad_input,
                  e.kind == ClEventKind::arc
                      ? "a circular move with a coordinate that is not a finite number"
                      : "a move with a coordinate that is not a finite number",
                  at);
    }
    if (!(e.tool_axis.norm() > 1e-9))
      throw Error(ErrorCode::bad_input, "a move with a tool axis of zero length", at);
    // As motion.cpp's circular_move refuses them when the arc is tracked (issue 48: the plan
    // buffered the arc, and the call that brought it returned RP_OK).
    if (e.kind == ClEventKind::arc && !(e.arc_axis.norm() > 1e-9))
      throw Error(ErrorCode::bad_input, "a circular move with an axis of zero length", at);
    if (e.kind == ClEventKind::arc && e.value < 0.0) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("a circular move with a negative radius {} mm", e.value), at);
    }
    if (e.p_mm.cwiseAbs().maxCoeff() > kMaxCoordinateMm ||
        (e.kind == ClEventKind::arc && (e.arc_centre_mm.cwiseAbs().maxCoeff() > kMaxCoordinateMm ||
                                        e.value > kMaxCoordinateMm))) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("a move to a coordinate beyond {:g} mm (the CL reader's bound): "
                              "check the units and the values",
                              kMaxCoordinateMm),
                  at);
    }
  }
  m.deferred.push_back(e);
  if (e.kind == ClEventKind::move || e.kind == ClEventKind::arc) {
    if (e.p_mm.allFinite() && m.deferred_tail.allFinite())
      m.deferred_length_mm += (e.p_mm - m.deferred_tail).norm();
    if (e.p_mm.allFinite())
      m.deferred_tail = e.p_mm;
  } else if (e.kind == ClEventKind::tool_change) {
    m.deferred_barrier = true;
  }
  // Only when a window may be complete: the planner walks the whole buffer.
  if (m.deferred_barrier || m.deferred_length_mm >= m.window_mm() || m.deferred.size() >= 20000)
    pump(false);
  return true;
}

// Tracks and writes the calls of a batch, after what the plan does before them.
void PostSession::dispatch(PlanBatch& batch) {
  Impl& m = *impl_;
  const DispatchingScope scope;
  m.apply_plan(batch);
  for (std::size_t k = 0; k < batch.calls.size(); ++k) {
    route(batch.calls[k]);
    if (k < batch.end_s.size() && !std::isnan(batch.end_s[k]))
      m.plan_s = batch.end_s[k];
  }
}

void PostSession::pump(bool flush) {
  Impl& m = *impl_;
  // With two threads or more, the tracking and writing go to a thread of their own; the
  // planning threads are the rest (planner_for_active).
  if (!m.stage && resolved_threads(m.o.plan_threads) >= 2) {
    if (!m.plan_pool)
      m.plan_pool = std::make_unique<WorkerPool>(resolved_threads(m.o.plan_threads) - 1);
    m.stage = std::make_unique<DispatchStage<PlanBatch>>([this](PlanBatch& b) { dispatch(b); });
  }
  PlanBatch batch;
  while (!m.deferred.empty()) {
    if (!m.plan_window(flush, batch))
      return;
    m.advance_cursor(batch);
    const bool released = !batch.calls.empty();
    // What the reading warned of since the last batch comes before it, as in the serial
    // session, which warned at once.
    batch.front_warnings.swap(m.front_warnings);
    if (m.stage)
      m.stage->push(std::move(batch));
    else
      dispatch(batch);
    if (!released)
      return;
    // The estimate again, over what is left.
    m.deferred_length_mm = 0.0;
    m.deferred_barrier = false;
    m.deferred_tail = m.cursor.cl_point;
    for (const ClEvent& e : m.deferred) {
      if ((e.kind == ClEventKind::move || e.kind == ClEventKind::arc) && e.p_mm.allFinite()) {
        m.deferred_length_mm += (e.p_mm - m.deferred_tail).norm();
        m.deferred_tail = e.p_mm;
      }
      m.deferred_barrier = m.deferred_barrier || e.kind == ClEventKind::tool_change;
    }
  }
}

// Under the pipeline a call may fail here for its own reason while a call released before it
// fails on the tracking thread: the earlier one is the error, as without the pipeline.
void PostSession::rethrow_earlier() const {
  if (impl_->stage && impl_->stage->drain_quietly())
    impl_->stage->drain();  // throws the tracking thread's error
}

void PostSession::handle(const ClEvent& event) {
  Impl& m = *impl_;
  try {
    m.front.push(event);
    ClEvent e, r;
    while (m.front.next(e)) {
      m.reducer.push(e);
      while (m.reducer.next(r))
        route(r);
    }
  } catch (...) {
    rethrow_earlier();
    throw;
  }
}

void PostSession::front(const ClEvent& event, std::vector<FrontItem>& out) {
  Impl& m = *impl_;
  struct Sink {
    Impl& m;
    Sink(Impl& impl, std::vector<FrontItem>& out) : m(impl) { m.front_sink = &out; }
    ~Sink() { m.front_sink = nullptr; }
    Sink(const Sink&) = delete;
    Sink& operator=(const Sink&) = delete;
  } sink(m, out);
  m.front.push(event);
  ClEvent e, r;
  while (m.front.next(e)) {
    m.reducer.push(e);
    while (m.reducer.next(r))
      out.push_back(FrontItem{std::move(r), {}, false});
  }
}

void PostSession::route_front(const FrontItem& item) {
  Impl& m = *impl_;
  try {
    if (item.is_warning)
      (m.stage ? m.front_warnings : m.summary.warnings).push_back(item.warning);
    else
      route(item.event);
  } catch (...) {
    rethrow_earlier();
    throw;
  }
}

// Each call defers itself under the plan (after the checks it makes at once).
void PostSession::route(const ClEvent& e) {
  switch (e.kind) {
    case ClEventKind::part_name:
      comment("part " + e.text);
      break;
    case ClEventKind::tool_change:
      tool_change(e.tool_number, e.text, e.tool_diameter_mm, e.tool_length_mm, e.line);
      break;
    case ClEventKind::spindle:
      spindle(e.value, e.direction, e.line);
      break;
    case ClEventKind::feed:
      feed(e.value, e.line);
      break;
    case ClEventKind::rapid:
      rapid();
      break;
    case ClEventKind::move: {
      if (defer(e))
        return;
      if (e.rapid)
        rapid();
      ClearancePlane cycle;
      cycle.point = e.clearance_p_mm;
      cycle.normal = e.tool_axis.normalized();
      impl_->move_first_line = e.first_line;
      impl_->move(e.p_mm, e.tool_axis, e.line, e.has_clearance ? &cycle : nullptr);
      impl_->move_first_line = 0;
      break;
    }
    case ClEventKind::coolant:
      coolant(e.flag, e.text);
      break;
    case ClEventKind::operation_start:
      operation_start(e.text);
      break;
    case ClEventKind::operation_end:
      operation_end();
      break;
    case ClEventKind::comment:
      comment(e.text);
      break;
    case ClEventKind::literal:
      literal(e.text, e.line);
      break;
    case ClEventKind::dwell:
      dwell(e.value, e.line);
      break;
    case ClEventKind::arc:
      if (defer(e))
        return;
      if (e.rapid)
        rapid();
      // An arc the point reduction fitted through CL points keeps the reducer's other half of
      // the tolerance; a CIRCLE the chordal tolerance (cl_arc_tolerance_mm).
      impl_->move_first_line = e.first_line;
      impl_->circular_move(e.arc_centre_mm, e.arc_axis, e.value, e.p_mm, e.tool_axis, e.line,
                           e.origin == MoveOrigin::fitted_arc ? impl_->reducer.arc_tolerance_mm()
                                                              : impl_->cl_arc_tolerance_mm());
      impl_->move_first_line = 0;
      break;
    case ClEventKind::machine_frame:
      machine_frame(e.tool_axis, e.flag, e.line);
      break;
    case ClEventKind::unknown_word:
    case ClEventKind::end_of_program:
      break;
    case ClEventKind::cycle:
    case ClEventKind::cycle_on:
    case ClEventKind::cycle_off:
    case ClEventKind::hole:
    case ClEventKind::nurbs:
    case ClEventKind::msys:
    case ClEventKind::operator_text:
    case ClEventKind::cutcom:
      // Toolpath events: the expander has turned them into the plain events above.
      throw Error(ErrorCode::internal, "a toolpath event reached the session unexpanded");
  }
}

void PostSession::tool_change(int number, const std::string& name, double diameter_mm,
                              double length_mm, int cl_line) {
  ClEvent e;
  e.kind = ClEventKind::tool_change;
  e.tool_number = number;
  e.text = name;
  e.tool_diameter_mm = diameter_mm;
  e.tool_length_mm = length_mm;
  e.line = cl_line;
  if (defer(e))
    return;
  impl_->tool_diameter_mm = diameter_mm;
  impl_->tool_change(number, name, length_mm, cl_line);
}

void PostSession::dwell(double seconds, int cl_line) {
  if (!std::isfinite(seconds) || seconds < 0.0 || seconds > kMaxDwellSeconds) {
    throw Error(
        ErrorCode::bad_input,
        fmt::format("a dwell of {} s: it must be 0 to {:g} seconds", seconds, kMaxDwellSeconds),
        SourceLocation{impl_->o.source_name, cl_line, 0});
  }
  ClEvent e;
  e.kind = ClEventKind::dwell;
  e.value = seconds;
  e.line = cl_line;
  if (defer(e))
    return;
  impl_->writer.dwell(seconds);
  impl_->timing_stop(seconds);
}

void PostSession::machine_frame(const Eigen::Vector3d& z_mcs_in_absolute, bool applied,
                                int cl_line) {
  ClEvent e;
  e.kind = ClEventKind::machine_frame;
  e.tool_axis = z_mcs_in_absolute;
  e.flag = applied;
  e.line = cl_line;
  if (defer(e))
    return;
  impl_->msys_line = cl_line;
  impl_->msys_applied = applied;
  impl_->msys_z = z_mcs_in_absolute;
}

void PostSession::spindle(double rpm, SpindleDirection direction, int cl_line) {
  if (!std::isfinite(rpm) || rpm < 0.0) {
    throw Error(ErrorCode::bad_input, fmt::format("spindle speed {} rpm is not valid", rpm),
                SourceLocation{impl_->o.source_name, cl_line, 0});
  }
  if (rpm > kMaxSpindleRpm) {
    throw Error(ErrorCode::bad_input,
                fmt::format("spindle speed {} rpm is beyond {:g} rpm: is it a surface speed or "
                            "in other units? Give the spindle's rpm",
                            rpm, kMaxSpindleRpm),
                SourceLocation{impl_->o.source_name, cl_line, 0});
  }
  ClEvent e;
  e.kind = ClEventKind::spindle;
  e.line = cl_line;
  e.value = rpm;
  e.direction = direction;
  if (defer(e))
    return;
  impl_->writer.spindle(direction == SpindleDirection::off ? 0.0 : rpm,
                        direction != SpindleDirection::counter_clockwise);
  Impl& m = *impl_;
  if (direction == SpindleDirection::off || rpm == 0.0) {
    m.spindle_state = Impl::Spindle::off;
  } else {
    m.spindle_state = Impl::Spindle::on;
    m.spindle_rpm = rpm;
    m.spindle_cw = direction != SpindleDirection::counter_clockwise;
  }
}

void PostSession::feed(double mm_per_min, int cl_line) {
  const SourceLocation at{impl_->o.source_name, cl_line, 0};
  if (!std::isfinite(mm_per_min) || !(mm_per_min > 0.0))
    throw Error(ErrorCode::bad_input, fmt::format("feed {} mm/min is not valid", mm_per_min), at);
  // What `redpost check` accepts of a $VEL.CP (krl/check.hpp), and what prints as more than 0.
  const double m_per_s = mm_per_min / 60000.0;
  const double smallest = 0.5 * std::pow(10.0, -impl_->velocity_decimals);
  if (m_per_s > kKrlMaxVelCp) {
    throw Error(ErrorCode::bad_input,
                fmt::format("feed {:g} mm/min is {:g} m/s: $VEL.CP takes at most {:g} m/s "
                            "({:g} mm/min); check the feed's unit (MMPM, IPM)",
                            mm_per_min, m_per_s, kKrlMaxVelCp, 60000.0 * kKrlMaxVelCp),
                at);
  }
  if (m_per_s < smallest) {
    throw Error(ErrorCode::bad_input,
                fmt::format("feed {:g} mm/min would be written as $VEL.CP = 0 at the template "
                            "set's {} decimals (at least {:g} mm/min); check the feed's unit",
                            mm_per_min, impl_->velocity_decimals, 60000.0 * smallest),
                at);
  }
  ClEvent e;
  e.kind = ClEventKind::feed;
  e.value = mm_per_min;
  if (defer(e))
    return;
  impl_->feed_mm_per_min = mm_per_min;
}

void PostSession::rapid() {
  ClEvent e;
  e.kind = ClEventKind::rapid;
  if (defer(e))
    return;
  impl_->next_rapid = true;
}

void PostSession::move(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& tool_axis, int cl_line) {
  ClEvent e;
  e.kind = ClEventKind::move;
  e.p_mm = p_mm;
  e.tool_axis = tool_axis;
  e.line = cl_line;
  if (defer(e))
    return;
  impl_->move(p_mm, tool_axis, cl_line, nullptr);
}

void PostSession::circular_move(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis,
                                double radius_mm, const Eigen::Vector3d& p_mm,
                                const Eigen::Vector3d& tool_axis, int cl_line) {
  ClEvent e;
  e.kind = ClEventKind::arc;
  e.arc_centre_mm = centre;
  e.arc_axis = axis;
  e.value = radius_mm;
  e.p_mm = p_mm;
  e.tool_axis = tool_axis;
  e.line = cl_line;
  if (defer(e))
    return;
  impl_->circular_move(centre, axis, radius_mm, p_mm, tool_axis, cl_line,
                       impl_->cl_arc_tolerance_mm());
}

void PostSession::coolant(bool on, const std::string& mode) {
  ClEvent e;
  e.kind = ClEventKind::coolant;
  e.flag = on;
  e.text = mode;
  if (defer(e))
    return;
  impl_->writer.coolant(on, mode);
}
void PostSession::operation_start(const std::string& name) {
  ClEvent e;
  e.kind = ClEventKind::operation_start;
  e.text = name;
  if (defer(e))
    return;
  impl_->writer.comment("operation " + name);
  impl_->operation_name = name;
  ++impl_->operation_serial;
}
void PostSession::operation_end() {
  ClEvent e;
  e.kind = ClEventKind::operation_end;
  if (defer(e))
    return;
  // Moves after END-OF-PATH belong to no operation (the deflection's figures per operation).
  impl_->operation_name.clear();
  ++impl_->operation_serial;
}
void PostSession::comment(const std::string& text) {
  ClEvent e;
  e.kind = ClEventKind::comment;
  e.text = text;
  if (defer(e))
    return;
  impl_->writer.comment(text);
}
void PostSession::literal(const std::string& text, int cl_line) {
  // Code passed through (INSERT/KRL:, rp_literal, the NX insert event) must be a statement a
  // controller accepts and redpost check reads: refused with its line otherwise.
  if (const std::string why = krl::statement_problem(text); !why.empty()) {
    // Control bytes are shown escaped: a CR printed as it is would take the terminal's cursor
    // back over the message's file:line.
    std::string shown;
    for (char c : text.substr(0, 200)) {
      const auto u = static_cast<unsigned char>(c);
      shown += (u < 0x20 || u == 0x7f) ? fmt::format("\\x{:02X}", u) : std::string(1, c);
    }
    if (text.size() > 200)
      shown += "...";
    throw Error(ErrorCode::bad_input, "'" + shown + "' cannot be passed to the KRL program: " + why,
                SourceLocation{impl_->o.source_name, cl_line, 0});
  }
  ClEvent e;
  e.kind = ClEventKind::literal;
  e.text = text;
  e.line = cl_line;
  if (defer(e))
    return;
  impl_->writer.literal(text);
  // A statement passed through may stop the advance (WAIT, HALT, a call): timed as a stop.
  impl_->timing_stop(0.0);
}

void PostSession::Impl::warn_about_parts() {
  const KrlSplitReport& split = writer.split();
  if (split.mid_cut > 0) {
    std::string lines;
    for (std::size_t i = 0; i < split.mid_cut_lines.size(); ++i)
      lines += fmt::format("{}{}", i > 0 ? ", " : "", split.mid_cut_lines[i]);
    // With the set's continued_src the part after such a boundary continues the cut, blended
    // (KrlWriter: end_part); without one it starts with the BCO run's exact-stop PTP.
    const std::string after =
        split.continued == split.mid_cut
            ? "the part after each continues the cut without a stop (blended across the call: it "
              "has no INI fold and no BCO run, and runs only after the part before it)"
            : "the next part starts there with an exact-stop PTP, which may mark the surface (the "
              "template set has no continued_src file)";
    // --split N ends a part after every N motions, wherever the tool is.
    const bool by_count = o.program.motions_per_file > 0;
    summary.warnings.push_back(fmt::format(
        "{}: {} of the {} part boundaries fall where the tool may be in the material (after CL "
        "line {}{}): {}, so {}; {} (docs/krl-templates.md, \"Splitting\")",
        o.source_name, split.mid_cut, split.parts - 1, lines,
        split.mid_cut > static_cast<long>(split.mid_cut_lines.size()) ? ", ..." : "",
        by_count ? fmt::format("--split {} ends a part after every {} motions",
                               o.program.motions_per_file, o.program.motions_per_file)
                 : "no rapid or approach came in the last quarter of the part's byte budget",
        after,
        by_count ? "leave --split out to split by bytes at rapids"
                 : "let the CAM system retract more often, or raise --max-bytes"));
  }
  if (program_memory_bytes > 0 && split.program_bytes > program_memory_bytes) {
    summary.warnings.push_back(fmt::format(
        "{}: the program's files take {} bytes, more than the {} bytes of program memory the "
        "template set gives the controller (<limits program-memory>): it cannot be loaded at "
        "once; copy its parts to the controller one at a time (docs/krl-templates.md, "
        "\"Splitting\")",
        o.source_name, split.program_bytes, program_memory_bytes));
  }
}

const PostSummary& PostSession::prepare() {
  Impl& m = *impl_;
  if (m.prepared)
    return m.summary;
  try {
    // The last run of the point reduction.
    m.reducer.finish();
    for (ClEvent r; m.reducer.next(r);)
      route(r);
    pump(true);
    if (m.stage) {
      m.stage->drain();
      m.stage.reset();
    }
    m.take_front_warnings();
  } catch (...) {
    rethrow_earlier();
    throw;
  }
  m.summary.reducible_points = m.reducer.moves_in();
  m.summary.reduced_moves = m.reducer.moves_out();
  m.summary.reduced_arcs = m.reducer.arcs_out();
  if (!m.started) {
    throw Error(ErrorCode::bad_input, "the toolpath has no move: nothing to write",
                SourceLocation{m.o.source_name, 0, 0});
  }
  // The last segment of an open SPLINE block is written before the time model's last motions
  // are: whether it runs at the motion rate is known then (on_timed).
  m.writer.end_block();
  m.finish_timing();
  for (DeflectionStats& d : m.summary.deflection) {
    d.rms_mm = std::sqrt(d.rms_mm / static_cast<double>(d.motions));
    d.rms_normal_mm = std::sqrt(d.rms_normal_mm / static_cast<double>(d.motions));
  }
  if (m.csv)
    m.csv->prepare();
  m.writer.prepare();
  m.warn_about_parts();
  m.prepared = true;
  return m.summary;
}

const PostSummary& PostSession::finish() {
  Impl& m = *impl_;
  prepare();
  // The joints log first: if the program cannot be completed after it, the log is complete and
  // correct, whereas a program without its log would be the worse half to leave behind.
  if (m.csv) {
    m.csv->commit();
    m.csv.reset();  // committed: nothing left to remove, and a second finish() cannot touch it
  }
  m.summary.files = m.writer.finish();
  return m.summary;
}

void PostSession::set_motion_observer(MotionObserver observer) {
  // The tracking thread of the pipeline calls it: not while it runs.
  if (impl_->stage)
    impl_->stage->drain_quietly();
  impl_->o.on_motion = std::move(observer);
}

// Both wait for the tracking thread of the pipeline (if any) to have caught up.
const PoseResult& PostSession::last_pose() const {
  if (impl_->stage)
    impl_->stage->drain_quietly();
  return impl_->last;
}
const PostSummary& PostSession::summary() const {
  if (impl_->stage && !impl_->stage->drain_quietly())
    impl_->take_front_warnings();
  return impl_->summary;
}
const Cell& PostSession::cell() const {
  return impl_->cell;
}

}  // namespace redpost
