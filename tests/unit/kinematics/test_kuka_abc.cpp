// KUKA A, B, C against closed forms and as a round trip.
#include <random>

#include "catch_compat.hpp"
#include "redpost/kinematics/kuka_abc.hpp"

using namespace redpost;

TEST_CASE("abc: known rotations") {
  // A about Z first: A 90 turns x onto y.
  Eigen::Matrix3d R = rotation_from_abc({90, 0, 0});
  CHECK((R * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm() < 1e-15);
  // Tool down (A180 B0 C180) is Rz(pi) Rx(pi) = diag(-1, 1, -1): z points down.
  R = rotation_from_abc({180, 0, 180});
  CHECK((R - Eigen::Vector3d(-1, 1, -1).asDiagonal().toDenseMatrix()).norm() < 1e-14);
  // Intrinsic Z-Y'-X'': Rz(A) * Ry(B) * Rx(C), written out for one case.
  const double a = 0.3, b = -0.5, c = 1.1;
  Eigen::Matrix3d Rz, Ry, Rx;
  Rz << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  Ry << std::cos(b), 0, std::sin(b), 0, 1, 0, -std::sin(b), 0, std::cos(b);
  Rx << 1, 0, 0, 0, std::cos(c), -std::sin(c), 0, std::sin(c), std::cos(c);
  R = rotation_from_abc({rad_to_deg(a), rad_to_deg(b), rad_to_deg(c)});
  CHECK((R - Rz * Ry * Rx).norm() < 1e-15);
}

TEST_CASE("abc: round trip away from gimbal lock") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ac(-179.9, 179.9), bd(-89.0, 89.0);
  for (int k = 0; k < 10000; ++k) {
    const KukaAbc in{ac(rng), bd(rng), ac(rng)};
    const KukaAbc out = abc_from_rotation(rotation_from_abc(in));
    CHECK(out.a_deg == Approx(in.a_deg).margin(1e-9));
    CHECK(out.b_deg == Approx(in.b_deg).margin(1e-9));
    CHECK(out.c_deg == Approx(in.c_deg).margin(1e-9));
  }
}

TEST_CASE("abc: gimbal lock keeps the rotation and reports C = 0") {
  for (double b : {90.0, -90.0}) {
    const Eigen::Matrix3d R = rotation_from_abc({30, b, -20});
    const KukaAbc out = abc_from_rotation(R);
    CHECK(out.c_deg == 0.0);
    CHECK((rotation_from_abc(out) - R).norm() < 1e-12);
  }
}
