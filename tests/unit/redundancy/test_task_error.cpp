// The task error of Andres eq. 14-16 against closed forms.
#include <random>

#include "catch_compat.hpp"
#include "redpost/redundancy/task_error.hpp"

using namespace redpost;

TEST_CASE("task error: vect() is the axial vector, sin(phi) u for a rotation") {
  std::mt19937_64 rng(41);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Vector3d u = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const double phi = std::uniform_real_distribution<double>(-3.0, 3.0)(rng);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(phi, u).toRotationMatrix();
    CHECK((vect(R) - std::sin(phi) * u).norm() < 1e-14);
  }
}

TEST_CASE("task error: eq. 14 in {B}, and the log map beyond 90 degrees") {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int k = 0; k < 1000; ++k) {
    Isometry T = Isometry::Identity();
    T.linear() = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(g(rng), g(rng), g(rng)) * 300.0;
    const Eigen::Vector3d u_B = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const double phi = std::uniform_real_distribution<double>(0.0, 3.1)(rng);
    // Desired: the current frame turned by phi about u_B (expressed in {B}).
    const Eigen::Matrix3d R_d = Eigen::AngleAxisd(phi, u_B).toRotationMatrix() * T.linear();
    const Eigen::Vector3d p_d = T.translation() + Eigen::Vector3d(1, -2, 3);
    const Vector6d dt = task_error(T, R_d, p_d);
    const double expected = phi < kPi / 2 ? std::sin(phi) : phi;
    CHECK((dt.head<3>() - expected * u_B).norm() < 1e-12);
    CHECK((dt.tail<3>() - Eigen::Vector3d(1, -2, 3)).norm() < 1e-12);
  }
}

TEST_CASE("task error: a free spin asks only for the axis") {
  Isometry T = Isometry::Identity();
  T.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  // Target: same axis, any spin -> zero orientation error.
  const Eigen::Vector3d z = T.linear().col(2);
  TcpTarget t = TcpTarget::axis(T.translation(), z);
  Eigen::Matrix3d R_d = desired_rotation(t, T.linear());
  CHECK((R_d - T.linear()).norm() < 1e-15);
  CHECK(orientation_error(t, T.linear()) < 1e-15);
  // A tilted axis: the desired frame has that axis and the error is perpendicular to z.
  t.z_B = (z + 0.1 * T.linear().col(0)).normalized();
  R_d = desired_rotation(t, T.linear());
  CHECK((R_d.col(2) - t.z_B).norm() < 1e-14);
  const Vector6d dt = task_error(T, R_d, t.p_B_mm);
  CHECK(std::abs(dt.head<3>().dot(z)) < 1e-14);
  CHECK(orientation_error(t, T.linear()) == Approx(std::atan(0.1)).epsilon(1e-12));
}

TEST_CASE("task error: the free-spin shortcut equals eq. 14 with the smallest rotation") {
  std::mt19937_64 rng(43);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int k = 0; k < 2000; ++k) {
    Isometry T = Isometry::Identity();
    T.linear() = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(g(rng), g(rng), g(rng)) * 300.0;
    const TcpTarget t = TcpTarget::axis(Eigen::Vector3d(g(rng), g(rng), g(rng)) * 300.0,
                                        Eigen::Vector3d(g(rng), g(rng), g(rng)));
    const Vector6d general = task_error(T, desired_rotation(t, T.linear()), t.p_B_mm);
    CHECK((task_error(T, t) - general).norm() < 1e-12 * (1.0 + general.norm()));
  }
}
