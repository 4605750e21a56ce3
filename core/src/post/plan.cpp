// Whole-path planning in the session (docs/redundancy.md, "Whole-path planning"): the calls are
// buffered until the path ahead covers the planning horizon (or a tool change or the end comes),
// the free joints are planned over that window by dynamic programming (path_plan.hpp), the
// first 85 % of the window are committed, and the calls they cover are released to be
// tracked and written, the tracker pulled towards the committed plan at every pose. The next
// window starts from the last committed keyframe, so memory stays flat in the path's length.
#include <algorithm>
#include <cmath>
#include <limits>

#include "post/session_impl.hpp"
#include "redpost/io/error.hpp"
#include "redpost/machining/elastostatic.hpp"
#include "redpost/machining/quality.hpp"
#include "redpost/post/plan_time.hpp"

namespace redpost {

namespace {

bool is_motion(const ClEvent& e) {
  return e.kind == ClEventKind::move || e.kind == ClEventKind::arc;
}

// Calls a buffer holds at most before a window is planned whatever its length.
constexpr std::size_t kMaxDeferred = 20000;
// Tool axis turn between keyframes at most (deg).
constexpr double kTurnDeg = 5.0;
// A keyframe this close to a rapid's end stands for it (no second keyframe there), mm.
constexpr double kAirGapMm = 0.5;
// A feed move within this angle of the tool axis, away from the part, is a retract (deg)...
constexpr double kRetractDeg = 10.0;
// ... where it is at least this long (mm). A shorter one may stay between the part's walls (NX's
// 3 mm departures in a pocket, nx_cutcom_load_tool): taken as air there, it gave the centring a
// free place at every pass's end, and the track went 760 mm in one direction over that job
// instead of 240 (2026-12-07).
constexpr double kRetractMinMm = 10.0;

// Caro's criterion for the plan (path_plan.hpp), where the cell's six arm joints have stiffness
// data: the tool's deflection normal to the feed and the tool axis, c = |n . dX|, under a nominal
// 100 N load along that normal n (the radial cutting force, which spoils the machined surface
// most; Caro 2014 eq. 5.1 with the elastostatic model of eq. 4.1). Empty otherwise.
constexpr double kNominalRadialForceN = 100.0;

std::function<double(const JointVector&, const Eigen::Vector3d&, const Eigen::Vector3d&)>
nominal_deflection(const Cell& cell) {
  int compliant = 0;
  for (int i = 0; i < cell.size(); ++i)
    compliant += cell.joint(i).stiffness ? 1 : 0;
  if (compliant != 6)
    return {};
  return [&cell](const JointVector& q, const Eigen::Vector3d& feed_B, const Eigen::Vector3d& z_B) {
    const Eigen::Vector3d n = z_B.cross(feed_B).normalized();
    Vector6d w = Vector6d::Zero();
    w.tail<3>() = kNominalRadialForceN * n;
    const Vector6d dX = tcp_displacement(cell, q, w);
    return normal_tool_deflection_mm(dX.tail<3>(), z_B, feed_B);
  };
}

// Walks the buffered calls along the path, as the session will track it (CL points in order,
// arcs as their chords), placing a keyframe every `spacing` mm of path.
struct KeyframeWalk {
  const PostOptions& o;
  double spacing;
  std::vector<PlanKeyframe> kf;
  // Where each motion (each of an arc's chords) ends, as the time model's points
  // (estimate_plan_time).
  std::vector<PlanKeyframe> ends;
  Eigen::Vector3d p_cl, z_cl;  // the walker's CL point and tool axis (CL frame)
  double s = 0.0;              // path length in {B} at p_cl
  double next_kf_s = 0.0;      // where the next keyframe goes
  double feed_mm_s = 0.0;
  bool rapid_next = false;
  bool rapid_now = false;  // the motion walked is a rapid traverse (PTP or LIN)
  bool air_now = false;    // ... is out of the material: a rapid, or a retract at feed
  bool ptp_now = false;    // ... written as a PTP (above its clearance plane)
  Eigen::Vector3d plane_point = Eigen::Vector3d::Zero();  // that plane (CL frame)
  Eigen::Vector3d plane_normal = Eigen::Vector3d::UnitZ();
  // Where the run of air moves walked began (infinity: none): a keyframe whose previous one is at
  // or after it is reached in the air (PlanKeyframe::in_air).
  double air_since_s = std::numeric_limits<double>::infinity();

  PlanKeyframe at(const Eigen::Vector3d& p, const Eigen::Vector3d& z, double s_mm, double speed,
                  int line) const {
    PlanKeyframe k;
    k.target = TcpTarget::axis(o.T_B_part * p, o.T_B_part.linear() * z.normalized());
    k.s_mm = s_mm;
    k.speed_mm_s = speed;
    k.rapid = ptp_now;
    if (ptp_now) {
      k.clearance_point_B = o.T_B_part * plane_point;
      k.clearance_normal_B = o.T_B_part.linear() * plane_normal;
    }
    k.traverse = rapid_now;
    k.in_air = air_now && !kf.empty() && kf.back().s_mm >= air_since_s - kAirGapMm;
    k.cl_line = line;
    return k;
  }

  void segment(const Eigen::Vector3d& p1, const Eigen::Vector3d& z1, double speed, int line) {
    const double length = (o.T_B_part.linear() * (p1 - p_cl)).norm();
    const Eigen::Vector3d z1n = z1.normalized();
    // Keyframes every `spacing` mm, and every kTurnDeg of tool axis turn: a 5-axis path may turn
    // the tool fast over little length, and the plan must see the wrist's way through it.
    const double turn = std::acos(std::clamp(z_cl.dot(z1n), -1.0, 1.0));
    const int turns = static_cast<int>(std::ceil(rad_to_deg(turn) / kTurnDeg - 1e-9));
    // An air move's ends are keyframes, so that the plan can move the external axes within it
    // and not in the cut before or after (PathPlanSettings::w_travel_cut).
    if (air_now && !kf.empty() && kf.back().s_mm < s - kAirGapMm) {
      kf.push_back(at(p_cl, z_cl, s, speed, line));
      next_kf_s = s + spacing;
    }
    std::vector<double> at_t;
    while (length > 0.0 && next_kf_s <= s + length - 1e-9) {
      at_t.push_back((next_kf_s - s) / length);
      next_kf_s += spacing;
    }
    for (int k = 1; k < turns; ++k)
      at_t.push_back(static_cast<double>(k) / turns);
    std::sort(at_t.begin(), at_t.end());
    double last_t = -1.0;
    for (double t : at_t) {
      if (t - last_t < 1e-9)
        continue;
      last_t = t;
      const Eigen::Vector3d z = ((1.0 - t) * z_cl + t * z1n).normalized();
      kf.push_back(at(p_cl + t * (p1 - p_cl), z, s + t * length, speed, line));
    }
    if (turns > 1 && length <= 0.0)
      kf.push_back(at(p1, z1n, s, speed, line));  // a pure turn: its end
    if (air_now && !kf.empty() && kf.back().s_mm < s + length - kAirGapMm) {
      kf.push_back(at(p1, z1n, s + length, speed, line));
      next_kf_s = s + length + spacing;
    }
    s += length;
    p_cl = p1;
    z_cl = z1n;
    ends.push_back(at(p_cl, z_cl, s, speed, line));
  }

  // Whether a rapid to e is written as a PTP: both its ends at or above its clearance plane
  // (the cycle's, or --clearance; motion.cpp, rapid_move). One that crosses the plane is split
  // there, partly a LIN: it is taken as a LIN.
  bool above_plane(const ClEvent& e) {
    Eigen::Vector3d& point = plane_point;
    Eigen::Vector3d& normal = plane_normal;
    if (e.has_clearance) {
      point = e.clearance_p_mm;
      normal = e.tool_axis.normalized();
    } else if (std::isfinite(o.clearance_z_mm)) {
      point = Eigen::Vector3d(0.0, 0.0, o.clearance_z_mm);
      normal = Eigen::Vector3d::UnitZ();
    } else {
      return false;
    }
    constexpr double kOn = 1e-6;  // as rapid_move: a point on the plane counts as above it
    return normal.dot(p_cl - point) >= -kOn && normal.dot(e.p_mm - point) >= -kOn;
  }

  // Whether e is a retract at feed: a move that leaves along the tool axis (within kRetractDeg,
  // the axis fixed, at least kRetractMinMm long), as CAM systems write a departure from the cut.
  // It moves out of the material whatever the stock. A plunge is not taken as air: it ends in
  // the cut.
  bool retract(const ClEvent& e) const {
    if (e.kind != ClEventKind::move || !e.p_mm.allFinite() || !e.tool_axis.allFinite())
      return false;
    const Eigen::Vector3d d = e.p_mm - p_cl;
    const double length = d.norm();
    const double n = e.tool_axis.norm();
    if (length < kRetractMinMm || n < 1e-9 || z_cl.dot(e.tool_axis / n) < std::cos(deg_to_rad(0.1)))
      return false;
    return d.dot(z_cl) >= length * std::cos(deg_to_rad(kRetractDeg));
  }

  // The path of one motion call; its end's s.
  double motion(const ClEvent& e) {
    const bool was_air = air_now;
    rapid_now = e.rapid || rapid_next;
    ptp_now = rapid_now && above_plane(e);
    air_now = rapid_now || retract(e);
    if (!air_now)
      air_since_s = std::numeric_limits<double>::infinity();
    else if (!was_air)
      air_since_s = s;
    const double speed = rapid_now ? 1000.0 * o.rapid_velocity_m_per_s : feed_mm_s;
    rapid_next = false;
    if (e.kind == ClEventKind::arc) {
      const double norm = e.arc_axis.norm();
      if (norm > 1e-9 && e.p_mm.allFinite() && e.arc_centre_mm.allFinite()) {
        const detail::ArcBuild built =
            detail::make_arc_chords(p_cl, e.arc_centre_mm, e.arc_axis / norm, e.value, e.p_mm,
                                    o.arc_point_tolerance_mm, o.chordal_tolerance_mm);
        if (built.problem == detail::ArcProblem::none) {
          for (long k = 1; k <= built.arc.chords; ++k)
            segment(built.arc.point(k), k == built.arc.chords ? e.tool_axis : z_cl, speed, e.line);
          return s;
        }
      }
    }
    if (e.p_mm.allFinite() && e.tool_axis.allFinite() && e.tool_axis.norm() > 1e-9)
      segment(e.p_mm, e.tool_axis, speed, e.line);
    return s;
  }
};

// Walks the buffered calls from index `from` (feeds, rapids, motions) up to a tool change or the
// end; b.end_s, end_p and end_z get each motion's path length, CL point and tool axis at its end.
// Returns where the walk stopped.
std::size_t walk_calls(const std::deque<ClEvent>& calls, std::size_t from, KeyframeWalk& w,
                       PlanBatch& b, bool& barrier) {
  for (std::size_t i = from; i < calls.size(); ++i) {
    const ClEvent& e = calls[i];
    if (e.kind == ClEventKind::tool_change) {
      barrier = true;
      return i;
    }
    if (e.kind == ClEventKind::feed && std::isfinite(e.value) && e.value > 0.0) {
      w.feed_mm_s = e.value / 60.0;
    } else if (e.kind == ClEventKind::rapid) {
      w.rapid_next = true;
    } else if (is_motion(e)) {
      b.end_s[i] = w.motion(e);
      b.end_p[i] = w.p_cl;
      b.end_z[i] = w.z_cl;
    }
  }
  return calls.size();
}

// The batch's per-call vectors for `n` calls, none a motion's end yet.
void size_batch(PlanBatch& b, std::size_t n) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  b.end_s.assign(n, nan);
  b.end_p.assign(n, Eigen::Vector3d::Constant(nan));
  b.end_z.assign(n, Eigen::Vector3d::Constant(nan));
}

// The batch keeps its first n calls' entries.
void keep_first(PlanBatch& b, std::size_t n) {
  b.end_s.resize(n);
  b.end_p.resize(n);
  b.end_z.resize(n);
}

}  // namespace

// The first window after an approach (the program's start, a tool change) picks the branch the
// rest follows: where the table stands, where the track starts. Seen over one horizon (800 mm) a
// branch may look cheapest that runs an axis into its limit soon after; the first window sees
// three horizons (and commits as much as any window).
constexpr double kFirstWindowHorizons = 3.0;

double PostSession::Impl::window_mm() const {
  const bool fresh = !cursor.started || cursor.approach_pending;
  return fresh ? kFirstWindowHorizons * o.plan_horizon_mm : o.plan_horizon_mm;
}

void PostSession::Impl::reset_plan() {
  plan_kf.clear();
  plan_q.clear();
  plan_s = 0.0;
  tracker.stop_following();
}

std::bitset<kMaxJoints> external_axes(const Cell& cell) {
  std::bitset<kMaxJoints> axes;
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    axes.set(static_cast<std::size_t>(i),
             j.axis.kind == AxisKind::external && j.type != JointType::virtual_spin);
  }
  return axes;
}

const PathPlanner& PostSession::Impl::planner_for_active(int cl_line) {
  if (!planner || planner_cell != active_cell) {
    std::string why;
    const ArmIk* ik = arm_ik_for_active(why);
    if (!ik) {
      throw Error(ErrorCode::bad_input,
                  "the whole-path plan needs the arm's closed-form inverse kinematics: " + why +
                      " (use --plan local)",
                  SourceLocation{o.source_name, cl_line, 0});
    }
    PathPlanSettings settings = o.plan_settings;
    settings.normal_deflection_mm = nominal_deflection(*active_cell);
    // Rapids are written as PTPs at the template set's share of the axis speeds.
    settings.rapid_velocity_fraction = ptp_velocity_fraction;
    // Under threads >= 2 the pool is the pipeline's (session.cpp, pump).
    settings.pool = plan_pool.get();
    planner = std::make_unique<PathPlanner>(*active_cell, *ik, settings);
    planner_cell = active_cell;
    // The rotary external axes the user left free, held at home for the second start.
    planner_held.reset();
    PathPlanSettings held = settings;
    if (held.lock_value.size() != active_cell->size())
      held.lock_value =
          JointVector::Constant(active_cell->size(), std::numeric_limits<double>::quiet_NaN());
    bool any = false;
    for (int i = 0; i < active_cell->size(); ++i) {
      const Joint& j = active_cell->joint(i);
      const auto iu = static_cast<std::size_t>(i);
      const bool in_arm =
          std::find(ik->arm_joints().begin(), ik->arm_joints().end(), i) != ik->arm_joints().end();
      if (in_arm || j.type != JointType::revolute || held.locked.test(iu))
        continue;
      held.locked.set(iu);
      held.lock_value[i] = j.home;
      any = true;
    }
    if (any)
      planner_held = std::make_unique<PathPlanner>(*active_cell, *ik, held);
    // Every external axis the user left free held where the window starts: the alternative
    // each window's plan is timed against (choose_still).
    planner_still.reset();
    PathPlanSettings still = settings;
    if (still.lock_value.size() != active_cell->size())
      still.lock_value =
          JointVector::Constant(active_cell->size(), std::numeric_limits<double>::quiet_NaN());
    const std::bitset<kMaxJoints> external = external_axes(*active_cell);
    any = false;
    for (int i = 0; i < active_cell->size(); ++i) {
      const auto iu = static_cast<std::size_t>(i);
      if (!external.test(iu) || still.locked.test(iu))
        continue;
      still.locked.set(iu);
      still.lock_value[i] = std::numeric_limits<double>::quiet_NaN();
      any = true;
    }
    if (any && settings.hold_gain >= 0.0)
      planner_still = std::make_unique<PathPlanner>(*active_cell, *ik, still);
  }
  return *planner;
}

void PostSession::Impl::follow_plan(double s_mm) {
  if (plan_q.empty()) {
    if (hold_unplanned)
      tracker.follow(tracker.q(), o.plan_follow_gain, 0.2, external_axes(*active_cell));
    else
      tracker.stop_following();
    return;
  }
  // The external axes (track, table) run exactly as planned; the arm and the spin follow.
  tracker.follow(interpolate_plan(plan_kf, plan_q, s_mm), o.plan_follow_gain, 0.2,
                 external_axes(*active_cell));
}

// Commits the plan's keyframes up to commit_s (at least to the end of the first motion) into the
// batch and returns how many buffered calls that releases: those whose motion ends within the
// committed plan, and the calls after them up to the next motion that does not.
std::size_t PostSession::Impl::commit_window(const std::vector<PlanKeyframe>& kf,
                                             const std::vector<JointVector>& q,
                                             const std::vector<double>& end_s, std::size_t end,
                                             double commit_s, bool fresh, PlanBatch& batch) const {
  for (std::size_t k = 0; k < end; ++k) {
    if (!std::isnan(end_s[k])) {
      commit_s = std::max(commit_s, end_s[k]);
      break;
    }
  }
  std::size_t committed = 0;
  while (committed + 1 < kf.size() && kf[committed + 1].s_mm <= commit_s + 1e-9)
    ++committed;
  if (kf[committed].s_mm + 1e-9 < commit_s && committed + 1 < kf.size())
    ++committed;  // the first keyframe beyond an end that falls between keyframes
  const double boundary_s = kf[committed].s_mm;
  for (std::size_t k = fresh ? 0 : 1; k <= committed; ++k) {
    batch.kf.push_back(kf[k]);
    batch.q.push_back(q[k]);
  }
  std::size_t n = 0;
  while (n < end && (std::isnan(end_s[n]) || end_s[n] <= boundary_s + 1e-9))
    ++n;
  return n;
}

void PostSession::Impl::apply_plan(const PlanBatch& batch) {
  summary.plan_windows += batch.windows;
  summary.plan_ik_evaluations += batch.ik_evaluations;
  summary.plan_fallback_windows += batch.fallback_windows;
  summary.plan_still_windows += batch.still_windows;
  for (const std::string& w : batch.front_warnings)
    summary.warnings.push_back(w);
  for (const std::string& w : batch.warnings)
    summary.warnings.push_back(w);
  if (batch.reset) {
    reset_plan();
    plan_s = batch.reset_plan_s;
  }
  if (batch.kf.empty())
    return;
  // Keep the committed keyframes the released calls still need (from the one before plan_s).
  std::size_t keep_from = 0;
  while (keep_from + 1 < plan_kf.size() && plan_kf[keep_from + 1].s_mm <= plan_s)
    ++keep_from;
  plan_kf.erase(plan_kf.begin(), plan_kf.begin() + static_cast<std::ptrdiff_t>(keep_from));
  plan_q.erase(plan_q.begin(), plan_q.begin() + static_cast<std::ptrdiff_t>(keep_from));
  plan_kf.insert(plan_kf.end(), batch.kf.begin(), batch.kf.end());
  plan_q.insert(plan_q.end(), batch.q.begin(), batch.q.end());
}

void PostSession::Impl::advance_cursor(const PlanBatch& batch) {
  PlanCursor& c = cursor;
  if (batch.reset) {
    c.plan_empty = true;
    c.plan_s = batch.reset_plan_s;
    c.tail_heading = {};
  }
  if (!batch.kf.empty()) {
    // The committed postures, from the last one before them (a plan that goes on).
    std::vector<JointVector> q;
    if (!c.plan_empty && c.tail_q.size() == batch.q.front().size())
      q.push_back(c.tail_q);
    q.insert(q.end(), batch.q.begin(), batch.q.end());
    update_heading(q, c.tail_heading);
    c.plan_empty = false;
    c.tail_kf = batch.kf.back();
    c.tail_q = batch.q.back();
  }
  for (std::size_t k = 0; k < batch.calls.size(); ++k) {
    const ClEvent& e = batch.calls[k];
    if (e.kind == ClEventKind::feed && std::isfinite(e.value) && e.value > 0.0) {
      c.feed_mm_per_min = e.value;
    } else if (e.kind == ClEventKind::rapid) {
      c.next_rapid = true;
    } else if (e.kind == ClEventKind::tool_change) {
      c.approach_pending = c.started;
      c.sync = true;  // the new tool's cell
    } else if (is_motion(e)) {
      c.next_rapid = false;
      c.started = true;
      c.approach_pending = false;
    }
    if (k < batch.end_s.size() && !std::isnan(batch.end_s[k])) {
      c.plan_s = batch.end_s[k];
      c.cl_point = batch.end_p[k];
      c.cl_axis = batch.end_z[k];
    }
  }
}

namespace {

// Moves the first n buffered calls into the batch.
void release(std::deque<ClEvent>& deferred, std::size_t n, PlanBatch& batch) {
  batch.calls.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    batch.calls.push_back(std::move(deferred.front()));
    deferred.pop_front();
  }
  keep_first(batch, n);
}

// No sequence on the lattice: the stretch up to the keyframe after the dead one is tracked pose
// by pose (Algorithm 1), which fails with its own message (the CL line, the joint, the advice)
// where the path is out of reach indeed, and goes on where only the lattice was too coarse; the
// next window is planned from where the tracker is then.
void fall_back(const std::vector<PlanKeyframe>& kf, int dead_keyframe, std::size_t end,
               const std::string& source_name, std::deque<ClEvent>& deferred, PlanBatch& batch) {
  const int last_kf = static_cast<int>(kf.size()) - 1;
  const auto dead =
      static_cast<std::size_t>(std::min(std::max(dead_keyframe + 1, 1), std::max(last_kf, 0)));
  batch.warnings.push_back(fmt::format(
      "{}:{}-{}: the whole-path plan found no posture sequence on its lattice here; this "
      "stretch is tracked pose by pose (docs/redundancy.md)",
      source_name, kf.front().cl_line, kf[dead].cl_line));
  ++batch.fallback_windows;
  batch.reset = true;
  batch.reset_plan_s = kf.front().s_mm;
  std::size_t n = 0;
  bool motion = false;
  while (n < end &&
         (std::isnan(batch.end_s[n]) || batch.end_s[n] <= kf[dead].s_mm + 1e-9 || !motion)) {
    motion = motion || !std::isnan(batch.end_s[n]);
    ++n;
  }
  release(deferred, n, batch);
}

}  // namespace

bool PostSession::Impl::plan_window(bool flush, PlanBatch& batch) {
  batch = PlanBatch{};
  // Calls before the first motion go at once; a tool change ends the plan (a new TCP, and an
  // approach from wherever the change leaves the robot).
  std::size_t lead = 0;
  while (lead < deferred.size() && !is_motion(deferred[lead])) {
    if (deferred[lead].kind == ClEventKind::tool_change) {
      batch.reset = true;
      size_batch(batch, lead + 1);
      release(deferred, lead + 1, batch);
      return true;
    }
    ++lead;
  }
  if (lead > 0) {
    size_batch(batch, lead);
    release(deferred, lead, batch);
    return true;
  }
  if (deferred.empty())
    return false;

  const PathPlanSettings& ps = o.plan_settings;
  const PlanCursor& c = cursor;
  const bool fresh = !c.started || c.approach_pending;
  // After a stretch tracked pose by pose (no plan held), the next window starts where the
  // tracker is: the tracking must have caught up, as after a tool change (its cell).
  const bool from_tracker = !fresh && c.plan_empty;
  if (stage && (c.sync || from_tracker))
    stage->drain();
  cursor.sync = false;
  KeyframeWalk w{o, ps.keyframe_spacing_mm, {}, {}, {}, {}, 0.0, 0.0, 0.0, c.next_rapid};
  w.feed_mm_s =
      (std::isnan(c.feed_mm_per_min) ? o.default_feed_mm_per_min : c.feed_mm_per_min) / 60.0;
  size_batch(batch, deferred.size());
  std::size_t i = 0;
  if (fresh) {
    // The approach goes to the first point: the plan starts there.
    const ClEvent& e0 = deferred[0];
    w.p_cl = e0.p_mm;
    w.z_cl = e0.tool_axis.normalized();
    w.kf.push_back(w.at(w.p_cl, w.z_cl, 0.0, w.feed_mm_s, e0.line));
    w.rapid_next = false;
    batch.end_s[0] = 0.0;
    batch.end_p[0] = w.p_cl;
    batch.end_z[0] = w.z_cl;
    i = 1;
  } else {
    w.p_cl = c.cl_point;
    w.z_cl = c.cl_axis;
    w.s = c.plan_s;
    if (from_tracker)
      w.kf.push_back(w.at(w.p_cl, w.z_cl, c.plan_s, w.feed_mm_s, deferred[0].line));
    else
      w.kf.push_back(c.tail_kf);
  }
  w.next_kf_s = w.kf.back().s_mm + ps.keyframe_spacing_mm;
  bool barrier = false;
  const std::size_t end = walk_calls(deferred, i, w, batch, barrier);
  const double start_s = w.kf.front().s_mm;
  if (!flush && !barrier && w.s - start_s < window_mm() && deferred.size() < kMaxDeferred)
    return false;
  // A keyframe at the end of the buffered path, so that the window covers every call in it.
  if (w.s > w.kf.back().s_mm + 1e-6)
    w.kf.push_back(w.at(w.p_cl, w.z_cl, w.s, w.kf.back().speed_mm_s, w.kf.back().cl_line));

  const PathPlanner& pl = planner_for_active(w.kf.front().cl_line);
  const JointVector start_q = fresh ? JointVector() : from_tracker ? tracker.q() : c.tail_q;
  PlanHistory history;
  history.heading = c.tail_heading;
  // After a tool change the axes stand where the last plan left them.
  if (fresh && c.started && c.tail_q.size() == active_cell->size())
    history.standing = c.tail_q;
  PlanWindowResult r = pl.plan(w.kf, fresh ? nullptr : &start_q, 0, nullptr, &history);
  ++batch.windows;
  batch.ik_evaluations += r.ik_evaluations;
  // The first window after an approach picks the branch the rest follows (where the table
  // stands, where the track starts). Its first keyframe's lattice is coarse, and the beam may
  // keep only one family of starts: a tilted 1500 mm pass once went round with the table (72
  // deg) and left the track 300 mm, at a cost above the plan that holds the table. The plan
  // with the rotary external axes held at home is the second start; the cheaper one is kept
  // (later windows move those axes freely again).
  if (fresh && planner_held) {
    PlanWindowResult held = planner_held->plan(w.kf, nullptr, 0, nullptr, &history);
    batch.ik_evaluations += held.ik_evaluations;
    if (held.feasible && (!r.feasible || held.cost < r.cost))
      r = std::move(held);
  }
  if (!r.feasible) {
    // The beam may have lost the way: search wider once.
    r = pl.plan(w.kf, fresh ? nullptr : &start_q, 8 * pl.settings().beam, nullptr, &history);
    batch.ik_evaluations += r.ik_evaluations;
  }
  if (!r.feasible) {
    fall_back(w.kf, r.dead_keyframe, end, o.source_name, deferred, batch);
    return true;
  }
  // Commit 85 % of the window (all of it at the end or before a tool change), and
  // at least up to the end of the first motion.
  const double commit_s = (flush || barrier) ? w.s : start_s + 0.85 * o.plan_horizon_mm;
  const bool still = choose_still(w.kf, w.ends, std::min(commit_s, w.s), fresh ? nullptr : &start_q,
                                  history, r, batch);
  const JointVector plan_start = r.q.front();
  avoid_in_plan(w.kf, r, still ? *planner_still : pl,
                !fresh  ? &start_q
                : still ? &plan_start
                        : nullptr,
                &history, batch);

  const std::size_t n = commit_window(w.kf, r.q, batch.end_s, end, commit_s, fresh, batch);
  release(deferred, n, batch);
  return true;
}

}  // namespace redpost
