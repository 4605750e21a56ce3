// Arcs written as one CIRC (docs/krl-templates.md, "CIRC"), where the template set has a circ
// statement and the arc is proven safe; otherwise the chords of circular_move.
//
// The proof replays what the controller will do with the CIRC as written: the TCP on the circle
// through the written start, auxiliary and end points (to the printed decimals), at a constant
// pace in angle; the orientation turned from the start's to the end's at the same pace
// ($ORI_TYPE #VAR, $CIRC_TYPE #BASE, which the set sets); the external axes linear in the same
// parameter. At every sample the arm is solved in closed form for the start's posture (KUKA
// keeps Status during a CP motion), and it must stay within its limits without a jump, reach the
// tracked end posture, and the path must stay within the chordal tolerance of the CL arc.
#include <algorithm>
#include <cmath>

#include "post/session_impl.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/circle.hpp"

namespace redpost {

namespace {

// Rounds every coordinate as the writer prints it.
Eigen::Vector3d printed(const Eigen::Vector3d& p, int decimals) {
  const double f = std::pow(10.0, decimals);
  return Eigen::Vector3d(std::round(p.x() * f) / f, std::round(p.y() * f) / f,
                         std::round(p.z() * f) / f);
}

}  // namespace

const ArmIk* PostSession::Impl::arm_ik_for_active(std::string& why) {
  if (arm_ik_cell != active_cell) {
    // The planner holds the IK it was built on: it goes with it (a tool change back to an
    // earlier tool's cell would otherwise find the planner of that cell on a freed IK).
    planner.reset();
    planner_held.reset();
    planner_still.reset();
    planner_cell = nullptr;
    arm_ik.reset();
    arm_ik_cell = active_cell;
    try {
      arm_ik = std::make_unique<ArmIk>(*active_cell);
    } catch (const Error& e) {
      arm_ik_problem = e.message();
    }
  }
  if (!arm_ik)
    why = "the arm cannot be replayed in closed form (" + arm_ik_problem + ")";
  return arm_ik.get();
}

Isometry PostSession::Impl::physical_tcp_fk(const JointVector& q) {
  q_physical = q;
  for (int i = 0; i < active_cell->size(); ++i) {
    if (active_cell->joint(i).type == JointType::virtual_spin)
      q_physical[i] = 0.0;
  }
  forward_kinematics(*active_cell, q_physical, data);
  return data.T_B_tcp;
}

bool PostSession::Impl::circ_replay_ok(const JointVector& q0, const JointVector& q1,
                                       const detail::ArcChords& arc, JointVector& peak_rate,
                                       std::string& why, MotionEnds* ends) {
  const ArmIk* ik = arm_ik_for_active(why);
  if (!ik)
    return false;
  const int decimals = templates_position_decimals;
  const Isometry T_base_B = o.T_B_base.inverse();
  const Isometry T0 = physical_tcp_fk(q0), T1 = physical_tcp_fk(q1);
  // The three points as the controller reads them, in $BASE.
  const Eigen::Vector3d mid_cl =
      arc.centre +
      arc.r0 * (std::cos(0.5 * arc.sweep_rad) * arc.u + std::sin(0.5 * arc.sweep_rad) * arc.v) +
      arc.h0 * arc.axis;
  const Eigen::Vector3d a = printed(T_base_B * T0.translation(), decimals);
  const Eigen::Vector3d b = printed(T_base_B * (o.T_B_part * mid_cl), decimals);
  const Eigen::Vector3d c = printed(T_base_B * T1.translation(), decimals);
  Circle path;
  if (!circle_through(a, b, c, path)) {
    why = "its start, middle and end points lie on one line";
    return false;
  }
  const Eigen::Quaterniond r0(T0.linear()), r1(T1.linear());
  const Isometry T_part_base = o.T_B_part.inverse() * o.T_B_base;
  const int status = status_turn(*active_cell, ik->status_model(), q0).status;
  const double length = path.radius * path.sweep;
  const int samples = std::clamp(
      static_cast<int>(std::ceil(std::max(path.sweep * 180.0 / kPi / 2.0, length / 1.0))), 16,
      4000);
  JointVector q_prev = q0, q_other = q0;
  peak_rate.setZero(active_cell->size());
  const double ds = length / samples;
  for (int k = 1; k <= samples; ++k) {
    const double s = static_cast<double>(k) / samples;
    // The CL arc: the controller's circle must stay within the chordal tolerance of it.
    const Eigen::Vector3d p_cl = T_part_base * path.at(s);
    const Eigen::Vector3d rel = p_cl - arc.centre;
    const double h = rel.dot(arc.axis) - arc.h0;
    const double radial = (rel - rel.dot(arc.axis) * arc.axis).norm() - arc.r0;
    if (std::hypot(h, radial) > arc.tolerance_mm) {
      why = fmt::format("the controller's circle leaves the CL arc by {:.4f} mm",
                        std::hypot(h, radial));
      return false;
    }
    for (int i = 0; i < active_cell->size(); ++i) {
      const Joint& j = active_cell->joint(i);
      q_other[i] = j.type == JointType::virtual_spin ? 0.0 : q0[i] + s * (q1[i] - q0[i]);
    }
    Isometry T = Isometry::Identity();
    T.linear() = r0.slerp(s, r1).toRotationMatrix();
    T.translation() = o.T_B_base * path.at(s);
    const JointVector q_before = q_prev;
    if (!detail::replay_sample(*ik, T, q_other, status, s, ds, "arc", q_prev, peak_rate, why))
      return false;
    // The arm's rates at the ends from the first and the last step; the other joints move
    // linearly along the arc (their chord's rate).
    if (ends && (k == 1 || k == samples)) {
      JointVector& rate = k == 1 ? ends->entry_rate : ends->exit_rate;
      rate = (q1 - q0) / length;
      for (const int i : ik->arm_joints())
        rate[i] = (q_prev[i] - q_before[i]) / ds;
    }
  }
  if (ends) {
    // The circle's direction at its start and end, in {B}.
    const Eigen::Matrix3d R_B_base = o.T_B_base.linear();
    ends->entry_tangent = (R_B_base * path.v).normalized();
    const double phi = path.sweep;
    ends->exit_tangent =
        (R_B_base * (-std::sin(phi) * path.u + std::cos(phi) * path.v)).normalized();
  }
  return detail::replay_ends_at(*ik, q_prev, q1, "arc", why);
}

// Tracks the arc's chords without writing them, proves the CIRC and writes it. False (tracker
// and summary as before the arc) when the CIRC is not safe: the caller writes the chords.
bool PostSession::Impl::try_circ(const detail::ArcChords& arc, const Eigen::Vector3d& tool_axis,
                                 int cl_line) {
  const Tracker saved_tracker = tracker;
  const TcpTarget saved_target = last_target;
  const long saved_poses = summary.poses;
  const std::vector<JointRange> saved_ranges = summary.joints;
  const double saved_lowest = summary.lowest_inv_condition;
  const int saved_lowest_line = summary.lowest_inv_condition_line;
  const JointVector q0 = tracker.q();
  if (std::isnan(feed_mm_per_min))
    return false;  // the chords give the warning of a move before any FEDRAT
  for (long k = 1; k <= arc.chords; ++k) {
    const TcpTarget chord = target_in_B(arc.point(k), tool_axis, cl_line);
    track_line(chord, cl_line, false);
    last_target = chord;
  }
  std::string why;
  JointVector peak;
  MotionEnds ends;
  if (!circ_replay_ok(q0, tracker.q(), arc, peak, why, &ends)) {
    tracker = saved_tracker;
    last_target = saved_target;
    summary.poses = saved_poses;
    summary.joints = saved_ranges;
    summary.lowest_inv_condition = saved_lowest;
    summary.lowest_inv_condition_line = saved_lowest_line;
    if (circ_fallbacks++ < 20) {
      summary.warnings.push_back(fmt::format(
          "{}:{}: the arc is written as chords, not as a CIRC: {}", o.source_name, cl_line, why));
    }
    return false;
  }
  set_speed(feed_mm_per_min / 60000.0, true);
  const Eigen::Vector3d mid_cl =
      arc.centre +
      arc.r0 * (std::cos(0.5 * arc.sweep_rad) * arc.u + std::sin(0.5 * arc.sweep_rad) * arc.v) +
      arc.h0 * arc.axis;
  KrlMotion aux;
  aux.T_base_tcp = Isometry::Identity();
  aux.T_base_tcp.translation() = o.T_B_base.inverse() * (o.T_B_part * mid_cl);
  const JointVector q1 = tracker.q();
  const KrlMotion end = motion_at(KrlMotionKind::lin, q1, cl_line);
  const Isometry T1 = o.T_B_base * end.T_base_tcp;
  TimedMotion t = timed_cp(q_written, T_written, q1, T1, arc.r0 * arc.sweep_rad, cl_line, &peak);
  t.entry_rate = ends.entry_rate;
  t.exit_rate = ends.exit_rate;
  t.tangent = ends.entry_tangent;
  t.exit_tangent = ends.exit_tangent;
  t.curvature_per_mm = 1.0 / arc.r0;
  // The circle through the start, the auxiliary point and the end, in {B}, for the collision
  // check along it.
  Circle circle_B;
  if (circle_through(T_written.translation(), o.T_B_base * aux.T_base_tcp.translation(),
                     T1.translation(), circle_B))
    check_clearance(KrlMotionKind::lin, q1, cl_line, &circle_B);
  else
    check_clearance(KrlMotionKind::lin, q1, cl_line);
  writer.velocity(t.command_mm_s / 1000.0);
  writer.circ(aux, end);
  after_write(end, q1, t);
  remember_written(q1, T1);
  last_target = target_in_B(arc.end, tool_axis, cl_line);
  remember_cl(arc.end, tool_axis);
  return true;
}

}  // namespace redpost
