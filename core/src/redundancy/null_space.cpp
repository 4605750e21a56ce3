#include "redpost/redundancy/null_space.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>

namespace redpost {

void inverse_condition_gradient(const Cell& cell, const KinematicsData& data, const Jacobian& J_B,
                                JointVector& gradient) {
  const int n = cell.size();
  gradient.setZero(n);
  const ConditioningSpec& cs = cell.conditioning;
  const int first = cs.declared() ? cs.first : 0;
  const int count = cs.declared() ? cs.count() : n;
  const double inv_L = 1.0 / cs.characteristic_length_mm;

  // J_N = arm columns with the linear rows scaled by 1/L; M = J_N J_N^T.
  Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::ColMajor, 6, kMaxJoints> JN =
      J_B.middleCols(first, count);
  JN.bottomRows<3>() *= inv_L;
  const Eigen::Matrix<double, 6, 6> M = JN * JN.transpose();
  Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(M);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-14 * M.trace()))
    return;
  const Eigen::Matrix<double, 6, 6> Minv = ldlt.solve(Eigen::Matrix<double, 6, 6>::Identity());
  const double tr = M.trace(), tr_inv = Minv.trace();
  const double f = 6.0 / std::sqrt(tr * tr_inv);  // 1/kappa_F

  // d f = <G, dJ_N>, G = -f (J_N / tr M - M^-2 J_N / tr M^-1).
  const Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::ColMajor, 6, kMaxJoints> G =
      -f * (JN / tr - (Minv * Minv * JN) / tr_inv);

  const Eigen::Vector3d p = data.T_B_tcp.translation();
  // Only joints from the first arm joint on change the arm's Jacobian relative to itself.
  for (int k = first; k < n; ++k) {
    const Eigen::Vector3d& zk = data.z_B_joint[static_cast<size_t>(k)];
    const Eigen::Vector3d& pk = data.p_B_joint[static_cast<size_t>(k)];
    const bool k_prismatic = cell.joint(k).type == JointType::prismatic;
    const Eigen::Vector3d dp = k_prismatic ? zk : Eigen::Vector3d(zk.cross(p - pk));  // d p / dq_k
    double df = 0.0;
    for (int c = 0; c < count; ++c) {
      const int i = first + c;
      const Eigen::Vector3d& zi = data.z_B_joint[static_cast<size_t>(i)];
      const Eigen::Vector3d& pi = data.p_B_joint[static_cast<size_t>(i)];
      Eigen::Vector3d dz = Eigen::Vector3d::Zero(), dpi = Eigen::Vector3d::Zero();
      if (k < i) {  // joint k moves joint i's axis
        if (!k_prismatic) {
          dz = zk.cross(zi);
          dpi = zk.cross(pi - pk);
        } else {
          dpi = zk;
        }
      }
      Eigen::Matrix<double, 6, 1> dJ;
      if (cell.joint(i).type == JointType::prismatic) {
        dJ.head<3>().setZero();
        dJ.tail<3>() = dz;
      } else {
        dJ.head<3>() = dz;
        dJ.tail<3>() = dz.cross(p - pi) + zi.cross(dp - dpi);
      }
      dJ.tail<3>() *= inv_L;
      df += G.col(c).dot(dJ);
    }
    gradient[k] = df;
  }
}

void limit_avoidance(const Cell& cell, const JointVector& q, double gain, double zone,
                     JointVector& h) {
  h.setZero(cell.size());
  if (gain == 0.0)
    return;
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    const double width = zone * (j.upper - j.lower);
    if (!(width > 0.0))
      continue;
    const double from_lower = q[i] - j.lower, from_upper = j.upper - q[i];
    if (from_lower < width)
      h[i] += gain * (width - from_lower);
    if (from_upper < width)
      h[i] -= gain * (width - from_upper);
  }
}

double smallest_limit_margin(const Cell& cell, const JointVector& q, int* joint) {
  double best = std::numeric_limits<double>::infinity();
  int best_joint = -1;
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    const double range = j.upper - j.lower;
    if (!(range > 0.0))
      continue;
    const double m = std::min(q[i] - j.lower, j.upper - q[i]) / range;
    if (m < best) {
      best = m;
      best_joint = i;
    }
  }
  if (joint)
    *joint = best_joint;
  return best;
}

}  // namespace redpost
