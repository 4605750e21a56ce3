#include "redpost/krl/motion_rate.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <Eigen/Geometry>

#include "redpost/kinematics/kuka_abc.hpp"

namespace redpost {

namespace {

bool cartesian(const KrlAggregate& t) {
  return t.has("X") && t.has("Y") && t.has("Z");
}

std::string upper(std::string s) {
  for (char& c : s)
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

bool is_cp(const std::string& kw) {
  return kw == "LIN" || kw == "CIRC" || kw == "SLIN" || kw == "SCIRC" || kw == "SPL";
}

struct Pose {
  double p[3] = {0, 0, 0};
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  bool has_orientation = false;
};

Pose pose_of(const KrlAggregate& t, const Pose& before) {
  Pose out;
  out.p[0] = t.values.at("X");
  out.p[1] = t.values.at("Y");
  out.p[2] = t.values.at("Z");
  if (t.has("A") && t.has("B") && t.has("C")) {
    out.R = rotation_from_abc({t.values.at("A"), t.values.at("B"), t.values.at("C")});
    out.has_orientation = true;
  } else {
    out.R = before.R;  // an orientation left out is kept (KRL's partial aggregates)
    out.has_orientation = before.has_orientation;
  }
  return out;
}

double distance(const double a[3], const double b[3]) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

}  // namespace

double krl_arc_length(const double a[3], const double b[3], const double c[3]) {
  const Eigen::Vector3d pa(a[0], a[1], a[2]), pb(b[0], b[1], b[2]), pc(c[0], c[1], c[2]);
  const Eigen::Vector3d ab = pb - pa, ac = pc - pa;
  const Eigen::Vector3d n = ab.cross(ac);
  const double n2 = n.squaredNorm();
  if (n2 < 1e-12 * std::max(1.0, ab.squaredNorm() * ac.squaredNorm()))
    return (pc - pa).norm();
  // The circumcentre of the triangle.
  const Eigen::Vector3d centre =
      pa + (ac.squaredNorm() * n.cross(ab) + ab.squaredNorm() * ac.cross(n)) / (2.0 * n2);
  const double r = (pa - centre).norm();
  const Eigen::Vector3d u = (pa - centre) / r, v = n.normalized().cross(u);
  const Eigen::Vector3d d = pc - centre;
  double phi = std::atan2(d.dot(v), d.dot(u));  // a -> b -> c turns positively about n
  if (phi <= 0.0)
    phi += 2.0 * M_PI;
  return r * phi;
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
  for (const KrlMotionRecord& m : program.motions) {
    const std::string kw = upper(m.keyword);
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
    double length = distance(last.p, now.p);
    if ((kw == "CIRC" || kw == "SCIRC") && m.aux && cartesian(*m.aux)) {
      const double b[3] = {m.aux->values.at("X"), m.aux->values.at("Y"), m.aux->values.at("Z")};
      length = krl_arc_length(last.p, b, now.p);
    }
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
