#include "redpost/machining/elastostatic.hpp"

#include <Eigen/LU>
#include <cmath>
#include <string>

#include "redpost/io/error.hpp"
#include "redpost/kinematics/jacobian.hpp"

namespace redpost {

namespace {

// Below this reciprocal condition number a 6 x 6 factorisation is treated as singular. The
// matrices here mix mm and rad, so well-posed cases sit around 1e-4 .. 1e-1; 1e-12 only
// catches what really has no solution.
constexpr double kMinRcond = 1e-12;

std::string cell_label(const Cell& cell) {
  return cell.source_file.empty() ? "cell '" + cell.name + "'" : cell.source_file;
}

// The columns of the geometric Jacobian at the TCP that belong to the compliant joints.
Matrix6d compliant_jacobian(const Cell& cell, const KinematicsData& data,
                            const std::array<int, 6>& idx) {
  Jacobian J_all;
  tcp_jacobian(cell, data, J_all);
  Matrix6d J;
  for (int i = 0; i < 6; ++i)
    J.col(i) = J_all.col(idx[static_cast<size_t>(i)]);
  return J;
}

// Eq. 4.4 from the compliant columns J = [omega_k; v_k] (k in chain order). Moving joint i
// turns every later frame by omega_i and carries the TCP along v_i, so for column j:
//   i before j:     d(col_j)/dtheta_i = [omega_i x omega_j; omega_i x v_j]
//                   (z_j, p_j and the TCP all turn with joint i, and the derivative of a cross
//                   product under a rotation is the rotated cross product),
//   i at/after j:   d(col_j)/dtheta_i = [0; omega_j x v_i]
//                   (only the TCP moves, by v_i).
// A prismatic joint (omega = 0) fits the same rules: it translates what follows it, so only the
// TCP's lever arm on the earlier revolute joints changes. K_C(j, i) = w . d(col_j)/dtheta_i.
Matrix6d complementary_from_columns(const Matrix6d& J, const Vector6d& w) {
  const Eigen::Vector3d m = w.head<3>(), f = w.tail<3>();
  Matrix6d K_C;
  for (int i = 0; i < 6; ++i) {
    const Eigen::Vector3d om_i = J.col(i).head<3>(), v_i = J.col(i).tail<3>();
    for (int j = 0; j < 6; ++j) {
      const Eigen::Vector3d om_j = J.col(j).head<3>(), v_j = J.col(j).tail<3>();
      if (i < j)
        K_C(j, i) = m.dot(om_i.cross(om_j)) + f.dot(om_i.cross(v_j));
      else
        K_C(j, i) = f.dot(om_j.cross(v_i));
    }
  }
  return K_C;
}

Vector6d stiffness_diagonal(const Cell& cell, const std::array<int, 6>& idx) {
  Vector6d k;
  for (int i = 0; i < 6; ++i)
    k[i] = *cell.joint(idx[static_cast<size_t>(i)]).stiffness;
  return k;
}

}  // namespace

std::array<int, 6> compliant_joints(const Cell& cell) {
  std::array<int, 6> idx{};
  int count = 0;
  for (int i = 0; i < cell.size(); ++i) {
    if (!cell.joint(i).stiffness)
      continue;
    if (count < 6)
      idx[static_cast<size_t>(count)] = i;
    ++count;
  }
  if (count != 6)
    throw Error(ErrorCode::bad_input,
                cell_label(cell) +
                    ": the elastostatic model needs exactly six joints with a "
                    "<stiffness>, this cell has " +
                    std::to_string(count) +
                    "; give each arm joint its stiffness (docs/cell-format.md)");
  return idx;
}

Matrix6d joint_stiffness(const Cell& cell) {
  return stiffness_diagonal(cell, compliant_joints(cell)).asDiagonal();
}

Matrix6d complementary_stiffness(const Cell& cell, const KinematicsData& data, const Vector6d& w) {
  return complementary_from_columns(compliant_jacobian(cell, data, compliant_joints(cell)), w);
}

Matrix6d complementary_stiffness(const Cell& cell, const JointVector& q, const Vector6d& w) {
  KinematicsData data;
  forward_kinematics(cell, q, data, false);
  return complementary_stiffness(cell, data, w);
}

Matrix6d cartesian_stiffness(const Cell& cell, const JointVector& q, const Vector6d& w,
                             const ElastostaticOptions& options) {
  const std::array<int, 6> idx = compliant_joints(cell);
  KinematicsData data;
  forward_kinematics(cell, q, data, false);
  const Matrix6d J = compliant_jacobian(cell, data, idx);
  Matrix6d K = stiffness_diagonal(cell, idx).asDiagonal();
  if (options.complementary)
    K -= complementary_from_columns(J, w);
  const Eigen::PartialPivLU<Matrix6d> lu(J);
  if (!(lu.rcond() > kMinRcond))
    throw Error(ErrorCode::bad_input,
                cell_label(cell) +
                    ": the Jacobian of the compliant joints is singular at this posture, so the "
                    "Cartesian stiffness K_X (Caro eq. 4.2) does not exist; move the pose away "
                    "from the singularity");
  const Matrix6d J_inv = lu.inverse();
  return J_inv.transpose() * K * J_inv;
}

Vector6d tcp_displacement(const Cell& cell, const KinematicsData& data, const Vector6d& w,
                          const ElastostaticOptions& options) {
  const std::array<int, 6> idx = compliant_joints(cell);
  const Matrix6d J = compliant_jacobian(cell, data, idx);
  const Vector6d k = stiffness_diagonal(cell, idx);
  // The joints' static balance: J^T w are the torques the wrench puts on them, and the springs
  // answer with (K_theta - K_C) dtheta. The TCP then moves by J dtheta (eq. 4.1 with 4.2).
  const Vector6d tau = J.transpose() * w;
  Vector6d dtheta;
  if (!options.complementary) {
    dtheta = tau.cwiseQuotient(k);
  } else {
    Matrix6d K = k.asDiagonal();
    K -= complementary_from_columns(J, w);
    const Eigen::PartialPivLU<Matrix6d> lu(K);
    // A vanishing pivot against the stiffest joint: as telling as rcond() here (K is K_theta
    // plus a load term) at a fraction of its cost, which was a quarter of this function's.
    const double pivot = lu.matrixLU().diagonal().cwiseAbs().minCoeff();
    if (!(pivot > kMinRcond * k.maxCoeff()))
      throw Error(ErrorCode::bad_input,
                  cell_label(cell) +
                      ": K_theta - K_C is singular for this wrench (Caro eq. 4.2): the wrench is "
                      "too large for the linear elastostatic model");
    dtheta = lu.solve(tau);
  }
  return J * dtheta;
}

Vector6d tcp_displacement(const Cell& cell, const JointVector& q, const Vector6d& w,
                          const ElastostaticOptions& options) {
  KinematicsData data;
  forward_kinematics(cell, q, data, false);
  return tcp_displacement(cell, data, w, options);
}

}  // namespace redpost
