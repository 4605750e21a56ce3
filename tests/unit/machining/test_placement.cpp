// Workpiece placement and spin planning (Caro 2014 chapter 5): the frames of eqs. 2.7-2.10
// against the printed matrices and forward kinematics, the tool path against plain geometry, the
// dynamic programme against brute-force enumeration, the deflection against the elastostatic
// model, the two-thread cost map against the single-thread one, the job loader's errors, and the
// optimum against 10 000 random feasible placements.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/machining/elastostatic.hpp"
#include "redpost/machining/placement.hpp"
#include "redpost/machining/placement_job.hpp"
#include "redpost/machining/quality.hpp"
#include "test_support.hpp"

namespace {

using namespace redpost;

const std::string kJob = "examples/placement/caro2014_job.xml";

const PlacementJob& example_job() {
  static const PlacementJob job = load_placement_job(test::source_path(kJob));
  return job;
}

// The example job on a coarse grid: 4 points per segment, 15 deg spin steps.
PlacementJob coarse_job() {
  PlacementJob job = example_job();
  for (ContourSegment& s : job.segments)
    s.points = 4;
  job.spin.step_rad = deg_to_rad(15.0);
  job.spin.max_step_rad = deg_to_rad(30.0);
  job.spin.max_joint_step_rad = deg_to_rad(45.0);
  return job;
}

// Eq. 2.10 exactly as printed.
Eigen::Matrix3d printed_7R_P(double beta) {
  Eigen::Matrix3d R;
  R << std::cos(beta), std::sin(beta), 0.0,  //
      std::sin(beta), -std::cos(beta), 0.0,  //
      0.0, 0.0, -1.0;
  return R;
}

// Replaces the first occurrence of `from` in `text`; the test fails if there is none.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

std::string example_text() {
  std::string text = read_text_file(test::source_path(kJob));
  // Absolute cell path: the text is parsed under another name.
  return replaced(text, "../../definitions", test::source_path("definitions"));
}

}  // namespace

TEST_CASE("placement: eq. 2.8 is a rotation about z by 2 atan2(Q4, Q1)", "[placement]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    const Placement p{300 * u(rng), -1900 + 300 * u(rng), -400 + 100 * u(rng), u(rng)};
    const Isometry T = workpiece_frame(p);
    // Q4 = sin(theta/2) with u_z = 1 (eqs. 2.1, 2.4 with Q2 = Q3 = 0).
    const double theta = 2.0 * std::asin(p.q4);
    const Eigen::Matrix3d Rz =
        Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    CHECK((T.linear() - Rz).norm() < 1e-12);
    CHECK((T.translation() - Eigen::Vector3d(p.x_mm, p.y_mm, p.z_mm)).norm() < 1e-12);
  }
}

TEST_CASE("placement: the TCP target solves eq. 2.7 with beta as the virtual joint",
          "[placement]") {
  const Cell& cell = example_job().cell;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int spin = cell.size() - 1;
  for (int k = 0; k < 100; ++k) {
    JointVector q = test::random_posture(cell, rng);
    const double beta = q[spin];
    // F7 from the chain with the spin at 0: {B} -> F6 -> 6T_7 (eq. 2.9); the cell's tool frame
    // after the spin (z turned to point from the tip to the spindle) taken off.
    JointVector q0 = q;
    q0[spin] = 0.0;
    const Isometry T_B_7 = tcp_pose(cell, q0) * cell.T_last_tcp.inverse(Eigen::Isometry);
    // Any placement; F_Pi from eq. 2.7: 0T_W WT_Pi = 0T_7 7T_Pi with 7T_Pi as printed.
    const Isometry T_0_W = workpiece_frame(Placement{100 * u(rng), -1800, -300, u(rng)});
    Isometry T_7_P = Isometry::Identity();
    T_7_P.linear() = printed_7R_P(beta);
    const Isometry T_W_P =
        T_0_W.inverse(Eigen::Isometry) * cell.T_B_0.inverse(Eigen::Isometry) * T_B_7 * T_7_P;
    const Isometry target = tcp_target(cell, T_0_W, T_W_P);
    const Isometry T_B_tcp = tcp_pose(cell, q);
    CHECK((target.translation() - T_B_tcp.translation()).norm() < 1e-8);
    CHECK((target.linear() - T_B_tcp.linear()).norm() < 1e-12);
  }
}

TEST_CASE("placement: the tool path runs along the contour, offset by the tool radius",
          "[placement]") {
  const PlacementJob& job = example_job();
  const std::vector<PathPoint> path = tool_path(job);
  REQUIRE(static_cast<int>(path.size()) == job.point_count());
  const double radius = 0.5 * job.milling.tool_diameter_mm;
  size_t i = 0;
  for (size_t s = 0; s < job.segments.size(); ++s) {
    const ContourSegment& seg = job.segments[s];
    const Eigen::Vector3d d = (seg.to_W_mm - seg.from_W_mm).normalized();
    const Eigen::Vector3d left = Eigen::Vector3d::UnitZ().cross(d);
    for (int k = 0; k < seg.points; ++k, ++i) {
      const PathPoint& p = path[i];
      CHECK(p.segment == static_cast<int>(s));
      const Eigen::Vector3d r = p.T_W_P.translation() - seg.from_W_mm;
      // Material on the right: the tool centre is one radius to the left of the contour.
      CHECK(std::fabs(r.dot(left) - radius) < 1e-9);
      CHECK(std::fabs(r.dot(d) - (k + 0.5) * 200.0 / seg.points) < 1e-9);
      CHECK((p.T_W_P.linear().col(0) - d).norm() < 1e-12);
      CHECK((p.T_W_P.linear().col(2) - Eigen::Vector3d::UnitZ()).norm() < 1e-12);
      CHECK(std::fabs(p.T_W_P.linear().determinant() - 1.0) < 1e-12);
      // Down-milling with the material on -y_P: the tool pushes the workpiece towards -y_P.
      CHECK(p.force_on_workpiece_P_N.y() < 0.0);
    }
  }
}

namespace {

// Every plan of the small instance, enumerated: per segment and posture, every beta sequence.
double brute_force(const CostMap& map, const std::vector<SegmentRange>& segs,
                   const ContinuityLimits& lim, PlanGoal goal, bool& feasible) {
  const double inf = std::numeric_limits<double>::infinity();
  double total = 0.0;
  feasible = true;
  for (const SegmentRange& seg : segs) {
    double best = goal == PlanGoal::best ? inf : -inf;
    for (int mu = 1; mu <= kPostures; ++mu) {
      std::vector<int> b(static_cast<size_t>(seg.count), 0);
      while (true) {
        bool ok = true;
        double sum = 0.0;
        for (int k = 0; k < seg.count && ok; ++k) {
          const int i = seg.first + k;
          const double c = map.c(i, b[static_cast<size_t>(k)], mu);
          ok = c == c;
          sum += c;
          if (ok && k > 0) {
            const int step = std::abs(b[static_cast<size_t>(k)] - b[static_cast<size_t>(k - 1)]);
            ok = std::min(step, map.betas - step) <= lim.max_beta_steps;
            const double* qa = map.q(i - 1, b[static_cast<size_t>(k - 1)], mu);
            const double* qb = map.q(i, b[static_cast<size_t>(k)], mu);
            for (int j = 0; j < 6 && ok; ++j) {
              double dq = qb[j] - qa[j];
              if (lim.wraps[static_cast<size_t>(j)])
                dq = std::remainder(dq, 2.0 * kPi);
              ok = std::fabs(dq) <= lim.max_joint_step_rad;
            }
          }
        }
        if (ok)
          best = goal == PlanGoal::best ? std::min(best, sum) : std::max(best, sum);
        int k = 0;
        while (k < seg.count && ++b[static_cast<size_t>(k)] == map.betas)
          b[static_cast<size_t>(k++)] = 0;
        if (k == seg.count)
          break;
      }
    }
    if (!std::isfinite(best))
      feasible = false;
    else
      total += best;
  }
  return total;
}

}  // namespace

TEST_CASE("placement: the DP plan equals brute-force enumeration (best and worst)", "[placement]") {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int feasible_instances = 0, infeasible_instances = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const std::vector<SegmentRange> segs = {{0, 4}, {4, 3}, {7, 2}};
    CostMap map;
    map.resize(9, 6);
    ContinuityLimits lim;
    lim.max_beta_steps = trial % 3;
    lim.max_joint_step_rad = 0.5;
    lim.wraps = {true, false, false, true, false, true};
    const double p_missing = 0.1 + 0.6 * u01(rng);
    for (int i = 0; i < map.points; ++i) {
      for (int b = 0; b < map.betas; ++b) {
        for (int mu = 1; mu <= kPostures; ++mu) {
          const size_t at = map.index(i, b, mu);
          map.c_mm[at] = u01(rng) < p_missing ? std::nan("") : u01(rng);
          for (int j = 0; j < 6; ++j) {
            // Joint values near one of two branches; the wrapping joints sometimes across the
            // +-pi seam (a 2 pi shift that the continuity test must see through).
            const bool seam = lim.wraps[static_cast<size_t>(j)] && u01(rng) < 0.3;
            map.q_arm[at * 6 + static_cast<size_t>(j)] =
                (u01(rng) < 0.03 ? 1.0 : 0.0) + 0.3 * u01(rng) + (seam ? 2 * kPi : 0.0);
          }
        }
      }
    }
    DpWorkspace ws;
    for (PlanGoal goal : {PlanGoal::best, PlanGoal::worst}) {
      bool feasible = false;
      const double expected = brute_force(map, segs, lim, goal, feasible);
      const SpinPlan plan = plan_spin(map, segs, lim, goal, ws);
      REQUIRE(plan.feasible == feasible);
      if (!feasible) {
        ++infeasible_instances;
        continue;
      }
      ++feasible_instances;
      CHECK(std::fabs(plan.f_mqc_mm * map.points - expected) < 1e-12);
      // The returned plan obeys its own constraints and adds up to its value.
      double sum = 0.0, max_c = 0.0;
      for (size_t s = 0; s < segs.size(); ++s) {
        for (int k = 0; k < segs[s].count; ++k) {
          const int i = segs[s].first + k;
          const double c = map.c(i, plan.beta_index[static_cast<size_t>(i)], plan.mu[s]);
          REQUIRE(c == c);
          sum += c;
          max_c = std::max(max_c, c);
          if (k > 0) {
            const int step = std::abs(plan.beta_index[static_cast<size_t>(i)] -
                                      plan.beta_index[static_cast<size_t>(i - 1)]);
            CHECK(std::min(step, map.betas - step) <= lim.max_beta_steps);
          }
        }
      }
      CHECK(std::fabs(sum - expected) < 1e-12);
      CHECK(plan.max_c_mm == max_c);
    }
  }
  // Both outcomes were exercised.
  CHECK(feasible_instances > 20);
  CHECK(infeasible_instances > 5);
}

TEST_CASE("placement: c_i is eq. 5.1 of the elastostatic model's displacement", "[placement]") {
  const PlacementProblem problem(coarse_job());
  const Cell& cell = problem.cell();
  const Placement p{0.0, -1900.0, -400.0, 0.3};
  const Isometry T_B_W = cell.T_B_0 * workpiece_frame(p);
  JointVector q_other = cell.home();
  int checked = 0;
  for (int i = 0; i < static_cast<int>(problem.path().size()); i += 3) {
    Vector6d w;
    Eigen::Vector3d y_B;
    problem.point_load(T_B_W, i, w, y_B);
    const Isometry& T_W_P = problem.path()[static_cast<size_t>(i)].T_W_P;
    const Isometry target = tcp_target(cell, workpiece_frame(p), T_W_P);
    for (int b = 0; b < problem.grid().count; b += 5) {
      q_other[problem.spin_joint()] = problem.grid().beta_rad(b);
      const ArmIkSolutions sol = problem.ik().solve(target, q_other);
      for (size_t m = 0; m < 8; ++m) {
        if (!sol.valid[m])
          continue;
        double inv_kappa = 0.0;
        const double c = problem.deflection_mm(sol.q[m], w, y_B, &inv_kappa);
        if (!(inv_kappa > problem.job().constraints.inv_kappa_min)) {
          CHECK(std::isnan(c));
          continue;
        }
        // Independent: the model's dX = J K_theta^-1 J^T w, and eq. 5.1 with z_7 and x_Pi.
        const Vector6d dX = tcp_displacement(cell, sol.q[m], w);
        const Isometry T_B_tcp = tcp_pose(cell, sol.q[m]);
        const Eigen::Vector3d z7 = -T_B_tcp.linear().col(2);  // F7's z = -z_Pi (eq. 2.10)
        const Eigen::Vector3d x_P = (T_B_W * T_W_P).linear().col(0);
        const double expected = normal_tool_deflection_mm(dX.tail<3>(), z7, x_P);
        CHECK(std::fabs(c - expected) < 1e-9 * std::max(1.0, expected));
        ++checked;
      }
    }
  }
  CHECK(checked > 20);
}

TEST_CASE("placement: the two-thread cost map equals the single-thread one", "[placement]") {
  PlacementJob job = coarse_job();
  job.optimiser.threads = 1;
  const PlacementProblem one(job);
  job.optimiser.threads = 2;
  const PlacementProblem two(job);
  unsigned long long state = 99;
  for (int k = 0; k < 5; ++k) {
    const Placement p = random_placement(job.volume, state);
    CostMap a, b;
    const int ra = one.fill_cost_map(p, a, false);
    const int rb = two.fill_cost_map(p, b, false);
    CHECK(ra == rb);
    REQUIRE(a.c_mm.size() == b.c_mm.size());
    bool same = true;
    for (size_t i = 0; i < a.c_mm.size(); ++i) {
      const bool na = std::isnan(a.c_mm[i]), nb = std::isnan(b.c_mm[i]);
      same = same && na == nb && (na || a.c_mm[i] == b.c_mm[i]);
    }
    CHECK(same);
  }
}

TEST_CASE("placement: job errors name the file and line", "[placement]") {
  const std::string good = example_text();
  auto message_of = [](const std::string& text) {
    try {
      parse_placement_job(text, "job.xml");
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::bad_input);
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK_NOTHROW(parse_placement_job(good, "job.xml"));
  CHECK(message_of("<placement_job format=\"1\"><cell").find("job.xml:1: not well-formed") !=
        std::string::npos);
  CHECK(
      message_of(replaced(good, "x_min=\"-0.3m\"", "x_min=\"0.4m\"")).find("x: min is above max") !=
      std::string::npos);
  CHECK(message_of(replaced(good, "caro2014_kr270_table.xml", "nothing.xml"))
            .find("does not exist") != std::string::npos);
  CHECK(message_of(replaced(good, "GN_CRS2_LM", "GN_MAGIC")).find("GN_MAGIC") != std::string::npos);
  CHECK(message_of(replaced(good, "ae=\"5\"", "ae=\"25\"")).find("exceeds the tool diameter") !=
        std::string::npos);
  CHECK(message_of(replaced(good, "<tool diameter", "<tool colour=\"red\" diameter"))
            .find("unknown attribute 'colour'") != std::string::npos);
  const std::string wrong_step = message_of(replaced(good, "step=\"5deg\"", "step=\"7deg\""));
  CHECK(wrong_step.find("job.xml:") == 0);
  CHECK(wrong_step.find("<spin> step") != std::string::npos);
}

TEST_CASE("placement: no feasible placement is an error", "[placement]") {
  PlacementJob job = coarse_job();
  // Out of reach: O_W 6 m away from the A1 axis.
  job.volume.y_min_mm = -6100.0;
  job.volume.y_max_mm = -6000.0;
  job.optimiser.global_evaluations = 30;
  const PlacementProblem problem(job);
  CHECK_THROWS_AS(search_placement(problem, PlanGoal::best, job.optimiser), Error);
}

TEST_CASE("placement: the optimum beats 10 000 random feasible placements", "[placement]") {
  // REDPOST_TEST_LIGHT (set by scripts/reliability.sh for the sanitizer build, where this test
  // runs ~40 times slower): a shorter search against 1000 random placements.
  const bool light = std::getenv("REDPOST_TEST_LIGHT") != nullptr;
  const int samples = light ? 1000 : 10000;
  PlacementJob job = coarse_job();
  job.optimiser.global_evaluations = light ? 150 : 600;
  job.optimiser.local_evaluations = light ? 50 : 200;
  const PlacementProblem problem(job);
  const auto t0 = std::chrono::steady_clock::now();
  const PlacementSearch best = search_placement(problem, PlanGoal::best, job.optimiser);
  const PlacementSearch worst = search_placement(problem, PlanGoal::worst, job.optimiser);
  InnerWorkspace ws;
  unsigned long long state = 20240601;
  int feasible = 0, drawn = 0;
  double lowest = std::numeric_limits<double>::infinity(), highest = 0.0;
  while (feasible < samples && drawn < 200000) {
    ++drawn;
    const InnerResult r = problem.solve(random_placement(job.volume, state), ws, false);
    if (!r.feasible)
      continue;
    ++feasible;
    lowest = std::min(lowest, r.best.f_mqc_mm);
    highest = std::max(highest, r.best.f_mqc_mm);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "placement: optimum %.5f / %.5f mm, random best-of-%d %.5f / %.5f mm (%d drawn), "
      "%.1f s\n",
      best.inner.best.f_mqc_mm, worst.inner.best.f_mqc_mm, feasible, lowest, highest, drawn,
      seconds);
  REQUIRE(feasible == samples);
  CHECK(best.inner.best.f_mqc_mm <= lowest);
  CHECK(worst.inner.best.f_mqc_mm >= highest);
}
