// The time model's view of a candidate plan (post/plan_time.hpp).
#include "redpost/post/plan_time.hpp"

#include <cmath>

#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/timing/timed_motion.hpp"

namespace redpost {

namespace {

// Samples of a PTP's path at most, where the estimate asks whether it stays above its plane.
constexpr int kEstimatePtpSamples = 64;

// In line: directions within 0.5 deg (the cosine).
const double kInLineCos = std::cos(deg_to_rad(0.5));

// The motions of one candidate, pushed into the timer as the session would write them.
struct CandidateMotions {
  const Cell& cell;
  const ControllerTiming& controller;
  double blend_mm;
  PathTimer& timer;
  KinematicsData fk;
  JointVector q_prev;
  Isometry T_prev = Isometry::Identity();
  long index = 0;

  void start(const JointVector& q0) {
    q_prev = q0;
    forward_kinematics(cell, q_prev, fk, false);
    T_prev = fk.T_B_tcp;
  }

  void lin(const JointVector& q, double speed_mm_s, int cl_line) {
    forward_kinematics(cell, q, fk, false);
    const double length = (fk.T_B_tcp.translation() - T_prev.translation()).norm();
    TimedMotion t = cp_motion(cell, q_prev, T_prev, q, fk.T_B_tcp, length, speed_mm_s,
                              controller.orientation_velocity_rad_s, blend_mm);
    t.at_feed = true;
    push(t, q, cl_line);
    T_prev = fk.T_B_tcp;
  }

  void ptp(const JointVector& q, int cl_line) {
    TimedMotion t = synchronous_ptp(cell, q_prev, q, controller);
    forward_kinematics(cell, q, fk, false);
    T_prev = fk.T_B_tcp;
    push(t, q, cl_line);
  }

  void push(TimedMotion& t, const JointVector& q, int cl_line) {
    t.index = ++index;
    t.cl_line = cl_line;
    timer.push(t);
    q_prev = q;
  }
};

}  // namespace

bool ptp_stays_above(const Cell& cell, const JointVector& q0, const JointVector& q1,
                     const Eigen::Vector3d& point_B, const Eigen::Vector3d& normal_B,
                     KinematicsData& data, int max_samples) {
  double largest = 0.0;
  for (int i = 0; i < cell.size(); ++i) {
    const double d = std::fabs(q1[i] - q0[i]);
    largest = std::max(largest,
                       cell.joint(i).type == JointType::prismatic ? d / 0.5 : rad_to_deg(d) / 0.5);
  }
  const int samples = std::max(
      16, static_cast<int>(std::min(std::ceil(largest), static_cast<double>(max_samples))));
  JointVector q = q0;
  for (int k = 1; k < samples; ++k) {
    const double s = static_cast<double>(k) / samples;
    for (int i = 0; i < cell.size(); ++i)
      q[i] = q0[i] + s * (q1[i] - q0[i]);
    forward_kinematics(cell, q, data);
    if (normal_B.dot(data.T_B_tcp.translation() - point_B) < 0.0)
      return false;
  }
  return true;
}

PlanTimeEstimate estimate_plan_time(const Cell& cell, const PathPlanner& planner,
                                    const ControllerTiming& controller, double blend_mm,
                                    const std::vector<PlanKeyframe>& keyframes,
                                    const std::vector<JointVector>& q,
                                    const std::vector<PlanKeyframe>& ends, double until_s,
                                    const JointVector* approach_from) {
  PlanTimeEstimate out;
  if (keyframes.empty() || q.size() != keyframes.size())
    return out;
  PathTimer timer(cell, controller, [](const TimedMotion&, const MotionTiming&) {});
  CandidateMotions m{cell, controller, blend_mm, timer, {}, {}, Isometry::Identity(), 0};
  if (approach_from && approach_from->size() == q.front().size()) {
    m.start(*approach_from);
    m.ptp(q.front(), keyframes.front().cl_line);
  } else {
    m.start(q.front());
  }
  double s_prev = keyframes.front().s_mm;
  std::size_t k = 1;  // the next keyframe after s_prev
  JointVector q_at(cell.size());
  // Where the last motion timed ends: a CL point in line with it, with the same tool axis and
  // speed, is passed over, as the program's point reduction merges it (the keyframes, 20 mm
  // apart, still carry the plan's course of the axes). A raster's million points are then a
  // few per line, and its line ends the corners they are.
  Eigen::Vector3d p_anchor = keyframes.front().target.p_B_mm;
  Eigen::Vector3d z_anchor = keyframes.front().target.z_B.normalized();
  const auto in_line = [&](const PlanKeyframe& a, const PlanKeyframe& b) {
    const Eigen::Vector3d d0 = a.target.p_B_mm - p_anchor, d1 = b.target.p_B_mm - a.target.p_B_mm;
    const double n0 = d0.norm(), n1 = d1.norm();
    return !b.rapid && b.speed_mm_s == a.speed_mm_s && n0 > 1e-6 && n1 > 1e-6 &&
           d0.dot(d1) > kInLineCos * n0 * n1 &&
           b.target.z_B.normalized().dot(z_anchor) > kInLineCos;
  };
  for (std::size_t j = 0; j < ends.size(); ++j) {
    const PlanKeyframe& e = ends[j];
    if (e.s_mm <= s_prev + 1e-9)
      continue;
    if (e.s_mm > until_s + 1e-9)
      break;
    while (k < keyframes.size() && keyframes[k].s_mm <= s_prev + 1e-9)
      ++k;
    // A rapid written as a LIN moves the external axes at one rate from end to end: the
    // keyframes inside it are no points of the program.
    if (!e.traverse) {
      for (; k < keyframes.size() && keyframes[k].s_mm < e.s_mm - 1e-6; ++k) {
        m.lin(q[k], e.speed_mm_s, keyframes[k].cl_line);
        p_anchor = keyframes[k].target.p_B_mm;
        z_anchor = keyframes[k].target.z_B.normalized();
        s_prev = keyframes[k].s_mm;
      }
      if (j + 1 < ends.size() && ends[j + 1].s_mm <= until_s + 1e-9 && in_line(e, ends[j + 1]))
        continue;
    }
    if (!planner.solve_at(e.target, interpolate_plan(keyframes, q, e.s_mm), q_at)) {
      out.failed_cl_line = e.cl_line;
      return out;
    }
    // A PTP that would dip below its plane is written as a LIN (motion.cpp, rapid_piece).
    if (e.rapid && ptp_stays_above(cell, m.q_prev, q_at, e.clearance_point_B, e.clearance_normal_B,
                                   m.fk, kEstimatePtpSamples))
      m.ptp(q_at, e.cl_line);
    else
      m.lin(q_at, e.speed_mm_s, e.cl_line);
    s_prev = e.s_mm;
    p_anchor = e.target.p_B_mm;
    z_anchor = e.target.z_B.normalized();
  }
  timer.finish();
  out.time_s = timer.elapsed_s();
  out.feasible = true;
  return out;
}

}  // namespace redpost
