#include "redpost/task_error.hpp"

#include <cmath>

namespace redpost {

Eigen::Matrix3d desired_rotation(const TcpTarget& target, const Eigen::Matrix3d& R_B_tcp) {
  if (target.spin_fixed)
    return target.R_B;
  // The smallest rotation taking the current z onto the target axis, applied to the current
  // frame. Built from the two axes directly (Rodrigues), which stays exact for small angles.
  const Eigen::Vector3d z = R_B_tcp.col(2);
  const Eigen::Vector3d& zd = target.z_B;
  const Eigen::Vector3d axis = z.cross(zd);
  const double s = axis.norm(), c = z.dot(zd);
  if (s < 1e-15) {
    if (c > 0.0)
      return R_B_tcp;
    // Opposite axes: any half turn about an axis normal to z; take the TCP's x.
    return Eigen::AngleAxisd(kPi, R_B_tcp.col(0)).toRotationMatrix() * R_B_tcp;
  }
  return Eigen::AngleAxisd(std::atan2(s, c), axis / s).toRotationMatrix() * R_B_tcp;
}

Vector6d task_error(const Isometry& T_B_tcp, const Eigen::Matrix3d& R_B_desired,
                    const Eigen::Vector3d& p_B_desired) {
  const Eigen::Matrix3d& Q = T_B_tcp.linear();
  const Eigen::Matrix3d dQ = Q.transpose() * R_B_desired;  // eq. 15
  Vector6d dt;
  const double cos_phi = 0.5 * (dQ.trace() - 1.0);
  if (cos_phi > 0.0) {
    dt.head<3>() = Q * vect(dQ);  // eq. 14, 16
  } else {
    // Beyond 90 deg: phi u exactly, so that the step does not vanish near a half turn.
    const Eigen::AngleAxisd aa(dQ);
    dt.head<3>() = Q * (aa.angle() * aa.axis());
  }
  dt.tail<3>() = p_B_desired - T_B_tcp.translation();
  return dt;
}

double orientation_error(const TcpTarget& target, const Eigen::Matrix3d& R_B_tcp) {
  if (target.spin_fixed) {
    return Eigen::AngleAxisd(R_B_tcp.transpose() * target.R_B).angle();
  }
  const Eigen::Vector3d z = R_B_tcp.col(2);
  return std::atan2(z.cross(target.z_B).norm(), z.dot(target.z_B));
}

}  // namespace redpost
