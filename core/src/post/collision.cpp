// Collisions in a post session (PostSession::Impl, post/session_impl.hpp; docs/collision.md):
// the cell's bodies, the set-up's and the tool's in one scene, and every written motion checked
// along its whole path as the controller runs it (a PTP joint-linear, a LIN on its line, a CIRC
// on its circle, the blend of $APO.CDIS around its corners) before it is written. A motion that
// would bring two bodies closer than the margin is refused with the CL line, the two bodies and
// their distance: nothing is written.
#include <algorithm>
#include <cmath>

#include "post/session_impl.hpp"
#include "redpost/io/error.hpp"

namespace redpost {

namespace {

// The zone beyond the margin where the tracker's clearance goal pushes the bodies apart (mm):
// the plan keeps this much beyond the margin too (CollisionOptions::plan_extra_mm).
constexpr double kGoalZoneMm = 10.0;

const char* motion_words(KrlMotionKind kind) {
  switch (kind) {
    case KrlMotionKind::lin:
      return "straight motion (LIN)";
    case KrlMotionKind::ptp_axes:
      return "PTP";
    case KrlMotionKind::rapid:
      return "rapid (PTP)";
  }
  return "motion";
}

// What to try, from the roles of the two bodies.
std::string collision_advice(const Body& a, const Body& b, bool planned) {
  const auto either = [&](BodyRole r) { return a.role == r || b.role == r; };
  std::string advice;
  if (either(BodyRole::part)) {
    advice =
        "only the cutter's flute may touch the part: a longer flute or tool (the tool table's "
        "flute-length and length, docs/tools.md), or a tool axis tilted away from the wall in "
        "the CAM system";
  } else if (either(BodyRole::fixture)) {
    advice =
        "check that the fixture's STL is in the CL frame (the frame the toolpath is in); move "
        "the part and fixture in the cell (--placement), or use a longer tool or holder so that "
        "the spindle stays farther from the fixture";
  } else {
    advice = "the cell would hit itself: move the part in the cell (--placement)";
  }
  if (planned)
    advice += "; let the plan move the track and the table (no --lock)";
  return advice +
         "; or, if the bodies are drawn too large, lower --collision-margin (default 5 mm)";
}

}  // namespace

void PostSession::Impl::start_collision() {
  if (!o.collision.check)
    return;
  cell_bodies = load_cell_bodies(cell);
  setup = setup_bodies(o.collision.setup, o.T_B_part);
  if (!std::isfinite(o.collision.margin_mm) || o.collision.margin_mm < 0.0 ||
      o.collision.margin_mm > 1000.0) {
    throw Error(ErrorCode::bad_input,
                fmt::format("the collision margin must be a number of mm from 0 to 1000, got {}",
                            o.collision.margin_mm));
  }
  summary.collision_margin_mm = o.collision.margin_mm;
  // The tracker with the clearance goal (made before any pose is tracked).
  o.tracker.extra_goal = &goal_proxy;
  tracker = Tracker(*active_cell, o.tracker);
  if (!setup.empty() && !cell_bodies.declared) {
    summary.warnings.push_back(fmt::format(
        "the cell {} has no <collision> bodies: the set-up is checked against the tool only "
        "(docs/cell-format.md, \"<collision>\")",
        cell.source_file.empty() ? cell.name : cell.source_file));
  }
  rebuild_scene();
}

// The scene of the cell, the set-up and the active tool, on the active tool's cell; the
// monitor starts again at the last written posture (a tool change is a stop).
void PostSession::Impl::rebuild_scene() {
  std::vector<Body> bodies = cell_bodies.bodies;
  const int cell_count = static_cast<int>(bodies.size());
  bodies.insert(bodies.end(), setup.begin(), setup.end());
  const int shared = static_cast<int>(bodies.size());
  bodies.insert(bodies.end(), tool_bodies_in_use.begin(), tool_bodies_in_use.end());
  (void)cell_count;
  std::unique_ptr<CollisionScene> next = std::make_unique<CollisionScene>(
      *active_cell, std::move(bodies), cell_bodies.allowed, scene.get(),
      scene ? std::min(shared, scene->body_count()) : 0);
  clearance.reset();
  goal_proxy.goal = nullptr;
  clearance_goal.reset();
  // The planning side's monitor too: a new scene may take the old one's address. (A tool
  // change drains the pipeline before the next window is planned: no plan runs meanwhile.)
  plan_monitor.reset();
  plan_monitor_scene = nullptr;
  scene = std::move(next);
  summary.collision_bodies = scene->body_count();
  summary.collision_pairs = static_cast<int>(scene->pairs().size());
  summary.collision_checked = summary.collision_checked || !scene->pairs().empty();
  pair_names.clear();
  for (std::size_t p = 0; p < scene->pairs().size(); ++p)
    pair_names.push_back(scene->pair_name(static_cast<int>(p)));
  if (scene->pairs().empty())
    return;
  ClearanceSettings settings;
  settings.margin_mm = o.collision.margin_mm;
  clearance = std::make_unique<ClearanceMonitor>(*scene, settings);
  clearance_goal = std::make_unique<ClearanceGoal>(*scene, settings.margin_mm + kGoalZoneMm);
  goal_proxy.goal = clearance_goal.get();
  if (have_written)
    clearance_goal->set_active(clearance->start(q_written).nearest_mm <
                               settings.margin_mm + kGoalZoneMm);
}

// A tool change: the tool's cylinders from the tool table's geometry, else the CL file's
// diameter and length (docs/tools.md, "Geometry").
void PostSession::Impl::collision_tool(const ToolEntry* entry, double length_mm, int number,
                                       int cl_line) {
  if (!o.collision.check)
    return;
  ToolGeometry g;
  g.name = fmt::format("tool {}", number);
  g.length_mm = length_mm > 0.0 ? length_mm : cell.tools.reference_length_mm;
  g.diameter_mm = tool_diameter_mm;
  if (entry) {
    if (std::isfinite(entry->diameter_mm))
      g.diameter_mm = entry->diameter_mm;
    g.flute_length_mm = entry->flute_length_mm;
    g.shank_diameter_mm = entry->shank_diameter_mm;
    g.holder_diameter_mm = entry->holder_diameter_mm;
    g.holder_length_mm = entry->holder_length_mm;
  }
  std::string note;
  tool_bodies_in_use = tool_bodies(g, &note);
  if (!note.empty() && tool_notes++ < 20)
    summary.warnings.push_back(fmt::format("{}:{}: {}", o.source_name, cl_line, note));
  rebuild_scene();
}

// The motion to q1 (kind, and for a CIRC its circle in {B}) checked along its whole path from the
// last written posture; refused (Error) where two bodies come closer than the margin. The first
// motion comes from wherever the robot stands: only its end is checked.
void PostSession::Impl::check_clearance(KrlMotionKind kind, const JointVector& q1, int cl_line,
                                        const Circle* arc_B) {
  motion_clearance.reset();
  if (!clearance)
    return;
  MotionClearance c;
  if (!clearance->started() || !have_written) {
    c = clearance->start(q1);
    last_cp_length = 0.0;
  } else if (kind != KrlMotionKind::lin) {
    c = clearance->advance(JointLinePath(q_written, q1));
    last_cp_length = 0.0;  // an exact stop: no blend into the next motion
  } else {
    std::string why;
    const ArmIk* ik = arm_ik_for_active(why);
    std::unique_ptr<JointPath> path;
    if (ik && arc_B)
      path = std::make_unique<CartesianPath>(*ik, *active_cell, q_written, q1, *arc_B);
    else if (ik)
      path = std::make_unique<CartesianPath>(*ik, *active_cell, q_written, q1);
    else
      path = std::make_unique<JointLinePath>(q_written, q1);
    // The blend of $APO.CDIS at each end: the controller leaves the corner within that
    // distance, in the joints' hull of the two motions' ends (to first order); and a SPLINE
    // block's segments stray from their chords within the tolerance the writer keeps.
    const Eigen::Vector3d step = physical_tcp_fk(q1).translation() - T_written.translation();
    const double length = step.norm();
    // The corner at the start, between the last CP motion's direction and this one's: the
    // blend strays from the written path by at most sin(angle / 2) of its reach into each.
    double share = 0.0;
    if (last_cp_length > 0.0 && length > 1e-9) {
      const double cosine = std::clamp(last_cp_direction.dot(step / length), -1.0, 1.0);
      share = std::sqrt(0.5 * (1.0 - cosine));
    } else if (length <= 1e-9) {
      share = 1.0;  // a turn on the spot: its corners are not known by a direction
    }
    path->blend_fraction = share * (length > 1e-9 ? std::min(0.5, apo_mm / length) : 0.5);
    path->blend_fraction_before =
        share * (last_cp_length > 1e-9 ? std::min(0.5, apo_mm / last_cp_length) : 0.5);
    path->allowance_mm = spline_allowance_mm;
    if (length > 1e-9) {
      last_cp_direction = step / length;
      last_cp_length = length;
    }
    c = clearance->advance(*path);
  }
  summary.clearance_queries = clearance->distance_queries();
  if (c.nearest_mm < summary.least_clearance_mm) {
    summary.least_clearance_mm = c.nearest_mm;
    summary.least_clearance_line = cl_line;
    summary.least_clearance_pair = scene->pair_name(c.nearest_pair);
  }
  summary.proven_clearance_mm = std::min(summary.proven_clearance_mm, c.least_mm);
  if (c.path_lost) {
    throw Error(ErrorCode::unreachable,
                fmt::format("the controller's path of this {} cannot be followed by the arm in "
                            "the posture it starts in (at {:.0f} % of it), so its clearance "
                            "cannot be checked",
                            motion_words(kind), 100.0 * c.s),
                SourceLocation{o.source_name, cl_line, 0});
  }
  motion_clearance = c;
  // The tracker steers clear where this motion came near a body (its extra goal).
  if (clearance_goal)
    clearance_goal->set_active(c.nearest_mm < o.collision.margin_mm + kGoalZoneMm);
  if (!c.clear)
    collision_fail(c, kind, cl_line);
}

void PostSession::Impl::collision_fail(const MotionClearance& c, KrlMotionKind kind, int cl_line) {
  const BodyPair& p = scene->pairs()[static_cast<std::size_t>(c.pair)];
  const Body& a = scene->body(p.a);
  const Body& b = scene->body(p.b);
  const std::string where = c.s <= 0.0   ? "at its start"
                            : c.s >= 1.0 ? "at its end"
                                         : fmt::format("at {:.0f} % of it", 100.0 * c.s);
  const std::string rapid =
      routing_rapid ? "this rapid traverse, also when routed up along the tool axis by 100, 200 "
                      "and 400 mm; "
                    : "";
  const char* unproven =
      "cannot be proven to stay apart (no distance computed on it is below the margin, but the "
      "bound of the motion between them did not close: a joint that jumps within it?)";
  const ClearanceShortfall why = shortfall(c);
  const std::string distance =
      why == ClearanceShortfall::touching ? std::string("would touch or pass through each other")
      : why == ClearanceShortfall::unproven
          ? std::string(unproven)
          : fmt::format("would come within {:.2f} mm of each other", c.least_mm);
  throw Error(ErrorCode::unreachable,
              fmt::format("collision: the {} and the {} {} on this {} ({}{}; {:g} mm must stay "
                          "between them, --collision-margin). Try: {}",
                          a.name, b.name, distance, motion_words(kind), rapid, where,
                          o.collision.margin_mm, collision_advice(a, b, planning())),
              SourceLocation{o.source_name, cl_line, 0});
}

// The keyframes whose posture, or the joints' straight line to it from the one before, comes
// closer to a body than `need` (mm).
std::vector<int> PostSession::Impl::unclear_keyframes(const std::vector<JointVector>& q,
                                                      double need) {
  std::vector<int> out;
  if (!scene || scene->pairs().empty() || q.empty())
    return out;
  if (!plan_monitor || plan_monitor_scene != scene.get() ||
      plan_monitor->settings().margin_mm != need) {
    ClearanceSettings settings;
    settings.margin_mm = need;
    settings.resolution_mm = 0.5;  // a plan's check: the written motions are proven
    plan_monitor = std::make_unique<ClearanceMonitor>(*scene, settings);
    plan_monitor_scene = scene.get();
  }
  if (!plan_monitor->start(q.front()).clear)
    out.push_back(0);
  for (std::size_t k = 1; k < q.size(); ++k) {
    if (!plan_monitor->advance(JointLinePath(q[k - 1], q[k])).clear) {
      out.push_back(static_cast<int>(k));
      plan_monitor->start(q[k]);  // on from here, to find the next place
    }
  }
  return out;
}

// The window planned again, without the postures that come too close to a body on the
// keyframes around each place found (lazily: only where the plan found came too close, which
// gives the plan a full check of every node would give where it is clear; docs/collision.md,
// "The plan"): first with the plan's extra room beyond the margin (the tracker follows the plan
// closely, not exactly), then, where no plan keeps that much, with less. The last plan found is
// kept either way: what is written is checked again, motion by motion, and refused there if it
// still comes too close.
void PostSession::Impl::avoid_in_plan(const std::vector<PlanKeyframe>& kf, PlanWindowResult& r,
                                      const PathPlanner& pl, const JointVector* start,
                                      const PlanHistory* history, PlanBatch& batch) {
  constexpr int kAttempts = 8;
  const double margin = o.collision.margin_mm, extra = o.collision.plan_extra_mm;
  for (const double need : {margin + extra, margin + 0.25 * extra, margin + 0.05 * extra}) {
    std::vector<int> unclear = unclear_keyframes(r.q, need);
    if (unclear.empty())
      return;
    const CollisionScene* s = scene.get();
    PlanNodeFilter filter;
    filter.layers.assign(kf.size(), 0);
    filter.clear = [s, need](const JointVector& q) {
      // One set of poses per thread of the pool, sized for this scene.
      thread_local ScenePoses poses;
      thread_local KinematicsData fk;
      thread_local const CollisionScene* sized = nullptr;
      // A new scene may take a freed one's address: its size tells them apart as well.
      if (sized != s || poses.T_B_body.size() != static_cast<std::size_t>(s->body_count())) {
        s->prepare(poses);
        sized = s;
      }
      return posture_clearance(*s, q, need, poses, fk) >= need;
    };
    for (int attempt = 0; attempt < kAttempts && !unclear.empty(); ++attempt) {
      // The keyframes around each place (more each time a place comes back).
      const int reach = 2 + 2 * attempt;
      const int final_kf = static_cast<int>(kf.size()) - 1;
      for (int k : unclear) {
        for (int j = std::max(0, k - reach); j <= std::min(final_kf, k + reach); ++j)
          filter.layers[static_cast<std::size_t>(j)] = 1;
      }
      PlanWindowResult again = pl.plan(kf, start, 0, &filter, history);
      batch.ik_evaluations += again.ik_evaluations;
      if (!again.feasible)
        break;  // none keeps this much room here: try with less
      r = std::move(again);
      unclear = unclear_keyframes(r.q, need);
    }
    if (unclear.empty())
      return;
  }
}

PoseResult PostSession::Impl::clear_first_pose(const TcpTarget& target, const PoseResult& solved) {
  if (!scene || scene->pairs().empty())
    return solved;
  ScenePoses poses;
  scene->prepare(poses);
  KinematicsData fk;
  // A little beyond the margin: the PTP to it and the motions from it are checked again.
  const double need = o.collision.margin_mm + 1.0;
  if (posture_clearance(*scene, solved.q, need, poses, fk) >= need)
    return solved;
  std::string why;
  const ArmIk* ik = arm_ik_for_active(why);
  if (!ik)
    return solved;
  // The TCP frames of the target (z the tool axis, every 15 deg of turn about it: the spin),
  // the arm's eight postures at each, the external axes where the tracker put them.
  const Cell& c = *active_cell;
  const Eigen::Vector3d z = target.z_B.normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z.x() * z;
  if (x.norm() < 1e-6)
    x = Eigen::Vector3d::UnitY() - z.y() * z;
  x.normalize();
  const JointVector home = c.home(), w = c.weights();
  JointVector best;
  double best_cost = std::numeric_limits<double>::infinity();
  for (int turn = 0; turn < 24; ++turn) {
    Isometry T = Isometry::Identity();
    const Eigen::Vector3d xt = Eigen::AngleAxisd(deg_to_rad(15.0 * turn), z) * x;
    T.linear().col(0) = xt;
    T.linear().col(1) = z.cross(xt);
    T.linear().col(2) = z;
    T.translation() = target.p_B_mm;
    const ArmIkSolutions sol = ik->solve(T, solved.q, &solved.q);
    for (std::size_t mu = 0; mu < 8; ++mu) {
      if (!sol.valid[mu])
        continue;
      const JointVector& q = sol.q[mu];
      const double cost = (q - home).cwiseAbs2().cwiseProduct(w).sum();
      if (cost >= best_cost)
        continue;
      if (posture_clearance(*scene, q, need, poses, fk) >= need) {
        best = q;
        best_cost = cost;
      }
    }
  }
  if (best.size() == 0)
    return solved;  // none clear: the first motion's check refuses with the bodies and the line
  // The tracker's own result at that posture (its conditioning and margins).
  const JointVector kept = tracker.q();
  tracker.reset(best);
  PoseResult r = tracker.correct(target);
  tracker.reset(kept);
  if (r.status != PoseStatus::converged)
    return solved;
  return r;
}

PostSession::Impl::TrackedState PostSession::Impl::tracked_state() const {
  TrackedState s;
  s.poses = summary.poses;
  s.joints = summary.joints;
  s.lowest = summary.lowest_inv_condition;
  s.lowest_line = summary.lowest_inv_condition_line;
  s.plan_s = plan_s;
  s.last_target = last_target;
  s.cl_point = last_cl_point;
  s.cl_axis = last_cl_axis;
  return s;
}

void PostSession::Impl::restore_tracked(const TrackedState& s, const JointVector& q) {
  summary.poses = s.poses;
  summary.joints = s.joints;
  summary.lowest_inv_condition = s.lowest;
  summary.lowest_inv_condition_line = s.lowest_line;
  plan_s = s.plan_s;
  last_target = s.last_target;
  last_cl_point = s.cl_point;
  last_cl_axis = s.cl_axis;
  tracker.reset(q);
  line_steps.clear();
}

bool PostSession::Impl::probe_clear(const JointVector& qa, const JointVector& qb, bool ptp) {
  std::string why;
  const ArmIk* ik = ptp ? nullptr : arm_ik_for_active(why);
  return ik ? clearance->probe(CartesianPath(*ik, *active_cell, qa, qb)).clear
            : clearance->probe(JointLinePath(qa, qb)).clear;
}

bool PostSession::Impl::rapid_clear(const JointVector& q1, bool ptp) {
  if (!clearance || !clearance->started() || !have_written)
    return true;
  return probe_clear(q_written, q1, ptp);
}

void PostSession::Impl::route_rapid_up(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis,
                                       int cl_line) {
  const JointVector q_start = tracker.q();
  const TrackedState start = tracked_state();
  const Eigen::Vector3d z0 = last_cl_axis, z1 = axis.normalized();
  for (const double lift : {100.0, 200.0, 400.0}) {
    // Up along the tool axis (out of the material), over at the higher of the two heights,
    // down along the target's axis.
    const Eigen::Vector3d up0 = start.cl_point + lift * z0;
    const Eigen::Vector3d up1 = p_mm + lift * z1;
    const Eigen::Vector3d legs[3] = {up0, up1, p_mm};
    const Eigen::Vector3d axes[3] = {z0, z1, z1};
    bool clear = true;
    try {
      for (int k = 0; k < 3 && clear; ++k) {
        const JointVector qa = tracker.q();
        const TcpTarget t = target_in_B(legs[k], axes[k], cl_line);
        track_line(t, cl_line, false);
        last_target = t;
        // Each leg from where the one before ends: probe it from there.
        clear = !clearance || probe_clear(qa, tracker.q(), false);
      }
    } catch (const Error&) {
      clear = false;  // a leg out of reach: higher, or refused below
    }
    restore_tracked(start, q_start);
    if (!clear)
      continue;
    summary.warnings.push_back(fmt::format(
        "{}:{}: this rapid traverse would come closer than {:g} mm to a body: it is written "
        "{:g} mm up along the tool axis, over and down instead (docs/collision.md)",
        o.source_name, cl_line, o.collision.margin_mm, lift));
    routing_rapid = true;
    set_speed(o.rapid_velocity_m_per_s, false);
    for (int k = 0; k < 3; ++k) {
      const TcpTarget t = target_in_B(legs[k], axes[k], cl_line);
      track_line(t, cl_line, false);
      emit_line(cl_line);
      last_target = t;
      remember_cl(legs[k], axes[k]);
    }
    routing_rapid = false;
    return;
  }
  // None clear: the straight rapid is tracked and written as it was, and its check refuses it
  // with the two bodies and the distance.
  routing_rapid = true;
  const TcpTarget target = target_in_B(p_mm, axis, cl_line);
  track_line(target, cl_line, false);
  set_speed(o.rapid_velocity_m_per_s, false);
  emit_line(cl_line);
  routing_rapid = false;
  last_target = target;
  remember_cl(p_mm, axis);
}

std::vector<Body> PostSession::collision_bodies() const {
  std::vector<Body> out;
  if (!impl_->scene)
    return out;
  for (int i = 0; i < impl_->scene->body_count(); ++i)
    out.push_back(impl_->scene->body(i));
  return out;
}

}  // namespace redpost
