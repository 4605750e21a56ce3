// The choice between a window's plan and the plan with the external axes held (issue 47,
// docs/redundancy.md "Held or moved", "Where to hold"): both timed by the time model, the places
// a fresh window may hold them, and the arm's conditioning as a constraint.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include "post/session_impl.hpp"
#include "redpost/kinematics/conditioning.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/jacobian.hpp"
#include "redpost/post/plan_time.hpp"

namespace redpost {

namespace {

// Whether the plan moves any external axis over its keyframes up to until_s.
bool moves_external(const Cell& cell, const std::vector<PlanKeyframe>& kf,
                    const std::vector<JointVector>& q, double until_s) {
  const std::bitset<kMaxJoints> external = external_axes(cell);
  for (std::size_t k = 1; k < q.size() && kf[k - 1].s_mm <= until_s; ++k) {
    for (int i = 0; i < cell.size(); ++i) {
      if (external.test(static_cast<std::size_t>(i)) && std::fabs(q[k][i] - q[0][i]) > 1e-4)
        return true;
    }
  }
  return false;
}

// The lowest 1/kappa_F of the arm over the postures (1 where the cell declares no
// conditioning).
double lowest_inverse_condition(const Cell& cell, const std::vector<JointVector>& q) {
  if (!cell.conditioning.declared())
    return 1.0;
  KinematicsData data;
  Jacobian J;
  double lowest = 1.0;
  for (const JointVector& qk : q) {
    forward_kinematics(cell, qk, data, false);
    tcp_jacobian(cell, data, J);
    lowest = std::min(lowest, arm_inverse_condition(cell, J));
  }
  return lowest;
}

// Where a fresh window (the first, or the first after a tool change) may hold the external
// axes: no motion is committed yet, and the axes go wherever the approach takes them before the
// cut. Where the moving plan starts; where it has taken them by the end of its committed part (a
// plan that moves the track over once to a better place holds it there from the start); and
// every free axis a step either side of the start or not, in every combination: a track 300 mm
// (a third of the arm's reach: another posture of the arm, the part still within reach), a table
// a quarter turn; within the limits (a step clamped at a limit let the first of
// swcam_gasket_circles' short operations hold the track at its end, which the next tools then
// paid for: 1 s more in all). The combinations matter: nx_cycle_drill_deep's time estimate is
// 2.19 s with the track 300 mm along and the table a quarter turn round, 2.33 s with the track
// alone moved, 2.98 s with the table alone (2.2 s against 2.3 s as written). Each a posture whose
// external axes are the values to hold (the arm's joints are not used).
std::vector<JointVector> fresh_holds(const Cell& cell, const std::bitset<kMaxJoints>& user_locked,
                                     const std::vector<JointVector>& q, std::size_t last_kf) {
  constexpr double kTrackStepMm = 300.0;
  constexpr double kTableStepRad = 0.5 * kPi;
  std::vector<JointVector> out{q.front()};
  const std::bitset<kMaxJoints> external = external_axes(cell);
  JointVector moved = q.front();
  bool differs = false;
  for (int i = 0; i < cell.size(); ++i) {
    if (external.test(static_cast<std::size_t>(i))) {
      differs = differs || std::fabs(q[last_kf][i] - moved[i]) > 1e-3;
      moved[i] = q[last_kf][i];
    }
  }
  if (differs)
    out.push_back(moved);
  // Each free axis's values: the start's, and a step either side within the limits.
  std::vector<std::pair<int, std::vector<double>>> values;
  for (int i = 0; i < cell.size(); ++i) {
    const auto iu = static_cast<std::size_t>(i);
    if (!external.test(iu) || user_locked.test(iu))
      continue;  // a user's lock stays
    const Joint& j = cell.joint(i);
    const double step = j.type == JointType::prismatic ? kTrackStepMm : kTableStepRad;
    std::vector<double> v{q.front()[i]};
    for (const double sign : {-1.0, 1.0}) {
      const double x = q.front()[i] + sign * step;
      if (x >= j.lower && x <= j.upper)
        v.push_back(x);
    }
    values.emplace_back(i, std::move(v));
  }
  // Every combination but the start's own (an odometer over the axes' values).
  std::vector<std::size_t> digit(values.size(), 0);
  for (;;) {
    std::size_t a = 0;
    while (a < values.size() && ++digit[a] == values[a].second.size())
      digit[a++] = 0;
    if (a == values.size())
      break;
    JointVector shifted = q.front();
    for (std::size_t b = 0; b < values.size(); ++b)
      shifted[values[b].first] = values[b].second[digit[b]];
    out.push_back(shifted);
  }
  return out;
}

}  // namespace

// Issue 47 (docs/redundancy.md, "Held or moved", "Where to hold"): a window's plan moves the
// track and the table only where holding them is not faster. The plan with every external axis
// held where the window starts is the alternative (in a fresh window, the fastest of the places
// fresh_holds gives); both are timed by the time model over the window's CL points up to until_s
// (estimate_plan_time: what the lattice's velocity terms do not see, the corners a slow axis
// makes at the path's corners). The held plan must keep the plan's room to the bodies and the
// arm's conditioning at the threshold or above the moving plan's; it is taken where it is
// faster by hold_gain, or where it keeps the conditioning at the threshold and the moving plan
// does not.
bool PostSession::Impl::choose_still(const std::vector<PlanKeyframe>& kf,
                                     const std::vector<PlanKeyframe>& ends, double until_s,
                                     const JointVector* start, const PlanHistory& history,
                                     PlanWindowResult& r, PlanBatch& batch) {
  if (!planner_still || !r.feasible)
    return false;
  // A fresh window after a tool change pays for its approach from where the axes stand.
  const JointVector* from = !start && history.standing.size() > 0 ? &history.standing : nullptr;
  // A window has a choice where its plan moves the axes; a fresh one also where it might hold
  // them elsewhere (fresh_holds). After a tool change the places are searched (up to ten window
  // plans more with a track and a table) only for an operation of at least kSearchMotions
  // motions: a shorter one cannot repay them, and a program of many short operations (each hole
  // its own tool) would be planned eleven times over.
  constexpr long kSearchMotions = 20;
  const bool search =
      !start && (!from || std::count_if(ends.begin(), ends.end(), [&](const auto& e) {
                            return e.s_mm > kf.front().s_mm + 1e-9 && e.s_mm <= until_s + 1e-9;
                          }) >= kSearchMotions);
  if (!search && !moves_external(*active_cell, kf, r.q, until_s))
    return false;
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  PlanChoice choice{kf.front().cl_line, kf.back().cl_line, nan, nan, false, {}};
  std::size_t last_kf = 0;  // the last keyframe of the committed part
  for (std::size_t k = 0; k < kf.size(); ++k) {
    if (kf[k].s_mm <= until_s + 1e-9) {
      choice.last_cl_line = kf[k].cl_line;
      last_kf = k;
    }
  }
  const Cell& c = *active_cell;
  // The CL points are the motions' ends here; under the point reduction the program merges the
  // dense ones (0.5 mm apart on a raster: shorter than one interpolation cycle at 10 m/min, and
  // too short for the look-ahead to stop in) into motions long enough for both.
  ControllerTiming controller = controller_timing;
  if (reducer.enabled()) {
    controller.interpolation_cycle_s = 0.0;
    controller.lookahead_motions = -1;
  }
  const std::vector<JointVector> holds =
      search ? fresh_holds(c, planner->settings().locked, r.q, last_kf)
             : std::vector<JointVector>{start ? *start : r.q.front()};
  // Held axes must keep the room the plan keeps (avoid_in_plan) and its conditioning: where
  // they do not, the axes move as planned.
  const double threshold = planner_still->settings().condition_threshold;
  const double kappa_moving = lowest_inverse_condition(c, r.q);
  // The conditioning is a constraint that vanishes once safe: a plan at or above the threshold
  // is taken over one below it, and between two on the same side the faster (issue 47, item 1).
  const bool moving_ok = kappa_moving >= threshold;
  bool best_ok = false;
  PlanWindowResult best;
  for (std::size_t h = 0; h < holds.size(); ++h) {
    const JointVector& hold = holds[h];
    // Held elsewhere than the moving plan starts, the plan must keep the whole room the plan
    // keeps (margin + plan_extra_mm) without avoid_in_plan's second search: a raster held 300 mm
    // further along with less passed its keyframes and then brought the cutter within 4.77 mm
    // of the robot's base between them, where the tracker follows the plan.
    const double need = o.collision.margin_mm + (h == 0 ? 0.05 : 1.0) * o.collision.plan_extra_mm;
    // A fresh window's held plan starts as a plan with the axes locked at those values would
    // (`--lock E1=v`): the lattice picks the posture and the spin at its first keyframe.
    std::optional<PathPlanner> locked;
    if (!start) {
      PathPlanSettings at = planner_still->settings();
      for (int i = 0; i < c.size(); ++i) {
        if (at.locked.test(static_cast<std::size_t>(i)) && std::isnan(at.lock_value[i]))
          at.lock_value[i] = hold[i];
      }
      locked.emplace(c, planner_still->ik(), at);
    }
    const PathPlanner& p = locked ? *locked : *planner_still;
    PlanWindowResult held = p.plan(kf, start, 0, nullptr, &history);
    batch.ik_evaluations += held.ik_evaluations;
    double kappa_held = 0.0;
    if (!held.feasible || !unclear_keyframes(held.q, need).empty() ||
        ((kappa_held = lowest_inverse_condition(c, held.q)) < threshold &&
         kappa_held < kappa_moving))
      continue;
    const PlanTimeEstimate still =
        estimate_plan_time(c, p, controller, apo_mm, kf, held.q, ends, until_s, from);
    const bool ok = kappa_held >= threshold;
    if (still.feasible &&
        ((ok && !best_ok) || (ok == best_ok && !(still.time_s >= choice.still_s)))) {
      choice.still_s = still.time_s;
      choice.still_start = held.q.front();
      best_ok = ok;
      best = std::move(held);
    }
  }
  // The moving plan is timed where there is a choice to make (or somebody asks).
  if (!std::isnan(choice.still_s) || o.on_plan_choice) {
    const PlanTimeEstimate moving =
        estimate_plan_time(c, *planner, controller, apo_mm, kf, r.q, ends, until_s, from);
    if (moving.feasible)
      choice.moving_s = moving.time_s;
  }
  const double gain = planner->settings().hold_gain;
  choice.still =
      !std::isnan(choice.still_s) && ((best_ok && !moving_ok) || std::isnan(choice.moving_s) ||
                                      choice.still_s < (1.0 - gain) * choice.moving_s);
  if (o.on_plan_choice)
    o.on_plan_choice(choice);
  if (!choice.still)
    return false;
  r = std::move(best);
  ++batch.still_windows;
  return true;
}

}  // namespace redpost
