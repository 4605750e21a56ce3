// KUKA Status and Turn against the worked values of shared/PARAMETERS.md section 3, the
// closed-form wrist position of the same section, and across cells that share an arm.
#include <cmath>
#include <random>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

// The joint vector of a cell with the arm at A1..A6 (deg) and the other axes at home.
JointVector posture(const Cell& cell, const std::array<double, 6>& a_deg, double e1 = 0.0,
                    double e2 = 0.0) {
  AxisValues axes = to_controller_axes(cell, cell.home());
  for (int n = 1; n <= 6; ++n)
    axes.arm(n) = a_deg[static_cast<size_t>(n - 1)];
  if (!std::isnan(axes.external(1)))
    axes.external(1) = e1;
  if (!std::isnan(axes.external(2)))
    axes.external(2) = e2;
  return from_controller_axes(cell, axes, cell.home());
}

// PARAMETERS.md 1.4 / 2.1: x of the wrist point in the A1 frame, KUKA angles.
double closed_form_wrist_x(double a1, double a2, double l, double c, double A2_deg, double A3_deg) {
  const double t2 = deg_to_rad(A2_deg), t23 = deg_to_rad(A2_deg + A3_deg);
  return a1 + a2 * std::cos(t2) + l * std::cos(t23) + c * std::sin(t23);
}

double distance_to_line(const Eigen::Vector3d& p, const Eigen::Vector3d& on_line,
                        const Eigen::Vector3d& dir) {
  const Eigen::Vector3d d = dir.normalized();
  const Eigen::Vector3d r = p - on_line;
  return (r - r.dot(d) * d).norm();
}

}  // namespace

TEST_CASE("status_turn: worked values of PARAMETERS.md on the Caro cell (geometry B)") {
  const Cell cell = test::shipped_cell("caro2014_kr270_table");
  const ArmStatusModel model = make_arm_status_model(cell);
  struct Case {
    std::array<double, 6> a;
    int s, t;
  };
  const Case cases[] = {
      {{0, -90, 90, 0, 0, 0}, 2, 2},           // HOME: 'B010', 'B000010'
      {{0, -120, -30, 0, 30, 0}, 1, 6},        // overhead
      {{-45, -30, 80, -170, 60, 200}, 2, 11},  //
      {{30, -60, 100, 20, -45, -10}, 6, 50},   // the common "S 6, T 50"
  };
  for (const Case& c : cases) {
    const StatusTurn st = status_turn(cell, model, posture(cell, c.a));
    INFO("A = " << c.a[0] << " " << c.a[1] << " " << c.a[2] << " " << c.a[3] << " " << c.a[4] << " "
                << c.a[5]);
    CHECK(st.status == c.s);
    CHECK(st.turn == c.t);
  }
}

TEST_CASE("status_turn: phi = atan2(c, l) of PARAMETERS.md") {
  // Geometry B: c = -55 mm, l = 1100 mm -> -2.862 deg.
  const ArmStatusModel caro = make_arm_status_model(test::shipped_cell("caro2014_kr270_table"));
  CHECK(caro.phi_deg == Approx(rad_to_deg(std::atan2(-55.0, 1100.0))).margin(1e-9));
  CHECK(caro.phi_deg == Approx(-2.862).margin(5e-4));
  // KR15/2 with the 155 mm offset above the A3 axis: +14.48 deg, on the arm alone and in the
  // Andres cell.
  for (const char* name : {"kr15_2", "andres2011_kr15_track_table"}) {
    INFO(name);
    const ArmStatusModel m = make_arm_status_model(test::shipped_cell(name));
    CHECK(m.phi_deg == Approx(rad_to_deg(std::atan2(155.0, 600.0))).margin(1e-9));
    CHECK(m.phi_deg == Approx(14.48).margin(5e-3));
    CHECK(m.forward_from_a2_offset);
  }
}

TEST_CASE("status_turn: bit 1 switches at phi") {
  const Cell cell = test::shipped_cell("kr15_2");
  const ArmStatusModel model = make_arm_status_model(cell);
  const double phi = model.phi_deg;
  CHECK((status_turn(cell, model, posture(cell, {0, -90, phi + 1e-6, 0, 10, 0})).status & 2) == 2);
  CHECK((status_turn(cell, model, posture(cell, {0, -90, phi - 1e-6, 0, 10, 0})).status & 2) == 0);
  // A3 = 0 is already "below phi" on this arm: the offset matters.
  CHECK((status_turn(cell, model, posture(cell, {0, -90, 0, 0, 10, 0})).status & 2) == 0);
}

TEST_CASE("status_turn: Turn bits and the A5 = 0 convention") {
  const Cell cell = test::shipped_cell("caro2014_kr270_table");
  const ArmStatusModel model = make_arm_status_model(cell);
  // From a posture where only A2 is negative (Turn 2), flipping one axis flips its bit alone.
  const std::array<double, 6> base{10, -60, 90, 10, 10, 10};
  REQUIRE(status_turn(cell, model, posture(cell, base)).turn == 2);
  for (int n = 1; n <= 6; ++n) {
    std::array<double, 6> a = base;
    a[static_cast<size_t>(n - 1)] = -a[static_cast<size_t>(n - 1)];
    INFO("axis A" << n);
    CHECK(status_turn(cell, model, posture(cell, a)).turn == (2 ^ (1 << (n - 1))));
  }
  const StatusTurn zero = status_turn(cell, model, posture(cell, {0, -90, 90, 0, 0, 0}));
  CHECK((zero.status & 4) == 0);  // A5 = 0: bit 2 clear (HOME is S 2)
  CHECK((zero.turn & 1) == 0);    // A1 = 0: bit 0 clear
}

TEST_CASE("status_turn: the same axis values give the same Status/Turn on three cells' arms") {
  const Cell kr15 = test::shipped_cell("kr15_2");
  const Cell andres = test::shipped_cell("andres2011_kr15_track_table");
  const ArmStatusModel m_kr15 = make_arm_status_model(kr15);
  const ArmStatusModel m_andres = make_arm_status_model(andres);
  std::mt19937_64 rng(20240601);
  std::uniform_real_distribution<double> a1(-185, 185), a2(-155, 35), a3(-130, 154), a4(-350, 350),
      a5(-130, 130), a6(-350, 350), track(-500, 3000), table(-720, 720);
  int overhead = 0, seen_bits = 0;
  for (int k = 0; k < 2000; ++k) {
    const std::array<double, 6> a{a1(rng), a2(rng), a3(rng), a4(rng), a5(rng), a6(rng)};
    const StatusTurn s1 = status_turn(kr15, m_kr15, posture(kr15, a));
    const StatusTurn s2 = status_turn(andres, m_andres, posture(andres, a, track(rng), table(rng)));
    CHECK(s1.status == s2.status);
    CHECK(s1.turn == s2.turn);
    overhead += s1.status & 1;
    seen_bits |= s1.status;
  }
  CHECK(overhead > 0);    // the random postures do reach the overhead area
  CHECK(seen_bits == 7);  // and every Status bit is exercised
}

TEST_CASE("status_turn: bit 0 against the closed-form wrist position (brute force)") {
  struct Arm {
    const char* cell;
    double a1, a2, l, c;  // PARAMETERS.md 1.4 (geometry B) and 2.1 (offset above)
  };
  const Arm arms[] = {{"caro2014_kr270_table", 350, 1250, 1100, -55},
                      {"kr15_2", 300, 650, 600, 155},
                      {"andres2011_kr15_track_table", 300, 650, 600, 155}};
  for (const Arm& arm : arms) {
    INFO(arm.cell);
    const Cell cell = test::shipped_cell(arm.cell);
    const ArmStatusModel model = make_arm_status_model(cell);
    std::mt19937_64 rng(7);
    int mismatches = 0, overhead = 0;
    for (int k = 0; k < 5000; ++k) {
      const JointVector q = test::random_posture(cell, rng);
      const AxisValues ax = to_controller_axes(cell, q);
      const double expected =
          closed_form_wrist_x(arm.a1, arm.a2, arm.l, arm.c, ax.arm(2), ax.arm(3));
      const double got = wrist_x_in_a1_frame_mm(cell, model, q);
      if (std::fabs(got - expected) > 1e-6)
        ++mismatches;
      const int bit0 = status_turn(cell, model, q).status & 1;
      if (bit0 != (expected < 0.0 ? 1 : 0))
        ++mismatches;
      overhead += bit0;
    }
    CHECK(mismatches == 0);
    CHECK(overhead > 0);
  }
}

TEST_CASE("status_turn: an arm without A1-A2 offset finds 'forward' from the stretched posture") {
  Cell cell = test::shipped_cell("caro2014_kr270_table");
  cell.joints[1].a_mm = 0.0;  // theta_2: the A1 -> A2 offset a1 (modified DH)
  finalize_cell(cell);
  const ArmStatusModel model = make_arm_status_model(cell);
  CHECK_FALSE(model.forward_from_a2_offset);
  std::mt19937_64 rng(11);
  int mismatches = 0;
  for (int k = 0; k < 2000; ++k) {
    const JointVector q = test::random_posture(cell, rng);
    const AxisValues ax = to_controller_axes(cell, q);
    const double expected = closed_form_wrist_x(0.0, 1250, 1100, -55, ax.arm(2), ax.arm(3));
    if (std::fabs(wrist_x_in_a1_frame_mm(cell, model, q) - expected) > 1e-6)
      ++mismatches;
  }
  CHECK(mismatches == 0);
}

TEST_CASE("status_turn: the wrist root point is where the A4, A5 and A6 axes meet") {
  for (const char* name : test::kShippedCells) {
    INFO(name);
    const Cell cell = test::shipped_cell(name);
    const ArmStatusModel model = make_arm_status_model(cell);
    const auto j = [&](int n) { return static_cast<size_t>(model.joint_of_axis[n - 1]); };
    std::mt19937_64 rng(3);
    KinematicsData data;
    double worst = 0.0;
    for (int k = 0; k < 500; ++k) {
      forward_kinematics(cell, test::random_posture(cell, rng), data);
      const Eigen::Vector3d w = data.p_B_joint[j(5)];
      for (int n : {4, 5, 6})
        worst = std::max(worst, distance_to_line(w, data.p_B_joint[j(n)], data.z_B_joint[j(n)]));
    }
    CHECK(worst < 1e-9);
  }
}

TEST_CASE("status_turn: a cell that does not map A1..A6 is refused, naming the axis") {
  Cell cell = test::shipped_cell("kr15_2");
  cell.joints[3].axis = ControllerAxis{};  // theta_4 drove A4
  try {
    make_arm_status_model(cell);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::bad_input);
    CHECK(std::string(e.what()).find("A4") != std::string::npos);
  }
}
