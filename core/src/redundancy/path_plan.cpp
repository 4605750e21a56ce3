// Whole-path planning of the free joints (path_plan.hpp, docs/redundancy.md).
#include "redpost/redundancy/path_plan.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "redpost/io/error.hpp"
#include "redpost/kinematics/conditioning.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/jacobian.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "redundancy/surroundings_memo.hpp"

namespace redpost {

namespace {

// The TCP frame of a 5-DOF target: z the tool axis, x a fixed choice across it. The spin about
// z is the virtual joint's business (its lattice value), not the frame's.
Isometry target_frame(const TcpTarget& t) {
  const Eigen::Vector3d z = t.z_B.normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z.x() * z;
  if (x.norm() < 1e-6)
    x = Eigen::Vector3d::UnitY() - z.y() * z;
  x.normalize();
  Isometry T = Isometry::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = z.cross(x);
  T.linear().col(2) = z;
  T.translation() = t.p_B_mm;
  return T;
}

bool is_arm_joint(const ArmIk& ik, int i) {
  return std::find(ik.arm_joints().begin(), ik.arm_joints().end(), i) != ik.arm_joints().end();
}

// Range of a joint sampled in a program's first layer: one turn around home at most.
void first_range(const Joint& j, double& lo, double& hi) {
  lo = j.lower;
  hi = j.upper;
  if (j.type != JointType::prismatic && hi - lo > 2.0 * kPi) {
    lo = std::max(lo, j.home - kPi);
    hi = std::min(hi, j.home + kPi);
  }
}

// The external axes' travel in the cut is priced (w_travel_cut) after the window's first air move:
// what they do there they could have done in that rapid, or do in the next. Before it (a window
// that starts in a pass, the program's first pass, a long pass) there is no such place in view,
// and the track carries the path as the centring asks. The first keyframe reached in the air;
// -1: none.
int first_in_air(const std::vector<PlanKeyframe>& keyframes) {
  for (std::size_t k = 1; k < keyframes.size(); ++k) {
    if (keyframes[k].in_air)
      return static_cast<int>(k);
  }
  return -1;
}

}  // namespace

PathPlanSettings plan_preset(PlanPreset preset) {
  PathPlanSettings s;
  switch (preset) {
    case PlanPreset::smooth:
      break;
    case PlanPreset::stiff:
      // Conditioning and compliance first: the arm kept far from singular postures, and where
      // the cell has stiffness data, in the postures that deflect least (Caro 2014), at the
      // price of travel.
      s.w_condition = 10.0;
      s.w_compliance = 30.0;
      s.condition_threshold = 0.4;
      s.w_travel = 0.3;
      s.w_travel_arm = 1.0;
      // Its axes move for the compliance, which the time model does not see: never held for
      // time alone.
      s.hold_gain = -1.0;
      break;
    case PlanPreset::fast:
      // Time first: every second the axes would add weighs more. The arm carries the path and
      // the slow external axes hold where the arm can do without them: a KUKA LIN moves an
      // external axis at one rate per motion, so each change of its rate between blended
      // motions is a corner at its own, low acceleration (the time model's corner rule), which
      // no velocity term sees. Centring is weak, external travel dear, the arm's cheap.
      s.w_time = 100.0;
      s.w_centre = 1.0;
      s.w_travel = 3.0;
      s.w_travel_arm = 0.3;
      break;
  }
  return s;
}

PathPlanner::PathPlanner(const Cell& cell, const ArmIk& ik, const PathPlanSettings& settings)
    : cell_(&cell), ik_(&ik), settings_(settings) {
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    const auto iu = static_cast<std::size_t>(i);
    arm_.set(iu, is_arm_joint(ik, i));
    if (j.has_speed()) {
      travel_per_unit_[iu] =
          (arm_.test(iu) ? settings.w_travel_arm : settings.w_travel) / j.max_velocity;
      need_per_unit_[iu] = 1.0 / (settings.speed_margin * j.max_velocity);
      if (!arm_.test(iu) && j.type != JointType::virtual_spin)
        cut_per_unit_[iu] = settings.w_travel_cut / j.max_velocity;
    }
  }
  // The joints an edge looks at: the arm's (their step is bounded) and those with a speed.
  for (int i = 0; i < cell.size(); ++i) {
    if (arm_.test(static_cast<std::size_t>(i)) || cell.joint(i).has_speed())
      timed_.push_back(i);
  }
  max_arm_step_rad_ = deg_to_rad(settings.max_arm_step_deg);
  for (int i = 0; i < cell.size(); ++i) {
    if (is_arm_joint(ik, i) || settings.locked.test(static_cast<std::size_t>(i)))
      continue;
    const Joint& j = cell.joint(i);
    if (j.type != JointType::virtual_spin && !j.has_speed()) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("joint '{}' has no <speed>: the whole-path plan needs every "
                              "axis's velocity and acceleration (docs/cell-format.md), or use "
                              "--plan local",
                              j.name),
                  SourceLocation{cell.source_file, j.source_line, 0});
    }
    if (static_cast<int>(free_.size()) == kMaxFreeJoints) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("the cell has more than {} joints besides the arm to plan ('{}' is "
                              "one too many): lock one (--lock)",
                              kMaxFreeJoints, j.name),
                  SourceLocation{cell.source_file, j.source_line, 0});
    }
    step_[free_.size()] = j.type == JointType::prismatic
                              ? settings.prismatic_step_spacings * settings.keyframe_spacing_mm
                          : j.type == JointType::revolute ? deg_to_rad(settings.rotary_step_deg)
                                                          : deg_to_rad(settings.spin_step_deg);
    external_[free_.size()] = j.type != JointType::virtual_spin;
    free_.push_back(i);
  }
}

bool PathPlanner::evaluate(const Isometry& T_B_tcp, const LatticeKey& key,
                           const JointVector& origin, const JointVector& q_near, JointVector& q,
                           double& cost, int* limit_joint) const {
  const Cell& cell = *cell_;
  JointVector q_other = origin;
  for (std::size_t f = 0; f < free_.size(); ++f) {
    const int i = free_[f];
    const double v = origin[i] + key.step[f] * step_[f];
    const Joint& j = cell.joint(i);
    if (v < j.lower || v > j.upper)
      return false;
    q_other[i] = v;
  }
  // The table, track and spin settings recur across a keyframe's nodes: their links are
  // composed once per setting and thread. No round trip per node: the closed form is exact
  // (arm_ik.hpp), and the tracker checks every pose it follows the plan through.
  thread_local detail::SurroundingsMemo memo;
  const ArmIkSolutions sol =
      ik_->solve(T_B_tcp, memo.before(*ik_, q_other), memo.after(*ik_, q_other), q_other, &q_near,
                 key.posture, RoundTrip::skip);
  const auto mu = static_cast<std::size_t>(key.posture);
  if (!sol.valid[mu]) {
    if (limit_joint && sol.exists[mu]) {
      for (int i : ik_->arm_joints()) {
        const Joint& j = cell.joint(i);
        if (sol.q[mu][i] < j.lower || sol.q[mu][i] > j.upper)
          *limit_joint = i;
      }
    }
    return false;
  }
  q = sol.q[mu];
  const PathPlanSettings& s = settings_;
  cost = 0.0;
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    const double range = j.upper - j.lower;
    if (!(range > 0.0))
      continue;
    if (s.w_centre > 0.0 && arm_.test(static_cast<std::size_t>(i))) {
      const double c = (q[i] - j.home) / (0.5 * range);
      cost += s.w_centre * c * c;
    }
    const double margin = std::min(q[i] - j.lower, j.upper - q[i]) / range;
    if (margin < s.limit_zone) {
      const double d = (s.limit_zone - margin) / s.limit_zone;
      cost += s.w_limit * d * d;
    }
  }
  return true;
}

// The conditioning term of a node's cost, apart from evaluate() because it needs the FK and the
// Jacobian: the DP asks for it only for nodes that may enter the beam (lattice_dp's refine).
double PathPlanner::condition_cost(const JointVector& q) const {
  const PathPlanSettings& s = settings_;
  const Cell& cell = *cell_;
  if (!(s.w_condition > 0.0) || !cell.conditioning.declared())
    return 0.0;
  KinematicsData data;
  Jacobian J;
  forward_kinematics(cell, q, data, false);
  tcp_jacobian(cell, data, J);
  const double inv_kappa = arm_inverse_condition(cell, J);
  if (!(inv_kappa < s.condition_threshold))
    return 0.0;
  const double d = (s.condition_threshold - inv_kappa) / s.condition_threshold;
  return s.w_condition * d * d;
}

// Caro's machining-quality term of a node (path_plan.hpp): lazy as well (the elastostatic model
// solves a 6 x 6 system per node).
double PathPlanner::compliance_cost(const JointVector& q, const Eigen::Vector3d& feed_B,
                                    const Eigen::Vector3d& z_B) const {
  const PathPlanSettings& s = settings_;
  // No feed across the tool axis (a plunge, a pure turn): no direction to deflect across.
  if (!(s.w_compliance > 0.0) || !s.normal_deflection_mm || !(z_B.cross(feed_B).norm() > 1e-6))
    return 0.0;
  return s.w_compliance * s.normal_deflection_mm(q, feed_B, z_B) / s.compliance_ref_mm;
}

double PathPlanner::edge_cost(const PlanKeyframe& from, const PlanKeyframe& to,
                              const JointVector& q0, const JointVector& q1, bool price_cut) const {
  const PathPlanSettings& s = settings_;
  const double ds = std::max(to.s_mm - from.s_mm, 0.0);
  const double dt = to.speed_mm_s > 0.0 ? ds / to.speed_mm_s : 0.0;
  double travel_s = 0.0, need_s = 0.0;
  for (int i : timed_) {
    const auto iu = static_cast<std::size_t>(i);
    const double dq = std::fabs(q1[i] - q0[i]);
    if (arm_.test(iu) && dq > max_arm_step_rad_)
      return std::numeric_limits<double>::infinity();
    travel_s += (price_cut && !to.in_air ? travel_per_unit_[iu] + cut_per_unit_[iu]
                                         : travel_per_unit_[iu]) *
                dq;
    need_s = std::max(need_s, need_per_unit_[iu] * dq);
  }
  if (to.rapid)
    return travel_s + s.w_time * need_s * s.speed_margin / s.rapid_velocity_fraction;
  return travel_s + s.w_time * std::max(0.0, need_s - dt);
}

// An external axis that turns back (Andres's redundancy has no view of it): it stops and starts
// again at its own low acceleration, a corner in the time model, wear on the heavy axis, and
// the shuttle a programmer sees under every raster line. The tool's spin is no axis.
double PathPlanner::reversal_cost(const LatticeNode& a, const LatticeNode& b) const {
  double cost = 0.0;
  for (std::size_t f = 0; f < free_.size(); ++f) {
    const int d = b.key.step[f] - a.key.step[f];
    if (d != 0 && external_[f] && a.heading[f] == (d > 0 ? -1 : 1))
      cost += settings_.w_reversal;
  }
  return cost;
}

// The approach to a fresh window's start: the time the slowest external axis needs from where
// it stands, at its velocity limit.
double PathPlanner::reposition_cost(const JointVector& standing, const JointVector& q) const {
  double need_s = 0.0;
  for (std::size_t f = 0; f < free_.size(); ++f) {
    const auto i = static_cast<std::size_t>(free_[f]);
    if (external_[f])
      need_s = std::max(need_s, need_per_unit_[i] * std::fabs(q[free_[f]] - standing[free_[f]]));
  }
  return settings_.w_reposition * need_s;
}

std::vector<LatticeKey> PathPlanner::first_layer(const PlanKeyframe& kf, JointVector& origin,
                                                 int& stride_out) const {
  (void)kf;
  const Cell& cell = *cell_;
  std::array<int, kMaxFreeJoints> lo{}, hi{};
  for (std::size_t f = 0; f < free_.size(); ++f) {
    const Joint& j = cell.joint(free_[f]);
    double a = 0.0, b = 0.0;
    first_range(j, a, b);
    origin[free_[f]] = j.home;
    lo[f] = static_cast<int>(std::ceil((a - j.home) / step_[f] - 1e-9));
    hi[f] = static_cast<int>(std::floor((b - j.home) / step_[f] + 1e-9));
  }
  int stride = std::max(1, settings_.first_layer_stride);
  auto count = [&](int st) {
    long n = 8;
    for (std::size_t f = 0; f < free_.size(); ++f)
      n *= (hi[f] - lo[f]) / st + 1;
    return n;
  };
  while (count(stride) > settings_.first_layer_max_nodes)
    ++stride;
  std::vector<LatticeKey> keys;
  LatticeKey k;
  // Odometer over the free joints, the posture innermost (one solve serves all eight).
  std::array<int, kMaxFreeJoints> at = lo;
  while (true) {
    for (int mu = 0; mu < 8; ++mu) {
      k.step = at;
      k.posture = mu;
      keys.push_back(k);
    }
    std::size_t f = 0;
    for (; f < free_.size(); ++f) {
      at[f] += stride;
      if (at[f] <= hi[f])
        break;
      at[f] = lo[f];
    }
    if (f == free_.size())
      break;
  }
  stride_out = stride;
  return keys;
}

namespace {
// The feed direction at each keyframe: towards the next one (from the one before at the end);
// zero where the tool only turns.
std::vector<Eigen::Vector3d> feed_directions(const std::vector<PlanKeyframe>& keyframes) {
  std::vector<Eigen::Vector3d> feed_B(keyframes.size(), Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < keyframes.size(); ++k) {
    const std::size_t a = k + 1 < keyframes.size() ? k : k - std::min<std::size_t>(k, 1);
    const std::size_t b = std::min(a + 1, keyframes.size() - 1);
    const Eigen::Vector3d d = keyframes[b].target.p_B_mm - keyframes[a].target.p_B_mm;
    if (d.norm() > 1e-6)
      feed_B[k] = d.normalized();
  }
  return feed_B;
}
}  // namespace

LatticeDpSettings PathPlanner::dp_settings(int beam, const PlanHistory* history) const {
  LatticeDpSettings dp;
  dp.free_joints = static_cast<int>(free_.size());
  dp.reach = {settings_.reach, settings_.reach, settings_.reach};
  dp.max_moving = settings_.max_moving;
  dp.beam = beam > 0 ? beam : settings_.beam;
  dp.pool = settings_.pool;
  for (std::size_t f = 0; history && f < free_.size(); ++f)
    dp.first_heading[f] = history->heading[static_cast<std::size_t>(free_[f])];
  return dp;
}

PlanWindowResult PathPlanner::plan(const std::vector<PlanKeyframe>& keyframes,
                                   const JointVector* start, int beam, const PlanNodeFilter* filter,
                                   const PlanHistory* history) const {
  PlanWindowResult out;
  if (keyframes.empty())
    return out;
  const Cell& cell = *cell_;
  JointVector origin(cell.size());
  for (int i = 0; i < cell.size(); ++i)
    origin[i] = cell.joint(i).home;
  std::vector<LatticeKey> first;
  int stride = 1;
  if (start) {
    origin = *start;
    LatticeKey k;
    k.posture = status_turn(cell, ik_->status_model(), *start).status;
    first.push_back(k);
  } else {
    first = first_layer(keyframes.front(), origin, stride);
  }
  for (int i = 0; i < cell.size(); ++i) {
    if (settings_.locked.test(static_cast<std::size_t>(i)) && settings_.lock_value.size() > i &&
        std::isfinite(settings_.lock_value[i]))
      origin[i] = settings_.lock_value[i];
  }
  const JointVector q_near = origin;
  std::vector<Isometry> frames;
  frames.reserve(keyframes.size());
  for (const PlanKeyframe& kf : keyframes)
    frames.push_back(target_frame(kf.target));
  const std::vector<Eigen::Vector3d> feed_B =
      settings_.normal_deflection_mm
          ? feed_directions(keyframes)
          : std::vector<Eigen::Vector3d>(keyframes.size(), Eigen::Vector3d::Zero());
  const LatticeDpSettings dp = dp_settings(beam, history);
  const JointVector* standing =
      !start && history && history->standing.size() == cell.size() ? &history->standing : nullptr;
  // Counted from the pool's threads at once.
  std::vector<std::atomic<int>> limit_hits(static_cast<std::size_t>(cell.size()));
  const int first_air = first_in_air(keyframes);
  const auto search = [&](const std::vector<LatticeKey>& first_keys) {
    return lattice_dp(
        static_cast<int>(keyframes.size()), first_keys, dp,
        [&](int layer, const LatticeKey& key, JointVector& q, double& cost) {
          int limit_joint = -1;
          bool ok = evaluate(frames[static_cast<std::size_t>(layer)], key, origin, q_near, q, cost,
                             &limit_joint);
          if (ok && layer == 0 && standing)
            cost += reposition_cost(*standing, q);
          const auto lu = static_cast<std::size_t>(layer);
          if (ok && filter && lu < filter->layers.size() && filter->layers[lu] && !filter->clear(q))
            ok = false;
          if (limit_joint >= 0)
            limit_hits[static_cast<std::size_t>(limit_joint)].fetch_add(1,
                                                                        std::memory_order_relaxed);
          return ok;
        },
        [&](int layer, const LatticeNode& a, const LatticeNode& b) {
          return edge_cost(keyframes[static_cast<std::size_t>(layer - 1)],
                           keyframes[static_cast<std::size_t>(layer)], a.q, b.q,
                           first_air >= 0 && first_air < layer) +
                 reversal_cost(a, b);
        },
        [&](int layer, const LatticeNode& n) {
          const auto k = static_cast<std::size_t>(layer);
          return condition_cost(n.q) +
                 compliance_cost(n.q, feed_B[k], keyframes[k].target.z_B.normalized());
        });
  };
  LatticeDpResult r = search(first);
  out.ik_evaluations = r.evaluations;
  // Coarse to fine: the first keyframe's lattice is `stride` steps apart, so the best start is
  // only as good as that grid, and the plan may spend its first keyframes walking an axis to
  // where it should have started (a tilted pass once moved the track 124 mm back during the
  // plunge, then forward). The search again from every lattice point within a stride of the
  // start found, in its posture; the cheaper is kept.
  if (!start && r.feasible && stride > 1) {
    const LatticeKey best = r.path.front().key;
    std::vector<LatticeKey> fine;
    std::array<int, kMaxFreeJoints> at{};
    const int n_free = static_cast<int>(free_.size());
    const int span = stride - 1;
    for (int f = 0; f < n_free; ++f)
      at[static_cast<std::size_t>(f)] = -span;
    while (true) {
      LatticeKey k = best;
      for (int f = 0; f < n_free; ++f)
        k.step[static_cast<std::size_t>(f)] += at[static_cast<std::size_t>(f)];
      fine.push_back(k);
      int f = 0;
      for (; f < n_free; ++f) {
        if (++at[static_cast<std::size_t>(f)] <= span)
          break;
        at[static_cast<std::size_t>(f)] = -span;
      }
      if (f == n_free)
        break;
    }
    LatticeDpResult refined = search(fine);
    out.ik_evaluations += refined.evaluations;
    if (refined.feasible && refined.cost < r.cost)
      r = std::move(refined);
  }
  if (!r.feasible) {
    out.dead_keyframe = r.dead_layer;
    const auto most = std::max_element(limit_hits.begin(), limit_hits.end());
    out.limiting_joint = *most > 0 ? static_cast<int>(most - limit_hits.begin()) : -1;
    return out;
  }
  out.feasible = true;
  out.cost = r.cost;
  out.q.reserve(r.path.size());
  for (const LatticeNode& n : r.path)
    out.q.push_back(n.q);
  smooth(keyframes, r, out.q, filter);
  return out;
}

void update_heading(const std::vector<JointVector>& q, JointHeading& heading, double tol) {
  for (std::size_t k = 1; k < q.size(); ++k) {
    for (int i = 0; i < std::min<int>(static_cast<int>(q[k].size()), kMaxJoints); ++i) {
      const double d = q[k][i] - q[k - 1][i];
      if (std::fabs(d) > tol)
        heading[static_cast<std::size_t>(i)] = d > 0.0 ? 1 : -1;
    }
  }
}

// The lattice quantises the free joints: a step of a lattice unit at one keyframe and none at the
// next is a jump in the axis's rate. A centred moving average over the keyframes (two passes of
// settings.smoothing keyframes each side) smooths it; the arm is solved again for the smoothed
// free joints, and a keyframe whose smoothed posture is not valid keeps the lattice's. The
// first keyframe (the committed start of a window) stays as it is.
void PathPlanner::smooth(const std::vector<PlanKeyframe>& keyframes, const LatticeDpResult& r,
                         std::vector<JointVector>& q, const PlanNodeFilter* filter) const {
  const int n = static_cast<int>(q.size());
  const int half = settings_.smoothing;
  if (half <= 0 || n < 3)
    return;
  std::vector<JointVector> free_values = q;
  // The average stays within a run of edges of one kind (all in the air, or none): a change the
  // lattice put in a rapid is not spread into the cut beside it (w_travel_cut).
  const auto in_air = [&](int k) { return keyframes[static_cast<std::size_t>(k)].in_air; };
  for (int pass = 0; pass < 2; ++pass) {
    const std::vector<JointVector> before = free_values;
    for (int k = 1; k < n; ++k) {
      const int a = std::max(0, k - half), b = std::min(n - 1, k + half);
      const int reach = std::min(k - a, b - k);  // symmetric, so the ends are not dragged
      int w = 0;
      while (w < reach && in_air(k - w) == in_air(k) && in_air(k + w + 1) == in_air(k))
        ++w;
      for (int f : free_) {
        double sum = 0.0;
        for (int m = k - w; m <= k + w; ++m)
          sum += before[static_cast<std::size_t>(m)][f];
        free_values[static_cast<std::size_t>(k)][f] = sum / (2 * w + 1);
      }
    }
  }
  for (int k = 1; k < n; ++k) {
    const auto ku = static_cast<std::size_t>(k);
    JointVector q_other = q[ku];
    for (int f : free_)
      q_other[f] = free_values[ku][f];
    const int posture = r.path[ku].key.posture;
    const ArmIkSolutions sol =
        ik_->solve(target_frame(keyframes[ku].target), q_other, &q[ku], posture);
    const auto mu = static_cast<std::size_t>(posture);
    if (!sol.valid[mu])
      continue;
    bool near = true;
    for (int i : ik_->arm_joints())
      near = near && std::fabs(sol.q[mu][i] - q[ku][i]) < deg_to_rad(settings_.max_arm_step_deg);
    // Where the filter checks postures, the smoothed one must pass too.
    if (near && filter && ku < filter->layers.size() && filter->layers[ku])
      near = filter->clear(sol.q[mu]);
    if (near)
      q[ku] = sol.q[mu];
  }
}

bool PathPlanner::solve_at(const TcpTarget& target, const JointVector& q_plan,
                           JointVector& q) const {
  const int posture = status_turn(*cell_, ik_->status_model(), q_plan).status;
  // No round trip: the closed form is exact, and what the estimate is for (the session's choice
  // between candidate plans) is followed by the tracker, which checks every pose.
  ArmBefore before;
  ArmAfter after;
  ik_->before_arm(q_plan, before);
  ik_->after_arm(q_plan, after);
  const ArmIkSolutions sol =
      ik_->solve(target_frame(target), before, after, q_plan, &q_plan, posture, RoundTrip::skip);
  const auto mu = static_cast<std::size_t>(posture);
  if (!sol.valid[mu])
    return false;
  q = sol.q[mu];
  return true;
}

JointVector interpolate_plan(const std::vector<PlanKeyframe>& keyframes,
                             const std::vector<JointVector>& q, double s_mm) {
  if (s_mm <= keyframes.front().s_mm)
    return q.front();
  if (s_mm >= keyframes.back().s_mm)
    return q.back();
  const auto it = std::upper_bound(keyframes.begin(), keyframes.end(), s_mm,
                                   [](double s, const PlanKeyframe& k) { return s < k.s_mm; });
  const std::size_t b = static_cast<std::size_t>(it - keyframes.begin());
  const std::size_t a = b - 1;
  const double span = keyframes[b].s_mm - keyframes[a].s_mm;
  const double t = span > 0.0 ? (s_mm - keyframes[a].s_mm) / span : 1.0;
  return q[a] + t * (q[b] - q[a]);
}

}  // namespace redpost
