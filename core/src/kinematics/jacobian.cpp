#include "redpost/kinematics/jacobian.hpp"

namespace redpost {

void tcp_jacobian(const Cell& cell, const KinematicsData& data, Jacobian& J_B) {
  const int n = cell.size();
  J_B.resize(6, n);
  const Eigen::Vector3d& p = data.T_B_tcp.translation();
  const double px = p.x(), py = p.y(), pz = p.z();
  double* col = J_B.data();  // column-major, 6 rows: written in place, column by column
  for (int i = 0; i < n; ++i, col += 6) {
    const auto k = static_cast<size_t>(i);
    const double zx = data.z_B_joint[k].x(), zy = data.z_B_joint[k].y(), zz = data.z_B_joint[k].z();
    if (cell.joints[k].type == JointType::prismatic) {
      col[0] = col[1] = col[2] = 0.0;
      col[3] = zx, col[4] = zy, col[5] = zz;
    } else {
      // [z; z x (p_tcp - p_i)]
      const double rx = px - data.p_B_joint[k].x(), ry = py - data.p_B_joint[k].y(),
                   rz = pz - data.p_B_joint[k].z();
      col[0] = zx, col[1] = zy, col[2] = zz;
      col[3] = zy * rz - zz * ry;
      col[4] = zz * rx - zx * rz;
      col[5] = zx * ry - zy * rx;
    }
  }
}

}  // namespace redpost
