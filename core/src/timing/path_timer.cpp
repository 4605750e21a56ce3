#include "redpost/timing/path_timer.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace redpost {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Past this many motions waiting, the front half is timed as if a stop followed: slower than
// the controller, never faster, and memory stays bounded on any program.
constexpr std::size_t kMaxBuffered = 1u << 16;
// Planning runs after this many motions (and at every stop): amortised O(1) per motion.
constexpr std::size_t kPlanEvery = 64;
// "Shorter than a cycle" leaves out motions within 1e-4 of one cycle: a 2 mm step at
// 10 m/min lasts exactly 12 ms, and the printed $VEL.CP's last decimal must not decide.
constexpr double kBelowCycle = 1.0 - 1e-4;

bool same(double a, double b) {
  return a == b || std::fabs(a - b) <= 1e-9 * std::max(std::fabs(a), std::fabs(b));
}

}  // namespace

const char* to_string(TimingLimit limit) {
  switch (limit) {
    case TimingLimit::none:
      return "none";
    case TimingLimit::axis_velocity:
      return "axis velocity";
    case TimingLimit::axis_acceleration:
      return "axis acceleration";
    case TimingLimit::path_acceleration:
      return "path acceleration";
    case TimingLimit::corner:
      return "corner";
    case TimingLimit::orientation:
      return "orientation speed";
    case TimingLimit::stop:
      return "exact stop";
    case TimingLimit::motion_rate:
      return "motion rate";
    case TimingLimit::lookahead:
      return "look-ahead";
    case TimingLimit::curvature:
      return "curvature";
  }
  return "?";
}

PathTimer::PathTimer(const Cell& cell, const ControllerTiming& controller, Callback done)
    : cell_(&cell), controller_(controller), done_(std::move(done)) {
  controller_.lookahead_motions = std::min(controller_.lookahead_motions, kMaxLookaheadMotions);
  if (controller_.lookahead_motions > 0)
    recent_.resize(static_cast<std::size_t>(controller_.lookahead_motions) + 1);
  if (!(controller_.interpolation_cycle_s > 0.0))
    controller_.interpolation_cycle_s = 0.0;
}

double PathTimer::velocity_cap(const Cell& cell, const JointVector& rate, int* joint) {
  double cap = kInf;
  int which = -1;
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    const double r = std::fabs(rate[i]);
    if (!j.has_speed() || !(r > 0.0))
      continue;
    const double v = j.max_velocity / r;
    if (v < cap) {
      cap = v;
      which = i;
    }
  }
  if (joint)
    *joint = which;
  return cap;
}

double PathTimer::acceleration_cap(const Cell& cell, const JointVector& rate, int* joint) {
  double cap = kInf;
  int which = -1;
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    const double r = std::fabs(rate[i]);
    if (!j.has_speed() || !(r > 0.0))
      continue;
    const double a = j.max_acceleration / r;
    if (a < cap) {
      cap = a;
      which = i;
    }
  }
  if (joint)
    *joint = which;
  return cap;
}

double PathTimer::stop_to_stop_s(double distance, double v_max, double a_max) {
  distance = std::fabs(distance);
  if (!(distance > 0.0))
    return 0.0;
  if (!std::isfinite(v_max) || !std::isfinite(a_max))
    return 0.0;  // no limits known: takes no time in the model
  // Triangle when the axis cannot reach v_max within the distance.
  if (distance <= v_max * v_max / a_max)
    return 2.0 * std::sqrt(distance / a_max);
  return distance / v_max + v_max / a_max;
}

double PathTimer::segment_s(double length, double v0, double v1, double v_cap, double a) {
  if (!(length > 0.0))
    return 0.0;
  if (!std::isfinite(a)) {
    return length / v_cap;
  }
  const double peak = std::min(v_cap, std::sqrt(0.5 * (2.0 * a * length + v0 * v0 + v1 * v1)));
  const double up = std::max(0.0, peak - v0) / a, down = std::max(0.0, peak - v1) / a;
  const double d_up = std::max(0.0, peak * peak - v0 * v0) / (2.0 * a);
  const double d_down = std::max(0.0, peak * peak - v1 * v1) / (2.0 * a);
  const double cruise = std::max(0.0, length - d_up - d_down);
  return up + down + (peak > 0.0 ? cruise / peak : 0.0);
}

void PathTimer::push(const TimedMotion& motion) {
  Entry e;
  e.m = motion;
  // Ends not given: a straight motion's, its chord's.
  if (e.m.entry_rate.size() != e.m.chord_rate.size()) {
    e.m.entry_rate = e.m.chord_rate;
    e.m.exit_rate = e.m.chord_rate;
    e.m.exit_tangent = e.m.tangent;
  }
  if (motion.kind == TimedMotion::Kind::cp) {
    int vj = -1;
    const double v_axes = velocity_cap(*cell_, motion.peak_rate, &vj);
    e.cruise = std::min({motion.command_mm_s, motion.orientation_cap_mm_s, v_axes});
    e.accel = std::min(controller_.path_acceleration_mm_s2,
                       acceleration_cap(*cell_, motion.peak_rate, &e.accel_joint));
    if (e.accel >= controller_.path_acceleration_mm_s2)
      e.accel_joint = -1;
    e.cruise_free = e.cruise;
    // The motion block takes at least one interpolation cycle (the controller prepares one
    // block per cycle at most): cruise at most length / cycle. But a segment that joins the one
    // before it smoothly in a SPLINE block is part of one path the controller plans whole and
    // samples on its cycle: no cycle of its own (nor for the segment before it, below).
    if (controller_.interpolation_cycle_s > 0.0 && motion.length_mm > 0.0 && !motion.entry_smooth) {
      e.rate_cap = motion.length_mm / controller_.interpolation_cycle_s;
      e.cruise = std::min(e.cruise, e.rate_cap);
    }
    if (motion.curvature_per_mm > 0.0) {
      e.curvature_cap = std::sqrt(controller_.path_acceleration_mm_s2 / motion.curvature_per_mm);
      e.cruise = std::min(e.cruise, e.curvature_cap);
      e.cruise_free = std::min(e.cruise_free, e.curvature_cap);
    }
  }
  if (!buffer_.empty()) {
    Entry& prev = buffer_.back();
    prev.junction = 0.0;
    prev.corner_joint = -1;
    const bool cp_pair = prev.m.kind == TimedMotion::Kind::cp &&
                         e.m.kind == TimedMotion::Kind::cp && !prev.m.stop_after;
    const bool smooth = cp_pair && e.m.entry_smooth;
    if (smooth) {
      prev.cruise = prev.cruise_free;
      prev.rate_cap = std::numeric_limits<double>::infinity();
      prev.joined = e.joined = true;
    }
    const bool blended = cp_pair && (smooth || prev.m.blend_mm > 0.0);
    if (blended) {
      const double reach = smooth ? std::numeric_limits<double>::infinity() : prev.m.blend_mm;
      const double d = std::min({reach, 0.5 * prev.m.length_mm, 0.5 * e.m.length_mm});
      double v = std::min(prev.cruise, e.cruise);
      int which = -1;
      if (d > 0.0) {
        for (int i = 0; i < cell_->size(); ++i) {
          const Joint& j = cell_->joint(i);
          const double dr = std::fabs(e.m.entry_rate[i] - prev.m.exit_rate[i]);
          if (!j.has_speed() || !(dr > 0.0))
            continue;
          const double c = std::sqrt(j.max_acceleration * d / dr);
          if (c < v) {
            v = c;
            which = i;
          }
        }
        const double dt = (e.m.tangent - prev.m.exit_tangent).norm();
        if (dt > 0.0) {
          // The velocity turns by v |t_next - t| over the blend. Past 120 deg of turn the blend
          // has less room than its length: the widest arc between the two legs, tangent to
          // them d from the corner, has the radius d / tan(turn / 2), which reaches 0 at a
          // reversal (a peck's bottom): there the path stops.
          const double half_turn_sin = std::min(1.0, 0.5 * dt);
          const double half_turn_tan =
              half_turn_sin / std::sqrt(std::max(0.0, 1.0 - half_turn_sin * half_turn_sin));
          const double c =
              std::sqrt(controller_.path_acceleration_mm_s2 * d / std::max(dt, half_turn_tan));
          if (c < v) {
            v = c;
            which = -2;
          }
        }
      } else {
        v = 0.0;
      }
      // $ADVANCE 0: no blending at all (the controller stops at every point).
      if (controller_.lookahead_motions == 0)
        v = 0.0;
      prev.junction = v;
      prev.corner_joint = which;
    }
  }
  buffer_.push_back(e);
  if (!recent_.empty()) {
    Recent& r = recent_[static_cast<std::size_t>(pushed_) % recent_.size()];
    r.length_mm = e.m.kind == TimedMotion::Kind::cp ? e.m.length_mm : 0.0;
    r.accel = e.accel;
    r.ptp = e.m.kind == TimedMotion::Kind::ptp;
  }
  if (e.m.kind == TimedMotion::Kind::ptp)
    last_stop_ = pushed_;
  ++pushed_;
  bound_by_lookahead();
  const bool at_rest = e.m.kind == TimedMotion::Kind::ptp || e.m.stop_after;
  if (at_rest) {
    plan(true);
  } else if (++since_plan_ >= kPlanEvery || buffer_.size() >= kMaxBuffered) {
    plan(false);
  }
}

// The planner sees the current motion and the next `lookahead_motions`: motion k must be able
// to stop by the end of motion k + A. From rest at that end, going backward over motions that
// may all brake at their path acceleration, the highest speed at the end of k is
// v^2 = 2 sum_{j=k+1}^{k+A} a_j S_j. A stop (a PTP, a statement) inside the window is seen by
// the planner and already bounds k through the junctions; the window then adds nothing.
void PathTimer::bound_by_lookahead() {
  const int a = controller_.lookahead_motions;
  if (a <= 0 || pushed_ <= a)
    return;
  const long k = pushed_ - 1 - a;  // the motion whose window is now complete
  if (last_stop_ > k)
    return;
  double sum = 0.0;
  for (long j = k + 1; j < pushed_; ++j) {
    const Recent& r = recent_[static_cast<std::size_t>(j) % recent_.size()];
    sum += 2.0 * r.accel * r.length_mm;
  }
  const long first_buffered = pushed_ - static_cast<long>(buffer_.size());
  if (k < first_buffered)
    return;  // already timed: its exit was planned within fewer motions, lower still
  Entry& ek = buffer_[static_cast<std::size_t>(k - first_buffered)];
  const double v = std::sqrt(sum);
  if (ek.m.kind == TimedMotion::Kind::cp && v < ek.junction) {
    ek.junction = v;
    ek.lookahead_bound = true;
  }
}

void PathTimer::stop(double dwell_s) {
  last_stop_ = pushed_ - 1;
  if (buffer_.empty()) {
    clock_s_ += dwell_s;
    return;
  }
  buffer_.back().m.stop_after = true;
  buffer_.back().m.dwell_after_s += dwell_s;
  buffer_.back().junction = 0.0;
  plan(true);
}

void PathTimer::finish() {
  if (!buffer_.empty())
    plan(true);
}

// The two passes over the buffer. at_rest: the last motion ends at rest (a stop, the end), so
// every motion is final; otherwise only those that a later motion cannot change.
void PathTimer::plan(bool at_rest) {
  since_plan_ = 0;
  const std::size_t n = buffer_.size();
  if (n == 0)
    return;
  // exit speeds going backward: b0 with the last motion ending at rest, binf with it ending as
  // fast as it may; where they agree, the future no longer matters.
  std::vector<double> b0(n), binf(n);
  auto reach = [&](std::size_t k, double exit) {
    // The highest entry speed of motion k from which `exit` can still be reached.
    const Entry& e = buffer_[k];
    if (e.m.kind == TimedMotion::Kind::ptp)
      return 0.0;
    return std::sqrt(exit * exit + 2.0 * e.accel * e.m.length_mm);
  };
  b0[n - 1] = 0.0;
  binf[n - 1] = buffer_[n - 1].m.kind == TimedMotion::Kind::ptp ? 0.0 : buffer_[n - 1].cruise;
  for (std::size_t k = n - 1; k-- > 0;) {
    const double j = buffer_[k].junction;
    b0[k] = std::min(j, reach(k + 1, b0[k + 1]));
    binf[k] = std::min(j, reach(k + 1, binf[k + 1]));
  }
  std::size_t final_count = n;
  if (!at_rest) {
    final_count = 0;
    while (final_count < n - 1 && same(b0[final_count], binf[final_count]))
      ++final_count;
    if (final_count == 0 && n >= kMaxBuffered)
      final_count = n / 2;  // a stop assumed after the front half (see kMaxBuffered)
  }
  // Forward pass over the final motions.
  double v = entry_speed_;
  for (std::size_t k = 0; k < final_count; ++k) {
    Entry& e = buffer_[k];
    if (e.m.kind == TimedMotion::Kind::ptp) {
      e.exit = 0.0;
    } else {
      const double up = std::sqrt(v * v + 2.0 * e.accel * e.m.length_mm);
      e.exit = std::min(b0[k], up);
    }
    v = e.exit;
  }
  emit_front(final_count);
}

void PathTimer::emit_front(std::size_t count) {
  for (std::size_t k = 0; k < count; ++k) {
    const Entry& e = buffer_.front();
    const TimedMotion& m = e.m;
    MotionTiming t;
    t.start_s = clock_s_;
    if (m.kind == TimedMotion::Kind::ptp) {
      t.duration_s = m.ptp_time_s;
      t.limit = TimingLimit::none;
      // The leading axis reaches the PTP share of its limit (if the move is long enough).
      t.axis_fraction_joint = m.ptp_joint;
      if (m.ptp_joint >= 0) {
        const Joint& j = cell_->joint(m.ptp_joint);
        const double d = std::fabs(m.chord_rate[m.ptp_joint]);
        const double v_top = controller_.ptp_velocity_fraction * j.max_velocity;
        const double a_top = controller_.ptp_acceleration_fraction * j.max_acceleration;
        t.axis_fraction = std::min(v_top, std::sqrt(a_top * d)) / j.max_velocity;
      }
      entry_speed_ = 0.0;
    } else {
      const double v0 = entry_speed_, v1 = e.exit;
      t.entry_mm_s = v0;
      t.exit_mm_s = v1;
      t.duration_s = segment_s(m.length_mm, v0, v1, e.cruise, e.accel);
      t.peak_mm_s =
          m.length_mm > 0.0
              ? std::min(e.cruise,
                         std::sqrt(0.5 * (2.0 * e.accel * m.length_mm + v0 * v0 + v1 * v1)))
              : 0.0;
      // What kept it below the asked speed.
      if (controller_.interpolation_cycle_s > 0.0 && m.length_mm > 0.0 &&
          std::isfinite(e.rate_cap) &&
          m.length_mm < std::min(m.command_mm_s, m.orientation_cap_mm_s) *
                            controller_.interpolation_cycle_s * kBelowCycle)
        t.below_cycle = true;
      t.spline_joined = e.joined;
      if (t.peak_mm_s < m.asked_mm_s * (1.0 - 1e-6)) {
        int vj = -1;
        const double v_axes = velocity_cap(*cell_, m.peak_rate, &vj);
        // The motion rate is what limits it where the cycle's cap is the cruise speed (below
        // $VEL.CP by more than the rounding, kBelowCycle) and the motion reaches it; a motion
        // kept lower by its junctions is classified by them below.
        const bool rate_binds = e.rate_cap < m.command_mm_s * kBelowCycle &&
                                e.rate_cap < m.orientation_cap_mm_s && same(e.cruise, e.rate_cap) &&
                                t.peak_mm_s >= e.cruise * (1.0 - 1e-6);
        // $VEL.CP written at the motion rate (the session's, with the point reduction on): the
        // clock's limit written into the program, which the motion reaches.
        const bool rate_written = m.command_joint == TimedMotion::kMotionRate &&
                                  m.command_mm_s < m.asked_mm_s && same(e.cruise, m.command_mm_s) &&
                                  t.peak_mm_s >= e.cruise * (1.0 - 1e-6);
        if (rate_binds || rate_written) {
          t.limit = TimingLimit::motion_rate;
        } else if (m.command_joint >= 0 && m.command_mm_s < m.asked_mm_s) {
          t.limit = TimingLimit::axis_velocity;
          t.joint = m.command_joint;
        } else if (v_axes < m.asked_mm_s && same(e.cruise, v_axes)) {
          t.limit = TimingLimit::axis_velocity;
          t.joint = vj;
        } else if (m.orientation_cap_mm_s < m.asked_mm_s &&
                   same(e.cruise, m.orientation_cap_mm_s)) {
          t.limit = TimingLimit::orientation;
        } else if (e.curvature_cap < m.asked_mm_s && same(e.cruise, e.curvature_cap) &&
                   t.peak_mm_s >= e.cruise * (1.0 - 1e-6)) {
          t.limit = TimingLimit::curvature;
        } else {
          // Not reaching the cruise speed: the junctions or the acceleration.
          const bool stop_in = v0 == 0.0, stop_out = v1 == 0.0;
          const bool corner_out = e.corner_joint != -1 && same(v1, e.junction);
          if (e.lookahead_bound && same(v1, e.junction)) {
            t.limit = TimingLimit::lookahead;
          } else if (corner_out) {
            t.limit = TimingLimit::corner;
            t.joint = e.corner_joint >= 0 ? e.corner_joint : -1;
          } else if (e.accel_joint >= 0) {
            t.limit = TimingLimit::axis_acceleration;
            t.joint = e.accel_joint;
          } else if (stop_in || stop_out) {
            t.limit = TimingLimit::stop;
          } else {
            t.limit = TimingLimit::path_acceleration;
          }
        }
      }
      for (int i = 0; i < cell_->size(); ++i) {
        const Joint& j = cell_->joint(i);
        if (!j.has_speed())
          continue;
        const double f = std::fabs(m.peak_rate[i]) * t.peak_mm_s / j.max_velocity;
        if (f > t.axis_fraction) {
          t.axis_fraction = f;
          t.axis_fraction_joint = i;
        }
      }
      entry_speed_ = v1;
    }
    clock_s_ += t.duration_s + m.dwell_after_s;
    if (m.stop_after)
      entry_speed_ = 0.0;
    done_(m, t);
    buffer_.pop_front();
  }
}

}  // namespace redpost
