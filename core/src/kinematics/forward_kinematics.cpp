#include "redpost/kinematics/forward_kinematics.hpp"

#include <cassert>
#include <cmath>
#include <utility>

#include "kinematics/sincos.hpp"

namespace redpost {

namespace {

// A frame as three axes and an origin in plain scalars, updated in place link by link.
// Composing with the sparse DH factors directly (rotations about x and z, translations along x
// and z) costs a fraction of a general 4x4 product, and scalars keep the whole frame in
// registers (Eigen's 3-vectors go through 2-wide packets plus a remainder at this size).
struct Frame {
  double x0, x1, x2, y0, y1, y2, z0, z1, z2, p0, p1, p2;

  void set(const Isometry& T) {
    const auto& M = T.matrix();
    x0 = M(0, 0), x1 = M(1, 0), x2 = M(2, 0);
    y0 = M(0, 1), y1 = M(1, 1), y2 = M(2, 1);
    z0 = M(0, 2), z1 = M(1, 2), z2 = M(2, 2);
    p0 = M(0, 3), p1 = M(1, 3), p2 = M(2, 3);
  }
  void compose(const Isometry& T) {  // this := this * T
    const auto& M = T.matrix();
    const double t0 = M(0, 3), t1 = M(1, 3), t2 = M(2, 3);
    p0 += t0 * x0 + t1 * y0 + t2 * z0;
    p1 += t0 * x1 + t1 * y1 + t2 * z1;
    p2 += t0 * x2 + t1 * y2 + t2 * z2;
    double c[3][3];
    for (int k = 0; k < 3; ++k) {
      c[k][0] = M(0, k) * x0 + M(1, k) * y0 + M(2, k) * z0;
      c[k][1] = M(0, k) * x1 + M(1, k) * y1 + M(2, k) * z1;
      c[k][2] = M(0, k) * x2 + M(1, k) * y2 + M(2, k) * z2;
    }
    x0 = c[0][0], x1 = c[0][1], x2 = c[0][2];
    y0 = c[1][0], y1 = c[1][1], y2 = c[1][2];
    z0 = c[2][0], z1 = c[2][1], z2 = c[2][2];
  }
  void rot_x(double c, double s) {  // this := this * Rx: y' = c y + s z, z' = c z - s y
    const double n0 = c * y0 + s * z0, n1 = c * y1 + s * z1, n2 = c * y2 + s * z2;
    z0 = c * z0 - s * y0, z1 = c * z1 - s * y1, z2 = c * z2 - s * y2;
    y0 = n0, y1 = n1, y2 = n2;
  }
  void rot_z(double c, double s) {  // this := this * Rz: x' = c x + s y, y' = c y - s x
    const double n0 = c * x0 + s * y0, n1 = c * x1 + s * y1, n2 = c * x2 + s * y2;
    y0 = c * y0 - s * x0, y1 = c * y1 - s * x1, y2 = c * y2 - s * x2;
    x0 = n0, x1 = n1, x2 = n2;
  }
  void rot_x(const Cell::LinkConstants& k) {
    using Twist = Cell::LinkConstants::Twist;
    switch (k.twist) {
      case Twist::zero:
        break;
      case Twist::plus_quarter:  // y' = z, z' = -y
        std::swap(y0, z0), std::swap(y1, z1), std::swap(y2, z2);
        z0 = -z0, z1 = -z1, z2 = -z2;
        break;
      case Twist::minus_quarter:  // y' = -z, z' = y
        std::swap(y0, z0), std::swap(y1, z1), std::swap(y2, z2);
        y0 = -y0, y1 = -y1, y2 = -y2;
        break;
      case Twist::general:
        rot_x(k.cos_alpha, k.sin_alpha);
        break;
    }
  }
  void translate_x(double a) { p0 += a * x0, p1 += a * x1, p2 += a * x2; }
  void translate_z(double d) { p0 += d * z0, p1 += d * z1, p2 += d * z2; }
  void z_axis(Eigen::Vector3d& z) const { z = Eigen::Vector3d(z0, z1, z2); }
  void origin(Eigen::Vector3d& p) const { p = Eigen::Vector3d(p0, p1, p2); }
  void store(Isometry& T) const {   // the top 3x4; the bottom row stays (0 0 0 1)
    double* m = T.matrix().data();  // column-major 4x4
    m[0] = x0, m[1] = x1, m[2] = x2;
    m[4] = y0, m[5] = y1, m[6] = y2;
    m[8] = z0, m[9] = z1, m[10] = z2;
    m[12] = p0, m[13] = p1, m[14] = p2;
  }
};

}  // namespace

void forward_kinematics(const Cell& cell, const JointVector& q, KinematicsData& data,
                        bool link_frames) {
  assert(q.size() == cell.size());
  const int n = cell.size();
  data.joint_count = n;

  // All sines and cosines first: independent of each other, so they overlap in the pipeline,
  // and the frame loop below then runs without calls that spill the running frame.
  double theta[kMaxJoints], ct_all[kMaxJoints], st_all[kMaxJoints];
  for (int i = 0; i < n; ++i) {
    const Joint& j = cell.joints[static_cast<size_t>(i)];
    theta[i] = j.type == JointType::prismatic ? j.theta_rad : j.theta_rad + q[i];
  }
  detail::sincos_batch(theta, st_all, ct_all, n);

  Frame F;
  F.set(cell.T_B_0);
  for (int i = 0; i < n; ++i) {
    const Joint& j = cell.joints[static_cast<size_t>(i)];
    const Cell::LinkConstants& k = cell.link[static_cast<size_t>(i)];
    if (j.has_fixed_before)
      F.compose(j.T_prev_link);

    const double ct = ct_all[i], st = st_all[i];
    const double d = j.type == JointType::prismatic ? j.d_mm + q[i] : j.d_mm;

    if (j.convention == DhConvention::standard) {
      // Rz(theta) Tz(d) Tx(a) Rx(alpha): the joint acts about z of the incoming frame.
      F.z_axis(data.z_B_joint[static_cast<size_t>(i)]);
      F.origin(data.p_B_joint[static_cast<size_t>(i)]);
      F.rot_z(ct, st);
      if (d != 0.0)
        F.translate_z(d);
      if (j.a_mm != 0.0)
        F.translate_x(j.a_mm);
      F.rot_x(k);
    } else {
      // Rx(alpha) Tx(a) Rz(theta) Tz(d): the joint acts about z after Rx(alpha) Tx(a).
      F.rot_x(k);
      if (j.a_mm != 0.0)
        F.translate_x(j.a_mm);
      F.z_axis(data.z_B_joint[static_cast<size_t>(i)]);
      F.origin(data.p_B_joint[static_cast<size_t>(i)]);
      F.rot_z(ct, st);
      if (d != 0.0)
        F.translate_z(d);
    }
    if (link_frames)
      F.store(data.T_B_link[static_cast<size_t>(i)]);
  }
  if (cell.has_tcp_frame)
    F.compose(cell.T_last_tcp);
  F.store(data.T_B_tcp);
}

Isometry tcp_pose(const Cell& cell, const JointVector& q) {
  KinematicsData data;
  forward_kinematics(cell, q, data);
  return data.T_B_tcp;
}

}  // namespace redpost
