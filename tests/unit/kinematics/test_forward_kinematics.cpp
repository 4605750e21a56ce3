// Forward kinematics against published test vectors and against a second, independently
// written model of the same arm.
#include <random>

#include "catch_compat.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

struct KukaVector {
  double axes_deg[6];
  double x, y, z, a, b, c;  // $FLANGE in $ROBROOT, mm and deg
};

JointVector from_axes(const Cell& cell, const double* axes_deg) {
  JointVector q = cell.home();
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    if (j.axis.kind == AxisKind::arm)
      q[i] = from_axis_value(j, axes_deg[j.axis.number - 1]);
  }
  return q;
}

// Compares a frame with a KRL X Y Z A B C, as rotations (ABC is singular at B = +-90).
void check_frame(const Isometry& T, const KukaVector& v, double pos_tol_mm, double ang_tol_deg) {
  INFO("axes " << v.axes_deg[0] << " " << v.axes_deg[1] << " " << v.axes_deg[2] << " "
               << v.axes_deg[3] << " " << v.axes_deg[4] << " " << v.axes_deg[5]);
  CHECK(T.translation().x() == Approx(v.x).margin(pos_tol_mm));
  CHECK(T.translation().y() == Approx(v.y).margin(pos_tol_mm));
  CHECK(T.translation().z() == Approx(v.z).margin(pos_tol_mm));
  const Eigen::Matrix3d R_expected = rotation_from_abc({v.a, v.b, v.c});
  const double angle = Eigen::AngleAxisd(R_expected.transpose() * T.linear()).angle();
  CHECK(rad_to_deg(angle) < ang_tol_deg);
}

// shared/PARAMETERS.md 1.5, geometry (B) (KR 2000 series), printed to 0.01 mm and 0.001 deg.
const KukaVector kKr270Vectors[] = {
    {{0, -90, 90, 0, 0, 0}, 1680, 0, 1945, 0, 90, 0},
    {{0, -90, 90, 0, 90, 0}, 1450, 0, 1715, 180, 0, 180},
    {{30, -60, 100, 20, -45, -10}, 1764.29, -954.39, 1095.87, -75.132, 83.926, -59.006},
    {{-45, -30, 80, -170, 60, 200}, 1617.20, 1666.11, 534.99, -17.897, 61.964, -69.424},
    {{10, -100, 120, 35, -70, 90}, 1284.31, -100.58, 1692.57, -86.532, -32.615, -43.957},
};

// shared/PARAMETERS.md 2.2 (KR15/2, wrist offset above A3).
const KukaVector kKr15Vectors[] = {
    {{0, -90, 90, 0, 0, 0}, 1040, 0, 1480, 0, 90, 0},
    {{0, -90, 90, 0, 90, 0}, 900, 0, 1340, 180, 0, 180},
    {{30, -60, 100, 20, -45, -10}, 1159.99, -630.62, 978.61, -75.132, 83.926, -59.006},
};

}  // namespace

TEST_CASE("fk: KR270-2 flange matches the PARAMETERS.md 1.5 test vectors (geometry B)") {
  const Cell cell = test::shipped_cell("caro2014_kr270_table");
  KinematicsData data;
  for (const KukaVector& v : kKr270Vectors) {
    forward_kinematics(cell, from_axes(cell, v.axes_deg), data);
    // $FLANGE = F6 * Tz(f), f = 230 mm; F6 is the frame after the sixth link.
    const Isometry T_flange = data.T_B_link[5] * Eigen::Translation3d(0, 0, 230);
    check_frame(T_flange, v, 0.006, 0.0006);
  }
}

TEST_CASE("fk: KR15/2 flange matches the PARAMETERS.md 2.2 test vectors") {
  const Cell cell = test::shipped_cell("kr15_2");
  for (const KukaVector& v : kKr15Vectors) {
    check_frame(tcp_pose(cell, from_axes(cell, v.axes_deg)), v, 0.006, 0.0006);
  }
}

TEST_CASE("fk: KR270-2 spindle frame is the flange composed with Caro eq. 2.9") {
  const Cell cell = test::shipped_cell("caro2014_kr270_table");
  std::mt19937_64 rng(7);
  Eigen::Matrix3d R_6_7;  // eq. 2.9 as printed, columns
  const double h = std::sqrt(2.0) / 2.0;
  R_6_7 << 0, -h, h, 1, 0, 0, 0, h, h;
  KinematicsData data;
  for (int k = 0; k < 200; ++k) {
    JointVector q = test::random_posture(cell, rng);
    q[6] = 0.0;  // beta = 0: the TCP is F7 turned by pi about x7 (z from the tip to the spindle)
    forward_kinematics(cell, q, data);
    const Isometry& T_B_6 = data.T_B_link[5];
    const Eigen::Matrix3d Rx_pi = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
    CHECK((data.T_B_tcp.linear() - T_B_6.linear() * R_6_7 * Rx_pi).norm() < 1e-12);
    const Eigen::Vector3d p = T_B_6 * Eigen::Vector3d(0, 0, 684);
    CHECK((data.T_B_tcp.translation() - p).norm() < 1e-9);
  }
}

TEST_CASE("fk: the Andres cell's arm agrees with the stand-alone KR15/2 model") {
  // Two definitions of the same arm: Table 1 of Andres et al. (alpha_5 = +pi/2, tilted spindle)
  // and PARAMETERS.md 2.2 (alpha_5 = -pi/2, flange). With the controller mappings chosen in the
  // cell files, the same A1..A6 must put the flange in the same place. Andres' link 8 then
  // carries the spindle mount 443.4 - 140 = 303.4 mm beyond the flange, tilted by 0.3564 rad.
  const Cell andres = test::shipped_cell("andres2011_kr15_track_table");
  const Cell kr15 = test::shipped_cell("kr15_2");
  std::mt19937_64 rng(11);
  KinematicsData da, dk;
  for (int k = 0; k < 500; ++k) {
    const JointVector q_k = test::random_posture(kr15, rng);
    double axes[6];
    for (int i = 0; i < 6; ++i)
      axes[i] = to_axis_value(kr15.joint(i), q_k[i]);
    JointVector q_a = test::random_posture(andres, rng);  // random table, track and spin
    for (int i = 0; i < andres.size(); ++i) {
      const Joint& j = andres.joint(i);
      if (j.axis.kind == AxisKind::arm)
        q_a[i] = from_axis_value(j, axes[j.axis.number - 1]);
    }
    forward_kinematics(andres, q_a, da);
    forward_kinematics(kr15, q_k, dk);
    // $ROBROOT of the arm on the carriage: F0 (z down) turned so that x faces the table.
    const Isometry T_B_robroot = da.T_B_link[1] * Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitY());
    const Isometry T_B_flange = T_B_robroot * dk.T_B_tcp;
    const Isometry expected = T_B_flange * Eigen::Translation3d(0, 0, 303.4) *
                              Eigen::AngleAxisd(kPi + 0.3564, Eigen::Vector3d::UnitX());
    CHECK((da.T_B_link[7].translation() - expected.translation()).norm() < 1e-9);
    CHECK((da.T_B_link[7].linear() - expected.linear()).norm() < 1e-12);
  }
}

TEST_CASE("fk: standard and modified DH describe the same link when written so") {
  // A modified link i+1 = Rx(alpha_i) Tx(a_i) Rz(theta_{i+1}) Tz(d_{i+1}) regroups the standard
  // factors; a chain rewritten between conventions must give the same TCP.
  Cell standard, modified;
  standard.joint_count = modified.joint_count = 3;
  const double alpha[3] = {0.3, -1.2, 0.7}, a[3] = {120, 450, -80}, d[3] = {-300, 25, 90};
  for (int i = 0; i < 3; ++i) {
    Joint& s = standard.joints[static_cast<size_t>(i)];
    s.name = "j" + std::to_string(i);
    s.alpha_rad = alpha[i];
    s.a_mm = a[i];
    s.d_mm = d[i];
    s.lower = -kPi;
    s.upper = kPi;
    Joint& m = modified.joints[static_cast<size_t>(i)];
    m = s;
    m.convention = DhConvention::modified;
    // Modified link i holds alpha, a of the previous standard link.
    m.alpha_rad = i == 0 ? 0.0 : alpha[i - 1];
    m.a_mm = i == 0 ? 0.0 : a[i - 1];
  }
  modified.T_last_tcp =
      Eigen::Translation3d(a[2], 0, 0) * Eigen::AngleAxisd(alpha[2], Eigen::Vector3d::UnitX());
  finalize_cell(standard);
  finalize_cell(modified);
  std::mt19937_64 rng(3);
  for (int k = 0; k < 100; ++k) {
    const JointVector q = test::random_posture(standard, rng);
    const Isometry Ts = tcp_pose(standard, q), Tm = tcp_pose(modified, q);
    CHECK((Ts.matrix() - Tm.matrix()).norm() < 1e-9);
  }
}
