// In-situ calibration of the external axes (issue 7, Andres et al. 2011 Section 3).
#include <cmath>
#include <fstream>
#include <iterator>
#include <random>

#include "catch_compat.hpp"
#include "redpost/calibration/identification.hpp"
#include "redpost/calibration/measurement.hpp"
#include "redpost/calibration/observability.hpp"
#include "redpost/calibration/parameters.hpp"
#include "redpost/calibration/plan.hpp"
#include "redpost/calibration/program.hpp"
#include "redpost/calibration/readings_csv.hpp"
#include "redpost/calibration/validation.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/krl/reader.hpp"
#include "redpost/krl/template.hpp"
#include "redpost/redundancy/tracker.hpp"
#include "temp_dir.hpp"
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

TEST_CASE("calibration: noise-free readings in the commanded-pose form recover them to 1e-9") {
  // As a user runs it: the plan's commanded poses and the readings written as a CSV (x, y, z,
  // A, B, C and the external axes), read back, the arm joints solved again on the nominal
  // model, then identified. The joints form keeps the joints, this one only the frames.
  const auto params = default_calibration_parameters();
  const Eigen::VectorXd delta = paper_perturbation();
  const auto pts = simulated(paper_plan(), delta, 0.0, 1);
  const std::string csv = format_readings_csv(andres(), pts);  // the commanded-pose form
  auto back = parse_readings_csv(csv, "pose.csv", andres());
  // The joints solved from each frame give that frame on the nominal model to rounding, as the
  // controller's exact inverse kinematics does (the tracker alone stops at 1e-4 mm).
  for (const CalibrationPoint& pt : back) {
    const Isometry T = tcp_pose(andres(), pt.q);
    CHECK((T.translation() - pt.T_B_commanded.translation()).norm() < 1e-9);
    CHECK(Eigen::AngleAxisd(T.linear().transpose() * pt.T_B_commanded.linear()).angle() < 1e-12);
  }
  // The readings a controller gives: the true cell at those exact joints.
  const Cell truth = apply_parameters(andres(), params, parameter_values(andres(), params) + delta);
  simulate_readings(truth, back, 0.0, 1);
  back = parse_readings_csv(format_readings_csv(andres(), back), "pose.csv", andres());
  const CalibrationResult res = calibrate(andres(), params, back);
  CHECK(res.converged);
  const Eigen::VectorXd err = res.values - res.initial - delta;
  INFO("iterations " << res.iterations << " error " << err.transpose());
  for (Eigen::Index j = 0; j < delta.size(); ++j)
    CHECK(std::abs(err[j]) <= 1e-9);  // mm or rad
  CHECK(res.rms_after_mm < 1e-9);
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

TEST_CASE("calibration: statistics of distances against their definitions") {
  Eigen::VectorXd d(4);
  d << 1.0, -2.0, 3.0, 2.0;  // mean 1, squares 1+4+9+4 = 18
  const DistanceStatistics st = distance_statistics(d);
  CHECK(st.count == 4);
  CHECK(st.mean_mm == Approx(1.0));
  CHECK(st.rms_mm == Approx(std::sqrt(18.0 / 4.0)));
  CHECK(st.std_mm == Approx(std::sqrt((0.0 + 9.0 + 4.0 + 1.0) / 3.0)));
  CHECK(st.max_abs_mm == Approx(3.0));
  CHECK(distance_statistics(Eigen::VectorXd()).count == 0);
}

TEST_CASE("calibration: validate_calibration on the paper's 96 random table points") {
  const auto params = default_calibration_parameters();
  const Eigen::VectorXd delta = paper_perturbation();
  const double sigma = 0.035;
  const Cell& nominal = andres();
  const Cell truth = apply_parameters(nominal, params, parameter_values(nominal, params) + delta);
  const CalibrationResult res =
      calibrate(nominal, params, simulated(paper_plan(), delta, sigma, 21));

  std::vector<CalibrationPoint> val = plan_validation(nominal);
  REQUIRE(val.size() == 96);
  for (const CalibrationPoint& pt : val) {
    CHECK(pt.plane == PlaneAxis::z);
    CHECK(within_limits(nominal, pt.q));
    CHECK(pt.q[0] >= 0.0);
    CHECK(pt.q[0] <= kPi);
    CHECK(pt.q[1] >= 0.0);
    CHECK(pt.q[1] <= 1000.0);
    // The nominal model puts the commanded TCP on the table plane (to the solver's tolerance).
    CHECK(std::abs(tcp_pose(nominal, pt.q).translation().z()) < 1e-4);
  }
  simulate_readings(truth, val, sigma, 99);
  const ValidationResult v = validate_calibration(nominal, res.calibrated, val);
  INFO("before: mean " << v.before.mean_mm << " RMS " << v.before.rms_mm << " std "
                       << v.before.std_mm << "; after: mean " << v.after.mean_mm << " RMS "
                       << v.after.rms_mm << " std " << v.after.std_mm);
  CHECK(v.before.rms_mm > 0.3);
  CHECK(v.after.rms_mm < 2.0 * sigma);
  // before = the raw readings here (the nominal model predicts 0 on the plane).
  for (size_t i = 0; i < val.size(); ++i)
    CHECK(std::abs(v.before_mm[static_cast<Eigen::Index>(i)] - val[i].reading_mm) < 1e-4);
}

TEST_CASE("calibration: the history has one entry per accepted step") {
  const auto params = default_calibration_parameters();
  const CalibrationResult res =
      calibrate(andres(), params, simulated(paper_plan(), paper_perturbation(), 0.035, 4));
  REQUIRE(res.value_history.size() == static_cast<size_t>(res.iterations) + 1);
  REQUIRE(res.rms_history_mm.size() == res.value_history.size());
  CHECK(res.rms_history_mm.front() == Approx(res.rms_before_mm));
  CHECK(res.rms_history_mm.back() == Approx(res.rms_after_mm));
  CHECK((res.value_history.front() - res.initial).norm() == 0.0);
  CHECK((res.value_history.back() - res.values).norm() == 0.0);
  CHECK(res.residuals_mm.size() == static_cast<Eigen::Index>(paper_plan().size()));
  CHECK(std::sqrt(res.residuals_mm.squaredNorm() / res.residuals_mm.size()) ==
        Approx(res.rms_after_mm));
}

TEST_CASE("calibration: a robust loss rejects outlying readings that spoil least squares") {
  const auto params = default_calibration_parameters();
  const Eigen::VectorXd delta = paper_perturbation();
  const double sigma = 0.035;
  std::vector<CalibrationPoint> pts = simulated(paper_plan(), delta, sigma, 8);
  // Six gross outliers (dirt on a plane, a reflection): 1.5-4 mm, on different planes.
  const std::vector<int> bad = {3, 20, 41, 57, 80, 101};
  for (size_t k = 0; k < bad.size(); ++k)
    pts[static_cast<size_t>(bad[k])].reading_mm += (k % 2 ? -1.0 : 1.0) * (1.5 + 0.5 * k);

  auto worst_error_in_se = [&](const CalibrationResult& r) {
    double worst = 0.0;
    for (Eigen::Index j = 0; j < delta.size(); ++j)
      worst =
          std::max(worst, std::abs(r.values[j] - r.initial[j] - delta[j]) / r.standard_errors[j]);
    return worst;
  };
  const CalibrationResult ls = calibrate(andres(), params, pts);
  CHECK(ls.outliers.empty());  // least squares weights everything 1
  for (RobustLoss loss : {RobustLoss::huber, RobustLoss::cauchy}) {
    CalibrationOptions opt;
    opt.loss = loss;
    const CalibrationResult rob = calibrate(andres(), params, pts, opt);
    INFO(to_string(loss) << ": least squares worst error " << worst_error_in_se(ls)
                         << " standard errors, robust " << worst_error_in_se(rob) << "; sigma_hat "
                         << ls.sigma_hat_mm << " vs " << rob.sigma_hat_mm);
    CHECK(rob.converged);
    CHECK(rob.outliers == bad);  // exactly the injected readings are flagged
    CHECK(worst_error_in_se(rob) < 3.0);
    CHECK(rob.sigma_hat_mm < 1.5 * sigma);
    CHECK(ls.sigma_hat_mm > 5.0 * sigma);  // the outliers inflate least squares' noise estimate
    // The parameters themselves: the robust estimate is closer to the truth.
    CHECK((rob.values - rob.initial - delta).cwiseQuotient(rob.standard_errors).norm() <
          (ls.values - ls.initial - delta).cwiseQuotient(rob.standard_errors).norm());
  }
  // Without outliers the robust fit agrees with least squares to a fraction of a standard error.
  const auto clean = simulated(paper_plan(), delta, sigma, 8);
  CalibrationOptions huber;
  huber.loss = RobustLoss::huber;
  const CalibrationResult a = calibrate(andres(), params, clean);
  const CalibrationResult b = calibrate(andres(), params, clean, huber);
  for (Eigen::Index j = 0; j < delta.size(); ++j)
    CHECK(std::abs(a.values[j] - b.values[j]) < 0.5 * a.standard_errors[j]);
  CHECK(parse_robust_loss("cauchy") == RobustLoss::cauchy);
  CHECK_THROWS_WITH(parse_robust_loss("l1"), Catch::Contains("unknown loss"));
}

TEST_CASE("calibration: the calibrated cell gives the corrected joints") {
  // What the calibration is for: the joints computed with the calibrated cell put the TCP of
  // the TRUE cell where it was commanded; those of the nominal cell miss by the calibration
  // error.
  const auto params = default_calibration_parameters();
  const Eigen::VectorXd delta = paper_perturbation();
  const Cell& nominal = andres();
  const Cell truth = apply_parameters(nominal, params, parameter_values(nominal, params) + delta);
  const CalibrationResult res =
      calibrate(nominal, params, simulated(paper_plan(), delta, 0.035, 5));
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> thM(0.0, kPi), dL(0.0, 1000.0), xy(-150.0, 150.0),
      z(20.0, 250.0);
  double worst_nominal = 0.0, worst_calibrated = 0.0;
  for (int i = 0; i < 30; ++i) {
    // A milling-like frame: the tool axis tilted up to ~20 deg from vertical.
    Isometry T = frame_from_xyzabc(xy(rng), xy(rng), z(rng), {xy(rng), 180.0 + xy(rng) / 8, 0.0});
    const std::vector<double> ext = {thM(rng), dL(rng)};
    JointVector q_nom, q_cal;
    try {
      q_nom = joints_for_commanded_frame(nominal, {0, 1}, ext, T);
      q_cal = joints_for_commanded_frame(res.calibrated, {0, 1}, ext, T);
    } catch (const Error&) {
      continue;  // out of reach for this random draw
    }
    const double e_nom = (tcp_pose(truth, q_nom).translation() - T.translation()).norm();
    const double e_cal = (tcp_pose(truth, q_cal).translation() - T.translation()).norm();
    worst_nominal = std::max(worst_nominal, e_nom);
    worst_calibrated = std::max(worst_calibrated, e_cal);
  }
  INFO("worst TCP error on the true cell: nominal joints "
       << worst_nominal << " mm, calibrated joints " << worst_calibrated << " mm");
  CHECK(worst_nominal > 0.5);
  CHECK(worst_calibrated < 0.1);
}

TEST_CASE("calibration: the plan's KRL program visits every point with the planned joints") {
  const Cell& cell = andres();
  const std::vector<CalibrationPoint>& plan = paper_plan();
  test::TempDir dir("redpost_calprog");
  const KrlTemplateSet templates =
      load_krl_templates(test::source_path("definitions/krl/krc4_lin.xml"));
  CalibrationProgramOptions opt;
  opt.output_dir = dir.path.string();
  const std::vector<std::string> files = write_calibration_program(cell, plan, templates, opt);
  REQUIRE(files.size() == 1);
  const KrlProgram prog = read_krl_program(files[0]);
  // Six groups (3 planes x 2 configurations): an approach before each, a retract after each.
  REQUIRE(prog.motions.size() == plan.size() + 2 * 6);
  std::ifstream in(files[0]);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  size_t m = 0, waits = 0;
  for (size_t pos = 0; (pos = text.find("WAIT SEC 2.00", pos)) != std::string::npos; ++pos)
    ++waits;
  CHECK(waits == plan.size());
  CHECK(text.find("point 108 of 108") != std::string::npos);
  // Every point's motion is a PTP to the planned joints, in order, between approach/retract.
  for (size_t i = 0; i < plan.size(); ++i) {
    if (i == 0 || plan[i].plane != plan[i - 1].plane ||
        plan[i].configuration != plan[i - 1].configuration)
      m += i == 0 ? 1 : 2;  // (retract of the previous group and) approach of this one
    const KrlMotionRecord& rec = prog.motions[m++];
    CHECK(rec.keyword == "PTP");
    const AxisValues ax = to_controller_axes(cell, plan[i].q);
    for (int a = 1; a <= 6; ++a)
      CHECK(rec.target.values.at("A" + std::to_string(a)) == Approx(ax.arm(a)).margin(1e-3));
    CHECK(rec.target.values.at("E1") == Approx(ax.external(1)).margin(1e-3));
    CHECK(rec.target.values.at("E2") == Approx(ax.external(2)).margin(1e-3));
  }
  // The approach and retract poses back off along the beam and stay within the limits.
  for (const KrlMotionRecord& rec : prog.motions) {
    AxisValues ax;
    for (int a = 1; a <= 6; ++a)
      ax.arm(a) = rec.target.values.at("A" + std::to_string(a));
    ax.external(1) = rec.target.values.at("E1");
    ax.external(2) = rec.target.values.at("E2");
    const JointVector q = from_controller_axes(cell, ax, cell.home());
    CHECK(within_limits(cell, q, 1e-6));
  }
}
