// One step of the redundancy resolution scheme: Andres et al. Algorithm 2, eq. 11, in a
// weighted metric and with damping near singularities.
//
// The joint step minimises sum_i w_i dq_i^2 subject to J dq = dt, plus a null-space motion:
//
//   dq = W^-1/2 [ Jw^+ dt + (I - Jw^+ Jw) W^1/2 h ],   Jw = S J W^-1/2
//
// W = diag(w_i) are the cell's joint weights (1 mm of track against 1 rad of wrist), S scales the
// linear task rows by 1/L (L the characteristic length) so that the damping threshold compares
// like with like; S does not change the exact solution. Algorithm 2 computes Jw^+ without
// forming it: a Householder QR of Jw^T = Q R, then
//   r = dt - Jw h~;   U^T y1 = r (forward substitution, U = R(1:6,:));   dy = Q [y1; 0] + h~.
// Near a singularity (smallest singular value sigma of Jw below eps) the forward substitution is
// replaced by damped least squares, y1 = U (U^T U + lambda^2 I)^-1 r, with the variable damping
// lambda^2 = (1 - (sigma/eps)^2) lambda_max^2 of Nakamura and Maciejewski: the step stays
// bounded as sigma -> 0 and is exact (lambda = 0) away from singularities. sigma is taken as the
// lower bound 1 / ||U^-1||_F (within a factor sqrt(6) of it). docs/redundancy.md.
#pragma once

#include <Eigen/Cholesky>

#include "redpost/kinematics/types.hpp"

namespace redpost {

struct RrsSettings {
  double characteristic_length_mm = 500.0;  // S = diag(1, 1, 1, 1/L, 1/L, 1/L)
  double singular_threshold = 0.02;         // eps, on sigma_min of S J W^-1/2
  double max_damping = 0.05;                // lambda_max
};

// Scratch space of one step: the Householder QR of A = (S J W^-1/2)^T (n x 6), stored as
// LAPACK does: R on and above the diagonal, the reflectors' tails below it, their factors in tau.
struct RrsWorkspace {
  double A[6][kMaxJoints];  // column-major: A[k] is column k
  double tau[6];
  JointVector y, h_w;
};

struct RrsStepInfo {
  double sigma_min = 0.0;  // lower bound on the smallest singular value of S J W^-1/2
  double damping = 0.0;    // lambda applied (0: exact Algorithm 2)
};

// dq for the task error dt (rows [omega; v], rad and mm) and the desired null-space motion h
// (joint units). inv_sqrt_w = W^-1/2 per joint; an entry of 0 locks that joint (it neither takes
// part in the task nor moves in the null space).
void rrs_step(const Jacobian& J_B, const Vector6d& dt, const JointVector& h,
              const JointVector& inv_sqrt_w, const RrsSettings& settings, RrsWorkspace& ws,
              JointVector& dq, RrsStepInfo& info);

}  // namespace redpost
