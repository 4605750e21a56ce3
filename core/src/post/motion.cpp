// A post session's moves (PostSession::Impl, post/session_impl.hpp): each CL move tracked by
// the redundancy resolution and written as a motion; rapids written as straight LINs where the
// tool may be inside the part and as PTPs only where their joint-interpolated path stays above
// the clearance plane (docs/convert.md, "Rapids"); the messages of a pose that cannot be
// reached.
#include <algorithm>
#include <cmath>

#include "cl/arc_chords.hpp"
#include "post/session_impl.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/tool_axis.hpp"
#include "redpost/post/plan_time.hpp"

namespace redpost {

namespace {

std::string joint_label(const Cell& cell, int i) {
  if (i < 0)
    return "?";
  const Joint& j = cell.joint(i);
  return j.axis.mapped() ? "'" + j.name + "' (" + axis_name(j.axis) + ")" : "'" + j.name + "'";
}

// A joint value as the robot programmer knows it: in controller units where the joint has an
// axis (A2 -90 deg rather than theta_2 -1.5708 rad), in DH degrees or mm otherwise.
std::string in_units(const Joint& j, double v) {
  const double shown = j.axis.mapped()                  ? to_axis_value(j, v)
                       : j.type == JointType::prismatic ? v
                                                        : rad_to_deg(v);
  return fmt::format(j.type == JointType::prismatic ? "{:.3f} mm" : "{:.3f} deg", shown);
}

std::string limits_text(const Joint& j) {
  std::string lo = in_units(j, j.lower), hi = in_units(j, j.upper);
  if (j.axis.mapped() && j.axis.sign < 0)
    std::swap(lo, hi);
  return "[" + lo + ", " + hi + "]";
}

// The external axes a cell has, for advice: "track and table", "the track", "".
std::string external_axes_words(const Cell& cell) {
  bool track = false, table = false;
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    if (j.axis.kind != AxisKind::external)
      continue;
    (j.type == JointType::prismatic ? track : table) = true;
  }
  return track && table ? "track and table" : track ? "the track" : table ? "the table" : "";
}

}  // namespace

// --- messages --------------------------------------------------------------------------------

// What to try when the first pose (or the approach after a tool change) cannot be reached: the
// placement always, the redundant external axes only where the cell has them, and the MSYS
// when the file's MCS is not z-up and was taken as it stands.
std::string PostSession::Impl::first_pose_advice() const {
  std::string advice =
      " Move the part in the cell (--placement x,y,z,a,b,c puts the CL frame in the cell's "
      "base frame)";
  const std::string axes = external_axes_words(*active_cell);
  if (!axes.empty())
    advice += ", or check that " + axes + " are free to help (their limits in the cell file)";
  advice += ".";
  if (msys_line > 0 && !msys_applied && msys_z.z() < 0.99) {
    advice += fmt::format(
        " The CL file's MSYS (line {}) turns its machine coordinate system so that its z axis "
        "is ({:.3f}, {:.3f}, {:.3f}) in NX's absolute frame, and the CL data are read in that "
        "MCS: if the part is set up z-up in NX's absolute frame, convert with --msys apply "
        "(docs/cl-format.md, \"MSYS\").",
        msys_line, msys_z.x(), msys_z.y(), msys_z.z());
  }
  return advice;
}

void PostSession::Impl::fail(const PoseResult& r, int cl_line, const char* what) {
  const bool first = std::string(what).find("first pose") != std::string::npos ||
                     std::string(what).find("approach") != std::string::npos;
  std::string msg = fmt::format("pose {} ({}): ", summary.poses + 1, what);
  const Cell& c = *active_cell;
  switch (r.status) {
    case PoseStatus::unreachable:
      msg += fmt::format(
          "the target cannot be reached: {:.4g} mm and {:.4g} deg from it after {} iterations.",
          r.position_error_mm, rad_to_deg(r.orientation_error_rad), r.iterations);
      msg += first ? first_pose_advice()
                   : " Check where the part is placed in the cell (--placement) and that the "
                     "toolpath fits the cell's work space";
      throw Error(ErrorCode::unreachable, msg, SourceLocation{o.source_name, cl_line, 0});
    case PoseStatus::joint_limit: {
      const int i = r.offending_joint;
      msg += fmt::format("joint {} would have to leave its limits {}.", joint_label(c, i),
                         i >= 0 ? limits_text(c.joint(i)) : "[?]");
      if (first) {
        msg += first_pose_advice();
      } else {
        const std::string axes = external_axes_words(c);
        msg += " Move the part (--placement)";
        if (!axes.empty())
          msg += ", or let the redundant axes help (are " + axes + " free?)";
        // The plan sees 800 mm ahead: a long turn may run an axis to its end that the pose-by-pose
        // centring would have held back (docs/redundancy.md, "A dead end the plan avoids").
        if (o.plan == RedundancyPlan::global && !axes.empty())
          msg += "; or try --plan local, which holds " + axes + " nearer home";
      }
      throw Error(ErrorCode::joint_limit, msg, SourceLocation{o.source_name, cl_line, 0});
    }
    case PoseStatus::joint_jump: {
      const int i = r.offending_joint;
      msg += fmt::format(
          "joint {} would jump by {} between two consecutive poses (a wrist flip or a "
          "discontinuous toolpath). Smooth the tool axis or split the operation",
          joint_label(c, i),
          i >= 0 ? (c.joint(i).type == JointType::prismatic
                        ? fmt::format("{:.3f} mm", r.offending_step)
                        : fmt::format("{:.3f} deg", rad_to_deg(r.offending_step)))
                 : "?");
      throw Error(ErrorCode::unreachable, msg, SourceLocation{o.source_name, cl_line, 0});
    }
    case PoseStatus::converged:
      break;
  }
  throw Error(ErrorCode::internal, "fail() on a converged pose");
}

// --- what is written -------------------------------------------------------------------------
void PostSession::Impl::record(const PoseResult& r, int cl_line, bool new_pose) {
  summary.poses += new_pose ? 1 : 0;
  last = r;
  if (r.inv_condition < summary.lowest_inv_condition) {
    summary.lowest_inv_condition = r.inv_condition;
    summary.lowest_inv_condition_line = cl_line;
  }
  for (int i = 0; i < cell.size(); ++i) {
    JointRange& jr = summary.joints[static_cast<size_t>(i)];
    const double q = r.q[i];
    jr.lowest = std::min(jr.lowest, q);
    jr.highest = std::max(jr.highest, q);
    jr.margin_lower = std::min(jr.margin_lower, q - cell.joint(i).lower);
    jr.margin_upper = std::min(jr.margin_upper, cell.joint(i).upper - q);
  }
}

// A PTP (the first motion, an approach, a rapid above the clearance plane) to the posture q.
void PostSession::Impl::emit(KrlMotionKind kind, const JointVector& q, int cl_line) {
  const KrlMotion m = motion_at(kind, q, cl_line);
  const TimedMotion t = timed_ptp(q, cl_line);
  check_clearance(kind, q, cl_line);
  writer.motion(m);
  after_write(m, q, t);
  remember_written(q, o.T_B_base * m.T_base_tcp);
}

// The motion to the posture q (the tracker's current one), checked against the limits.
KrlMotion PostSession::Impl::motion_at(KrlMotionKind kind, const JointVector& q, int cl_line) {
  // Never write a posture outside the limits: the tracker guarantees it, this makes sure.
  if (!within_limits(cell, q)) {
    throw Error(ErrorCode::internal, "a posture outside the joint limits reached the writer",
                SourceLocation{o.source_name, cl_line, 0});
  }
  KrlMotion m;
  m.kind = kind;
  m.axes = to_controller_axes(cell, q);
  m.cl_line = cl_line;
  // A PTP, or a line at the rapid speed: a rapid traverse or an approach, which ends in the air.
  m.in_air = kind != KrlMotionKind::lin || !asked_is_feed;
  m.T_base_tcp = o.T_B_base.inverse() * physical_tcp(q);
  m.status_turn = status_turn(cell, arm, q);
  return m;
}

// A written motion: counted, and handed to the time model, which makes its joints-log row and
// observer sample once it is timed (timing.cpp).
void PostSession::Impl::after_write(const KrlMotion& m, const JointVector& q,
                                    const TimedMotion& t) {
  ++summary.motions;
  PendingMotion p;
  p.index = summary.motions;
  p.cl_line = m.cl_line;
  p.first_line = move_first_line > 0 ? move_first_line : m.cl_line;
  p.kind = m.kind;
  p.q = q;
  p.axes = m.axes;
  p.inv_condition = last.inv_condition;
  p.iterations = last.iterations;
  if (m.kind == KrlMotionKind::lin && t.at_feed)
    p.feed_mm_per_min = feed_mm_per_min;
  // {base} -> {B} -> part: the TCP the controller is sent, in the CL frame.
  p.p_part_mm = o.T_B_part.inverse() * (o.T_B_base * m.T_base_tcp.translation());
  // The move's deflection belongs to the motion at its end (not to the steps written before it).
  if (move_deflection && m.kind == KrlMotionKind::lin && q == tracker.q()) {
    p.has_deflection = true;
    p.deflection = *move_deflection;
    move_deflection.reset();
  }
  if (const JointVector* plan = tracker.plan_target(); plan && o.on_motion) {
    p.planned = true;
    p.q_plan = *plan;
  }
  // The tool in force, for a host that draws it: its length, and how far its TCP lies beyond the
  // chain's own along -z of the TCP frame (cell_for_tool).
  p.tool_length_mm =
      std::isfinite(active_length_mm) ? active_length_mm : cell.tools.reference_length_mm;
  p.tcp_shift_mm = active_cell == &cell ? 0.0 : active_length_mm - cell.tools.reference_length_mm;
  if (motion_clearance) {
    const MotionClearance& c = *motion_clearance;
    p.clearance_mm = c.nearest_mm;
    p.clearance_proven_mm = c.least_mm;
    p.clearance_pair = c.nearest_pair;
    p.clearance_exact = c.nearest_where.exact;
    const Isometry T_part_B = o.T_B_part.inverse();
    p.clearance_a = T_part_B * c.nearest_where.point_a_B;
    p.clearance_b = T_part_B * c.nearest_where.point_b_B;
    motion_clearance.reset();
  }
  pending.push_back(std::move(p));
  TimedMotion timed = t;
  timed.index = summary.motions;
  timer->push(timed);
}

// The physical TCP is the chain's TCP with every virtual joint at 0: the controller's $TOOL
// knows nothing of the free spin. When the only virtual joint ends the chain with a pure
// Rz(theta) Tz(d) link (alpha = 0, a = 0, no tool frame after it), that is the tracked TCP
// turned back by -theta about its own z: no second forward kinematics per motion.
Isometry PostSession::Impl::physical_tcp(const JointVector& q) {
  // The tracker's own TCP serves only for its own posture: a step written before the end of a
  // move (emit_line) is another posture, whose TCP lies elsewhere on the line.
  if (spin_last >= 0 && q == tracker.q()) {
    Isometry T = tracker.tcp_pose_at_q();
    T.linear() = T.linear() * Eigen::AngleAxisd(-q[spin_last], Eigen::Vector3d::UnitZ());
    return T;
  }
  q_physical = q;
  for (int i = 0; i < active_cell->size(); ++i) {
    if (active_cell->joint(i).type == JointType::virtual_spin)
      q_physical[i] = 0.0;
  }
  forward_kinematics(*active_cell, q_physical, data);
  return data.T_B_tcp;
}

int PostSession::Impl::last_pure_spin(const Cell& c) {
  int virtuals = 0;
  for (int i = 0; i < c.size(); ++i)
    virtuals += c.joint(i).type == JointType::virtual_spin;
  const int last = c.size() - 1;
  const Joint& j = c.joint(last);
  const bool pure = virtuals == 1 && j.type == JointType::virtual_spin && j.alpha_rad == 0.0 &&
                    j.a_mm == 0.0 && !c.has_tcp_frame;
  return pure ? last : -1;
}

// --- moves -----------------------------------------------------------------------------------
TcpTarget PostSession::Impl::target_in_B(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis,
                                         int cl_line) {
  const double norm = axis.norm();
  if (!p_mm.allFinite() || !std::isfinite(norm)) {
    throw Error(ErrorCode::bad_input, "a move with a coordinate that is not a finite number",
                SourceLocation{o.source_name, cl_line, 0});
  }
  if (p_mm.cwiseAbs().maxCoeff() > kMaxCoordinateMm) {
    throw Error(ErrorCode::bad_input,
                fmt::format("a move to a coordinate beyond {:g} mm (the CL reader's bound): "
                            "check the units and the values",
                            kMaxCoordinateMm),
                SourceLocation{o.source_name, cl_line, 0});
  }
  if (!(norm > 1e-9)) {
    throw Error(ErrorCode::bad_input, "a move with a tool axis of zero length",
                SourceLocation{o.source_name, cl_line, 0});
  }
  return TcpTarget::axis(o.T_B_part * p_mm, o.T_B_part.linear() * (axis / norm));
}

std::optional<ClearancePlane> PostSession::Impl::plane_for(const ClearancePlane* cycle) const {
  if (cycle)
    return *cycle;
  if (std::isfinite(o.clearance_z_mm)) {
    ClearancePlane p;
    p.point = Eigen::Vector3d(0.0, 0.0, o.clearance_z_mm);
    return p;
  }
  return std::nullopt;
}

void PostSession::Impl::move(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis, int cl_line,
                             const ClearancePlane* cycle) {
  const std::optional<ClearancePlane> plane = plane_for(cycle);
  if (!started || approach_pending) {
    next_rapid = false;
    first_or_approach(p_mm, axis, cl_line, plane);
    return;
  }
  const bool rapid = next_rapid;
  next_rapid = false;
  // A CL point repeated (a cycle's expansion, CAM output) is no motion: tracking it would
  // write a LIN of zero length that only moves the redundant axes, which a controller cannot
  // time by its path speed.
  if ((p_mm - last_cl_point).norm() < 1e-9 && (axis.normalized() - last_cl_axis).norm() < 1e-12 &&
      axis.allFinite()) {
    return;
  }
  if (rapid) {
    rapid_move(p_mm, axis, cl_line, plane);
    return;
  }
  if (std::isnan(feed_mm_per_min)) {
    feed_mm_per_min = o.default_feed_mm_per_min;
    if (!feed_warned) {
      summary.warnings.push_back(
          fmt::format("{}:{}: a cutting move before any FEDRAT; using {} mm/min", o.source_name,
                      cl_line, o.default_feed_mm_per_min));
      feed_warned = true;
    }
  }
  set_speed(feed_mm_per_min / 60000.0, true);
  const TcpTarget cam = target_in_B(p_mm, axis, cl_line);
  // A drilling cycle's feed is axial: the side-milling force model has nothing to say of it.
  TcpTarget target = cam;
  if (deflection_on() && !cycle)
    target = track_cut(cam, p_mm, cl_line);
  else
    track_line(cam, cl_line, false);
  emit_line(cl_line);
  last_target = target;
  remember_cl(p_mm, axis);
}

// The first pose of the program, or the first after a tool change: far from where the robot
// is, so solved from several starts and reached with a PTP to the full posture. If the point is
// below a known clearance plane, the PTP goes to the point above it on the tool axis and a
// straight move goes down.
void PostSession::Impl::first_or_approach(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis,
                                          int cl_line, const std::optional<ClearancePlane>& plane) {
  const char* what = started ? "the approach after a tool change" : "the first pose of the path";
  Eigen::Vector3d entry = p_mm;
  bool below = false;
  if (plane) {
    const double h = plane->height(p_mm);
    const double rise = plane->normal.dot(axis.normalized());
    if (h < 0.0 && rise > 0.1) {
      entry = p_mm + (-h / rise) * axis.normalized();
      below = true;
    }
  }
  const TcpTarget target = target_in_B(entry, axis, cl_line);
  PoseResult r;
  if (planning() && !plan_q.empty()) {
    // The plan starts at the first point: reach the entry from its posture.
    tracker.reset(plan_q.front());
    follow_plan(0.0);
    r = tracker.track(target);
    if (r.status != PoseStatus::converged)
      r = tracker.solve_first_pose(target);
    plan_s = -(p_mm - entry).norm();
  } else {
    r = tracker.solve_first_pose(target);
  }
  if (r.status != PoseStatus::converged)
    fail(r, cl_line, what);
  r = clear_first_pose(target, r);
  tracker.reset(r.q);
  started = true;
  approach_pending = false;
  record(r, cl_line);
  emit(KrlMotionKind::ptp_axes, r.q, cl_line);
  last_target = target;
  remember_cl(entry, axis);
  if (below) {
    set_speed(o.rapid_velocity_m_per_s, false);
    const TcpTarget down = target_in_B(p_mm, axis, cl_line);
    track_line(down, cl_line, false);
    emit_line(cl_line);
    last_target = down;
    remember_cl(p_mm, axis);
  }
}

bool PostSession::Impl::track_line(const TcpTarget& target, int cl_line, bool rapid) {
  // Long moves in steps, so that the redundancy is resolved continuously along them.
  const double length = (target.p_B_mm - last_target.p_B_mm).norm();
  const double turn = std::acos(std::clamp(target.z_B.dot(last_target.z_B), -1.0, 1.0));
  const double step_count =
      std::ceil(std::max(length / o.max_step_mm, rad_to_deg(turn) / o.max_step_axis_deg));
  // Coordinates are bounded where they come in; this keeps the count an int whatever comes.
  if (!(step_count < 1e8)) {
    throw Error(ErrorCode::bad_input,
                fmt::format("a move of {:g} mm cannot be followed in steps of {:g} mm", length,
                            o.max_step_mm),
                SourceLocation{o.source_name, cl_line, 0});
  }
  const int steps = std::max(1, static_cast<int>(step_count));
  line_steps.clear();
  for (int s = 1; s <= steps; ++s) {
    TcpTarget step = target;
    if (s < steps) {
      const double t = static_cast<double>(s) / steps;
      step.p_B_mm = (1.0 - t) * last_target.p_B_mm + t * target.p_B_mm;
      step.z_B = slerp_axis(last_target.z_B, target.z_B, t);
    }
    if (planning())
      follow_plan(plan_s + length * static_cast<double>(s) / steps);
    PoseResult r = tracker.track(step);
    if (r.status != PoseStatus::converged && rapid) {
      // A rapid traverse that may go joint-interpolated (PTP) need not follow the straight
      // line, so its end may be solved directly from the current posture.
      r = tracker.solve_first_pose(target);
      if (r.status == PoseStatus::converged) {
        tracker.reset(r.q);
        summary.warnings.push_back(fmt::format(
            "{}:{}: the straight line of this rapid traverse is not trackable; its end was "
            "solved directly and is reached by PTP",
            o.source_name, cl_line));
        record(r, cl_line);
        return false;
      }
    }
    if (r.status != PoseStatus::converged)
      fail(r, cl_line,
           rapid          ? "rapid"
           : compensating ? "cutting move, its target moved against the arm's deflection"
                          : "cutting move");
    record(r, cl_line);
    if (steps > 1)
      line_steps.push_back(r.q);
  }
  plan_s += length;
  return true;
}

// A rapid from the last CL point to p_mm. Where it runs below the clearance plane (or no plane
// is known) the tool may be inside the part: that stretch is a LIN along the CL line. Above the
// plane it may be a PTP, if its joint-interpolated path stays above the plane.
void PostSession::Impl::rapid_move(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis,
                                   int cl_line, const std::optional<ClearancePlane>& plane) {
  if (!plane) {
    rapid_piece(p_mm, axis, cl_line, plane, true);
    return;
  }
  constexpr double kOn = 1e-6;  // a point on the plane counts as above it
  const double h0 = plane->height(last_cl_point), h1 = plane->height(p_mm);
  // An end on the plane is no crossing: splitting there would write a rapid of zero length.
  if ((h0 < -kOn) != (h1 < -kOn) && std::fabs(h0) > kOn && std::fabs(h1) > kOn) {
    // Split where the line crosses the plane: the part below straight, the part above free.
    const double t = h0 / (h0 - h1);
    const Eigen::Vector3d cross = last_cl_point + t * (p_mm - last_cl_point);
    const Eigen::Vector3d cross_axis = slerp_axis(last_cl_axis, axis.normalized(), t);
    rapid_piece(cross, cross_axis, cl_line, plane, h0 < -kOn);
    rapid_piece(p_mm, axis, cl_line, plane, h1 < -kOn);
    return;
  }
  rapid_piece(p_mm, axis, cl_line, plane, h0 < -kOn || h1 < -kOn);
}

void PostSession::Impl::rapid_piece(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis,
                                    int cl_line, const std::optional<ClearancePlane>& plane,
                                    bool below) {
  const TcpTarget target = target_in_B(p_mm, axis, cl_line);
  const JointVector q_from = tracker.q();
  const TrackedState before = tracked_state();
  const bool may_ptp = !below && plane.has_value();
  const bool on_line = track_line(target, cl_line, may_ptp);
  bool ptp = may_ptp && ptp_stays_above(q_from, tracker.q(), *plane);
  if (may_ptp && !ptp && !on_line) {
    throw Error(ErrorCode::unreachable,
                "the straight line of this rapid traverse is not trackable, and a PTP to its end "
                "would dip below the clearance plane",
                SourceLocation{o.source_name, cl_line, 0});
  }
  // A rapid that would come too close to a body goes up along the tool axis, over and down
  // instead (collision.cpp).
  if (!routing_rapid && !rapid_clear(tracker.q(), ptp)) {
    restore_tracked(before, q_from);
    route_rapid_up(p_mm, axis, cl_line);
    return;
  }
  if (ptp) {
    emit(KrlMotionKind::rapid, tracker.q(), cl_line);
  } else {
    set_speed(o.rapid_velocity_m_per_s, false);
    emit_line(cl_line);
  }
  last_target = target;
  remember_cl(p_mm, axis);
}

// A PTP moves every axis from q0 to q1 on the straight line in joint space (KUKA's synchronous
// PTP: all axes start and stop together, with the same profile): its TCP path must stay above
// the plane (post/plan_time.hpp, whose estimate asks the same).
bool PostSession::Impl::ptp_stays_above(const JointVector& q0, const JointVector& q1,
                                        const ClearancePlane& plane) {
  return redpost::ptp_stays_above(*active_cell, q0, q1, o.T_B_part * plane.point,
                                  o.T_B_part.linear() * plane.normal, data);
}

void PostSession::Impl::remember_cl(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis) {
  last_cl_point = p_mm;
  last_cl_axis = axis.normalized();
}

void PostSession::Impl::circular_move(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis,
                                      double radius_mm, const Eigen::Vector3d& p_mm,
                                      const Eigen::Vector3d& tool_axis, int cl_line,
                                      double chordal_tolerance_mm) {
  const SourceLocation at{o.source_name, cl_line, 0};
  if (!centre.allFinite() || !axis.allFinite() || !std::isfinite(radius_mm) || !p_mm.allFinite() ||
      !tool_axis.allFinite()) {
    throw Error(ErrorCode::bad_input,
                "a circular move with a coordinate that is not a finite number", at);
  }
  if (centre.cwiseAbs().maxCoeff() > kMaxCoordinateMm ||
      p_mm.cwiseAbs().maxCoeff() > kMaxCoordinateMm || radius_mm > kMaxCoordinateMm) {
    throw Error(
        ErrorCode::bad_input,
        fmt::format("a circular move with a coordinate or radius beyond {:g} mm", kMaxCoordinateMm),
        at);
  }
  const double norm = axis.norm();
  if (!(norm > 1e-9))
    throw Error(ErrorCode::bad_input, "a circular move with an axis of zero length", at);
  if (radius_mm < 0.0) {
    throw Error(ErrorCode::bad_input,
                fmt::format("a circular move with a negative radius {} mm", radius_mm), at);
  }
  if (!(tool_axis.norm() > 1e-9))
    throw Error(ErrorCode::bad_input, "a move with a tool axis of zero length", at);
  if (!started) {
    throw Error(ErrorCode::bad_input,
                "a circular move needs a start point, but no move came before it", at);
  }
  detail::ArcWording wording;
  wording.radius_from = "the circular move";
  const detail::ArcBuild built =
      detail::make_arc_chords(last_cl_point, centre, axis / norm, radius_mm, p_mm,
                              o.arc_point_tolerance_mm, chordal_tolerance_mm, wording);
  if (built.problem != detail::ArcProblem::none)
    throw Error(ErrorCode::bad_input, built.message, at);
  // Every chord of a rapid arc is rapid, as the reader marks them.
  const bool rapid = next_rapid;
  const Eigen::Vector3d chord_axis = last_cl_axis;
  // A feed arc in one plane with one tool axis may be one CIRC (circ.cpp); a full turn two, of
  // half a turn each (its start, middle and end give no circle: two of them coincide).
  const bool planar = std::fabs(built.arc.h1 - built.arc.h0) < 1e-9;
  const bool full_turn = built.arc.sweep_rad >= 2.0 * 3.14159265358979323846 - 1e-6;
  // Under the deflection model every chord is a cutting move with its own load and (under
  // compensate) its own moved target: a CIRC has one end and one via point only.
  if (!rapid && !approach_pending && writer.has_circ() && planar && built.arc.chords > 1 &&
      !deflection_on() && (tool_axis.normalized() - chord_axis).norm() < 1e-9) {
    next_rapid = false;
    if (!full_turn) {
      if (try_circ(built.arc, chord_axis, cl_line))
        return;
    } else {
      // Split at a chord's end, so that a half written as chords has the whole arc's chords.
      const long first = (built.arc.chords + 1) / 2;
      const double f = static_cast<double>(first) / static_cast<double>(built.arc.chords);
      const detail::ArcChords halves[2] = {
          detail::arc_piece(built.arc, 0.0, f, first),
          detail::arc_piece(built.arc, f, 1.0, built.arc.chords - first)};
      for (int h = 0; h < 2; ++h) {
        if (!try_circ(halves[h], chord_axis, cl_line))
          arc_chord_moves(halves[h], chord_axis, h == 1 ? tool_axis : chord_axis, false, cl_line);
      }
      return;
    }
  }
  arc_chord_moves(built.arc, chord_axis, tool_axis, rapid, cl_line);
}

// The chords of `arc` as moves, the last with the arc's end axis.
void PostSession::Impl::arc_chord_moves(const detail::ArcChords& arc,
                                        const Eigen::Vector3d& chord_axis,
                                        const Eigen::Vector3d& end_axis, bool rapid, int cl_line) {
  for (long k = 1; k <= arc.chords; ++k) {
    next_rapid = rapid;
    move(arc.point(k), k == arc.chords ? end_axis : chord_axis, cl_line, nullptr);
  }
}

}  // namespace redpost
