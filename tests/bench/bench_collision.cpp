// The collision check's per-query costs (docs/performance.md, "Collisions"): one distance between
// the shipped Andres cell's bodies and a set-up's (a primitive pair, a convex fixture, a triangle
// mesh of the part) at random postures, the posture check of the plan's node filter, the motion
// bound, and a written motion checked by the monitor (a 0.5 mm LIN of a raster, far from and
// near a fixture), with the heap allocations per call.
//
// Run: build/tests/bench/redpost_bench_collision --benchmark_repetitions=5
//        --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "allocation_counter.hpp"
#include "redpost/collision/cell_bodies.hpp"
#include "redpost/collision/clearance.hpp"
#include "redpost/collision/tool_bodies.hpp"
#include "redpost/kinematics/arm_ik.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "test_support.hpp"

namespace {

using namespace redpost;

constexpr std::size_t kPostures = 256;

// A closed box as a mesh; `dents` > 0 pushes a corner in, so that it is not convex (a triangle
// hierarchy in FCL) and subdivides each face into 2 * dents^2 triangles.
std::shared_ptr<TriangleMesh> box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                       int grid) {
  auto m = std::make_shared<TriangleMesh>();
  // Each face as a grid of grid x grid quads.
  const auto face = [&](int axis, bool top) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const int base = static_cast<int>(m->vertices.size());
    for (int i = 0; i <= grid; ++i) {
      for (int j = 0; j <= grid; ++j) {
        Eigen::Vector3d p;
        p[axis] = top ? hi[axis] : lo[axis];
        p[u] = lo[u] + (hi[u] - lo[u]) * i / grid;
        p[v] = lo[v] + (hi[v] - lo[v]) * j / grid;
        m->vertices.push_back(p);
      }
    }
    for (int i = 0; i < grid; ++i) {
      for (int j = 0; j < grid; ++j) {
        const int a = base + i * (grid + 1) + j, b = a + 1, c = a + grid + 1, d = c + 1;
        m->triangles.push_back({a, c, d});
        m->triangles.push_back({a, d, b});
      }
    }
  };
  for (int axis = 0; axis < 3; ++axis) {
    face(axis, false);
    face(axis, true);
  }
  return m;
}

Body mesh_body(const std::string& name, BodyRole role, std::shared_ptr<TriangleMesh> mesh) {
  Shape s;
  s.kind = ShapeKind::mesh;
  s.mesh = std::move(mesh);
  Body b;
  b.name = name;
  b.role = role;
  b.frame = kFrameBase;
  b.shapes.push_back(s);
  return b;
}

struct Workload {
  Cell cell;
  std::unique_ptr<CollisionScene> scene;
  std::vector<JointVector> q;
  int pair_primitive = -1, pair_convex = -1, pair_mesh = -1;
};

// The Andres cell's bodies, a 10 mm tool, a clamp (a convex box) and a part (a grid mesh of
// 2 400 triangles, seen as a triangle hierarchy since its faces are split), near the TCP.
const Workload& workload() {
  static const Workload w = [] {
    Workload out;
    out.cell = cell_for_tool(test::shipped_cell("andres2011_kr15_track_table"), 119.7);
    const CellBodies cb = load_cell_bodies(out.cell);
    std::vector<Body> bodies = cb.bodies;
    const Eigen::Vector3d tcp = tcp_pose(out.cell, out.cell.home()).translation();
    bodies.push_back(mesh_body("fixture clamp", BodyRole::fixture,
                               box_mesh(tcp + Eigen::Vector3d(-250, -120, -150),
                                        tcp + Eigen::Vector3d(-220, 120, 60), 1)));
    bodies.push_back(mesh_body("part", BodyRole::part,
                               box_mesh(tcp + Eigen::Vector3d(-200, -200, -200),
                                        tcp + Eigen::Vector3d(200, 200, -5), 20)));
    ToolGeometry t;
    t.length_mm = 119.7;
    t.diameter_mm = 10.0;
    t.flute_length_mm = 30.0;
    t.holder_diameter_mm = 40.0;
    t.holder_length_mm = 40.0;
    for (Body& b : tool_bodies(t))
      bodies.push_back(b);
    out.scene = std::make_unique<CollisionScene>(out.cell, bodies, cb.allowed);
    for (std::size_t p = 0; p < out.scene->pairs().size(); ++p) {
      const std::string n = out.scene->pair_name(static_cast<int>(p));
      if (n == "arm_link_2 vs spindle")
        out.pair_primitive = static_cast<int>(p);
      if (n == "spindle vs fixture clamp")
        out.pair_convex = static_cast<int>(p);
      if (n == "part vs tool 1 holder" || n == "part vs the tool holder")
        out.pair_mesh = static_cast<int>(p);
    }
    std::mt19937_64 rng(46);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (std::size_t k = 0; k < kPostures; ++k) {
      JointVector q = out.cell.home();
      for (int i = 0; i < out.cell.size(); ++i)
        q[i] += 0.15 * u(rng) * (out.cell.joint(i).type == JointType::prismatic ? 300.0 : 1.0);
      out.q.push_back(q);
    }
    return out;
  }();
  return w;
}

// One exact distance of a pair at a random posture (the poses placed beforehand).
void pair_distance(benchmark::State& state, int pair) {
  const Workload& w = workload();
  if (pair < 0) {
    state.SkipWithError("pair not found");
    return;
  }
  std::vector<ScenePoses> poses(kPostures);
  KinematicsData data;
  for (std::size_t k = 0; k < kPostures; ++k) {
    w.scene->prepare(poses[k]);
    forward_kinematics(w.cell, w.q[k], data);
    w.scene->place(data, poses[k]);
  }
  std::size_t k = 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(w.scene->distance(pair, poses[k++ % kPostures], 1e9));
  state.SetItemsProcessed(state.iterations());
}
void BM_distance_primitives(benchmark::State& s) {
  pair_distance(s, workload().pair_primitive);
}
void BM_distance_convex_fixture(benchmark::State& s) {
  pair_distance(s, workload().pair_convex);
}
void BM_distance_mesh_part(benchmark::State& s) {
  pair_distance(s, workload().pair_mesh);
}
BENCHMARK(BM_distance_primitives);
BENCHMARK(BM_distance_convex_fixture);
BENCHMARK(BM_distance_mesh_part);

// The plan's node filter: every pair at one posture, exact within the margin and the plan's
// 10 mm.
void BM_posture_clearance(benchmark::State& state) {
  const Workload& w = workload();
  ScenePoses poses;
  KinematicsData data;
  w.scene->prepare(poses);
  std::size_t k = 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(posture_clearance(*w.scene, w.q[k++ % kPostures], 15.0, poses, data));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_posture_clearance);

void BM_motion_bounds(benchmark::State& state) {
  const Workload& w = workload();
  ScenePoses poses;
  KinematicsData data;
  w.scene->prepare(poses);
  forward_kinematics(w.cell, w.q[0], data);
  w.scene->place(data, poses);
  std::vector<double> from;
  const JointVector dq = (w.q[1] - w.q[0]).cwiseAbs() * 0.01;
  {
    bench::AllocationScope allocations(state);
    for (auto _ : state) {
      w.scene->motion_bounds(data, poses, dq, from);
      benchmark::DoNotOptimize(from.data());
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_motion_bounds);

// A raster's written motion: a 0.5 mm LIN (the TCP along x, the arm solved), checked by the
// monitor as convert checks it, one after the other.
void BM_monitor_lin(benchmark::State& state) {
  const Workload& w = workload();
  const ArmIk ik(w.cell);
  ClearanceMonitor monitor(*w.scene, ClearanceSettings{});
  const JointVector home = w.cell.home();
  const int status = status_turn(w.cell, ik.status_model(), home).status;
  Isometry T = tcp_pose(w.cell, home);
  // 2000 postures along 1 m of x, back and forth.
  std::vector<JointVector> q;
  JointVector near = home;
  for (int k = 0; k < 2000; ++k) {
    Isometry Tk = T;
    Tk.translation().x() += 0.5 * (k < 1000 ? k : 2000 - k) - 250.0;
    const ArmIkSolutions sol = ik.solve(Tk, near, &near, status);
    near = sol.q[static_cast<std::size_t>(status)];
    q.push_back(near);
  }
  monitor.start(q[0]);
  std::size_t k = 0;
  for (auto _ : state) {
    const std::size_t a = k % 2000, b = (k + 1) % 2000;
    if (b == 0) {
      monitor.start(q[0]);
      ++k;
      continue;
    }
    benchmark::DoNotOptimize(monitor.advance(CartesianPath(ik, w.cell, q[a], q[b])).least_mm);
    ++k;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["distances/motion"] = benchmark::Counter(
      static_cast<double>(monitor.distance_queries()), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_monitor_lin);

}  // namespace

BENCHMARK_MAIN();
