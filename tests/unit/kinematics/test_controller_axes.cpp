// Controller axes <-> DH values: the mapping value = sign * q + offset, as a round trip and
// against hand-written cases.
#include <random>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "test_support.hpp"

using namespace redpost;

TEST_CASE("axes: round trip DH -> controller -> DH on every shipped cell") {
  std::mt19937_64 rng(21);
  for (const char* name : test::kShippedCells) {
    const Cell cell = test::shipped_cell(name);
    for (int k = 0; k < 1000; ++k) {
      const JointVector q = test::random_posture(cell, rng);
      const AxisValues axes = to_controller_axes(cell, q);
      const JointVector back = from_controller_axes(cell, axes, q);
      CHECK((back - q).cwiseAbs().maxCoeff() < 1e-12);
    }
  }
}

TEST_CASE("axes: round trip controller -> DH -> controller") {
  std::mt19937_64 rng(22);
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  for (int k = 0; k < 1000; ++k) {
    AxisValues axes;
    for (int n = 1; n <= 6; ++n) {
      std::uniform_real_distribution<double> u(-170, 170);
      axes.arm(n) = u(rng);
    }
    axes.external(1) = std::uniform_real_distribution<double>(0, 2000)(rng);
    axes.external(2) = std::uniform_real_distribution<double>(-700, 700)(rng);
    const JointVector q = from_controller_axes(cell, axes, cell.home());
    const AxisValues again = to_controller_axes(cell, q);
    for (size_t i = 0; i < 8; ++i)
      CHECK(again.value[i] == Approx(axes.value[i]).margin(1e-9));
    CHECK(std::isnan(again.external(3)));
  }
}

TEST_CASE("axes: the mappings written in the cell files") {
  const Cell andres = test::shipped_cell("andres2011_kr15_track_table");
  // KUKA HOME-like arm values with the table at 30 deg and the track at 250 mm.
  AxisValues axes;
  const double arm[6] = {0, -90, 90, 0, 90, 0};
  for (int n = 1; n <= 6; ++n)
    axes.arm(n) = arm[n - 1];
  axes.external(1) = 250;
  axes.external(2) = 30;
  const JointVector q = from_controller_axes(andres, axes, andres.home());
  CHECK(q[0] == Approx(deg_to_rad(30)));   // theta_M = E2
  CHECK(q[1] == Approx(250));              // d_L = E1, mm
  CHECK(q[2] == Approx(kPi));              // A1 = theta_1 - 180
  CHECK(q[3] == Approx(-kPi / 2));         // A2 = theta_2
  CHECK(q[4] == Approx(0).margin(1e-15));  // A3 = theta_3 + 90
  CHECK(q[5] == Approx(kPi));              // A4 = theta_4 - 180
  CHECK(q[6] == Approx(3 * kPi / 2));      // A5 = theta_5 - 180
  CHECK(q[7] == Approx(-kPi));             // A6 = theta_6 + 180

  // Caro: theta = (-A1, -A2, -A3 - 90, -A4, A5, -A6).
  const Cell caro = test::shipped_cell("caro2014_kr270_table");
  AxisValues k;
  const double a2[6] = {10, -100, 120, 35, -70, 90};
  for (int n = 1; n <= 6; ++n)
    k.arm(n) = a2[n - 1];
  const JointVector qc = from_controller_axes(caro, k, caro.home());
  const double expected_deg[6] = {-10, 100, -210, -35, -70, -90};
  for (int i = 0; i < 6; ++i)
    CHECK(rad_to_deg(qc[i]) == Approx(expected_deg[i]));
}

TEST_CASE("axes: a missing controller value is an error that names the axis") {
  const Cell cell = test::shipped_cell("kr15_2");
  AxisValues axes;  // all NaN
  try {
    from_controller_axes(cell, axes, cell.home());
    FAIL("expected an error");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::bad_input);
    CHECK(std::string(e.what()).find("A1") != std::string::npos);
  }
}
