// The written motions against the axes' speed limits, and their time (docs/timing.md).
//
// Every LIN is written at the lowest of the speed it is asked (the CL feed, or the rapid speed)
// and the path speed at which its fastest axis reaches its velocity limit (with 2 % to spare for
// the printed decimals); where that is lower, $VEL.CP is written lower for that motion and the
// stretch is reported. The axis rates come from the controller's own interpolation where the
// tracker took several steps along the move: the TCP on the straight line, the external axes
// linear, the arm solved in closed form for the start's posture (lin_replay). Every written
// motion then goes to the PathTimer; its joints-log row and observer sample are made once it is
// timed.
#include <algorithm>
#include <cmath>

#include "post/session_impl.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/tool_axis.hpp"
#include "redpost/krl/motion_rate.hpp"
#include "redpost/timing/timed_motion.hpp"

namespace redpost {

namespace {

// Headroom under an axis's velocity limit when $VEL.CP is lowered: the written positions are
// rounded, so a check from the printed program sees slightly different lengths.
constexpr double kSpeedMargin = 0.98;
// Warnings for slowed stretches; the rest are counted (every stretch is in the summary).
constexpr int kMaxSlowdownWarnings = 20;
constexpr std::size_t kMaxFeedLimits = 1000;
// A stretch is reported where an axis keeps the speed this far below the ask.
constexpr double kReportBelow = 0.95;

// How far the controller's LIN from T0 to T1 turns the tool axis (z of the TCP) off the great
// circle between the two axes (rad), the largest of 32 samples. A KUKA LIN turns the whole frame
// (the quaternion slerp of the standard orientation control, as lin_replay replays it); where
// the spin about the tool changes along with the axis, the axis leaves its great circle, by
// about turn x spin / 8 in the middle. The point reduction judged the dropped points against the
// great circle (cl/point_reduction.hpp), so a merged LIN must stay close to it.
double axis_off_great_circle(const Isometry& T0, const Isometry& T1) {
  const Eigen::Quaterniond r0(T0.linear()), r1(T1.linear());
  const Eigen::Vector3d z0 = T0.linear().col(2), z1 = T1.linear().col(2);
  double worst = 0.0;
  for (int k = 1; k < 32; ++k) {
    const double s = k / 32.0;
    const Eigen::Vector3d z = r0.slerp(s, r1).toRotationMatrix().col(2);
    worst = std::max(worst, angle_between(z, slerp_axis(z0, z1, s)));
  }
  return worst;
}

std::string axis_words(const Cell& cell, int joint) {
  if (joint < 0)
    return "an axis";
  const Joint& j = cell.joint(joint);
  return j.axis.mapped() ? axis_name(j.axis) + " ('" + j.name + "')" : "'" + j.name + "'";
}

}  // namespace

void PostSession::Impl::start_timing(const KrlTemplateSet& templates) {
  ControllerTiming c;
  c.path_acceleration_mm_s2 = templates.timing.path_acceleration_m_s2 * 1000.0;
  c.orientation_velocity_rad_s = deg_to_rad(templates.timing.orientation_velocity_deg_s);
  c.ptp_velocity_fraction = templates.timing.ptp_velocity_percent / 100.0;
  c.ptp_acceleration_fraction = templates.timing.ptp_acceleration_percent / 100.0;
  c.interpolation_cycle_s = templates.timing.interpolation_cycle_ms / 1000.0;
  // A SPLINE block is planned whole: its motions see to the block's end (at most its size).
  c.lookahead_motions = templates.spline
                            ? std::max(templates.max_spline_points, templates.timing.advance)
                            : templates.timing.advance;
  controller_timing = c;
  orientation_velocity_rad_s = c.orientation_velocity_rad_s;
  ptp_velocity_fraction = c.ptp_velocity_fraction;
  ptp_acceleration_fraction = c.ptp_acceleration_fraction;
  velocity_decimals = templates.velocity_decimals;
  // The motion rate in $VEL.CP goes with the point reduction (--fit-tol 0 writes 0.7's program),
  // and not in SPLINE blocks, which a $VEL.CP ends and which the controller plans whole.
  rate_vel = reducer.enabled() && !templates.spline && c.interpolation_cycle_s > 0.0;
  apo_mm = o.program.apo_mm;
  summary.axis_speeds_known = cell.has_axis_speeds();
  summary.interpolation_cycle_s = c.interpolation_cycle_s;
  timer = std::make_unique<PathTimer>(
      cell, c, [this](const TimedMotion& t, const MotionTiming& mt) { on_timed(t, mt); });
  if (!summary.axis_speeds_known) {
    summary.warnings.push_back(fmt::format(
        "the cell {} gives no axis speeds (<speed> in its joints): the axes' velocity limits "
        "are not checked and the cycle time assumes every feed is reached (docs/timing.md)",
        cell.source_file.empty() ? cell.name : cell.source_file));
  }
}

void PostSession::Impl::set_speed(double m_per_s, bool is_feed) {
  asked_m_per_s = m_per_s;
  asked_is_feed = is_feed;
}

void PostSession::Impl::remember_written(const JointVector& q, const Isometry& T_B) {
  q_written = q;
  T_written = T_B;
  have_written = true;
}

// A CP motion from (q0, T0) to (q1, T1) along `length_mm` of TCP path, at the asked speed.
TimedMotion PostSession::Impl::timed_cp(const JointVector& q0, const Isometry& T0,
                                        const JointVector& q1, const Isometry& T1, double length_mm,
                                        int cl_line, const JointVector* replay_peak) {
  TimedMotion t = cp_motion(cell, q0, T0, q1, T1, length_mm, asked_m_per_s * 1000.0,
                            orientation_velocity_rad_s, apo_mm);
  t.cl_line = cl_line;
  t.at_feed = asked_is_feed;
  if (t.length_mm > 0.0 && replay_peak)
    t.peak_rate = t.peak_rate.cwiseMax(*replay_peak);
  // $VEL.CP: the asked speed, or lower where an axis would exceed its velocity limit.
  int joint = -1;
  const double cap = PathTimer::velocity_cap(cell, t.peak_rate, &joint);
  t.command_mm_s = t.asked_mm_s;
  if (cap < t.asked_mm_s) {
    const double scale = std::pow(10.0, velocity_decimals);
    // Rounded down to the printed decimals (in m/s), never to zero.
    const double m_per_s =
        std::max(std::floor(cap * kSpeedMargin / 1000.0 * scale) / scale, 1.0 / scale);
    t.command_mm_s = m_per_s * 1000.0;
    t.command_joint = joint;
  }
  // The controller's clock: with the point reduction on, a motion that would still last less
  // than one interpolation cycle at its speed (a short arc, a lead-in, a dense stretch the
  // tolerance keeps) is written at the speed at which it lasts one, as the controller would run
  // it anyway (docs/timing.md, "Point reduction"). Its length is taken short by what the printed
  // decimals may take off both ends, so that a check from the written text finds a cycle too.
  if (rate_vel && length_mm > 1e-6) {
    const double m_per_s = krl_cycle_velocity(
        length_mm, std::min(t.command_mm_s, t.orientation_cap_mm_s) / 1000.0,
        summary.interpolation_cycle_s, templates_position_decimals, velocity_decimals);
    if (m_per_s * 1000.0 < t.command_mm_s) {
      t.command_mm_s = m_per_s * 1000.0;
      t.command_joint = TimedMotion::kMotionRate;
    }
  }
  return t;
}

// The synchronous PTP from the last written posture to q1 at the set's share of the limits.
TimedMotion PostSession::Impl::timed_ptp(const JointVector& q1, int cl_line) {
  if (!have_written) {
    // From wherever the robot stands: not timed (docs/timing.md).
    TimedMotion t = synchronous_ptp(cell, q1, q1, ControllerTiming{});
    t.cl_line = cl_line;
    return t;
  }
  TimedMotion t = synchronous_ptp(cell, q_written, q1, controller_timing);
  t.cl_line = cl_line;
  return t;
}

namespace detail {

bool replay_sample(const ArmIk& ik, const Isometry& T, const JointVector& q_other, int status,
                   double s, double ds, const char* what, JointVector& q_prev,
                   JointVector& peak_rate, std::string& why) {
  // Only the posture kept: the same solution as the full solve's (test_arm_ik), without the
  // seven others' round trips.
  const ArmIkSolutions sol = ik.solve(T, q_other, &q_prev, status);
  if (!sol.valid[static_cast<size_t>(status)]) {
    why = fmt::format("at {:.0f} % of the {} the arm cannot keep its posture within the limits",
                      100.0 * s, what);
    return false;
  }
  const JointVector& q = sol.q[static_cast<size_t>(status)];
  for (int m = 0; m < 6; ++m) {
    const int i = ik.arm_joints()[static_cast<size_t>(m)];
    if (std::fabs(q[i] - q_prev[i]) > deg_to_rad(10.0)) {
      why = fmt::format("A{} would jump by {:.1f} deg at {:.0f} % of the {}", m + 1,
                        rad_to_deg(std::fabs(q[i] - q_prev[i])), 100.0 * s, what);
      return false;
    }
    if (ds > 0.0)
      peak_rate[i] = std::max(peak_rate[i], std::fabs(q[i] - q_prev[i]) / ds);
  }
  q_prev = q;
  return true;
}

bool replay_ends_at(const ArmIk& ik, const JointVector& q_end, const JointVector& q1,
                    const char* what, std::string& why) {
  for (int m = 0; m < 6; ++m) {
    const int i = ik.arm_joints()[static_cast<size_t>(m)];
    if (std::fabs(q_end[i] - q1[i]) > deg_to_rad(0.01)) {
      why = fmt::format(
          "the controller would end the {} with A{} {:.3f} deg from the tracked "
          "posture",
          what, m + 1, rad_to_deg(std::fabs(q_end[i] - q1[i])));
      return false;
    }
  }
  return true;
}

}  // namespace detail

// Replays the controller's LIN from (q0, T0) to (q1, T1): the TCP on the straight line with
// the orientation turned at the same pace, the external axes linear, the arm in closed form for
// the start's posture. Fills the largest |dq/ds| of every joint; false (with why) if the arm
// leaves its limits, jumps, or ends elsewhere than q1.
bool PostSession::Impl::lin_replay(const JointVector& q0, const Isometry& T0, const JointVector& q1,
                                   const Isometry& T1, JointVector& peak_rate, double length_mm,
                                   std::string& why) {
  const ArmIk* ik = arm_ik_for_active(why);
  if (!ik)
    return false;
  const double turn = rotation_angle(T0.linear(), T1.linear());
  const int samples = std::clamp(
      static_cast<int>(std::ceil(std::max(length_mm / 1.0, rad_to_deg(turn) / 0.5))), 2, 20000);
  const double ds = length_mm / samples;
  const Eigen::Quaterniond r0(T0.linear()), r1(T1.linear());
  const int status = status_turn(*active_cell, ik->status_model(), q0).status;
  JointVector q_prev = q0, q_other = q0;
  peak_rate.setZero(active_cell->size());
  for (int k = 1; k <= samples; ++k) {
    const double s = static_cast<double>(k) / samples;
    for (int i = 0; i < active_cell->size(); ++i) {
      const Joint& j = active_cell->joint(i);
      q_other[i] = j.type == JointType::virtual_spin ? 0.0 : q0[i] + s * (q1[i] - q0[i]);
    }
    Isometry T = Isometry::Identity();
    T.linear() = r0.slerp(s, r1).toRotationMatrix();
    T.translation() = (1.0 - s) * T0.translation() + s * T1.translation();
    if (!detail::replay_sample(*ik, T, q_other, status, s, ds, "line", q_prev, peak_rate, why))
      return false;
  }
  if (!detail::replay_ends_at(*ik, q_prev, q1, "line", why))
    return false;
  // The external axes move linearly: their rate is the chord's.
  return true;
}

void PostSession::Impl::emit_line(int cl_line) {
  const JointVector q1 = tracker.q();
  if (line_steps.size() > 1 && have_written) {
    // The tracker took several steps: prove the controller's one straight line, or write them.
    const KrlMotion end = motion_at(KrlMotionKind::lin, q1, cl_line);
    const Isometry T1 = o.T_B_base * end.T_base_tcp;
    const double length = (T1.translation() - T_written.translation()).norm();
    JointVector peak;
    std::string why;
    // A LIN that stands for several CL points (the point reduction), whose orientation would
    // carry the tool axis off its great circle by more than the half of the angular tolerance
    // the reduction leaves for it, is written as the steps tracked (each on the line, its axis
    // on the circle): expected, so no warning.
    const bool axis_ok = move_first_line == 0 || axis_off_great_circle(T_written, T1) <=
                                                     reducer.controller_axis_budget_rad();
    if (axis_ok && lin_replay(q_written, T_written, q1, T1, peak, length, why)) {
      write_lin(q1, cl_line, &peak);
      return;
    }
    if (axis_ok && unproven_lines++ < 20) {
      summary.warnings.push_back(fmt::format(
          "{}:{}: written as {} shorter LINs, the steps tracked along it: the controller's one "
          "straight line cannot be proven ({})",
          o.source_name, cl_line, line_steps.size(), why));
    }
    const std::vector<JointVector> steps = line_steps;
    for (std::size_t k = 0; k + 1 < steps.size(); ++k)
      write_lin(steps[k], cl_line, nullptr);
  }
  write_lin(q1, cl_line, nullptr);
}

void PostSession::Impl::write_lin(const JointVector& q, int cl_line,
                                  const JointVector* replay_peak) {
  if (std::isnan(asked_m_per_s)) {
    throw Error(ErrorCode::internal, "a LIN without a speed reached the writer",
                SourceLocation{o.source_name, cl_line, 0});
  }
  const KrlMotion m = motion_at(KrlMotionKind::lin, q, cl_line);
  const Isometry T1 = o.T_B_base * m.T_base_tcp;
  TimedMotion t;
  if (have_written) {
    const double length = (T1.translation() - T_written.translation()).norm();
    t = timed_cp(q_written, T_written, q, T1, length, cl_line, replay_peak);
  } else {
    t = timed_cp(q, T1, q, T1, 0.0, cl_line, nullptr);
  }
  check_clearance(KrlMotionKind::lin, q, cl_line);
  writer.velocity(t.command_mm_s / 1000.0);
  writer.motion(m);
  t.entry_smooth = writer.joined_smoothly();
  after_write(m, q, t);
  remember_written(q, T1);
}

void PostSession::Impl::timing_stop(double dwell_s) {
  timer->stop(dwell_s);
}

// A motion has been timed. In a spline set the writer may have written an SLIN alone in its
// block at the motion rate (it knows once the next motion came, before the motion is timed):
// the record is of what the program says.
void PostSession::Impl::on_timed(const TimedMotion& t, const MotionTiming& mt) {
  double vel_m_per_s = 0.0;
  if (t.kind == TimedMotion::Kind::cp && writer.take_rate_segment(t.index, vel_m_per_s)) {
    TimedMotion written = t;
    MotionTiming timing = mt;
    written.command_mm_s = vel_m_per_s * 1000.0;
    written.command_joint = TimedMotion::kMotionRate;
    timing.below_cycle = false;
    record_timed(written, timing);
    return;
  }
  record_timed(t, mt);
}

// A motion as timed: its joints-log row and observer sample, and the summary.
void PostSession::Impl::record_timed(const TimedMotion& t, const MotionTiming& mt) {
  if (pending.empty() || pending.front().index != t.index) {
    throw Error(ErrorCode::internal, "the time model lost track of the written motions");
  }
  const PendingMotion p = std::move(pending.front());
  pending.pop_front();
  const int n = cell.size();
  const bool cp = t.kind == TimedMotion::Kind::cp;
  const double end_s = mt.start_s + mt.duration_s;
  summary.cycle_time_s = end_s + t.dwell_after_s;
  if (cp && t.at_feed && t.asked_mm_s > 0.0) {
    summary.cutting_time_s += mt.duration_s;
    summary.feed_time_s += t.tcp_length_mm / t.asked_mm_s;
  }
  if (cp) {
    ++summary.cp_motions;
    summary.below_cycle_motions += mt.below_cycle ? 1 : 0;
    summary.rate_limited_motions += mt.limit == TimingLimit::motion_rate ? 1 : 0;
    summary.lookahead_limited_motions += mt.limit == TimingLimit::lookahead ? 1 : 0;
    // Its time at the $VEL.CP written (and $VEL.ORI1), as a check of the program computes it.
    const double speed = std::min(t.command_mm_s, t.orientation_cap_mm_s);
    const double at_command = speed > 0.0 ? t.length_mm / speed : 0.0;
    if (t.length_mm > 0.0 && !mt.spline_joined &&
        (summary.shortest_motion_line == 0 || at_command < summary.shortest_motion_s)) {
      summary.shortest_motion_s = at_command;
      summary.shortest_motion_line = t.cl_line;
    }
  }

  // Per joint, the fraction of its velocity limit it reaches.
  fraction.setZero(n);
  double lead = 0.0;
  if (!cp && t.ptp_joint >= 0)
    lead = std::fabs(t.chord_rate[t.ptp_joint]);
  for (int i = 0; i < n; ++i) {
    const Joint& j = cell.joint(i);
    if (!j.has_speed())
      continue;
    fraction[i] = cp           ? std::fabs(t.peak_rate[i]) * mt.peak_mm_s / j.max_velocity
                  : lead > 0.0 ? mt.axis_fraction * (std::fabs(t.chord_rate[i]) / j.max_velocity) /
                                     (lead / cell.joint(t.ptp_joint).max_velocity)
                               : 0.0;
  }
  if (mt.axis_fraction > summary.peak_speed_fraction) {
    summary.peak_speed_fraction = mt.axis_fraction;
    summary.peak_speed_joint = mt.axis_fraction_joint;
    summary.peak_speed_line = t.cl_line;
  }

  // Stretches where $VEL.CP was written lower, and where an axis keeps the speed low.
  if (t.command_joint >= 0) {
    ++summary.slowed_motions;
    if (open_slowdown && open_slowdown->joint != t.command_joint)
      close_slowdown();
    if (!open_slowdown) {
      open_slowdown = FeedLimit{};
      open_slowdown->first_line = t.cl_line;
      open_slowdown->joint = t.command_joint;
      open_slowdown->lowest_mm_per_min = t.command_mm_s * 60.0;
      open_slowdown->asked_mm_per_min = t.asked_mm_s * 60.0;
    }
    open_slowdown->last_line = t.cl_line;
    ++open_slowdown->motions;
    open_slowdown->lowest_mm_per_min =
        std::min(open_slowdown->lowest_mm_per_min, t.command_mm_s * 60.0);
  } else if (open_slowdown) {
    close_slowdown();
  }
  if (t.command_joint == TimedMotion::kMotionRate)
    ++summary.rate_slowed_motions;
  const bool by_axis = cp && mt.peak_mm_s < kReportBelow * t.asked_mm_s &&
                       ((mt.joint >= 0 && (mt.limit == TimingLimit::axis_velocity ||
                                           mt.limit == TimingLimit::axis_acceleration ||
                                           mt.limit == TimingLimit::corner)) ||
                        mt.limit == TimingLimit::motion_rate ||
                        mt.limit == TimingLimit::lookahead || mt.limit == TimingLimit::curvature);
  if (by_axis) {
    const int stretch_joint = mt.limit == TimingLimit::motion_rate ||
                                      mt.limit == TimingLimit::lookahead ||
                                      mt.limit == TimingLimit::curvature
                                  ? -1
                                  : mt.joint;
    if (open_limit && (open_limit->joint != stretch_joint || open_limit->limit != mt.limit))
      close_limit();
    if (!open_limit) {
      open_limit = FeedLimit{};
      open_limit->first_line = t.cl_line;
      open_limit->joint = stretch_joint;
      open_limit->limit = mt.limit;
      open_limit->lowest_mm_per_min = mt.peak_mm_s * 60.0;
      open_limit->asked_mm_per_min = t.asked_mm_s * 60.0;
    }
    open_limit->last_line = t.cl_line;
    ++open_limit->motions;
    open_limit->lowest_mm_per_min = std::min(open_limit->lowest_mm_per_min, mt.peak_mm_s * 60.0);
    open_limit->asked_mm_per_min = std::max(open_limit->asked_mm_per_min, t.asked_mm_s * 60.0);
  } else if (open_limit) {
    close_limit();
  }

  if (csv)
    write_joints_row(p, end_s);
  if (o.on_motion)
    observe(p, t, mt);
}

// The motion's row of the joints log (docs/convert.md, --joints-csv), once it is timed.
void PostSession::Impl::write_joints_row(const PendingMotion& p, double end_s) {
  const int n = cell.size();
  line.clear();
  fmt::format_to(std::back_inserter(line), "{},{},{:.4f}", p.index, p.cl_line, end_s);
  for (int i = 0; i < n; ++i)
    fmt::format_to(std::back_inserter(line), ",{:.9f}", p.q[i]);
  for (int i = 0; i < n; ++i) {
    if (cell.joint(i).axis.mapped())
      fmt::format_to(std::back_inserter(line), ",{:.6f}", to_axis_value(cell.joint(i), p.q[i]));
  }
  if (o.deflection != DeflectionMode::off) {
    // "nan" where no load was modelled (a rapid, a PTP, a plunge, a step inside a move).
    const MotionDeflection& d = p.deflection;
    if (p.has_deflection) {
      fmt::format_to(std::back_inserter(line), ",{:.5f},{:.5f},{:.5f},{:.5f},{:.2f},{:.5f},{:.5f}",
                     d.translation_mm.x(), d.translation_mm.y(), d.translation_mm.z(), d.normal_mm,
                     d.force_N, d.compensation_mm, d.residual_mm);
    } else {
      fmt::format_to(std::back_inserter(line), ",nan,nan,nan,nan,nan,nan,nan");
    }
  }
  if (reducer.enabled())
    fmt::format_to(std::back_inserter(line), ",{}", p.first_line);
  // The least clearance along the motion (docs/collision.md); inf where no pair came within the
  // bound's reach, nan where none was checked.
  if (o.collision.check)
    fmt::format_to(std::back_inserter(line), ",{:.3f}", p.clearance_mm);
  line.push_back('\n');
  csv->write(line);
}

void PostSession::Impl::close_slowdown() {
  const FeedLimit& g = *open_slowdown;
  ++slowdown_groups;
  if (slowdown_warnings < kMaxSlowdownWarnings) {
    ++slowdown_warnings;
    summary.warnings.push_back(fmt::format(
        "{}:{}{}: {} would pass its velocity limit at the asked {:.0f} mm/min: $VEL.CP written "
        "lower on {} motion{} (down to {:.0f} mm/min; docs/timing.md)",
        o.source_name, g.first_line,
        g.last_line != g.first_line ? fmt::format("-{}", g.last_line) : std::string(),
        axis_words(cell, g.joint), g.asked_mm_per_min, g.motions, g.motions == 1 ? "" : "s",
        g.lowest_mm_per_min));
  }
  open_slowdown.reset();
}

void PostSession::Impl::close_limit() {
  ++summary.feed_limits_total;
  if (summary.feed_limits.size() < kMaxFeedLimits)
    summary.feed_limits.push_back(*open_limit);
  open_limit.reset();
}

void PostSession::Impl::finish_timing() {
  timer->finish();
  // A dwell with no motion left to time (after a PTP, a tool change) only advances the clock.
  summary.cycle_time_s = std::max(summary.cycle_time_s, timer->elapsed_s());
  if (open_slowdown)
    close_slowdown();
  if (open_limit)
    close_limit();
  if (slowdown_groups > slowdown_warnings) {
    summary.warnings.push_back(fmt::format(
        "{} more stretches written with a lower $VEL.CP (not listed; {} motions slowed in all)",
        slowdown_groups - slowdown_warnings, summary.slowed_motions));
  }
  if (unproven_lines > 20) {
    summary.warnings.push_back(fmt::format(
        "{} more lines written as their tracked steps (not listed)", unproven_lines - 20));
  }
}

void PostSession::Impl::observe(const PendingMotion& p, const TimedMotion& t,
                                const MotionTiming& mt) {
  MotionSample s;
  s.index = p.index;
  s.kind = p.kind;
  s.cl_line = p.cl_line;
  s.q = &p.q;
  s.axes = &p.axes;
  s.inv_condition = p.inv_condition;
  s.iterations = p.iterations;
  s.feed_mm_per_min = p.feed_mm_per_min;
  s.p_part_mm = p.p_part_mm;
  s.time_s = mt.start_s + mt.duration_s;
  s.duration_s = mt.duration_s;
  s.speed_mm_s = mt.peak_mm_s;
  s.asked_mm_s = t.asked_mm_s;
  s.command_mm_s = t.command_mm_s;
  s.limit = mt.limit;
  s.limit_joint = mt.joint;
  s.speed_fraction = &fraction;
  s.q_plan = p.planned ? &p.q_plan : nullptr;
  s.deflection = p.has_deflection ? &p.deflection : nullptr;
  s.tool_length_mm = p.tool_length_mm;
  s.tcp_shift_mm = p.tcp_shift_mm;
  s.clearance_mm = p.clearance_mm;
  s.clearance_proven_mm = p.clearance_proven_mm;
  s.clearance_pair = p.clearance_pair >= 0 && p.clearance_pair < static_cast<int>(pair_names.size())
                         ? &pair_names[static_cast<std::size_t>(p.clearance_pair)]
                         : nullptr;
  s.clearance_exact = p.clearance_exact;
  s.clearance_point_a = p.clearance_a;
  s.clearance_point_b = p.clearance_b;
  o.on_motion(s);
}

}  // namespace redpost
