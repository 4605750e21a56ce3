#include "redpost/redundancy/task_error.hpp"

#include <cmath>

namespace redpost {

Eigen::Matrix3d desired_rotation(const TcpTarget& target, const Eigen::Matrix3d& R_B_tcp) {
  if (target.spin_fixed)
    return target.R_B;
  // The smallest rotation taking the current z onto the target axis, applied to the current
  // frame. With k = z x z_d and c = z . z_d it is R = I + [k]x + [k]x^2 / (1 + c): no
  // trigonometry, exact for small angles, and fine up to nearly opposite axes.
  const Eigen::Vector3d z = R_B_tcp.col(2);
  const Eigen::Vector3d& zd = target.z_B;
  const double c = z.dot(zd);
  if (c < -1.0 + 1e-12) {
    // Opposite axes: any half turn about an axis normal to z; take the TCP's x.
    return Eigen::AngleAxisd(kPi, R_B_tcp.col(0)).toRotationMatrix() * R_B_tcp;
  }
  const Eigen::Vector3d k = z.cross(zd);
  const double f = 1.0 / (1.0 + c);
  Eigen::Matrix3d R_d;
  for (int col = 0; col < 3; ++col) {
    const Eigen::Vector3d v = R_B_tcp.col(col);
    const Eigen::Vector3d kv = k.cross(v);
    R_d.col(col) = v + kv + f * k.cross(kv);
  }
  return R_d;
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

Vector6d task_error(const Isometry& T_B_tcp, const TcpTarget& target) {
  if (target.spin_fixed)
    return task_error(T_B_tcp, target.R_B, target.p_B_mm);
  const Eigen::Vector3d z = T_B_tcp.linear().col(2);
  const Eigen::Vector3d k = z.cross(target.z_B);
  const double c = z.dot(target.z_B);
  Vector6d dt;
  if (c > 0.0) {
    dt.head<3>() = k;  // sin(phi) times the unit axis, as eq. 16 gives it
  } else {
    // Beyond 90 deg: phi times the unit axis (the log map), as in the general form above.
    const Eigen::Matrix3d R_d = desired_rotation(target, T_B_tcp.linear());
    dt.head<3>() = task_error(T_B_tcp, R_d, target.p_B_mm).head<3>();
  }
  dt.tail<3>() = target.p_B_mm - T_B_tcp.translation();
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
