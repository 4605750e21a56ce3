// Targets for the TCP and the task error of Andres et al. eq. 14-16.
//
//   dt = [ Q vect(Q^T Q_d) ; p_d - p ],   vect(M) = 1/2 [M32 - M23; M13 - M31; M21 - M12]
//
// Q, p: the TCP's current rotation and position in {B}; Q_d, p_d: the target's. The angular part
// is the axial vector of the rotation error, rotated into {B}; it equals sin(phi) u for an error
// of phi about u. Far from the target (phi > 90 deg, as on a first pose solved from home)
// sin(phi) falls back to 0 and the iteration would stall, so there the exact phi u (the log map)
// is used instead; near the target both agree to O(phi^3). docs/redundancy.md.
#pragma once

#include "redpost/kinematics/types.hpp"

namespace redpost {

// A TCP target in {B}. The tool axis is the TCP's z axis (from the tool tip towards the spindle,
// as the CL tool axis i, j, k). With spin_fixed the whole frame R_B is prescribed; otherwise the
// rotation about the axis is free and solved for through the virtual joint.
struct TcpTarget {
  Eigen::Vector3d p_B_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d z_B = Eigen::Vector3d::UnitZ();  // unit length
  Eigen::Matrix3d R_B = Eigen::Matrix3d::Identity();
  bool spin_fixed = false;

  static TcpTarget axis(const Eigen::Vector3d& p_B_mm, const Eigen::Vector3d& z_B) {
    TcpTarget t;
    t.p_B_mm = p_B_mm;
    t.z_B = z_B.normalized();
    return t;
  }
  static TcpTarget frame(const Isometry& T_B_tcp) {
    TcpTarget t;
    t.p_B_mm = T_B_tcp.translation();
    t.R_B = T_B_tcp.linear();
    t.z_B = t.R_B.col(2);
    t.spin_fixed = true;
    return t;
  }
};

// The axial vector of eq. 16.
inline Eigen::Vector3d vect(const Eigen::Matrix3d& M) {
  return 0.5 * Eigen::Vector3d(M(2, 1) - M(1, 2), M(0, 2) - M(2, 0), M(1, 0) - M(0, 1));
}

// The desired rotation for a target. For a free spin, Q_d is the current rotation turned by the
// smallest rotation that brings its z onto the target axis: the task then asks nothing about the
// spin, which the virtual joint and the null space are free to use.
Eigen::Matrix3d desired_rotation(const TcpTarget& target, const Eigen::Matrix3d& R_B_tcp);

// Eq. 14: [Q vect(Q^T Q_d); p_d - p], with the log map beyond 90 deg (see above).
Vector6d task_error(const Isometry& T_B_tcp, const Eigen::Matrix3d& R_B_desired,
                    const Eigen::Vector3d& p_B_desired);

// Eq. 14 for a target, with Q_d = desired_rotation(target, Q). For a free spin this reduces to
// [z x z_d; p_d - p] (vect is equivariant, Q vect(Q^T R Q) = vect(R), and vect of the smallest
// rotation from z to z_d is z x z_d), which is what is computed: no rotation matrix is formed.
Vector6d task_error(const Isometry& T_B_tcp, const TcpTarget& target);

// Angle between the TCP's z axis and the target axis (rad), and between frames if spin_fixed.
double orientation_error(const TcpTarget& target, const Eigen::Matrix3d& R_B_tcp);

}  // namespace redpost
