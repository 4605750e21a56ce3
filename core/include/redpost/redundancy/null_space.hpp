// Secondary goals of the redundancy resolution, combined as in Andres et al. eq. 13:
//
//   h = h_jnt + h_cond + h_grad + h_lim
//   h_jnt  = -H_jnt (q - q_ref)                 centring on a reference posture
//   h_cond = -H_cond kappa_F (q - q_Ts)          the paper's switch: active while 1/kappa_F of
//                                                the arm is below a threshold, pulling back
//                                                towards q_Ts, the posture where it crossed it
//   h_grad = +k_grad W^-1 grad(1/kappa_F)        ascent of the arm's conditioning (our addition)
//   h_lim  = k_lim * (push out of the zone near each limit)
//
// h is a desired joint motion (rad, mm) per pose; rrs_step projects it onto the null space of the
// task in the weighted metric, so it never disturbs the TCP to first order.
#pragma once

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost {

// A secondary goal beyond the four above, in the same form (eq. 13): a desired joint motion
// added to h at each pose before the cap, in the weighted metric. The clearance to the cell's
// bodies is one (redundancy/clearance_goal.hpp).
class ExtraGoal {
 public:
  virtual ~ExtraGoal() = default;
  virtual void add(const JointVector& q, JointVector& h) const = 0;
};

struct NullSpaceGains {
  double centring = 0.01;               // H_jnt (per pose), paper: diag(0.01)
  double conditioning = 0.01;           // H_cond, paper: diag(0.01)
  double conditioning_threshold = 0.3;  // switch on 1/kappa_F of the arm
  double conditioning_gradient = 0.1;   // k_grad on grad(1/kappa_F), active with the switch
  double limits = 0.1;                  // k_lim
  double limit_zone = 0.1;              // fraction of each joint's range near a limit
  // Largest null-space motion per pose, weighted norm sqrt(sum w_i h_i^2): 0.01 is 0.57 deg of
  // a wrist or 10 mm of the reference cell's track. The goals pull hard when far from what they
  // want (centring after a long excursion, the switch after a long stay below the threshold);
  // the cap keeps each pose's self-motion small and the joint trajectory smooth.
  double max_motion_per_pose = 0.01;
};

// Gradient of 1/kappa_F of the arm (cell.conditioning) with respect to every joint, from the
// analytic derivative of the geometric Jacobian (dJ_i/dq_k = the Lie bracket of the joint
// twists). Needs the frames in `data`. Joints that only move the arm rigidly (table, track)
// have zero gradient.
void inverse_condition_gradient(const Cell& cell, const KinematicsData& data, const Jacobian& J_B,
                                JointVector& gradient);

// Motion pushing joints out of the zone near their limits: 0 outside the zone, growing linearly
// to k_lim * zone width at the limit.
void limit_avoidance(const Cell& cell, const JointVector& q, double gain, double zone,
                     JointVector& h);

// Smallest distance of q to a limit, as a fraction of each joint's range; `joint` gets its
// index. 0.5 is a joint in mid-range, 0 at a limit, negative beyond.
double smallest_limit_margin(const Cell& cell, const JointVector& q, int* joint = nullptr);

}  // namespace redpost
