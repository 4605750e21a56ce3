#include "redpost/redundancy/tracker.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "redpost/io/error.hpp"
#include "redpost/kinematics/conditioning.hpp"
#include "redpost/kinematics/jacobian.hpp"

namespace redpost {

const char* to_string(PoseStatus status) {
  switch (status) {
    case PoseStatus::converged:
      return "converged";
    case PoseStatus::unreachable:
      return "unreachable";
    case PoseStatus::joint_limit:
      return "joint limit";
    case PoseStatus::joint_jump:
      return "joint jump";
  }
  return "unknown";
}

Tracker::Tracker(const Cell& cell, const TrackerOptions& options)
    : cell_(&cell), options_(options) {
  if (cell.size() < 6) {
    throw Error(ErrorCode::bad_input, "cell '" + cell.name + "' has " +
                                          std::to_string(cell.size()) +
                                          " joints; tracking a 6-D task needs at least 6");
  }
  if (cell.conditioning.declared()) {
    options_.rrs.characteristic_length_mm = cell.conditioning.characteristic_length_mm;
  }
  q_ref_ = options.q_ref.size() == cell.size() ? options.q_ref : cell.home();
  base_inv_sqrt_w_.resize(cell.size());
  for (int i = 0; i < cell.size(); ++i) {
    base_inv_sqrt_w_[i] =
        options_.locked[static_cast<size_t>(i)] ? 0.0 : 1.0 / std::sqrt(cell.joint(i).weight);
  }
  reset(cell.home());
}

void Tracker::reset(const JointVector& q) {
  q_ = q;
  q_prev_ = q;
  history_ = 0;
  scratch_valid_ = false;
  switch_ = SwitchState{};
  switch_.q_Ts = q;
}

namespace {
// How far inside its limits the tracker stops a joint (tracker.cpp's clamp): 0.01 deg or
// 0.01 mm, a quarter of the range at most.
double limit_inset(const Joint& j) {
  const double inset = j.type == JointType::prismatic ? 0.01 : deg_to_rad(0.01);
  return std::min(inset, 0.25 * (j.upper - j.lower));
}

// Scales h down so that its weighted norm is at most `cap`.
void cap_motion(const Cell& cell, double cap, JointVector& h) {
  double norm2 = 0.0;
  for (int i = 0; i < cell.size(); ++i)
    norm2 += cell.joint(i).weight * h[i] * h[i];
  if (norm2 > cap * cap)
    h *= cap / std::sqrt(norm2);
}
}  // namespace

void Tracker::null_space_motion(const JointVector& q, SwitchState& sw, bool full_goals,
                                Scratch& s) const {
  const Cell& cell = *cell_;
  const NullSpaceGains& g = options_.gains;
  if (following_) {
    // Following a plan: centring on the planned posture, the limits kept; the conditioning
    // switch would pull back towards where 1/kappa_F crossed its threshold, against the plan.
    s.h = -follow_gain_ * (q - q_plan_);
    if (full_goals) {
      limit_avoidance(cell, q, g.limits, g.limit_zone, s.h_lim);
      s.h += s.h_lim;
      if (options_.extra_goal)
        options_.extra_goal->add(q, s.h);
    }
    cap_motion(cell, follow_max_motion_, s.h);
    return;
  }
  // Eq. 13, first term: centring on the reference posture.
  s.h = -g.centring * (q - q_ref_);
  if (!full_goals) {
    cap_motion(cell, g.max_motion_per_pose, s.h);
    return;
  }

  // Eq. 13, second term: the switch on the arm's conditioning.
  const double inv_kappa =
      std::isnan(sw.inv_kappa_at_start) ? arm_inverse_condition(cell, s.J) : sw.inv_kappa_at_start;
  if (inv_kappa < g.conditioning_threshold) {
    if (!sw.active) {
      sw.active = true;
      sw.q_Ts = q;
    }
    const double kappa = inv_kappa > 0.0 ? 1.0 / inv_kappa : 1e6;
    s.h -= (g.conditioning * kappa) * (q - sw.q_Ts);
    if (g.conditioning_gradient > 0.0) {
      // Ascent of 1/kappa_F, in the weighted metric (W^-1 grad) like every other goal.
      inverse_condition_gradient(cell, s.data, s.J, s.grad);
      for (int i = 0; i < cell.size(); ++i) {
        s.h[i] += g.conditioning_gradient * s.grad[i] / cell.joint(i).weight;
      }
    }
  } else {
    sw.active = false;
  }

  limit_avoidance(cell, q, g.limits, g.limit_zone, s.h_lim);
  s.h += s.h_lim;
  if (options_.extra_goal)
    options_.extra_goal->add(q, s.h);
  cap_motion(cell, g.max_motion_per_pose, s.h);
}

PoseResult Tracker::iterate(const TcpTarget& target, JointVector q, SwitchState* goals,
                            bool full_goals, int max_iterations, bool start_evaluated,
                            Scratch& s) const {
  const Cell& cell = *cell_;
  const int n = cell.size();
  const TrackerOptions& o = options_;
  const double L = o.rrs.characteristic_length_mm;
  PoseResult r;
  s.inv_sqrt_w = base_inv_sqrt_w_;
  if (holding_) {
    for (int i = 0; i < n; ++i) {
      if (follow_hold_.test(static_cast<std::size_t>(i)))
        s.inv_sqrt_w[i] = 0.0;
    }
  }
  bool clamped_any = false;
  double previous_error = std::numeric_limits<double>::infinity();
  int stalled = 0;
  RrsStepInfo info;

  for (int it = 0;; ++it) {
    // The previous pose ended at this very posture: its frames and Jacobian are still in `s`.
    const bool evaluated = it == 0 && start_evaluated;
    if (!evaluated)
      forward_kinematics(cell, q, s.data, /*link_frames=*/false);
    const Vector6d dt = task_error(s.data.T_B_tcp, target);
    r.position_error_mm = dt.tail<3>().norm();
    // |Q vect(Q^T Q_d)| = sin(phi) <= phi (or phi itself beyond 90 deg): the exact angle is only
    // computed once, for the result.
    r.orientation_error_rad = dt.head<3>().norm();
    r.iterations = it;
    const bool within = r.position_error_mm <= o.position_tolerance_mm &&
                        r.orientation_error_rad <= o.axis_tolerance_rad;
    if (within && (it > 0 || goals == nullptr)) {
      r.status = PoseStatus::converged;
      break;
    }
    // Stall: the error no longer falls by at least 5 % per iteration, five times running.
    const double error = r.orientation_error_rad + r.position_error_mm / L;
    stalled = error > 0.95 * previous_error ? stalled + 1 : 0;
    previous_error = std::min(previous_error, error);
    if (it == max_iterations || stalled >= 5) {
      r.status = clamped_any ? PoseStatus::joint_limit : PoseStatus::unreachable;
      break;
    }

    if (!evaluated)
      tcp_jacobian(cell, s.data, s.J);
    if (goals != nullptr && it == 0) {
      null_space_motion(q, *goals, full_goals, s);
    } else {
      s.h.setZero(n);
    }
    rrs_step(s.J, dt, s.h, s.inv_sqrt_w, o.rrs, s.rrs, s.dq, info);

    // Trust region on the weighted step.
    double norm2 = 0.0;
    for (int i = 0; i < n; ++i) {
      if (s.inv_sqrt_w[i] > 0.0)
        norm2 += (s.dq[i] / s.inv_sqrt_w[i]) * (s.dq[i] / s.inv_sqrt_w[i]);
    }
    if (norm2 > o.max_iteration_step * o.max_iteration_step) {
      s.dq *= o.max_iteration_step / std::sqrt(norm2);
    }

    // A joint that would cross its limit stops just inside it and is locked for the rest of
    // this pose. Just inside: a LIN between two poses held at a limit bends off the line its
    // ends give that joint, and the printed pose's rounding (0.0001 deg an angle) moves the
    // wrist's axes too; at the limit itself either would stop the controller.
    for (int i = 0; i < n; ++i) {
      const Joint& j = cell.joint(i);
      const double inset = limit_inset(j);
      double next = q[i] + s.dq[i];
      if (next < j.lower + inset || next > j.upper - inset) {
        next = next < j.lower + inset ? j.lower + inset : j.upper - inset;
        s.inv_sqrt_w[i] = 0.0;
        clamped_any = true;
        r.offending_joint = i;
      }
      q[i] = next;
    }
  }
  r.sigma_min = info.sigma_min;
  r.damping = info.damping;
  r.orientation_error_rad = orientation_error(target, s.data.T_B_tcp.linear());
  if (r.status != PoseStatus::converged)
    return r;
  if (r.offending_joint >= 0)
    r.offending_joint = -1;  // clamped but reached: no failure

  r.q = q;
  tcp_jacobian(cell, s.data, s.J);
  r.inv_condition = arm_inverse_condition(cell, s.J);
  r.limit_margin = smallest_limit_margin(cell, q, &r.limit_joint);
  return r;
}

bool steady_continuation(const Eigen::Vector3d& p0, const Eigen::Vector3d& z0,
                         const Eigen::Vector3d& p1, const Eigen::Vector3d& z1,
                         const TcpTarget& next) {
  const Eigen::Vector3d dp1 = p1 - p0, dp2 = next.p_B_mm - p1;
  const Eigen::Vector3d dz1 = z1 - z0, dz2 = next.z_B - z1;
  return (dp2 - dp1).norm() <= 0.25 * dp2.norm() + 1e-9 &&
         (dz2 - dz1).norm() <= 0.25 * dz2.norm() + 1e-9;
}

bool Tracker::steady(const TcpTarget& target) const {
  return history_ >= 2 && steady_continuation(before_p_, before_z_, last_p_, last_z_, target);
}

void Tracker::follow(const JointVector& q_plan, double gain, double max_motion,
                     std::bitset<kMaxJoints> hold) {
  following_ = true;
  follow_hold_ = hold;
  q_plan_ = q_plan;
  follow_gain_ = gain;
  follow_max_motion_ = max_motion;
}

void Tracker::stop_following() {
  following_ = false;
}

// The jump bound between consecutive postures: a converged result that moves a joint further
// than the bound from the current posture becomes joint_jump.
void Tracker::check_jump(PoseResult& r) const {
  if (r.status != PoseStatus::converged)
    return;
  for (int i = 0; i < cell_->size(); ++i) {
    const double step = std::abs(r.q[i] - q_[i]);
    const double bound = cell_->joint(i).type == JointType::prismatic ? options_.max_joint_step_mm
                                                                      : options_.max_joint_step_rad;
    if (step > r.max_joint_step) {
      r.max_joint_step = step;
      r.max_step_joint = i;
    }
    if (step > bound && r.status == PoseStatus::converged) {
      r.status = PoseStatus::joint_jump;
      r.offending_joint = i;
      r.offending_step = step;
    }
  }
}

PoseResult Tracker::track(const TcpTarget& target) {
  // Start from the previous posture (Algorithm 1), or, on a steady stretch of path, from its
  // linear extrapolation: one Newton step from there usually meets the tolerance, where two are
  // needed from the previous posture (docs/redundancy.md).
  // Following a plan, the planned posture is the start: it is within a keyframe's interpolation
  // of the target, and starting there keeps the tracked joints as smooth as the plan (the
  // predictor would carry the last pose's self-motion on, against the plan's pull).
  const bool predict = following_ || (options_.extrapolate && steady(target));
  if (following_) {
    scratch_.dq = q_plan_;
    for (int i = 0; i < cell_->size(); ++i) {
      scratch_.dq[i] = std::clamp(scratch_.dq[i], cell_->joint(i).lower, cell_->joint(i).upper);
    }
  } else if (predict) {
    scratch_.dq = q_ + (q_ - q_prev_);
    for (int i = 0; i < cell_->size(); ++i) {
      scratch_.dq[i] = std::clamp(scratch_.dq[i], cell_->joint(i).lower, cell_->joint(i).upper);
    }
  }
  holding_ = following_ && follow_hold_.any();
  const JointVector start = predict ? scratch_.dq : q_;
  PoseResult r = iterate(target, start, &switch_, true, options_.max_iterations,
                         !predict && scratch_valid_, scratch_);
  check_jump(r);
  if (holding_ && r.status != PoseStatus::converged) {
    // The held axes at the plan's values leave the arm no solution here (between keyframes the
    // plan is only interpolated): every joint may move.
    holding_ = false;
    r = iterate(target, start, &switch_, true, options_.max_iterations, false, scratch_);
    check_jump(r);
  }
  holding_ = false;
  if (following_ && r.status != PoseStatus::converged) {
    // Near a wrist singularity the plan's interpolated posture may lie closer to another
    // branch than to the previous posture: track from the previous posture, still pulled
    // towards the plan.
    PoseResult again =
        iterate(target, q_, &switch_, true, options_.max_iterations, false, scratch_);
    check_jump(again);
    if (again.status == PoseStatus::converged)
      r = again;
  }
  // After a converged pose the scratch holds the frames and Jacobian at the new posture.
  scratch_valid_ = r.status == PoseStatus::converged;
  if (r.status == PoseStatus::converged) {
    q_prev_ = q_;
    q_ = r.q;
    switch_.inv_kappa_at_start = r.inv_condition;
    before_p_ = last_p_;
    before_z_ = last_z_;
    last_p_ = target.p_B_mm;
    last_z_ = target.z_B;
    history_ = std::min(history_ + 1, 2);
  } else {
    r.q = q_;
  }
  return r;
}

PoseResult Tracker::correct(const TcpTarget& target) {
  PoseResult r =
      iterate(target, q_, nullptr, false, options_.max_iterations, scratch_valid_, scratch_);
  check_jump(r);
  scratch_valid_ = r.status == PoseStatus::converged;
  if (r.status == PoseStatus::converged) {
    q_ = r.q;
    switch_.inv_kappa_at_start = r.inv_condition;
    last_p_ = target.p_B_mm;
    last_z_ = target.z_B;
  } else {
    r.q = q_;
  }
  return r;
}

Isometry Tracker::tcp_pose_at_q() const {
  return scratch_valid_ ? scratch_.data.T_B_tcp : tcp_pose(*cell_, q_);
}

std::size_t Tracker::track(const TcpTarget* targets, std::size_t count, PoseResult* results) {
  for (std::size_t k = 0; k < count; ++k) {
    results[k] = track(targets[k]);
    if (results[k].status != PoseStatus::converged)
      return k;
  }
  return count;
}

PoseResult Tracker::solve_first_pose(const TcpTarget& target, int perturbed_starts,
                                     std::uint64_t seed) const {
  const Cell& cell = *cell_;
  const int n = cell.size();
  const JointVector home = cell.home();
  Scratch s;

  PoseResult best;
  best.status = PoseStatus::unreachable;
  best.q = q_;
  double best_cost = std::numeric_limits<double>::infinity();
  double best_failed_error = std::numeric_limits<double>::infinity();

  auto attempt = [&](const JointVector& proposed) {
    // Locked joints are held at their current value, whatever the start proposes.
    JointVector start = proposed;
    for (int i = 0; i < n; ++i) {
      if (options_.locked[static_cast<size_t>(i)])
        start[i] = q_[i];
    }
    SwitchState sw;
    sw.q_Ts = start;
    PoseResult r = iterate(target, start, &sw, false, 200, false, s);
    if (r.status == PoseStatus::converged && within_limits(cell, r.q)) {
      double cost = 0.0;
      for (int i = 0; i < n; ++i)
        cost += cell.joint(i).weight * (r.q[i] - home[i]) * (r.q[i] - home[i]);
      if (cost < best_cost) {
        best_cost = cost;
        best = r;
      }
    } else if (best_cost == std::numeric_limits<double>::infinity()) {
      const double e = r.position_error_mm +
                       r.orientation_error_rad * cell.conditioning.characteristic_length_mm;
      if (e < best_failed_error) {
        best_failed_error = e;
        best.status = r.status;
        best.position_error_mm = r.position_error_mm;
        best.orientation_error_rad = r.orientation_error_rad;
        best.offending_joint = r.offending_joint;
        best.iterations = r.iterations;
      }
    }
  };

  attempt(q_);
  attempt(home);
  // Home with every virtual joint turned in 60 degree steps: the spin changes the arm's
  // posture a lot for a tilted tool.
  for (int k = 1; k < 6; ++k) {
    JointVector q = home;
    for (int i = 0; i < n; ++i) {
      if (cell.joint(i).type == JointType::virtual_spin) {
        q[i] = std::clamp(home[i] + deg_to_rad(60.0 * k), cell.joint(i).lower, cell.joint(i).upper);
      }
    }
    attempt(q);
  }
  std::mt19937_64 rng(seed);
  for (int k = 0; k < perturbed_starts; ++k) {
    JointVector q = home;
    for (int i = 0; i < n; ++i) {
      if (options_.locked[static_cast<size_t>(i)]) {
        q[i] = q_[i];
        continue;
      }
      const Joint& j = cell.joint(i);
      // Arm and spin joints anywhere within limits; external axes near home (a third of the
      // range), so that the solution found does not send the track to its far end.
      const double half = j.type == JointType::prismatic || j.axis.kind == AxisKind::external
                              ? (j.upper - j.lower) / 6.0
                              : (j.upper - j.lower) / 2.0;
      const double mid = j.type == JointType::prismatic || j.axis.kind == AxisKind::external
                             ? home[i]
                             : 0.5 * (j.lower + j.upper);
      std::uniform_real_distribution<double> u(std::max(j.lower, mid - half),
                                               std::min(j.upper, mid + half));
      q[i] = u(rng);
    }
    attempt(q);
  }
  if (best.status == PoseStatus::converged) {
    best.max_joint_step = 0.0;
  }
  return best;
}

}  // namespace redpost
