// A written motion as the time model sees it (path_timer.hpp's TimedMotion), from the postures
// at its two ends: the session builds each motion it writes with these, and the plan builds the
// motions a candidate plan would write (post/plan_time.hpp), so that both are timed alike.
#pragma once

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/types.hpp"
#include "redpost/timing/path_timer.hpp"

namespace redpost {

// Rotation angle between two orientations (rad).
double rotation_angle(const Eigen::Matrix3d& R_a, const Eigen::Matrix3d& R_b);

// A CP motion from (q0, T_B_tcp0) to (q1, T_B_tcp1) along length_mm of TCP path at asked_mm_s,
// blended over blend_mm at its end: its path parameter (the TCP's path, or for a motion that only
// turns, the turn at the orientation speed as mm at the asked speed), its orientation cap, the
// joints' chord rates (its entry and exit rates), its tangent. $VEL.CP is the asked speed.
TimedMotion cp_motion(const Cell& cell, const JointVector& q0, const Isometry& T_B_tcp0,
                      const JointVector& q1, const Isometry& T_B_tcp1, double length_mm,
                      double asked_mm_s, double orientation_velocity_rad_s, double blend_mm);

// KUKA's synchronous PTP from q0 to q1: every axis starts and stops with the slowest, each on a
// trapezoid at the controller's PTP share of its velocity and acceleration limits.
TimedMotion synchronous_ptp(const Cell& cell, const JointVector& q0, const JointVector& q1,
                            const ControllerTiming& controller);

}  // namespace redpost
