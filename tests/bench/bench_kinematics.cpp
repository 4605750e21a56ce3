// Forward kinematics and Jacobian of the 9-joint Andres cell: redpost against Orocos KDL on the
// same chain, plus a count of heap allocations per call; the closed-form arm IK and the
// whole-path planner (docs/performance.md).
//
// Run: build/tests/bench/redpost_bench_kinematics --benchmark_repetitions=5
//        --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>

#include "allocation_counter.hpp"
#include "kdl_chain.hpp"
#include "redpost/kinematics/arm_ik.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/jacobian.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "redpost/redundancy/path_plan.hpp"
#include "test_support.hpp"

namespace {

constexpr std::size_t kPostureCount = 1024;  // a power of two: the index wraps with a mask
constexpr std::uint64_t kSeed = 20110101;

struct Workload {
  redpost::Cell cell;
  std::vector<redpost::JointVector> q;
  std::vector<KDL::JntArray> q_kdl;
  KDL::Chain chain;
};

// Built once, outside every timed loop.
const Workload& workload() {
  static const Workload w = [] {
    Workload out;
    out.cell = redpost::test::shipped_cell("andres2011_kr15_track_table");
    std::mt19937_64 rng(kSeed);
    for (std::size_t k = 0; k < kPostureCount; ++k) {
      out.q.push_back(redpost::test::random_posture(out.cell, rng));
      KDL::JntArray qk(static_cast<unsigned>(out.cell.size()));
      for (int i = 0; i < out.cell.size(); ++i) {
        qk(static_cast<unsigned>(i)) = out.q.back()[i];
      }
      out.q_kdl.push_back(qk);
    }
    out.chain = redpost::test::kdl_chain_from_cell(out.cell);
    return out;
  }();
  return w;
}

void BM_redpost_fk(benchmark::State& state) {
  const Workload& w = workload();
  redpost::KinematicsData data;
  std::size_t k = 0;
  {
    redpost::bench::AllocationScope allocations(state);
    for (auto _ : state) {
      redpost::forward_kinematics(w.cell, w.q[k++ & (kPostureCount - 1)], data);
      benchmark::DoNotOptimize(data.T_B_tcp);
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_redpost_fk);

void BM_redpost_fk_jacobian(benchmark::State& state) {
  const Workload& w = workload();
  redpost::KinematicsData data;
  redpost::Jacobian J;
  std::size_t k = 0;
  {
    redpost::bench::AllocationScope allocations(state);
    for (auto _ : state) {
      redpost::forward_kinematics(w.cell, w.q[k++ & (kPostureCount - 1)], data);
      redpost::tcp_jacobian(w.cell, data, J);
      benchmark::DoNotOptimize(data.T_B_tcp);
      benchmark::DoNotOptimize(J);
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_redpost_fk_jacobian);

// KDL's FK alone, for a like-for-like comparison with BM_redpost_fk.
void BM_kdl_fk(benchmark::State& state) {
  const Workload& w = workload();
  KDL::ChainFkSolverPos_recursive fk(w.chain);
  KDL::Frame F;
  std::size_t k = 0;
  {
    redpost::bench::AllocationScope allocations(state);
    for (auto _ : state) {
      fk.JntToCart(w.q_kdl[k++ & (kPostureCount - 1)], F);
      benchmark::DoNotOptimize(F);
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_kdl_fk);

void BM_kdl_fk_jacobian(benchmark::State& state) {
  const Workload& w = workload();
  KDL::ChainFkSolverPos_recursive fk(w.chain);
  KDL::ChainJntToJacSolver jac_solver(w.chain);
  KDL::Frame F;
  KDL::Jacobian J(w.chain.getNrOfJoints());
  std::size_t k = 0;
  {
    redpost::bench::AllocationScope allocations(state);
    for (auto _ : state) {
      const KDL::JntArray& q = w.q_kdl[k++ & (kPostureCount - 1)];
      fk.JntToCart(q, F);
      jac_solver.JntToJac(q, J);
      benchmark::DoNotOptimize(F);
      benchmark::DoNotOptimize(J.data);
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_kdl_fk_jacobian);

// Closed-form arm inverse kinematics (issue 8): all eight postures of one target of the Caro
// cell, each checked by a forward-kinematics round trip inside solve().
void BM_arm_ik(benchmark::State& state) {
  static const redpost::Cell cell = redpost::test::shipped_cell("caro2014_kr270_table");
  const redpost::ArmIk ik(cell);
  redpost::AxisValues axes = redpost::to_controller_axes(cell, cell.home());
  const double a_deg[6] = {20.0, -120.0, 140.0, 30.0, 40.0, -20.0};  // all 8 postures exist
  for (int n = 1; n <= 6; ++n)
    axes.arm(n) = a_deg[n - 1];
  const redpost::JointVector q = redpost::from_controller_axes(cell, axes, cell.home());
  const redpost::Isometry T = redpost::tcp_pose(cell, q);
  int found = 0;
  {
    redpost::bench::AllocationScope allocations(state);
    for (auto _ : state) {
      const redpost::ArmIkSolutions sol = ik.solve(T, q);
      found = static_cast<int>(std::count(sol.exists.begin(), sol.exists.end(), true));
      benchmark::DoNotOptimize(sol);
    }
  }
  state.counters["postures"] = found;
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_arm_ik);

// The same target with one posture asked (only_status), as the whole-path planner solves each
// lattice node: the other shoulder, elbow and wrist flip are skipped, and nothing is copied or
// checked for them.
void BM_arm_ik_one_posture(benchmark::State& state) {
  static const redpost::Cell cell = redpost::test::shipped_cell("caro2014_kr270_table");
  const redpost::ArmIk ik(cell);
  redpost::AxisValues axes = redpost::to_controller_axes(cell, cell.home());
  const double a_deg[6] = {20.0, -120.0, 140.0, 30.0, 40.0, -20.0};
  for (int n = 1; n <= 6; ++n)
    axes.arm(n) = a_deg[n - 1];
  const redpost::JointVector q = redpost::from_controller_axes(cell, axes, cell.home());
  const redpost::Isometry T = redpost::tcp_pose(cell, q);
  const int status = redpost::status_turn(cell, ik.status_model(), q).status;
  bool valid = false;
  {
    redpost::bench::AllocationScope allocations(state);
    for (auto _ : state) {
      const redpost::ArmIkSolutions sol = ik.solve(T, q, nullptr, status);
      valid = sol.valid[static_cast<std::size_t>(status)];
      benchmark::DoNotOptimize(sol);
    }
  }
  state.counters["valid"] = valid ? 1 : 0;
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_arm_ik_one_posture);

// The whole-path planner on one window (docs/redundancy.md): the 1500 mm pass along the track
// of the Andres cell at 10 000 mm/min, keyframes 20 mm apart (76 layers), planned from scratch
// (the first layer over every posture and the free joints' ranges) and from a committed
// posture (as every window after a program's first). Counters: lattice nodes solved (one
// closed-form IK posture each) per second of planning, everything in it included.
std::vector<redpost::PlanKeyframe> long_pass_keyframes() {
  std::vector<redpost::PlanKeyframe> kf;
  for (int k = 0; k <= 75; ++k) {
    redpost::PlanKeyframe f;
    f.target = redpost::TcpTarget::axis(Eigen::Vector3d(-100.0, -300.0 - 20.0 * k, 60.0),
                                        Eigen::Vector3d::UnitZ());
    f.s_mm = 20.0 * k;
    f.speed_mm_s = 10000.0 / 60.0;
    f.cl_line = 10 + k;
    kf.push_back(f);
  }
  return kf;
}

void BM_plan_window(benchmark::State& state) {
  static const redpost::Cell cell = redpost::test::shipped_cell("andres2011_kr15_track_table");
  const redpost::ArmIk ik(cell);
  const redpost::PathPlanner planner(cell, ik, redpost::plan_preset(redpost::PlanPreset::smooth));
  const std::vector<redpost::PlanKeyframe> kf = long_pass_keyframes();
  const bool fresh = state.range(0) == 0;
  const redpost::PlanWindowResult first = planner.plan(kf, nullptr);
  const redpost::JointVector start = first.q.front();
  long evaluations = 0;
  for (auto _ : state) {
    const redpost::PlanWindowResult r = planner.plan(kf, fresh ? nullptr : &start);
    evaluations += r.ik_evaluations;
    benchmark::DoNotOptimize(r);
  }
  state.counters["ik_per_s"] =
      benchmark::Counter(static_cast<double>(evaluations), benchmark::Counter::kIsRate);
  state.counters["ik_per_window"] =
      static_cast<double>(evaluations) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_plan_window)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  return redpost::bench::run_benchmarks(argc, argv);
}
