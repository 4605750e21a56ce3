// The Frobenius condition number kappa_F of a Jacobian made homogeneous by a characteristic
// length L (Angeles; Andres Algorithm 1 step 8; Caro eq. 5.16):
//
//   J_N = [ J_omega ; J_v / L ]
//   kappa_F(J_N) = (1/m) * sqrt( tr(J_N J_N^T) * tr((J_N J_N^T)^-1) ),   m = 6 rows
//
// The 1/m factor makes kappa_F >= 1, so 1/kappa_F lies in [0, 1]: 1 is isotropic, 0 singular.
#pragma once

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost {

// 1/kappa_F of the 6 x n Jacobian J (rows [omega; v]) normalised by L (mm). Returns 0 for a
// rank-deficient J. Needs n >= 6.
double inverse_condition_frobenius(const Jacobian& J_B, double characteristic_length_mm);

// 1/kappa_F of the arm declared in the cell's <conditioning>, from the full-cell Jacobian: the
// arm's columns only. The base placement of the arm (track, table) rotates all its columns
// rigidly, which leaves kappa_F unchanged, so Andres' step 8.1 (theta_1 := 0) is not needed.
double arm_inverse_condition(const Cell& cell, const Jacobian& J_B);

}  // namespace redpost
