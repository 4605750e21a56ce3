// Tracking a 5-axis raster on the 9-joint Andres cell: redpost's tracker (Algorithm 1 + 2)
// against KDL's ChainIkSolverVel_pinv_nso driven by the same loop to the same tolerances
// (docs/performance.md, "Redundancy resolution along a path").
//
// Path: a 400 x 400 mm zigzag raster in the tool plane of the home posture, 0.5 mm between
// points, the tool axis tilting smoothly by up to 20 deg; 100 000+ poses. One benchmark
// iteration tracks the whole path from the same first posture.
//
// Run: build/tests/bench/redpost_bench_tracker --benchmark_repetitions=3
//        --benchmark_report_aggregates_only=true
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolvervel_pinv_nso.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>

#include "allocation_counter.hpp"
#include "kdl_chain.hpp"
#include "paths.hpp"
#include "redpost/redundancy/tracker.hpp"
#include "test_support.hpp"

namespace {

constexpr std::size_t kPoses = 100'500;
constexpr double kPositionTolMm = 1e-4, kAxisTolRad = 1e-7;
constexpr int kMaxIterations = 50;
constexpr double kNullSpaceGain = 0.01;  // redpost's default centring gain

struct Workload {
  redpost::Cell cell;
  std::vector<redpost::TcpTarget> path;
  redpost::JointVector q_first;
  KDL::Chain chain;
};

void report(benchmark::State& state, std::size_t path_size, double iterations, double failures) {
  const double poses = static_cast<double>(state.iterations()) * static_cast<double>(path_size);
  state.SetItemsProcessed(static_cast<int64_t>(poses));
  state.counters["poses/s"] = benchmark::Counter(poses, benchmark::Counter::kIsRate);
  state.counters["iter/pose"] = iterations / poses;
  state.counters["failed"] = failures;
}

const Workload& workload() {
  static const Workload w = [] {
    Workload out;
    out.cell = redpost::test::shipped_cell("andres2011_kr15_track_table");
    const double per_line = 400.0 / 0.5 + 1.0;
    const double lines = std::ceil(static_cast<double>(kPoses) / per_line);
    out.path = redpost::test::raster_in_tool_plane(out.cell, 400, 400, 0.5, 400.0 / (lines - 1),
                                                   20.0, kPoses);
    redpost::Tracker t(out.cell);
    const redpost::PoseResult first = t.solve_first_pose(out.path.front());
    if (first.status != redpost::PoseStatus::converged)
      std::abort();
    out.q_first = first.q;
    out.chain = redpost::test::kdl_chain_from_cell(out.cell);
    return out;
  }();
  return w;
}

void run_redpost(benchmark::State& state, bool extrapolate) {
  const Workload& w = workload();
  redpost::TrackerOptions options;
  options.extrapolate = extrapolate;
  redpost::Tracker tracker(w.cell, options);
  std::vector<redpost::PoseResult> results(w.path.size());
  double iterations = 0.0, failures = 0.0;
  {
    redpost::bench::AllocationScope allocations(state, static_cast<double>(w.path.size()));
    for (auto _ : state) {
      tracker.reset(w.q_first);
      const std::size_t done = tracker.track(w.path.data(), w.path.size(), results.data());
      failures += static_cast<double>(w.path.size() - done);
      for (std::size_t k = 0; k < done; ++k)
        iterations += results[k].iterations;
      benchmark::DoNotOptimize(results.data());
    }
  }
  report(state, w.path.size(), iterations, failures);
}

// KDL: the same outer loop as redpost's tracker (the same start, predictor or not; FK; the task
// error of eq. 14 with the same free-spin desired frame; a velocity IK step with the null-space
// motion on the first iteration of each pose; until the same tolerances), with
// ChainIkSolverVel_pinv_nso as the step.
void run_kdl(benchmark::State& state, bool extrapolate) {
  const Workload& w = workload();
  const unsigned n = static_cast<unsigned>(w.cell.size());
  KDL::ChainFkSolverPos_recursive fk(w.chain);
  KDL::JntArray opt_pos(n), weights(n);
  const redpost::JointVector home = w.cell.home();
  for (unsigned i = 0; i < n; ++i) {
    opt_pos(i) = home[static_cast<int>(i)];
    weights(i) = 1.0;
  }
  KDL::ChainIkSolverVel_pinv_nso ik(w.chain, opt_pos, weights, 1e-12, 150, kNullSpaceGain);
  KDL::JntArray q(n), q_prev(n), q_last(n), qdot(n);
  KDL::Frame F;
  double iterations = 0.0, failures = 0.0;
  {
    redpost::bench::AllocationScope allocations(state, static_cast<double>(w.path.size()));
    for (auto _ : state) {
      for (unsigned i = 0; i < n; ++i)
        q(i) = w.q_first[static_cast<int>(i)];
      q_prev = q;
      for (std::size_t k = 0; k < w.path.size(); ++k) {
        const redpost::TcpTarget& target = w.path[k];
        q_last = q;
        if (extrapolate && k >= 2 &&
            redpost::steady_continuation(w.path[k - 2].p_B_mm, w.path[k - 2].z_B,
                                         w.path[k - 1].p_B_mm, w.path[k - 1].z_B, target)) {
          for (unsigned i = 0; i < n; ++i)
            q(i) = 2.0 * q(i) - q_prev(i);
        }
        int it = 0;
        for (;; ++it) {
          fk.JntToCart(q, F);
          const redpost::Isometry T = redpost::test::isometry_from_kdl(F);
          const Eigen::Matrix3d R_d = redpost::desired_rotation(target, T.linear());
          // The task error of eq. 14, as for redpost. (KDL::diff would do in principle, but its
          // rotation vector is zero below KDL::epsilon = 1e-6 rad, so the loop could never
          // reach the 1e-7 rad axis tolerance.)
          const redpost::Vector6d dt = redpost::task_error(T, R_d, target.p_B_mm);
          if (dt.tail<3>().norm() <= kPositionTolMm && dt.head<3>().norm() <= kAxisTolRad)
            break;
          if (it == kMaxIterations) {
            failures += 1.0;
            break;
          }
          const KDL::Twist twist(KDL::Vector(dt[3], dt[4], dt[5]),
                                 KDL::Vector(dt[0], dt[1], dt[2]));
          ik.setAlpha(it == 0 ? kNullSpaceGain : 0.0);
          ik.CartToJnt(q, twist, qdot);
          KDL::Add(q, qdot, q);
        }
        q_prev = q_last;
        iterations += it;
      }
      benchmark::DoNotOptimize(q.data.data());
    }
  }
  report(state, w.path.size(), iterations, failures);
}

void BM_redpost_tracker(benchmark::State& state) {
  run_redpost(state, true);
}
void BM_redpost_tracker_no_predictor(benchmark::State& state) {
  run_redpost(state, false);
}
void BM_kdl_pinv_nso(benchmark::State& state) {
  run_kdl(state, true);
}
void BM_kdl_pinv_nso_no_predictor(benchmark::State& state) {
  run_kdl(state, false);
}
BENCHMARK(BM_redpost_tracker)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_kdl_pinv_nso)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_redpost_tracker_no_predictor)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_kdl_pinv_nso_no_predictor)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

int main(int argc, char** argv) {
  return redpost::bench::run_benchmarks(argc, argv);
}
