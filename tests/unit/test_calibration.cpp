// In-situ calibration of the external axes (issue 7, Andres et al. 2011 Section 3).
#include <cmath>
#include <random>

#include "catch_compat.hpp"
#include "redpost/calibration.hpp"
#include "redpost/error.hpp"
#include "redpost/forward_kinematics.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

const Cell& andres() {
  static const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  return cell;
}

// The paper's set-up: 6 x 6 grids on the three planes, {theta_M, d_L} = {0, 700}, {pi/4, 300}.
const std::vector<CalibrationPoint>& paper_plan() {
  static const std::vector<CalibrationPoint> plan = plan_calibration(andres());
  return plan;
}

// The paper's result beta(18) - beta(0) = [0.05 0.01 0.06 0.01 0.07 0.08], read as degrees for
// the angles (alpha_1, theta_M, theta_2) and mm for the lengths (a_1, d_1, d_L): see
// docs/calibration.md for why not rad.
Eigen::VectorXd paper_perturbation() {
  Eigen::VectorXd d(6);
  d << deg_to_rad(0.05), 0.01, deg_to_rad(0.06), 0.01, deg_to_rad(0.07), 0.08;
  return d;
}

std::vector<CalibrationPoint> simulated(const std::vector<CalibrationPoint>& plan,
                                        const Eigen::VectorXd& delta, double sigma,
                                        std::uint64_t seed) {
  const auto params = default_calibration_parameters();
  const Cell truth = apply_parameters(andres(), params, parameter_values(andres(), params) + delta);
  std::vector<CalibrationPoint> pts = plan;
  simulate_readings(truth, pts, sigma, seed);
  return pts;
}

}  // namespace

TEST_CASE("calibration: parameter names parse, print and apply to a copy of the cell") {
  const Cell& cell = andres();
  const auto p = parse_calibration_parameters("link1.alpha, link3.a,link9.theta,link2.d", cell);
  REQUIRE(p.size() == 4);
  CHECK(p[0].name() == "link1.alpha");
  CHECK(p[1].name() == "link3.a");
  CHECK(p[2].name() == "link9.theta");
  CHECK(p[3].name() == "link2.d");
  CHECK(parse_calibration_parameters("", cell).size() == 6);
  CHECK_THROWS_AS(parse_calibration_parameter("link0.a", cell), Error);
  CHECK_THROWS_AS(parse_calibration_parameter("link10.a", cell), Error);
  CHECK_THROWS_AS(parse_calibration_parameter("link1.b", cell), Error);
  CHECK_THROWS_AS(parse_calibration_parameter("joint1.a", cell), Error);
  CHECK_THROWS_AS(parse_calibration_parameters("link1.a,link1.a", cell), Error);

  const auto beta = default_calibration_parameters();
  const Eigen::VectorXd v0 = parameter_values(cell, beta);
  CHECK(v0[0] == Approx(kPi / 2));
  CHECK(v0[1] == 803.0);
  CHECK(v0[3] == -305.0);
  const Cell c2 = apply_parameters(cell, beta, v0 + paper_perturbation());
  CHECK((parameter_values(c2, beta) - v0 - paper_perturbation()).norm() < 1e-12);
  CHECK(parameter_values(cell, beta) == v0);  // the original is untouched
}

TEST_CASE("calibration: the laser reading is the exact ray-plane intersection") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MeasurementModel model;
  model.plane_offset_mm = {3.0, -2.0, 5.0};
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Isometry T = Isometry::Identity();
    T.linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().matrix();
    T.translation() = 500.0 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    const Eigen::Vector3d p = T.translation(), beam = -T.linear().col(2);
    for (int k = 0; k < 3; ++k) {
      const auto plane = static_cast<PlaneAxis>(k);
      if (std::abs(beam[k]) < model.min_incidence_cos) {
        CHECK_THROWS_AS(laser_reading(T, plane, model), Error);
        continue;
      }
      // Brute force: p + d beam = q0 + s e1 + t e2, solved as a 3 x 3 system in (d, s, t).
      const Eigen::Vector3d e1 = Eigen::Vector3d::Unit((k + 1) % 3);
      const Eigen::Vector3d e2 = Eigen::Vector3d::Unit((k + 2) % 3);
      const Eigen::Vector3d q0 =
          model.plane_offset_mm[static_cast<size_t>(k)] * Eigen::Vector3d::Unit(k);
      Eigen::Matrix3d A;
      A << beam, -e1, -e2;
      const Eigen::Vector3d x = A.colPivHouseholderQr().solve(q0 - p);
      CHECK(laser_reading(T, plane, model) == Approx(x[0]).margin(1e-9));
      ++checked;
    }
  }
  CHECK(checked > 500);

  // Positive when the plane lies beyond the TCP: 10 mm above the table, pointing down.
  Isometry T = Isometry::Identity();
  T.translation() = Eigen::Vector3d(1, 2, 10);
  CHECK(laser_reading(T, PlaneAxis::z) == Approx(10.0));
  T.translation().z() = -4;
  CHECK(laser_reading(T, PlaneAxis::z) == Approx(-4.0));
  // A beam along the plane is refused with a clear message.
  T.linear() = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  CHECK_THROWS_WITH(laser_reading(T, PlaneAxis::z), Catch::Contains("nearly parallel"));

  // The paper's approximation: the distance from the plane, exact for a perpendicular beam.
  MeasurementModel approx;
  approx.approximate = true;
  for (int k = 0; k < 3; ++k) {
    const auto plane = static_cast<PlaneAxis>(k);
    const Isometry C = commanded_frame(plane, Eigen::Vector3d(0, 0, 0), 7.5);
    CHECK(laser_reading(C, plane) == Approx(7.5));
    CHECK(laser_reading(C, plane, approx) == Approx(7.5));
    Isometry tilted = C;
    tilted.linear() = C.linear() * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX());
    CHECK(laser_reading(tilted, plane) == Approx(7.5 / std::cos(0.2)));
    CHECK(laser_reading(tilted, plane, approx) == Approx(7.5));
  }
}

TEST_CASE("calibration: the paper's plan has 108 points reached on the nominal model") {
  const auto& plan = paper_plan();
  REQUIRE(plan.size() == 108);
  const Cell& cell = andres();
  for (const auto& pt : plan) {
    const double thM = pt.configuration == 0 ? 0.0 : kPi / 4,
                 dL = pt.configuration == 0 ? 700 : 300;
    CHECK(pt.q[0] == thM);
    CHECK(pt.q[1] == dL);
    CHECK(within_limits(cell, pt.q));
    const Isometry T = tcp_pose(cell, pt.q);
    CHECK((T.translation() - pt.T_B_commanded.translation()).norm() < 1e-3);
    CHECK((T.linear() - pt.T_B_commanded.linear()).norm() < 1e-5);
    // The commanded point lies on its plane and the beam is perpendicular to it.
    const int k = static_cast<int>(pt.plane);
    CHECK(std::abs(pt.T_B_commanded.translation()[k]) < 1e-12);
    CHECK(std::abs(pt.T_B_commanded.linear()(k, 2)) == Approx(1.0));
    CHECK(laser_reading(T, pt.plane) == Approx(0.0).margin(1e-3));
  }
}

TEST_CASE(
    "calibration: the model's readings and AD Jacobian agree with FK and finite differences") {
  const Cell& cell = andres();
  const auto& plan = paper_plan();
  const auto params = parse_calibration_parameters(
      "link1.alpha,link1.a,link1.theta,link1.d,link2.theta,link2.d,link3.alpha,link5.a,link9.d",
      cell);
  Eigen::VectorXd v = parameter_values(cell, params);
  v.head(6) += paper_perturbation();
  v[7] += 0.3;
  const Cell moved = apply_parameters(cell, params, v);
  Eigen::VectorXd pred;
  const Eigen::MatrixXd W = observation_matrix(cell, params, v, plan, {}, &pred);
  REQUIRE(W.rows() == 108);
  REQUIRE(W.cols() == 9);
  for (size_t i = 0; i < plan.size(); ++i)
    CHECK(pred[static_cast<Eigen::Index>(i)] ==
          Approx(laser_reading(tcp_pose(moved, plan[i].q), plan[i].plane)).margin(1e-9));
  for (Eigen::Index j = 0; j < v.size(); ++j) {
    const double h = params[static_cast<size_t>(j)].is_angle() ? 1e-6 : 1e-4;
    Eigen::VectorXd vp = v, vm = v, rp, rm;
    vp[j] += h;
    vm[j] -= h;
    observation_matrix(cell, params, vp, plan, {}, &rp);
    observation_matrix(cell, params, vm, plan, {}, &rm);
    const Eigen::VectorXd fd = (rp - rm) / (2 * h);
    INFO(params[static_cast<size_t>(j)].name());
    CHECK((W.col(j) - fd).cwiseAbs().maxCoeff() < 1e-5 * std::max(1.0, fd.cwiseAbs().maxCoeff()));
  }
}

TEST_CASE("calibration: noise-free readings recover the true parameters to 1e-9") {
  const auto params = default_calibration_parameters();
  const Eigen::VectorXd delta = paper_perturbation();
  const auto pts = simulated(paper_plan(), delta, 0.0, 1);
  CalibrationOptions opt;
  const CalibrationResult res = calibrate(andres(), params, pts, opt);
  CHECK(res.converged);
  const Eigen::VectorXd err = res.values - res.initial - delta;
  INFO("iterations " << res.iterations << " error " << err.transpose());
  for (Eigen::Index j = 0; j < delta.size(); ++j)
    CHECK(std::abs(err[j]) < 1e-9 * std::abs(delta[j]));
  CHECK(res.rms_after_mm < 1e-9);
  CHECK(res.rms_before_mm > 0.1);
  CHECK_FALSE(res.observability.rank_deficient());
}

TEST_CASE("calibration: the paper's set-up recovers beta within 3 standard errors") {
  const auto params = default_calibration_parameters();
  const Eigen::VectorXd delta = paper_perturbation();
  const double sigma = 0.035;
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const auto pts = simulated(paper_plan(), delta, sigma, seed);
    const CalibrationResult res = calibrate(andres(), params, pts);
    INFO("seed " << seed << ", iterations " << res.iterations << ", rms " << res.rms_before_mm
                 << " -> " << res.rms_after_mm << ", kappa " << res.observability.condition_number);
    CHECK(res.converged);
    CHECK(res.iterations <= 10);
    CHECK_FALSE(res.observability.rank_deficient());
    CHECK(std::isfinite(res.observability.condition_number));
    CHECK(res.rms_after_mm < 1.5 * sigma);
    CHECK(res.sigma_hat_mm == Approx(sigma).epsilon(0.3));
    for (Eigen::Index j = 0; j < delta.size(); ++j) {
      INFO(params[static_cast<size_t>(j)].name()
           << ": error " << res.values[j] - res.initial[j] - delta[j] << ", standard error "
           << res.standard_errors[j]);
      CHECK(std::isfinite(res.standard_errors[j]));
      CHECK(std::abs(res.values[j] - res.initial[j] - delta[j]) < 3.0 * res.standard_errors[j]);
    }
  }
}

TEST_CASE("calibration: the paper's numbers read literally as rad and mm still converge") {
  Eigen::VectorXd delta(6);
  delta << 0.05, 0.01, 0.06, 0.01, 0.07, 0.08;
  const auto params = default_calibration_parameters();
  const auto pts = simulated(paper_plan(), delta, 0.035, 4);
  const CalibrationResult res = calibrate(andres(), params, pts);
  INFO("iterations " << res.iterations << ", rms " << res.rms_before_mm << " -> "
                     << res.rms_after_mm);
  CHECK(res.converged);
  CHECK(res.iterations <= 10);
  for (Eigen::Index j = 0; j < delta.size(); ++j)
    CHECK(std::abs(res.values[j] - res.initial[j] - delta[j]) < 3.0 * res.standard_errors[j]);
}

TEST_CASE("calibration: one plane or one configuration is rank-deficient, with names") {
  const auto params = default_calibration_parameters();
  const Eigen::VectorXd delta = paper_perturbation();
  const auto& plan = paper_plan();

  SECTION("the table plane only") {
    std::vector<CalibrationPoint> z_only;
    for (const auto& pt : plan)
      if (pt.plane == PlaneAxis::z)
        z_only.push_back(pt);
    const auto pts = simulated(z_only, delta, 0.0, 1);
    const Eigen::MatrixXd W =
        observation_matrix(andres(), params, parameter_values(andres(), params), pts);
    const ObservabilityReport rep = analyse_observability(W, params);
    INFO(rep.summary());
    CHECK(rep.rank_deficient());
    CHECK(rep.summary().find("link1.theta") != std::string::npos);
    CHECK(rep.summary().find("link1.a") != std::string::npos);
    CHECK(rep.summary().find("link2.d") != std::string::npos);
    CHECK_THROWS_WITH(calibrate(andres(), params, pts),
                      Catch::Contains("cannot identify") && Catch::Contains("link1.theta"));
    // With allow_partial, the observable subspace is identified and the rest left alone.
    CalibrationOptions partial;
    partial.allow_partial = true;
    const CalibrationResult res = calibrate(andres(), params, pts, partial);
    CHECK(res.observability.rank_deficient());
    CHECK(res.rms_after_mm < 1e-3);
  }
  SECTION("one external configuration only") {
    // With the paper's beta, one configuration is NOT deficient: the six parameters are a local
    // chart of the rigid transform {B} -> track carriage, which three planes fix. Adding the
    // arm base's theta (link3.theta) makes two configurations necessary.
    std::vector<CalibrationPoint> one;
    for (const auto& pt : plan)
      if (pt.configuration == 0)
        one.push_back(pt);
    const auto beta7 = parse_calibration_parameters(
        "link1.alpha,link1.a,link1.theta,link1.d,link2.theta,link2.d,link3.theta", andres());
    const Eigen::VectorXd v7 = parameter_values(andres(), beta7);
    const ObservabilityReport both =
        analyse_observability(observation_matrix(andres(), beta7, v7, plan), beta7);
    CHECK_FALSE(both.rank_deficient());
    const ObservabilityReport rep =
        analyse_observability(observation_matrix(andres(), beta7, v7, one), beta7);
    INFO(rep.summary());
    CHECK(rep.rank == 6);
    REQUIRE(rep.unobservable.size() == 1);
    CHECK(rep.summary() == "link1.a, link1.theta, link2.d and link3.theta cannot be separated");
    CHECK_THROWS_WITH(calibrate(andres(), beta7, one), Catch::Contains("cannot identify"));
    const ObservabilityReport six = analyse_observability(
        observation_matrix(andres(), params, parameter_values(andres(), params), one), params);
    CHECK_FALSE(six.rank_deficient());
  }
}

TEST_CASE("calibration: validation on 96 table points, random track and table (paper 3.3)") {
  const auto params = default_calibration_parameters();
  const Eigen::VectorXd delta = paper_perturbation();
  const double sigma = 0.035;
  const Cell& nominal = andres();
  const Cell truth = apply_parameters(nominal, params, parameter_values(nominal, params) + delta);
  const CalibrationResult res =
      calibrate(nominal, params, simulated(paper_plan(), delta, sigma, 11));

  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> thM(0.0, kPi), dL(0.0, 1000.0), xy(-200.0, 200.0);
  std::normal_distribution<double> noise(0.0, sigma);
  double ss_before = 0.0, ss_after = 0.0;
  const int nv = 96;
  for (int i = 0; i < nv; ++i) {
    const Isometry C = commanded_frame(PlaneAxis::z, Eigen::Vector3d(xy(rng), xy(rng), 0.0), 0.0);
    const JointVector q = joints_for_commanded_frame(nominal, {0, 1}, {thM(rng), dL(rng)}, C);
    const double reading = laser_reading(tcp_pose(truth, q), PlaneAxis::z) + noise(rng);
    // The error left on the table: what the controller commands (with the nominal or the
    // calibrated model) against what the laser sees. The nominal model predicts 0 here.
    const JointVector q_cal = joints_for_commanded_frame(res.calibrated, {0, 1}, {q[0], q[1]}, C);
    const double reading_cal = laser_reading(tcp_pose(truth, q_cal), PlaneAxis::z) + noise(rng);
    ss_before += reading * reading;
    ss_after += reading_cal * reading_cal;
  }
  const double rms_before = std::sqrt(ss_before / nv), rms_after = std::sqrt(ss_after / nv);
  INFO("validation RMS " << rms_before << " -> " << rms_after << " mm");
  CHECK(rms_before > 0.3);
  CHECK(rms_after < 2.0 * sigma);
}
