// The elastostatic model (Caro eqs. 4.1-4.4) against linearisations of forward_kinematics, the
// complementary stiffness against finite differences and against the loaded equilibrium it
// linearises, and the machining-quality criterion (eqs. 5.1, 5.3) against plain geometry.
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/jacobian.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/machining/cutting_force.hpp"
#include "redpost/machining/elastostatic.hpp"
#include "redpost/machining/quality.hpp"
#include "test_support.hpp"

namespace {

using redpost::Cell;
using redpost::Isometry;
using redpost::JointType;
using redpost::JointVector;
using redpost::Matrix6d;
using redpost::Vector6d;

const Cell& caro_cell() {
  static const Cell cell = redpost::test::shipped_cell("caro2014_kr270_table");
  return cell;
}

std::string describe(const JointVector& q) {
  std::ostringstream os;
  os.precision(17);
  os << "q = [" << q.transpose() << "]";
  return os.str();
}

// A wrench of a milling size: a force up to 500 N and a moment up to 20 N m, random directions.
Vector6d random_wrench(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector6d w;
  for (int i = 0; i < 6; ++i)
    w[i] = u(rng);
  w.head<3>() *= 20000.0 / std::sqrt(3.0);  // N mm
  w.tail<3>() *= 500.0 / std::sqrt(3.0);    // N
  return w;
}

// [rotation; translation] taking pose A to pose B, both in {B}: the log of R_B R_A^T and the
// difference of the origins.
Vector6d pose_difference(const Isometry& B, const Isometry& A) {
  const Eigen::AngleAxisd aa(B.linear() * A.linear().transpose());
  Vector6d d;
  d.head<3>() = aa.angle() * aa.axis();
  d.tail<3>() = B.translation() - A.translation();
  return d;
}

// The TCP's motion per unit step along the joint-space direction dq, by central differences of
// forward_kinematics. The step is scaled so that no joint moves more than `step`.
Vector6d directional_derivative(const Cell& cell, const JointVector& q, const JointVector& dq,
                                double step) {
  const double s = step / dq.cwiseAbs().maxCoeff();
  const JointVector qp = q + s * dq, qm = q - s * dq;
  return pose_difference(redpost::tcp_pose(cell, qp), redpost::tcp_pose(cell, qm)) / (2.0 * s);
}

JointVector unit_joint(const Cell& cell, int i) {
  JointVector e = JointVector::Zero(cell.size());
  e[i] = 1.0;
  return e;
}

// The compliant joints' Jacobian columns, taken from tcp_jacobian.
Matrix6d compliant_jacobian(const Cell& cell, const JointVector& q) {
  redpost::KinematicsData data;
  redpost::forward_kinematics(cell, q, data);
  redpost::Jacobian J_all;
  redpost::tcp_jacobian(cell, data, J_all);
  const std::array<int, 6> idx = redpost::compliant_joints(cell);
  Matrix6d J;
  for (int i = 0; i < 6; ++i)
    J.col(i) = J_all.col(idx[static_cast<size_t>(i)]);
  return J;
}

Vector6d stiffnesses(const Cell& cell) {
  const std::array<int, 6> idx = redpost::compliant_joints(cell);
  Vector6d k;
  for (int i = 0; i < 6; ++i)
    k[i] = *cell.joint(idx[static_cast<size_t>(i)]).stiffness;
  return k;
}

// The arm posture of KRL axis values A1..A6 (deg), every other joint at zero.
JointVector axis_posture(const Cell& cell, const double (&A_deg)[6]) {
  JointVector q = JointVector::Zero(cell.size());
  for (int i = 0; i < cell.size(); ++i) {
    const redpost::ControllerAxis& ax = cell.joint(i).axis;
    if (ax.kind == redpost::AxisKind::arm)
      q[i] = redpost::deg_to_rad((A_deg[ax.number - 1] - ax.offset) / ax.sign);
  }
  return q;
}

// A 7-joint chain with prismatic compliant joints, both DH conventions and fixed frames: the
// branches of the K_C rules the all-revolute KR270-2 does not reach.
Cell hand_built_cell() {
  using redpost::DhConvention;
  return redpost::test::hand_built_cell(
      "elastostatic_hand_built",
      redpost::frame_from_xyzabc(-200.0, 50.0, 400.0, {-35.0, 15.0, 80.0}),
      redpost::frame_from_xyzabc(0.0, 40.0, 220.0, {10.0, -30.0, 0.0}),
      {
          {JointType::revolute, DhConvention::modified, 0, 0, 10, 300, -3, 3, 2e8},
          {JointType::prismatic, DhConvention::modified, 90, 150, 30, 20, -500, 500, 5e4},
          {JointType::revolute, DhConvention::standard, 60, 700, -45, 0, -3, 3, 0},
          {JointType::prismatic, DhConvention::standard, -90, 0, 90, 100, 0, 800, 8e4},
          {JointType::revolute, DhConvention::modified, 90, 50, 0, 600, -3, 3, 6e7},
          {JointType::revolute, DhConvention::standard, -90, 0, 20, 0, -3, 3, 4e7},
          {JointType::revolute, DhConvention::modified, 20, 0, 0, 120, -3.2, 3.2, 3e7},
      },
      {{2, 30.0, -20.0, 10.0, 15.0, 25.0, 35.0}, {4, 0.0, 0.0, 90.0, 90.0, 0.0, 0.0}});
}

bool throws_bad_input(const std::function<void()>& f) {
  try {
    f();
  } catch (const redpost::Error& e) {
    return e.code() == redpost::ErrorCode::bad_input;
  }
  return false;
}

}  // namespace

TEST_CASE("elastostatic: TCP displacement is the FK linearisation of the joint deflection",
          "[elastostatic]") {
  // Independent of tcp_jacobian: the torques J^T w come from the TCP's motion per joint (finite
  // differences of FK, by virtual work), the joints yield dtheta = K_theta^-1 J^T w, and the TCP
  // displacement is FK's derivative along dtheta.
  const Cell& cell = caro_cell();
  const std::array<int, 6> idx = redpost::compliant_joints(cell);
  const Vector6d k = stiffnesses(cell);
  std::mt19937_64 rng(20140810);
  for (int trial = 0; trial < 50; ++trial) {
    const JointVector q = redpost::test::random_posture(cell, rng);
    const Vector6d w = random_wrench(rng);
    INFO(describe(q));
    JointVector dtheta = JointVector::Zero(cell.size());
    for (int i = 0; i < 6; ++i) {
      const int j = idx[static_cast<size_t>(i)];
      const Vector6d twist = directional_derivative(cell, q, unit_joint(cell, j), 1e-6);
      dtheta[j] = w.dot(twist) / k[i];
    }
    const Vector6d dX_fk = directional_derivative(cell, q, dtheta, 1e-6);
    const Vector6d dX = redpost::tcp_displacement(cell, q, w);
    const double rot = dX.head<3>().norm(), pos = dX.tail<3>().norm();
    INFO("dX = [" << dX.transpose() << "], from FK [" << dX_fk.transpose() << "]");
    CHECK((dX - dX_fk).head<3>().norm() < 1e-6 * rot + 1e-12);
    CHECK((dX - dX_fk).tail<3>().norm() < 1e-6 * pos + 1e-9);
  }
}

TEST_CASE("elastostatic: K_C is the derivative of J^T w", "[elastostatic]") {
  std::mt19937_64 rng(44);
  const Cell hand = hand_built_cell();
  for (const Cell* cell : {&caro_cell(), &hand}) {
    const std::array<int, 6> idx = redpost::compliant_joints(*cell);
    for (int trial = 0; trial < 30; ++trial) {
      const JointVector q = redpost::test::random_posture(*cell, rng);
      const Vector6d w = random_wrench(rng);
      INFO(cell->name << " " << describe(q));
      const Matrix6d K_C = redpost::complementary_stiffness(*cell, q, w);
      Matrix6d K_fd;
      for (int i = 0; i < 6; ++i) {
        const int j = idx[static_cast<size_t>(i)];
        const double h = cell->joint(j).type == JointType::prismatic ? 1e-4 : 1e-6;
        JointVector qp = q, qm = q;
        qp[j] += h;
        qm[j] -= h;
        K_fd.col(i) = (compliant_jacobian(*cell, qp).transpose() * w -
                       compliant_jacobian(*cell, qm).transpose() * w) /
                      (2.0 * h);
      }
      const double scale = std::max(1.0, K_fd.cwiseAbs().maxCoeff());
      INFO("K_C =\n" << K_C << "\nfinite differences =\n" << K_fd);
      CHECK((K_C - K_fd).cwiseAbs().maxCoeff() < 1e-6 * scale);
      CHECK(redpost::complementary_stiffness(*cell, q, Vector6d::Zero()) == Matrix6d::Zero());
    }
  }
}

TEST_CASE("elastostatic: with K_C, K_X linearises the loaded equilibrium", "[elastostatic]") {
  // The model behind eq. 4.2: the joints balance J(theta)^T w with K_theta (theta - theta_0).
  // Solve that equilibrium under w0 and under w0 +- eps dw (fixed-point iteration, which
  // contracts as |K_theta^-1 K_C| < 1), and compare the TCP's motion with K_X(w0)^-1 eps dw. A
  // 20 kN load makes K_C about a tenth of K_theta, so leaving it out must visibly fail.
  const Cell& cell = caro_cell();
  const std::array<int, 6> idx = redpost::compliant_joints(cell);
  const Vector6d k = stiffnesses(cell);
  const double A[6] = {10.0, -60.0, 110.0, 20.0, -40.0, 15.0};
  const JointVector q0 = axis_posture(cell, A);
  Vector6d w0;
  w0 << 3e5, -2e5, 1e5, 12000.0, -9000.0, 15000.0;
  Vector6d dw;
  dw << 1e3, 2e3, -1e3, 30.0, 50.0, -40.0;
  const double eps = 1e-3;

  const auto equilibrium = [&](const Vector6d& w) {
    JointVector q = q0;
    for (int it = 0; it < 200; ++it) {
      const Vector6d dtheta = (compliant_jacobian(cell, q).transpose() * w).cwiseQuotient(k);
      JointVector next = q0;
      for (int i = 0; i < 6; ++i)
        next[idx[static_cast<size_t>(i)]] += dtheta[i];
      const double change = (next - q).cwiseAbs().maxCoeff();
      q = next;
      if (change < 1e-17)
        break;
    }
    return q;
  };
  const JointVector q_loaded = equilibrium(w0);
  const Vector6d dX_true = pose_difference(redpost::tcp_pose(cell, equilibrium(w0 + eps * dw)),
                                           redpost::tcp_pose(cell, equilibrium(w0 - eps * dw))) /
                           2.0;
  const auto predicted = [&](bool complementary) {
    const Matrix6d K_X = redpost::cartesian_stiffness(cell, q_loaded, w0, {complementary});
    return Vector6d(K_X.partialPivLu().solve(eps * dw));
  };
  const Vector6d with_KC = predicted(true), without_KC = predicted(false);
  const auto rel = [&](const Vector6d& dX) { return (dX - dX_true).norm() / dX_true.norm(); };
  INFO("true [" << dX_true.transpose() << "]\nwith K_C [" << with_KC.transpose() << "]\nwithout ["
                << without_KC.transpose() << "]");
  CHECK(rel(with_KC) < 1e-7);
  CHECK(rel(without_KC) > 1e-2);
}

TEST_CASE("elastostatic: K_X is symmetric without K_C and maps dX back to w", "[elastostatic]") {
  const Cell& cell = caro_cell();
  std::mt19937_64 rng(7);
  // Postures away from the wrist singularity (A5 = 0), where J^-1 is well defined.
  int checked = 0;
  while (checked < 40) {
    const JointVector q = redpost::test::random_posture(cell, rng);
    if (std::abs(std::sin(q[4])) < 0.2)
      continue;
    ++checked;
    const Vector6d w = random_wrench(rng);
    INFO(describe(q));
    for (const bool complementary : {false, true}) {
      const redpost::ElastostaticOptions options{complementary};
      const Matrix6d K_X = redpost::cartesian_stiffness(cell, q, w, options);
      const Vector6d dX = redpost::tcp_displacement(cell, q, w, options);
      // Work-consistent scaling: rows and columns of rotation in N mm/rad, of translation in
      // N/mm; compare each block against its own size.
      const Vector6d residual = K_X * dX - w;
      CHECK(residual.head<3>().norm() < 1e-7 * w.head<3>().norm() + 1e-6 * w.tail<3>().norm());
      CHECK(residual.tail<3>().norm() < 1e-7 * w.tail<3>().norm() + 1e-9);
      if (!complementary) {
        const double asym = (K_X - K_X.transpose()).cwiseAbs().maxCoeff();
        CHECK(asym < 1e-9 * K_X.cwiseAbs().maxCoeff());
      }
    }
  }
}

TEST_CASE("elastostatic: KR270-2 deflection under a milling force is plausible", "[elastostatic]") {
  // A typical pose of Caro's cell: tool vertical (pointing down), 1.9 m ahead of the robot, 420
  // mm below the A2 axis. Slotting Al7075 at the Table 3.1 conditions, feeding away from the robot,
  // so that the larger force component (normal to the feed) is tangential to A1.
  const Cell& cell = caro_cell();
  const double A[6] = {0.0, -60.0, 125.0, 0.0, -20.0, 0.0};
  const JointVector q = axis_posture(cell, A);
  redpost::KinematicsData data;
  redpost::forward_kinematics(cell, q, data);
  const Eigen::Vector3d p = data.T_B_tcp.translation();
  // Caro's z7 points out of the tool; the cell's TCP z from the tip towards the spindle.
  const Eigen::Vector3d z7 = -data.T_B_tcp.linear().col(2);
  REQUIRE(z7.z() < -0.999);

  // F_P: x the feed, z the tool axis towards the robot (-z7), y = z x x.
  const Eigen::Vector3d x_P = Eigen::Vector3d(p.x(), p.y(), 0.0).normalized();
  const Eigen::Vector3d z_P = -z7;
  Eigen::Matrix3d R_B_P;
  R_B_P << x_P, z_P.cross(x_P), z_P;
  const Eigen::Vector3d F_P = redpost::mean_cutting_force_N(
      redpost::caro2014_milling_conditions(20.0, redpost::MillingMode::down));
  Vector6d w = Vector6d::Zero();
  w.tail<3>() = -(R_B_P * F_P);  // the tool receives the opposite of its force on the workpiece
  const Eigen::Vector3d f = w.tail<3>();
  const Vector6d dX = redpost::tcp_displacement(cell, data, w);
  const Eigen::Vector3d d = dX.tail<3>();

  // Independent bounds from the joint axes alone (FK's frames, no Jacobian): joint i, at
  // distance r_i from the TCP, turns by (its torque) / k_i <= |f| r_i / k_i and moves the TCP by
  // at most that times r_i; and since each joint's share of f . d is a square,
  // f . d >= (torque_1)^2 / k_1.
  const std::array<int, 6> idx = redpost::compliant_joints(cell);
  double upper = 0.0;
  double torque_1 = 0.0;
  for (int i = 0; i < 6; ++i) {
    const auto j = static_cast<size_t>(idx[static_cast<size_t>(i)]);
    const Eigen::Vector3d axis = data.z_B_joint[j];
    const Eigen::Vector3d r = p - data.p_B_joint[j];
    const double r_perp = (r - r.dot(axis) * axis).norm();
    upper += f.norm() * r_perp * r_perp / *cell.joint(idx[static_cast<size_t>(i)]).stiffness;
    if (i == 0)
      torque_1 = axis.dot(r.cross(f));
  }
  const double lower = torque_1 * torque_1 / *cell.joint(idx[0]).stiffness / f.norm();
  INFO("TCP at [" << p.transpose() << "] mm, force on the tool [" << f.transpose()
                  << "] N (|f| = " << f.norm() << ")");
  INFO("deflection [" << d.transpose() << "] mm, |d| = " << d.norm() << " mm, rotation "
                      << dX.head<3>().norm() << " rad");
  INFO("bounds from the axes: A1 alone " << lower << " mm <= along f <= |d| <= " << upper << " mm");
  CHECK(d.dot(f.normalized()) >= lower * (1.0 - 1e-9));
  CHECK(d.norm() <= upper);
  // The lateral push turns A1 (the softest joint, 0.237 MN m/rad, 1.9 m away): a sizeable share
  // of the deflection comes from it alone.
  CHECK(lower > 0.3 * d.norm());
  // Machining quality (eq. 5.1) at this point: the deflection normal to feed and tool axis.
  const double c = redpost::normal_tool_deflection_mm(d, z7, x_P);
  INFO("c = " << c << " mm");
  CHECK(c <= d.norm());
  CHECK(c > 0.0);
}

TEST_CASE("elastostatic: cells without six joint stiffnesses are refused", "[elastostatic]") {
  // The shipped KR15/2 cells with their (assumed) stiffness taken out, as a user's cell without
  // any would be.
  Cell kr15 = redpost::test::shipped_cell("kr15_2");
  Cell andres = redpost::test::shipped_cell("andres2011_kr15_track_table");
  for (Cell* c : {&kr15, &andres}) {
    for (redpost::Joint& j : c->joints)
      j.stiffness.reset();
  }
  Cell five = caro_cell();
  five.joints[3].stiffness.reset();
  Cell seven = hand_built_cell();
  seven.joints[2].stiffness = 1e8;
  for (const Cell* cell : {static_cast<const Cell*>(&kr15), static_cast<const Cell*>(&andres),
                           static_cast<const Cell*>(&five), static_cast<const Cell*>(&seven)}) {
    INFO(cell->name);
    const JointVector q = cell->home();
    const Vector6d w = Vector6d::Ones();
    CHECK(throws_bad_input([&] { redpost::compliant_joints(*cell); }));
    CHECK(throws_bad_input([&] { redpost::tcp_displacement(*cell, q, w); }));
    CHECK(throws_bad_input([&] { redpost::cartesian_stiffness(*cell, q, w); }));
    CHECK(throws_bad_input([&] { redpost::complementary_stiffness(*cell, q, w); }));
  }
  // A5 = 0 aligns A4 and A6: J is singular and K_X does not exist (tcp_displacement still does).
  const double A[6] = {0.0, -60.0, 110.0, 0.0, 0.0, 0.0};
  const JointVector q = axis_posture(caro_cell(), A);
  const Vector6d w = (Vector6d() << 0, 0, 0, 100, 0, 0).finished();
  CHECK(throws_bad_input([&] { redpost::cartesian_stiffness(caro_cell(), q, w); }));
  CHECK(redpost::tcp_displacement(caro_cell(), q, w).allFinite());
}

TEST_CASE("machining quality: c_i is the deflection normal to feed and tool axis",
          "[machining_quality]") {
  std::mt19937_64 rng(51);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<double> c;
  double sum = 0.0;
  for (int trial = 0; trial < 100; ++trial) {
    // A random orthonormal pair (feed, tool axis) and a random displacement.
    const Eigen::Matrix3d R =
        Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
    const Eigen::Vector3d x_feed = R.col(0), z7 = R.col(2);
    const Eigen::Vector3d dd(n(rng), n(rng), n(rng));
    // What is left of dd once its parts along the feed and the tool axis are removed.
    const double expected = (dd - dd.dot(x_feed) * x_feed - dd.dot(z7) * z7).norm();
    const double ci = redpost::normal_tool_deflection_mm(dd, z7, x_feed);
    CHECK(ci == Approx(expected).epsilon(1e-12).margin(1e-14));
    c.push_back(ci);
    sum += expected;
  }
  CHECK(redpost::machining_quality_criterion_mm(c.data(), c.size()) ==
        Approx(sum / 100.0).epsilon(1e-12));
  CHECK(throws_bad_input([&] { redpost::machining_quality_criterion_mm(c.data(), 0); }));
}
