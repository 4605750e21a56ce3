#include "redpost/krl/motion_rate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "krl/text.hpp"
#include "redpost/kinematics/circle.hpp"
#include "redpost/kinematics/kuka_abc.hpp"

namespace redpost {

namespace {

bool cartesian(const KrlAggregate& t) {
  return t.has("X") && t.has("Y") && t.has("Z");
}

Eigen::Vector3d point_of(const KrlAggregate& t) {
  return {t.values.at("X"), t.values.at("Y"), t.values.at("Z")};
}

bool is_cp(const std::string& kw) {
  return kw == "LIN" || kw == "CIRC" || kw == "SLIN" || kw == "SCIRC" || kw == "SPL";
}

using Pose = detail::KrlTcpPose;
using Joint = detail::KrlSplineJoint;

Pose pose_of(const KrlAggregate& t, const Pose& before) {
  Pose out;
  out.p = point_of(t);
  if (t.has("A") && t.has("B") && t.has("C")) {
    out.R = rotation_from_abc({t.values.at("A"), t.values.at("B"), t.values.at("C")});
    out.has_orientation = true;
  } else {
    out.R = before.R;  // an orientation left out is kept (KRL's partial aggregates)
    out.has_orientation = before.has_orientation;
  }
  return out;
}

// Of a motion, what says whether its neighbours join it smoothly: its SPLINE block, and SPL.
Joint joint_of(const KrlMotionRecord& m) {
  return {m.spline_block, krl::upper(m.keyword) == "SPL"};
}

// b joins a smoothly: both in one SPLINE block, and one of them an SPL (an SLIN next to an SPL
// gives their shared point its direction).
bool joins_smoothly(const Joint& a, const Joint& b) {
  return b.spline_block > 0 && a.spline_block == b.spline_block && (a.spl || b.spl);
}

}  // namespace

double krl_cycle_velocity(double length_mm, double vel_m_per_s, double cycle_s,
                          int position_decimals, int velocity_decimals) {
  // Each printed coordinate is within half a unit of its last decimal: an end moves by at most
  // sqrt(3) / 2 of one, the length by twice that.
  const double printed_mm = length_mm - std::sqrt(3.0) * std::pow(10.0, -position_decimals);
  if (!(printed_mm > 0.0) || !(cycle_s > 0.0))
    return std::numeric_limits<double>::quiet_NaN();
  const double rate_mm_s = printed_mm / cycle_s;
  if (!(1000.0 * vel_m_per_s > rate_mm_s))
    return std::numeric_limits<double>::quiet_NaN();
  const double scale = std::pow(10.0, velocity_decimals);
  return std::max(std::floor(rate_mm_s / 1000.0 * scale) / scale, 1.0 / scale);
}

KrlMotionRateCounter::KrlMotionRateCounter(const KrlMotionRateOptions& options)
    : options_(options) {}

void KrlMotionRateCounter::add(const KrlMotionRecord& m) {
  detail::KrlMeasuredMotion& next = held_[1 - current_];
  measure(m, next);
  if (holding_)
    count(held_[current_], &next.joint);
  current_ = 1 - current_;
  holding_ = true;
}

KrlMotionRate KrlMotionRateCounter::finish() {
  if (holding_)
    count(held_[current_], nullptr);
  holding_ = false;
  close_stretch();
  return std::move(out_);
}

void KrlMotionRateCounter::close_stretch() {
  if (open_.motions > 0) {
    ++out_.stretch_count;
    if (out_.stretches.size() < kKrlMaxShortStretches)
      out_.stretches.push_back(open_);
  }
  open_ = KrlShortStretch{};
}

// What the count needs of a motion, measured as it arrives: the TCP it starts from is the last
// measured one's end, which only the motions before it move.
void KrlMotionRateCounter::measure(const KrlMotionRecord& m, detail::KrlMeasuredMotion& out) {
  using Kind = detail::KrlMeasuredMotion::Kind;
  out.joint = joint_of(m);
  out.file = m.file;
  out.line = m.line;
  out.seconds = 0.0;
  const std::string kw = krl::upper(m.keyword);
  const bool cp = is_cp(kw);
  out.closes_stretch = !cp;
  if (m.relative || !cartesian(m.target)) {
    // An axis-only target (a PTP to an E6AXIS): where the TCP is next is not known here.
    out.kind = Kind::axis_target;
    out.unmeasured = cp && !m.relative;
    out.closes_stretch = true;
    have_last_ = false;
    return;
  }
  const Pose now = pose_of(m.target, last_);
  if (!cp || !have_last_ || !(m.vel_cp_m_per_s > 0.0)) {
    out.kind = Kind::untimed;
    out.unmeasured = cp;
    last_ = now;
    have_last_ = true;
    return;
  }
  out.unmeasured = false;
  double length = (now.p - last_.p).norm();
  Circle arc;
  if ((kw == "CIRC" || kw == "SCIRC") && m.aux && cartesian(*m.aux) &&
      circle_through(last_.p, point_of(*m.aux), now.p, arc))
    length = arc.length();
  double turn = 0.0;
  if (last_.has_orientation && now.has_orientation) {
    const double c = std::clamp(0.5 * ((last_.R.transpose() * now.R).trace() - 1.0), -1.0, 1.0);
    turn = std::acos(c);
  }
  const double ori_rad_s = options_.orientation_velocity_deg_s * M_PI / 180.0;
  out.seconds = std::max(length / (1000.0 * m.vel_cp_m_per_s), turn / ori_rad_s);
  // Nothing moves: not a motion the controller times.
  out.kind = out.seconds > 0.0 ? Kind::timed : Kind::still;
  last_ = now;
}

void KrlMotionRateCounter::count(const detail::KrlMeasuredMotion& m,
                                 const detail::KrlSplineJoint* next) {
  using Kind = detail::KrlMeasuredMotion::Kind;
  // Whether this motion joins the one before it, and the next one it (known now).
  const bool joined_before = have_before_ && joins_smoothly(before_, m.joint);
  const bool joined_after = next && joins_smoothly(m.joint, *next);
  before_ = m.joint;
  have_before_ = true;
  if (m.unmeasured)
    ++out_.unmeasured;
  if (m.kind != Kind::timed) {
    if (m.closes_stretch)
      close_stretch();
    return;
  }
  ++out_.cp_motions;
  // A segment joined smoothly to its neighbour is part of a path the controller plans whole
  // (docs/timing.md, "SPLINE blocks"): no cycle of its own.
  if (joined_before || joined_after) {
    ++out_.spline_joined;
    close_stretch();
    return;
  }
  if (out_.shortest_line == 0 || m.seconds < out_.shortest_s) {
    out_.shortest_s = m.seconds;
    out_.shortest_file = m.file;
    out_.shortest_line = m.line;
  }
  if (m.seconds < options_.interpolation_cycle_s * kKrlBelowCycle) {
    ++out_.below_cycle;
    if (open_.motions > 0 && open_.file != m.file)
      close_stretch();
    if (open_.motions == 0) {
      open_.file = m.file;
      open_.first_line = m.line;
      open_.shortest_s = m.seconds;
    }
    open_.last_line = m.line;
    ++open_.motions;
    open_.shortest_s = std::min(open_.shortest_s, m.seconds);
  } else {
    close_stretch();
  }
}

KrlMotionRate krl_motion_rate(const KrlProgram& program, const KrlMotionRateOptions& options) {
  KrlMotionRateCounter counter(options);
  for (const KrlMotionRecord& m : program.motions)
    counter.add(m);
  return counter.finish();
}

}  // namespace redpost
