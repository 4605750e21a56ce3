#include "redpost/kinematics/kuka_abc.hpp"

#include <cmath>

namespace redpost {

Eigen::Matrix3d rotation_from_abc(const KukaAbc& abc) {
  return (Eigen::AngleAxisd(deg_to_rad(abc.a_deg), Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(deg_to_rad(abc.b_deg), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(deg_to_rad(abc.c_deg), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

KukaAbc abc_from_rotation(const Eigen::Matrix3d& R) {
  // R = Rz(A) Ry(B) Rx(C): r31 = -sin B, r21/r11 = tan A, r32/r33 = tan C.
  KukaAbc out;
  const double cos_b = std::hypot(R(0, 0), R(1, 0));
  out.b_deg = rad_to_deg(std::atan2(-R(2, 0), cos_b));
  if (cos_b > 1e-12) {
    out.a_deg = rad_to_deg(std::atan2(R(1, 0), R(0, 0)));
    out.c_deg = rad_to_deg(std::atan2(R(2, 1), R(2, 2)));
  } else {
    // Gimbal lock: only A -+ C is defined. Put it all in A, as the controller does.
    out.c_deg = 0.0;
    out.a_deg = rad_to_deg(std::atan2(-R(0, 1), R(1, 1)));
  }
  // atan2 returns (-180, 180]; fold -180 to 180 so that the printed form is unique.
  if (out.a_deg == -180.0)
    out.a_deg = 180.0;
  if (out.c_deg == -180.0)
    out.c_deg = 180.0;
  return out;
}

Isometry frame_from_xyzabc(double x_mm, double y_mm, double z_mm, const KukaAbc& abc) {
  Isometry T = Isometry::Identity();
  T.linear() = rotation_from_abc(abc);
  T.translation() = Eigen::Vector3d(x_mm, y_mm, z_mm);
  return T;
}

}  // namespace redpost
