// The cutting file, the cutting load of a move and the tool's deflection (issue 20), against
// closed forms, the cutting-force model's own conventions and finite differences of forward
// kinematics.
#include <random>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/machining/cutting_conditions.hpp"
#include "redpost/machining/deflection.hpp"
#include "redpost/machining/elastostatic.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

std::string bad_input_message(const std::string& xml) {
  try {
    parse_cutting_table(xml, "cut.xml");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::bad_input);
    return e.what();
  }
  FAIL("accepted: " << xml);
  return "";
}

const char* const kHead = "<?xml version=\"1.0\"?>\n<cutting format=\"1\">\n";

}  // namespace

TEST_CASE("cutting file: defaults, operations and units", "[cutting]") {
  const CuttingTable t = parse_cutting_table(
      std::string(kHead) +
          "  <defaults teeth=\"3\" ae=\"40%\" ap=\"0.006m\" mode=\"up\" material=\"steel\" "
          "kt=\"2100\" kr=\"0.4\" spindle_rpm=\"9000\"/>\n"
          "  <operation name=\"FINISH\" ae=\"0.5\" teeth=\"6\"/>\n</cutting>\n",
      "cut.xml");
  CHECK(t.defaults.teeth == 3);
  CHECK(t.defaults.ae_fraction == Approx(0.4));
  CHECK(std::isnan(t.defaults.ae_mm));
  CHECK(t.defaults.ap_mm == Approx(6.0));
  CHECK(t.defaults.mode == MillingMode::up);
  CHECK(t.defaults.Kt_N_per_mm2 == 2100.0);
  CHECK(t.defaults.source_line == 3);
  const CuttingConditions& fin = t.for_operation("FINISH");
  CHECK(fin.teeth == 6);
  CHECK(fin.ae_mm == 0.5);
  CHECK(fin.Kr == 0.4);  // inherited from the defaults
  CHECK(fin.source_line == 4);
  CHECK(&t.for_operation("ROUGH") == &t.defaults);

  // fz = feed / (rpm teeth); ae as a fraction of the CL tool's diameter; the file's spindle
  // speed over the CL file's.
  const MillingConditions m = milling_conditions(t.defaults, 12.0, 5000.0, true, 2700.0);
  CHECK(m.fz_mm == Approx(2700.0 / (9000.0 * 3)));
  CHECK(m.ae_mm == Approx(4.8));
  CHECK(m.ap_mm == Approx(6.0));
}

TEST_CASE("cutting file: bad values are refused at their line", "[cutting]") {
  CHECK(bad_input_message(std::string(kHead) + "  <defaults kt=\"nan\" kr=\"0.2\"/>\n</cutting>")
            .find("cut.xml:3") != std::string::npos);
  CHECK(bad_input_message(std::string(kHead) + "  <defaults kt=\"-5\"/>\n</cutting>").find("kt") !=
        std::string::npos);
  CHECK(
      bad_input_message(std::string(kHead) + "  <defaults ae=\"150%\"/>\n</cutting>").find("ae") !=
      std::string::npos);
  CHECK(bad_input_message(std::string(kHead) + "  <defaults teeth=\"0\"/>\n</cutting>")
            .find("teeth") != std::string::npos);
  CHECK(bad_input_message(std::string(kHead) + "  <defaults feed=\"3\"/>\n</cutting>")
            .find("unknown attribute 'feed'") != std::string::npos);
  CHECK(bad_input_message(std::string(kHead) +
                          "  <operation name=\"A\"/>\n  <operation name=\"A\"/>\n</cutting>")
            .find("cut.xml:4: operation 'A' is given twice") != std::string::npos);
  CHECK(bad_input_message(std::string(kHead) + "  <defaults material=\"Ti6Al4V\"/>\n</cutting>")
            .find("give its kt and kr") != std::string::npos);
  CHECK(bad_input_message("<cutting format=\"2\"/>").find("format") != std::string::npos);
  // What the CL file must say: a diameter, a spindle speed, a feed above 0; ae within the tool.
  const CuttingConditions c;
  CHECK_THROWS_AS(milling_conditions(c, 0.0, 8000.0, true, 1000.0), Error);
  CHECK_THROWS_AS(milling_conditions(c, 10.0, std::nan(""), true, 1000.0), Error);
  CHECK_THROWS_AS(milling_conditions(c, 10.0, 8000.0, true, 0.0), Error);
  CuttingConditions wide;
  wide.ae_mm = 12.0;
  CHECK_THROWS_AS(milling_conditions(wide, 10.0, 8000.0, true, 1000.0), Error);
}

TEST_CASE("cutting load: the mean force on the tool, its lever and the material side",
          "[cutting]") {
  // Down-milling with a clockwise spindle (M3) leaves the material on the right of the feed
  // (Caro Figure 3.3): -y of F_P.
  CHECK(material_side_for(MillingMode::down, true) == -1);
  CHECK(material_side_for(MillingMode::up, true) == 1);
  CHECK(material_side_for(MillingMode::down, false) == 1);
  CuttingConditions cc;
  cc.ae_mm = 5.0;
  cc.ap_mm = 8.0;
  const MillingConditions mc = milling_conditions(cc, 20.0, 10000.0, true, 3000.0);
  const Eigen::Vector3d F_P = mean_cutting_force_N(mc);

  // A feed along +x of {B} with the tool vertical: F_P is {B} itself.
  const Eigen::Vector3d z(0, 0, 1), feed(3, 0, 0);
  CuttingLoad load;
  REQUIRE(cutting_load(mc, z, feed, load));
  CHECK((load.w_on_tcp.tail<3>() + F_P).norm() < 1e-12);
  CHECK(load.force_N == Approx(F_P.norm()));
  // The force acts 4 mm up the tool: m = (0, 0, 4) x f.
  CHECK((load.w_on_tcp.head<3>() - Eigen::Vector3d(0, 0, 4).cross(-F_P)).norm() < 1e-9);
  CHECK((load.n_material_B - Eigen::Vector3d(0, -1, 0)).norm() < 1e-12);
  // The material pushes the tool away from itself on average in down-milling: f . n < 0.
  CHECK(load.w_on_tcp.tail<3>().dot(load.n_material_B) < 0.0);

  // A feed with a component along the tool axis keeps the frame of its part across it.
  CuttingLoad ramp;
  REQUIRE(cutting_load(mc, z, Eigen::Vector3d(3, 0, -1), ramp));
  CHECK((ramp.w_on_tcp - load.w_on_tcp).norm() < 1e-9);
  // A plunge has no side-milling load.
  CHECK_FALSE(cutting_load(mc, z, Eigen::Vector3d(0.05, 0, -1), ramp));
  CHECK_FALSE(cutting_load(mc, z, Eigen::Vector3d::Zero(), ramp));
}

TEST_CASE("elastostatic: K_X against finite differences of forward kinematics", "[cutting]") {
  // C = K_X^-1 (eq. 4.2 without K_C) maps a wrench on the TCP to its small displacement. Column k
  // from the model must equal the displacement computed here from forward kinematics alone: the
  // joint torques tau = J^T w by central differences of the TCP pose, the joints turned by
  // tau / k, and the TCP's translation and rotation read off forward kinematics.
  const Cell cell = test::shipped_cell("caro2014_kr270_table");
  const std::array<int, 6> idx = compliant_joints(cell);
  std::mt19937_64 rng(20);
  int checked = 0;
  for (int trial = 0; trial < 40 && checked < 8; ++trial) {
    const JointVector q = test::random_posture(cell, rng);
    Matrix6d K_X;
    try {
      K_X = cartesian_stiffness(cell, q, Vector6d::Zero());
    } catch (const Error&) {
      continue;  // singular
    }
    if (Eigen::FullPivLU<Matrix6d>(K_X).rcond() < 1e-10)
      continue;
    const Matrix6d C = K_X.inverse();
    const Isometry T0 = tcp_pose(cell, q);
    for (int k = 0; k < 6; ++k) {
      // 1 N mm of moment or 1 N of force: small enough that second order terms vanish.
      Vector6d w = Vector6d::Zero();
      w[k] = 1.0;
      JointVector q1 = q;
      for (int i = 0; i < 6; ++i) {
        const int j = idx[static_cast<std::size_t>(i)];
        const double h = 1e-6;
        JointVector qp = q, qm = q;
        qp[j] += h;
        qm[j] -= h;
        const Isometry Tp = tcp_pose(cell, qp), Tm = tcp_pose(cell, qm);
        const Eigen::AngleAxisd turn(Tp.linear() * Tm.linear().transpose());
        const double tau = w.tail<3>().dot((Tp.translation() - Tm.translation()) / (2 * h)) +
                           w.head<3>().dot(turn.axis() * turn.angle() / (2 * h));
        q1[j] += tau / *cell.joint(j).stiffness;
      }
      const Isometry T1 = tcp_pose(cell, q1);
      const Eigen::AngleAxisd rot(T1.linear() * T0.linear().transpose());
      Vector6d dX;
      dX.head<3>() = rot.axis() * rot.angle();
      dX.tail<3>() = T1.translation() - T0.translation();
      const double scale = C.col(k).norm();
      INFO("posture " << trial << ", wrench component " << k << ": model " << C.col(k).transpose()
                      << ", finite differences " << dX.transpose());
      CHECK((dX - C.col(k)).norm() <= 1e-4 * scale);
    }
    ++checked;
  }
  CHECK(checked == 8);
}

TEST_CASE("tool deflection: the normal component is the displacement along the material side",
          "[cutting]") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  KinematicsData data;
  forward_kinematics(cell, cell.home(), data);
  CuttingConditions cc;
  const MillingConditions mc = milling_conditions(cc, 16.0, 8000.0, true, 2000.0);
  CuttingLoad load;
  const Eigen::Vector3d z = data.T_B_tcp.linear().col(2);
  REQUIRE(cutting_load(mc, z, z.unitOrthogonal(), load));
  const ToolDeflection d = tool_deflection(cell, data, load);
  const Vector6d dX = tcp_displacement(cell, data, load.w_on_tcp);
  CHECK((d.translation_mm - dX.tail<3>()).norm() < 1e-12);
  CHECK((d.rotation_rad - dX.head<3>()).norm() < 1e-15);
  CHECK(d.normal_mm == Approx(dX.tail<3>().dot(load.n_material_B)));
  // The springs store positive work: w . dX > 0.
  CHECK(load.w_on_tcp.dot(dX) > 0.0);
}
