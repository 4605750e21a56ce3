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

struct Pose {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  bool has_orientation = false;
};

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

// Motion i joins motion i - 1 smoothly: both in one SPLINE block, and one of them an SPL (an
// SLIN next to an SPL gives their shared point its direction).
bool joins_smoothly(const std::vector<KrlMotionRecord>& motions, std::size_t i) {
  if (i == 0 || i >= motions.size())
    return false;
  const KrlMotionRecord &a = motions[i - 1], &b = motions[i];
  return b.spline_block > 0 && a.spline_block == b.spline_block &&
         (krl::upper(a.keyword) == "SPL" || krl::upper(b.keyword) == "SPL");
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

KrlMotionRate krl_motion_rate(const KrlProgram& program, const KrlMotionRateOptions& options) {
  KrlMotionRate out;
  const double cycle = options.interpolation_cycle_s;
  const double ori_rad_s = options.orientation_velocity_deg_s * M_PI / 180.0;
  Pose last;
  bool have_last = false;
  KrlShortStretch open;
  auto close = [&] {
    if (open.motions > 0)
      out.stretches.push_back(open);
    open = KrlShortStretch{};
  };
  for (std::size_t i = 0; i < program.motions.size(); ++i) {
    const KrlMotionRecord& m = program.motions[i];
    const std::string kw = krl::upper(m.keyword);
    if (m.relative || !cartesian(m.target)) {
      // An axis-only target (a PTP to an E6AXIS): where the TCP is next is not known here.
      if (is_cp(kw) && !m.relative)
        ++out.unmeasured;
      have_last = false;
      close();
      continue;
    }
    const Pose now = pose_of(m.target, last);
    if (!is_cp(kw) || !have_last || !(m.vel_cp_m_per_s > 0.0)) {
      if (is_cp(kw))
        ++out.unmeasured;
      last = now;
      have_last = true;
      if (!is_cp(kw))
        close();
      continue;
    }
    double length = (now.p - last.p).norm();
    Circle arc;
    if ((kw == "CIRC" || kw == "SCIRC") && m.aux && cartesian(*m.aux) &&
        circle_through(last.p, point_of(*m.aux), now.p, arc))
      length = arc.length();
    double turn = 0.0;
    if (last.has_orientation && now.has_orientation) {
      const double c = std::clamp(0.5 * ((last.R.transpose() * now.R).trace() - 1.0), -1.0, 1.0);
      turn = std::acos(c);
    }
    const double seconds = std::max(length / (1000.0 * m.vel_cp_m_per_s), turn / ori_rad_s);
    last = now;
    if (!(seconds > 0.0))
      continue;  // nothing moves: not a motion the controller times
    ++out.cp_motions;
    // A segment joined smoothly to its neighbour is part of a path the controller plans whole
    // (docs/timing.md, "SPLINE blocks"): no cycle of its own.
    if (joins_smoothly(program.motions, i) || joins_smoothly(program.motions, i + 1)) {
      ++out.spline_joined;
      close();
      continue;
    }
    if (out.shortest_line == 0 || seconds < out.shortest_s) {
      out.shortest_s = seconds;
      out.shortest_file = m.file;
      out.shortest_line = m.line;
    }
    if (seconds < cycle * kKrlBelowCycle) {
      ++out.below_cycle;
      if (open.motions > 0 && open.file != m.file)
        close();
      if (open.motions == 0) {
        open.file = m.file;
        open.first_line = m.line;
        open.shortest_s = seconds;
      }
      open.last_line = m.line;
      ++open.motions;
      open.shortest_s = std::min(open.shortest_s, seconds);
    } else {
      close();
    }
  }
  close();
  return out;
}

}  // namespace redpost
