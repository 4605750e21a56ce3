// Tracking a stream of TCP targets with the whole cell: Andres et al. Algorithm 1.
//
// The tracker carries the joint vector q from one pose to the next. For each target it iterates
//   FK -> task error (eq. 14) -> Jacobian -> arm conditioning (step 8) -> RRS step (Alg. 2)
// until the TCP is within tolerance, applying the null-space goals (eq. 13) once per pose, on
// the first iteration, so that their effect per pose does not depend on how many correction
// iterations the pose needed. Joint limits are enforced by locking a joint that would cross
// its limit at the limit and solving again with the others; a pose that can only be reached
// beyond a limit fails. The first pose of a path, usually far from home, is solved from
// several starts (solve_first_pose). docs/redundancy.md.
#pragma once

#include <bitset>
#include <cstdint>
#include <limits>

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/redundancy/null_space.hpp"
#include "redpost/redundancy/rrs_step.hpp"
#include "redpost/redundancy/task_error.hpp"

namespace redpost {

struct TrackerOptions {
  double position_tolerance_mm = 1e-4;
  double axis_tolerance_rad = 1e-7;
  int max_iterations = 50;
  // Largest change of a joint between two consecutive poses (a wrist flip is larger).
  double max_joint_step_rad = deg_to_rad(15.0);
  double max_joint_step_mm = 100.0;
  // Largest weighted step per iteration (a trust region for poses far from the current one).
  double max_iteration_step = 0.3;
  NullSpaceGains gains;
  RrsSettings rrs;  // characteristic_length_mm is taken from the cell when it declares one
                    // Start each pose of a steady stretch of path (equal steps) from the linear
                    // extrapolation of
  // the last two postures instead of the last one; false: plain Algorithm 1.
  bool extrapolate = true;
  // Joints held at their current value (e.g. to compare with track and table frozen).
  std::bitset<kMaxJoints> locked;
  // Reference posture for centring; empty: the cell's home.
  JointVector q_ref;
  // A further goal (not owned; null: none), added at every pose whether following a plan or not.
  const ExtraGoal* extra_goal = nullptr;
};

enum class PoseStatus : std::uint8_t {
  converged,
  unreachable,  // the task error stalls above tolerance
  joint_limit,  // the pose needs a joint beyond its limit
  joint_jump,   // consecutive postures differ by more than the bound (e.g. a wrist flip)
};

const char* to_string(PoseStatus status);

struct PoseResult {
  PoseStatus status = PoseStatus::converged;
  JointVector q;  // the posture (on failure: the last good one, unchanged)
  int iterations = 0;
  double position_error_mm = 0.0;
  double orientation_error_rad = 0.0;
  double inv_condition = 0.0;   // 1/kappa_F of the arm at q
  double limit_margin = 0.0;    // smallest distance to a limit, fraction of that joint's range
  int limit_joint = -1;         // ... and which joint
  double max_joint_step = 0.0;  // largest |dq_i| from the previous pose (rad or mm)
  int max_step_joint = -1;      // ... and which joint
  int offending_joint = -1;     // for joint_limit / joint_jump: the joint concerned
  double offending_step = 0.0;  // for joint_jump: the step that joint would have made
  double sigma_min = 0.0;       // of the weighted, scaled Jacobian at the last iteration
  double damping = 0.0;         // damping used at the last iteration
};

// True when the step to `next` repeats the step from (p0, z0) to (p1, z1): same direction and
// length within a quarter, in position and in tool axis. On such a stretch the linear
// extrapolation of the last two postures is a second-order accurate start for the next pose.
bool steady_continuation(const Eigen::Vector3d& p0, const Eigen::Vector3d& z0,
                         const Eigen::Vector3d& p1, const Eigen::Vector3d& z1,
                         const TcpTarget& next);

class Tracker {
 public:
  Tracker(const Cell& cell, const TrackerOptions& options = {});

  // Sets the current posture (e.g. home, or the result of solve_first_pose). Resets the
  // conditioning switch.
  void reset(const JointVector& q);

  // Tracks one target from the current posture. On success the posture advances to the result.
  // Allocates nothing.
  PoseResult track(const TcpTarget& target);

  // Tracks `count` targets in order into `results`, stopping after the first pose that does not
  // converge (its result is written; later entries are left untouched). Returns the number of
  // converged poses. The outcome does not depend on how a path is split into calls.
  std::size_t track(const TcpTarget* targets, std::size_t count, PoseResult* results);

  // Moves the current posture onto `target`, a small correction of the last pose's target, by
  // the minimum-norm steps of Algorithm 2 alone: no secondary goals, so no self-motion. The
  // deflection compensation's fixed point (docs/deflection.md) moves a target by a fraction of a
  // millimetre once its posture is known; a fresh track() would add a null-space step each time
  // and the posture would wander along the self-motion instead of settling. On success the
  // posture becomes the result (and the predictor takes `target` as the last pose's).
  PoseResult correct(const TcpTarget& target);

  // Solves a target far from the current posture from several starts (the current posture, home
  // with the virtual joint turned in steps, seeded perturbations of home) without the jump bound,
  // and returns the converged posture within limits nearest home in the weighted metric. Does
  // not change the tracker's posture.
  PoseResult solve_first_pose(const TcpTarget& target, int perturbed_starts = 24,
                              std::uint64_t seed = 1) const;

  // Follows a planned posture (docs/redundancy.md, "Whole-path planning"): from the next pose
  // on, the centring of eq. 13 pulls towards q_plan with `gain` (per pose, instead of the
  // options' reference and gain), the conditioning switch is off (the plan has weighed the
  // conditioning), and the null-space motion per pose may reach `max_motion` (weighted norm).
  // Call before each pose; stop_following() returns to the options' goals.
  // The joints in `hold` (the external axes) are set to the plan's values and the step leaves
  // them there, unless the pose cannot be met so; the others are pulled towards it. The
  // minimum-norm step would otherwise move the heavy axes a little at every pose, back and
  // forth about the plan: corners at their low accelerations in every motion
  // (docs/redundancy.md, "Tracking the plan").
  void follow(const JointVector& q_plan, double gain, double max_motion,
              std::bitset<kMaxJoints> hold = {});
  void stop_following();
  bool following() const { return following_; }
  // The planned posture followed (null when not following).
  const JointVector* plan_target() const { return following_ ? &q_plan_ : nullptr; }

  const JointVector& q() const { return q_; }
  // The TCP pose at q() (valid after a converged track(); computed otherwise).
  Isometry tcp_pose_at_q() const;
  const Cell& cell() const { return *cell_; }
  const TrackerOptions& options() const { return options_; }

 private:
  struct Scratch {
    KinematicsData data;
    Jacobian J;
    RrsWorkspace rrs;
    JointVector h, h_lim, grad, dq, inv_sqrt_w;
  };
  // State of the conditioning switch of eq. 13.
  struct SwitchState {
    bool active = false;
    JointVector q_Ts;  // posture where 1/kappa_F crossed the threshold
    // 1/kappa_F at the posture the next pose starts from, when already known (the previous
    // pose ended there); NaN otherwise.
    double inv_kappa_at_start = std::numeric_limits<double>::quiet_NaN();
  };
  // Newton iterations from q towards the target, the core of track() and solve_first_pose().
  // With `goals`, the null-space motion is applied on the first iteration; `full_goals` adds the
  // conditioning and limit terms to the centring.
  PoseResult iterate(const TcpTarget& target, JointVector q, SwitchState* goals, bool full_goals,
                     int max_iterations, bool start_evaluated, Scratch& s) const;
  void null_space_motion(const JointVector& q, SwitchState& sw, bool full_goals, Scratch& s) const;
  void check_jump(PoseResult& r) const;

  const Cell* cell_;
  TrackerOptions options_;
  JointVector q_;
  JointVector q_ref_;
  bool following_ = false;
  std::bitset<kMaxJoints> follow_hold_;
  bool holding_ = false;  // follow_hold_ in force for the iterations under way
  JointVector q_plan_;
  double follow_gain_ = 0.0;
  double follow_max_motion_ = 0.0;
  JointVector base_inv_sqrt_w_;
  SwitchState switch_;
  // The last two converged poses, for the predictor.
  JointVector q_prev_;
  Eigen::Vector3d last_p_, last_z_, before_p_, before_z_;
  int history_ = 0;
  bool steady(const TcpTarget& target) const;
  Scratch scratch_;
  bool scratch_valid_ = false;  // scratch_ holds FK and Jacobian at q_
};

}  // namespace redpost
