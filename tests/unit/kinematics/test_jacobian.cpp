// The geometric Jacobian against central finite differences of forward_kinematics, and the
// Frobenius conditioning against an SVD.
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "catch_compat.hpp"
#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/conditioning.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/jacobian.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "test_support.hpp"

namespace {

using redpost::Cell;
using redpost::Isometry;
using redpost::JointType;
using redpost::JointVector;

constexpr int kPostures = 1000;

// Steps: central differences have truncation error ~h^2 |f'''| / 6 and rounding error
// ~eps |f| / h. With |p| ~ 3000 mm, h = 1e-5 rad balances the two at ~1e-10 relative for a
// revolute column. A prismatic joint moves the TCP affinely, so there is no truncation error
// and a large step keeps the rounding error small.
constexpr double kStepRevolute = 1e-5;   // rad
constexpr double kStepPrismatic = 1e-2;  // mm
// On the angular rows (absolute) and on the linear rows relative to the positions' size (see
// jacobian_error). The observed errors are ~1e-11, so a column that is off by a sign, a
// swapped axis or a reference point moved by a millimetre fails by orders of magnitude.
constexpr double kTol = 1e-9;

std::string describe(const JointVector& q) {
  std::ostringstream os;
  os.precision(17);
  os << "q = [" << q.transpose() << "]";
  return os.str();
}

// omega such that R_plus R_minus^T = exp(2h [omega]x): the exact log, via an angle-axis.
Eigen::Vector3d angular_difference(const Eigen::Matrix3d& R_plus, const Eigen::Matrix3d& R_minus,
                                   double two_h) {
  const Eigen::AngleAxisd aa(R_plus * R_minus.transpose());
  return aa.angle() * aa.axis() / two_h;
}

// The Jacobian column by column from forward_kinematics alone, rows [omega; v].
redpost::Jacobian finite_difference_jacobian(const Cell& cell, const JointVector& q) {
  redpost::Jacobian J(6, cell.size());
  for (int i = 0; i < cell.size(); ++i) {
    const double h = cell.joint(i).type == JointType::prismatic ? kStepPrismatic : kStepRevolute;
    JointVector qp = q, qm = q;
    qp[i] += h;
    qm[i] -= h;
    const Isometry Tp = redpost::tcp_pose(cell, qp);
    const Isometry Tm = redpost::tcp_pose(cell, qm);
    J.col(i).head<3>() = angular_difference(Tp.linear(), Tm.linear(), 2 * h);
    J.col(i).tail<3>() = (Tp.translation() - Tm.translation()) / (2 * h);
  }
  return J;
}

// The worst disagreement. The angular rows are unit vectors and compare absolutely. The linear
// rows' rounding error is eps |p| / h, where |p| is the size of the positions the FK handled,
// whatever the column's own size (a wrist column whose axis passes near the TCP is ~0 mm/rad but is
// still the difference of two ~2 m positions), so they compare relative to that length.
double jacobian_error(const redpost::Jacobian& J, const redpost::Jacobian& J_fd,
                      const Eigen::Vector3d& p_tcp) {
  const double length =
      std::max({1.0, p_tcp.norm(), J.bottomRows<3>().cwiseAbs().maxCoeff()});  // mm
  const double angular = (J.topRows<3>() - J_fd.topRows<3>()).cwiseAbs().maxCoeff();
  const double linear = (J.bottomRows<3>() - J_fd.bottomRows<3>()).cwiseAbs().maxCoeff() / length;
  return std::max(angular, linear);
}

struct Worst {
  double error = 0.0;
  JointVector q;
};

Worst check_against_finite_differences(const Cell& cell, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  redpost::KinematicsData data;
  redpost::Jacobian J;
  Worst worst;
  for (int k = 0; k <= kPostures; ++k) {
    const JointVector q = k == 0 ? cell.home() : redpost::test::random_posture(cell, rng);
    redpost::forward_kinematics(cell, q, data);
    redpost::tcp_jacobian(cell, data, J);
    REQUIRE(J.rows() == 6);
    REQUIRE(J.cols() == cell.size());
    const double e =
        jacobian_error(J, finite_difference_jacobian(cell, q), data.T_B_tcp.translation());
    if (k == 0 || e > worst.error) {
      worst = {e, q};
    }
  }
  return worst;
}

// Modified DH, prismatic joints in both conventions, fixed frames, base and tool: the branches
// the shipped cells leave out.
Cell hand_built_cell() {
  using redpost::DhConvention;
  return redpost::test::hand_built_cell(
      "jacobian_hand_built", redpost::frame_from_xyzabc(-200.0, 50.0, 400.0, {-35.0, 15.0, 80.0}),
      redpost::frame_from_xyzabc(0.0, 40.0, 220.0, {10.0, -30.0, 0.0}),
      {
          {JointType::revolute, DhConvention::modified, 0, 0, 10, 300, -3, 3},
          {JointType::prismatic, DhConvention::modified, 90, 150, 30, 20, -500, 500},
          {JointType::revolute, DhConvention::standard, 60, 700, -45, 0, -3, 3},
          {JointType::prismatic, DhConvention::standard, -90, 0, 90, 100, 0, 800},
          {JointType::revolute, DhConvention::modified, 90, 50, 0, 600, -3, 3},
          {JointType::revolute, DhConvention::standard, -90, 0, 20, 0, -3, 3},
          {JointType::virtual_spin, DhConvention::modified, 20, 0, 0, 120, -3.2, 3.2},
      },
      {{2, 30.0, -20.0, 10.0, 15.0, 25.0, 35.0}, {4, 0.0, 0.0, 90.0, 90.0, 0.0, 0.0}});
}

// A random 6 x n matrix with entries in [-1, 1].
redpost::Jacobian random_jacobian(int n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  redpost::Jacobian J(6, n);
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < 6; ++r) {
      J(r, c) = u(rng);
    }
  }
  return J;
}

// kappa_F from singular values: (1/6) sqrt(sum s_i^2 * sum 1/s_i^2), after the same 1/L
// scaling of the linear rows. An SVD shares no code path with the LDLT in conditioning.cpp.
double inverse_condition_by_svd(const redpost::Jacobian& J, double L) {
  Eigen::MatrixXd JN = J;
  JN.bottomRows(3) /= L;
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(JN).singularValues();
  const double kappa = std::sqrt(s.squaredNorm() * s.cwiseInverse().squaredNorm()) / 6.0;
  return 1.0 / kappa;
}

// The relative accuracy to expect of 1/kappa_F. conditioning.cpp factors J_N J_N^T, whose
// condition number is the square of J_N's, so its rounding error grows with cond(J_N)^2; a
// wrong formula (a missing 1/L, 1/6 or square root) is off by O(1) instead.
double conditioning_tolerance(const redpost::Jacobian& J, double L) {
  Eigen::MatrixXd JN = J;
  JN.bottomRows(3) /= L;
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(JN).singularValues();
  const double cond = s(0) / s(s.size() - 1);
  return std::max(1e-13, 10.0 * std::numeric_limits<double>::epsilon() * cond * cond);
}

}  // namespace

TEST_CASE("jacobian: matches central finite differences of forward_kinematics") {
  std::uint64_t seed = 2011;
  for (const char* name : redpost::test::kShippedCells) {
    const Cell cell = redpost::test::shipped_cell(name);
    const Worst w = check_against_finite_differences(cell, seed++);
    INFO(name << ": worst error " << w.error << " at " << describe(w.q));
    CHECK(w.error <= kTol);
  }
}

TEST_CASE("jacobian: a hand-built modified-DH cell with prismatic joints matches differences") {
  const Cell cell = hand_built_cell();
  const Worst w = check_against_finite_differences(cell, 77);
  INFO("worst error " << w.error << " at " << describe(w.q));
  CHECK(w.error <= kTol);
}

TEST_CASE("jacobian: finite differences notice a wrong reference point") {
  // The check must be able to fail: moving the reference point of the linear rows by 1 mm
  // (v' = v + omega x r) is a plausible bug and has to exceed the tolerance.
  const Cell cell = redpost::test::shipped_cell("andres2011_kr15_track_table");
  const JointVector q = cell.home();
  redpost::KinematicsData data;
  redpost::Jacobian J;
  redpost::forward_kinematics(cell, q, data);
  redpost::tcp_jacobian(cell, data, J);
  const Eigen::Vector3d r(1.0, 0.0, 0.0);
  redpost::Jacobian shifted = J;
  for (int i = 0; i < J.cols(); ++i) {
    shifted.col(i).tail<3>() += J.col(i).head<3>().cross(r);
  }
  const redpost::Jacobian J_fd = finite_difference_jacobian(cell, q);
  const Eigen::Vector3d p_tcp = data.T_B_tcp.translation();
  CHECK(jacobian_error(J, J_fd, p_tcp) <= kTol);
  CHECK(jacobian_error(shifted, J_fd, p_tcp) > 1e3 * kTol);
}

TEST_CASE("jacobian: a prismatic column has no angular part and a unit linear part") {
  const Cell cell = redpost::test::shipped_cell("andres2011_kr15_track_table");
  const int track = cell.find_joint("d_L");
  REQUIRE(track >= 0);
  REQUIRE(cell.joint(track).type == JointType::prismatic);
  std::mt19937_64 rng(5);
  redpost::KinematicsData data;
  redpost::Jacobian J;
  for (int k = 0; k < 100; ++k) {
    const JointVector q = redpost::test::random_posture(cell, rng);
    redpost::forward_kinematics(cell, q, data);
    redpost::tcp_jacobian(cell, data, J);
    CHECK(J.col(track).head<3>().isZero(0.0));  // exactly zero: no rotation from a slide
    CHECK(std::abs(J.col(track).tail<3>().norm() - 1.0) <= 1e-12);
    // The track moves along z of frame 1 (the table's link frame), whatever the arm does.
    const Eigen::Vector3d z1 = data.T_B_link[0].linear().col(2);
    CHECK((J.col(track).tail<3>() - z1).cwiseAbs().maxCoeff() <= 1e-12);
  }
}

TEST_CASE("jacobian: inverse_condition_frobenius is 1 for an isotropic Jacobian") {
  const double L = 500.0;
  // J_N = [R 0; 0 R] (orthogonal) once the linear rows are divided by L.
  const Eigen::Matrix3d R = redpost::rotation_from_abc({30.0, -20.0, 75.0});
  redpost::Jacobian J = redpost::Jacobian::Zero(6, 6);
  J.block<3, 3>(0, 0) = R;
  J.block<3, 3>(3, 3) = L * R;
  CHECK(std::abs(redpost::inverse_condition_frobenius(J, L) - 1.0) <= 1e-14);
  // The plain identity with L = 1.
  redpost::Jacobian I = redpost::Jacobian::Identity(6, 6);
  CHECK(std::abs(redpost::inverse_condition_frobenius(I, 1.0) - 1.0) <= 1e-15);
  // The wrong L makes it anisotropic: 1/kappa_F = 6 / sqrt((3 + 3 s^2)(3 + 3 / s^2)), s = 2.
  const double expected = 6.0 / std::sqrt((3.0 + 3.0 * 4.0) * (3.0 + 3.0 / 4.0));
  CHECK(std::abs(redpost::inverse_condition_frobenius(J, L / 2.0) - expected) <= 1e-14);
}

TEST_CASE("jacobian: inverse_condition_frobenius agrees with singular values") {
  std::mt19937_64 rng(616);
  std::uniform_real_distribution<double> length(0.1, 2000.0);
  for (int k = 0; k < 500; ++k) {
    const int n = 6 + k % 4;  // 6..9 columns, as the cells have
    redpost::Jacobian J = random_jacobian(n, rng);
    const double L = length(rng);
    J.bottomRows<3>() *= L;  // linear rows in mm, as a real Jacobian's
    const double expected = inverse_condition_by_svd(J, L);
    const double got = redpost::inverse_condition_frobenius(J, L);
    INFO("sample " << k << ", n = " << n << ", L = " << L << ": " << got << " vs " << expected);
    CHECK(std::abs(got - expected) <= conditioning_tolerance(J, L) * expected);
  }
  // And on real Jacobians of the Andres cell, whose conditioning spans a wide range.
  const Cell cell = redpost::test::shipped_cell("andres2011_kr15_track_table");
  redpost::KinematicsData data;
  redpost::Jacobian J;
  for (int k = 0; k < 200; ++k) {
    const JointVector q = redpost::test::random_posture(cell, rng);
    redpost::forward_kinematics(cell, q, data);
    redpost::tcp_jacobian(cell, data, J);
    const double L = cell.conditioning.characteristic_length_mm;
    const double expected = inverse_condition_by_svd(J, L);
    CHECK(std::abs(redpost::inverse_condition_frobenius(J, L) - expected) <=
          conditioning_tolerance(J, L) * expected);
  }
}

TEST_CASE("jacobian: inverse_condition_frobenius is 0 for a rank-deficient Jacobian") {
  std::mt19937_64 rng(3);
  // Two equal columns in a 6 x 6.
  redpost::Jacobian J = random_jacobian(6, rng);
  J.col(4) = J.col(1);
  CHECK(redpost::inverse_condition_frobenius(J, 1.0) == 0.0);
  // Rank 5 with more columns than rows: every column orthogonal to one direction of R^6.
  redpost::Jacobian W = random_jacobian(9, rng);
  const Eigen::Matrix<double, 6, 1> u = random_jacobian(1, rng).col(0).normalized();
  W -= u * (u.transpose() * W);
  CHECK(redpost::inverse_condition_frobenius(W, 1.0) == 0.0);
  // All zero.
  CHECK(redpost::inverse_condition_frobenius(redpost::Jacobian::Zero(6, 7), 100.0) == 0.0);
}

TEST_CASE("jacobian: inverse_condition_frobenius is invariant under a rotation of the base") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> angle(-180.0, 180.0);
  for (int k = 0; k < 200; ++k) {
    const int n = 6 + k % 4;
    redpost::Jacobian J = random_jacobian(n, rng);
    J.bottomRows<3>() *= 500.0;
    const Eigen::Matrix3d R =
        redpost::rotation_from_abc({angle(rng), angle(rng) / 2.0, angle(rng)});
    redpost::Jacobian Jr(6, n);
    Jr.topRows<3>() = R * J.topRows<3>();
    Jr.bottomRows<3>() = R * J.bottomRows<3>();
    const double a = redpost::inverse_condition_frobenius(J, 500.0);
    const double b = redpost::inverse_condition_frobenius(Jr, 500.0);
    INFO("sample " << k << ": " << a << " vs " << b);
    CHECK(std::abs(a - b) <= conditioning_tolerance(J, 500.0) * a);
  }
}
