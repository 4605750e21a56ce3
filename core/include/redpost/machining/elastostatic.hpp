// The elastostatic model of a milling robot (Caro 2014 chapter 4, eqs. 4.1-4.4; issue 8):
//
//   w = K_X dX,   K_X = J^-T (K_theta - K_C) J^-1,   K_C = [dJ^T/dtheta_1 w ... dJ^T/dtheta_6 w]
//
// J is the 6 x 6 Jacobian of the arm joints that carry a <stiffness> (rows [omega; v] at the TCP,
// in {B}); every other joint (track, table, the virtual spin) is rigid. Internal units: N, mm,
// rad; K_theta in N mm/rad (N/mm for a prismatic joint). The wrench w = [m; f] (N mm, N) is the
// one applied TO the TCP, expressed in {B} at the TCP point, so that w^T dX is work: the
// tool-on-workpiece force of cutting_force.hpp enters with the opposite sign. dX = [d_rot; d_pos]
// (rad, mm).
//
// K_C comes from differentiating the joint torques J^T(theta) w at constant w: K_theta dtheta =
// J^T dw + K_C dtheta. It is not symmetric in general.
#pragma once

#include <array>

#include <Eigen/Core>

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct ElastostaticOptions {
  // Include the complementary stiffness K_C (eq. 4.4). Off by default: it scales with |w| and
  // most placement studies drop it (PARAMETERS.md 1.3).
  bool complementary = false;
};

// The chain indices of the compliant joints (those with a stiffness), in chain order. Throws
// Error(bad_input) unless there are exactly six.
std::array<int, 6> compliant_joints(const Cell& cell);

// K_theta of eq. 4.3: the compliant joints' stiffnesses on the diagonal.
Matrix6d joint_stiffness(const Cell& cell);

// K_C of eq. 4.4 (N mm/rad) at q for the wrench w: column i = (dJ^T / dtheta_i) w, J restricted
// to the compliant joints. Analytic (no finite differences).
Matrix6d complementary_stiffness(const Cell& cell, const JointVector& q, const Vector6d& w);
// The same from the frames of a forward_kinematics(cell, q, data) call.
Matrix6d complementary_stiffness(const Cell& cell, const KinematicsData& data, const Vector6d& w);

// K_X of eq. 4.2 at q. Throws Error(bad_input) when J is singular.
Matrix6d cartesian_stiffness(const Cell& cell, const JointVector& q, const Vector6d& w,
                             const ElastostaticOptions& options = {});

// The small displacement screw dX = K_X^-1 w of the TCP (eq. 4.1), computed without inverting J:
// dX = J (K_theta - K_C)^-1 J^T w. No allocation. Throws Error(bad_input) when K_theta - K_C is
// singular (a wrench so large that the arm would buckle).
Vector6d tcp_displacement(const Cell& cell, const JointVector& q, const Vector6d& w,
                          const ElastostaticOptions& options = {});
// The same from the frames of a forward_kinematics(cell, q, data) call, for callers that have
// them already (the placement search).
Vector6d tcp_displacement(const Cell& cell, const KinematicsData& data, const Vector6d& w,
                          const ElastostaticOptions& options = {});

}  // namespace redpost
