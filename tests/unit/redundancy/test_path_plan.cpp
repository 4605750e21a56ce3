// Whole-path planning (lattice_dp.hpp, path_plan.hpp): the layered dynamic programming finds the
// same minimum as a brute-force enumeration of every key sequence on small lattices, the beam
// only ever costs optimality, and the planner on the reference cell gives postures that reach
// every keyframe exactly, keep every axis within its speed at the feed, and follow a long pass
// with the track instead of swinging it.
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/arm_ik.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "redpost/machining/elastostatic.hpp"
#include "redpost/machining/quality.hpp"
#include "redpost/redundancy/lattice_dp.hpp"
#include "redpost/redundancy/path_plan.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

// A synthetic problem on a lattice of `dims` free joints with keys in [-R, R]^dims: seeded
// random node costs (some keys infeasible) and edge costs (some edges forbidden).
struct Toy {
  int dims = 1, R = 2, layers = 4, reach = 1, max_moving = kMaxFreeJoints;
  std::uint64_t seed = 1;

  static double hash01(std::uint64_t x) {
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdull;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ull;
    x ^= x >> 33;
    return static_cast<double>(x % 1000003) / 1000003.0;
  }
  std::uint64_t code(int layer, const LatticeKey& k) const {
    std::uint64_t c = seed * 1315423911ull + static_cast<std::uint64_t>(layer);
    for (int j = 0; j < dims; ++j)
      c = c * 131 + static_cast<std::uint64_t>(k.step[static_cast<std::size_t>(j)] + 50);
    return c;
  }
  bool inside(const LatticeKey& k) const {
    for (int j = 0; j < dims; ++j) {
      if (std::abs(k.step[static_cast<std::size_t>(j)]) > R)
        return false;
    }
    return true;
  }
  bool node(int layer, const LatticeKey& k, double& cost) const {
    if (!inside(k))
      return false;
    const double u = hash01(code(layer, k));
    if (u < 0.15)
      return false;  // infeasible here
    cost = 10.0 * u;
    return true;
  }
  double edge(int layer, const LatticeKey& a, const LatticeKey& b) const {
    const double u = hash01(code(layer, a) * 7919 + code(layer + 100, b));
    if (u < 0.1)
      return std::numeric_limits<double>::infinity();
    double d = 0.0;
    for (int j = 0; j < dims; ++j)
      d += std::abs(a.step[static_cast<std::size_t>(j)] - b.step[static_cast<std::size_t>(j)]);
    return 3.0 * u + d;
  }
  std::vector<LatticeKey> all_keys() const {
    std::vector<LatticeKey> out;
    LatticeKey k;
    std::function<void(int)> rec = [&](int j) {
      if (j == dims) {
        out.push_back(k);
        return;
      }
      for (int v = -R; v <= R; ++v) {
        k.step[static_cast<std::size_t>(j)] = v;
        rec(j + 1);
      }
    };
    rec(0);
    return out;
  }
  // The minimum over every sequence of keys, one per layer, each step within the reach.
  double brute_force() const {
    const std::vector<LatticeKey> keys = all_keys();
    double best = std::numeric_limits<double>::infinity();
    std::vector<LatticeKey> seq(static_cast<std::size_t>(layers));
    std::function<void(int, double)> rec = [&](int layer, double so_far) {
      if (layer == layers) {
        best = std::min(best, so_far);
        return;
      }
      for (const LatticeKey& k : keys) {
        double c = 0.0;
        if (!node(layer, k, c))
          continue;
        double e = 0.0;
        if (layer > 0) {
          const LatticeKey& p = seq[static_cast<std::size_t>(layer - 1)];
          bool near = true;
          int moving = 0;
          for (int j = 0; j < dims; ++j) {
            const int d =
                std::abs(p.step[static_cast<std::size_t>(j)] - k.step[static_cast<std::size_t>(j)]);
            near = near && d <= reach;
            moving += d != 0 ? 1 : 0;
          }
          if (!near || moving > max_moving)
            continue;
          e = edge(layer, p, k);
          if (!std::isfinite(e))
            continue;
        }
        seq[static_cast<std::size_t>(layer)] = k;
        rec(layer + 1, so_far + c + e);
      }
    };
    rec(0, 0.0);
    return best;
  }
  LatticeDpSettings settings(int beam) const {
    LatticeDpSettings s;
    s.free_joints = dims;
    s.reach = {reach, reach, reach};
    s.beam = beam;
    s.max_moving = max_moving;
    return s;
  }
  LatticeDpResult dp(int beam, WorkerPool* pool = nullptr) const {
    LatticeDpSettings s = settings(beam);
    s.pool = pool;
    return lattice_dp(
        layers, all_keys(), s,
        [&](int layer, const LatticeKey& k, JointVector& q, double& cost) {
          q.setZero(1);
          return node(layer, k, cost);
        },
        [&](int layer, const LatticeNode& a, const LatticeNode& b) {
          return edge(layer, a.key, b.key);
        });
  }
  // The node cost split in two: `lazy` of every node's cost left to refine (lattice_dp's lazy
  // term), which must not change the path that is found.
  LatticeDpResult dp_lazy(int beam, double lazy, long* refined = nullptr,
                          WorkerPool* pool = nullptr) const {
    LatticeDpSettings s = settings(beam);
    s.pool = pool;
    const LatticeDpResult r = lattice_dp(
        layers, all_keys(), s,
        [&](int layer, const LatticeKey& k, JointVector& q, double& cost) {
          q.setZero(1);
          const bool ok = node(layer, k, cost);
          cost *= 1.0 - lazy;
          return ok;
        },
        [&](int layer, const LatticeNode& a, const LatticeNode& b) {
          return edge(layer, a.key, b.key);
        },
        [&](int layer, const LatticeNode& n) {
          double cost = 0.0;
          node(layer, n.key, cost);
          return lazy * cost;
        });
    if (refined)
      *refined = r.refinements;
    return r;
  }
};

}  // namespace

TEST_CASE("lattice_dp: the exact minimum of a brute-force enumeration on small lattices",
          "[path_plan]") {
  int feasible = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    Toy t;
    t.seed = seed;
    t.dims = 1 + static_cast<int>(seed % 3);
    t.R = t.dims == 1 ? 3 : 1;
    t.layers = t.dims == 1 ? 6 : t.dims == 2 ? 4 : 3;
    // Three free joints, as the planner has them: two of them may move at once, or all three.
    t.max_moving = t.dims == 3 && seed % 2 == 0 ? 2 : kMaxFreeJoints;
    INFO("seed " << seed << ", " << t.dims << " free joints");
    const double brute = t.brute_force();
    const LatticeDpResult r = t.dp(0);
    REQUIRE(r.feasible == std::isfinite(brute));
    if (!r.feasible)
      continue;
    ++feasible;
    CHECK(r.cost == Approx(brute).epsilon(1e-12));
    // The path is consistent: its own costs add up to the total, steps within the reach.
    double sum = 0.0;
    for (int layer = 0; layer < t.layers; ++layer) {
      const LatticeKey& k = r.path[static_cast<std::size_t>(layer)].key;
      double c = 0.0;
      REQUIRE(t.node(layer, k, c));
      sum += c;
      if (layer > 0) {
        const LatticeKey& p = r.path[static_cast<std::size_t>(layer - 1)].key;
        int moving = 0;
        for (int j = 0; j < t.dims; ++j) {
          const int d =
              std::abs(p.step[static_cast<std::size_t>(j)] - k.step[static_cast<std::size_t>(j)]);
          CHECK(d <= t.reach);
          moving += d != 0 ? 1 : 0;
        }
        CHECK(moving <= t.max_moving);
        sum += t.edge(layer, p, k);
      }
    }
    CHECK(sum == Approx(r.cost).epsilon(1e-12));
    // A beam can only lose optimality, never find a cheaper path than the exact one.
    const LatticeDpResult b = t.dp(2);
    if (b.feasible)
      CHECK(b.cost >= r.cost - 1e-12);
  }
  CHECK(feasible >= 20);
}

TEST_CASE("lattice_dp: a lazy node cost keeps the path and the beam an eager one finds",
          "[path_plan]") {
  // The planner leaves the conditioning term to refine(), asked in the order of the other
  // costs: exact for the unbounded search, and the same beam (so the same path) with a beam.
  long evaluations = 0, refinements = 0;
  int compared = 0;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    Toy t;
    t.seed = seed;
    t.dims = 2;
    t.R = 3;
    t.layers = 6;
    INFO("seed " << seed);
    for (int beam : {0, 4, 12}) {
      const LatticeDpResult eager = t.dp(beam);
      long refined = 0;
      const LatticeDpResult lazy = t.dp_lazy(beam, 0.3, &refined);
      REQUIRE(eager.feasible == lazy.feasible);
      if (!eager.feasible)
        continue;
      ++compared;
      CHECK(lazy.cost == Approx(eager.cost).epsilon(1e-12));
      for (std::size_t k = 0; k < eager.path.size(); ++k)
        CHECK(lazy.path[k].key == eager.path[k].key);
      if (beam == 4) {
        evaluations += lazy.evaluations;
        refinements += refined;
      }
    }
  }
  CHECK(compared >= 40);
  // With a narrow beam most nodes are never refined.
  CHECK(refinements < evaluations / 2);
}

TEST_CASE("lattice_dp: a pool of threads finds the same path, bit for bit", "[path_plan]") {
  // Larger lattices than the brute force can take: hundreds of nodes per layer, so that every
  // thread takes its share of each layer.
  WorkerPool pool(4);
  REQUIRE(pool.threads() == 4);
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    Toy t;
    t.seed = seed;
    t.dims = 3;
    t.R = 4;
    t.layers = 12;
    t.max_moving = seed % 2 == 0 ? 2 : kMaxFreeJoints;
    INFO("seed " << seed);
    for (int beam : {0, 24}) {
      const LatticeDpResult serial = t.dp(beam), threaded = t.dp(beam, &pool);
      REQUIRE(threaded.feasible == serial.feasible);
      CHECK(threaded.evaluations == serial.evaluations);
      CHECK(threaded.dead_layer == serial.dead_layer);
      if (!serial.feasible)
        continue;
      CHECK(threaded.cost == serial.cost);  // the same sums in the same order: exactly equal
      for (int layer = 0; layer < t.layers; ++layer)
        CHECK(threaded.path[static_cast<std::size_t>(layer)].key.step ==
              serial.path[static_cast<std::size_t>(layer)].key.step);
      // With the lazy term: the pool refines each layer's first `beam` nodes beforehand; the
      // beam, the path and the count of refinements are the serial search's.
      long refined_serial = 0, refined_threaded = 0;
      const LatticeDpResult lazy_serial = t.dp_lazy(beam, 0.3, &refined_serial);
      const LatticeDpResult lazy_threaded = t.dp_lazy(beam, 0.3, &refined_threaded, &pool);
      REQUIRE(lazy_threaded.feasible == lazy_serial.feasible);
      CHECK(refined_threaded == refined_serial);
      if (!lazy_serial.feasible)
        continue;
      CHECK(lazy_threaded.cost == lazy_serial.cost);
      for (int layer = 0; layer < t.layers; ++layer)
        CHECK(lazy_threaded.path[static_cast<std::size_t>(layer)].key.step ==
              lazy_serial.path[static_cast<std::size_t>(layer)].key.step);
    }
  }
}

TEST_CASE("lattice_dp: a layer no key reaches is reported", "[path_plan]") {
  LatticeDpSettings s;
  s.free_joints = 1;
  const LatticeDpResult r = lattice_dp(
      5, {LatticeKey{}}, s,
      [](int layer, const LatticeKey& k, JointVector& q, double& cost) {
        q.setZero(1);
        cost = 0.0;
        return layer < 3 || k.step[0] > 5;  // from layer 3 on only keys out of reach
      },
      [](int, const LatticeNode&, const LatticeNode&) { return 0.0; });
  CHECK_FALSE(r.feasible);
  CHECK(r.dead_layer == 3);
}

namespace {

std::vector<PlanKeyframe> straight_pass(double from_y, double to_y, double spacing,
                                        double feed_mm_per_min) {
  std::vector<PlanKeyframe> kf;
  const int n = static_cast<int>(std::round(std::fabs(to_y - from_y) / spacing));
  for (int k = 0; k <= n; ++k) {
    PlanKeyframe f;
    const double y = from_y + (to_y - from_y) * k / n;
    f.target = TcpTarget::axis(Eigen::Vector3d(-100.0, y, 60.0), Eigen::Vector3d::UnitZ());
    f.s_mm = std::fabs(y - from_y);
    f.speed_mm_s = feed_mm_per_min / 60.0;
    f.cl_line = 10 + k;
    kf.push_back(f);
  }
  return kf;
}

}  // namespace

TEST_CASE("path_plan: a 1500 mm pass on the reference cell, planned from scratch", "[path_plan]") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const ArmIk ik(cell);
  const PathPlanSettings settings = plan_preset(PlanPreset::smooth);
  const PathPlanner planner(cell, ik, settings);
  REQUIRE(planner.free_joints().size() == 3);
  const std::vector<PlanKeyframe> kf = straight_pass(-300.0, -1800.0, 20.0, 10000.0);
  const PlanWindowResult r = planner.plan(kf, nullptr);
  REQUIRE(r.feasible);
  // The way found does not hang on the beam: a narrower and a far wider search find the same
  // cost within 0.1 % (a track lattice step of one keyframe spacing did not: a track left
  // behind could never catch up, and the beam decided whether it was).
  for (int beam : {12, 96}) {
    INFO("beam " << beam);
    const PlanWindowResult other = planner.plan(kf, nullptr, beam);
    REQUIRE(other.feasible);
    CHECK(other.cost == Approx(r.cost).epsilon(1e-3));
    CHECK(std::fabs(other.q.back()[1] - other.q.front()[1]) >= 1400.0);
  }
  REQUIRE(r.q.size() == kf.size());
  double track_travel = 0.0;
  for (std::size_t k = 0; k < kf.size(); ++k) {
    INFO("keyframe " << k);
    // Every planned posture reaches its keyframe (FK, independent of the IK).
    const Isometry T = tcp_pose(cell, r.q[k]);
    CHECK((T.translation() - kf[k].target.p_B_mm).norm() < 1e-6);
    CHECK((T.linear().col(2) - kf[k].target.z_B).norm() < 1e-9);
    for (int i = 0; i < cell.size(); ++i) {
      CHECK(r.q[k][i] >= cell.joint(i).lower);
      CHECK(r.q[k][i] <= cell.joint(i).upper);
    }
    if (k == 0)
      continue;
    track_travel += std::fabs(r.q[k][1] - r.q[k - 1][1]);
    // Within every axis's velocity limit at 10 000 mm/min between keyframes.
    const double dt = (kf[k].s_mm - kf[k - 1].s_mm) / kf[k].speed_mm_s;
    for (int i = 0; i < cell.size(); ++i) {
      if (cell.joint(i).has_speed())
        CHECK(std::fabs(r.q[k][i] - r.q[k - 1][i]) / dt <= cell.joint(i).max_velocity);
    }
  }
  // The track carries the pass (issue 17: at least 1400 mm of the 1500, at most 1650 mm of
  // travel in all), without going back and forth.
  const double track_net = std::fabs(r.q.back()[1] - r.q.front()[1]);
  CHECK(track_net >= 1400.0);
  CHECK(track_travel <= 1650.0);
  CHECK(track_travel <= 1.05 * track_net + 1e-9);
}

TEST_CASE("path_plan: a window continues from a committed posture and keeps its posture",
          "[path_plan]") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const ArmIk ik(cell);
  const PathPlanner planner(cell, ik, plan_preset(PlanPreset::smooth));
  const std::vector<PlanKeyframe> kf = straight_pass(-300.0, -700.0, 20.0, 3000.0);
  const PlanWindowResult first = planner.plan(kf, nullptr);
  REQUIRE(first.feasible);
  const JointVector start = first.q[10];
  std::vector<PlanKeyframe> rest(kf.begin() + 10, kf.end());
  const PlanWindowResult next = planner.plan(rest, &start);
  REQUIRE(next.feasible);
  const StatusTurn st = status_turn(cell, ik.status_model(), start);
  for (const JointVector& q : next.q)
    CHECK(status_turn(cell, ik.status_model(), q).status == st.status);
  // Its first posture is the committed one's free joints, the arm solved for them.
  for (int f : planner.free_joints())
    CHECK(next.q.front()[f] == Approx(start[f]).margin(1e-12));
}

TEST_CASE("path_plan: a free joint without <speed> is refused naming the cell's line",
          "[path_plan]") {
  Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  cell.joints[1].max_velocity = 0.0;
  const ArmIk ik(cell);
  try {
    const PathPlanner planner(cell, ik, plan_preset(PlanPreset::smooth));
    FAIL("accepted a track without a speed");
  } catch (const Error& e) {
    CHECK(e.where().line == cell.joint(1).source_line);
    CHECK(std::string(e.what()).find("has no <speed>") != std::string::npos);
  }
}

TEST_CASE("path_plan: with stiffness data the plan lowers Caro's normal deflection",
          "[path_plan]") {
  // Caro 2014's KR270-2 (its spindle tilted on the flange, so the tool spin moves the whole
  // arm), a 300 mm pass along y through the home TCP, the tool tilted 30 deg towards -x. Under a
  // nominal 100 N load normal to the feed and the tool axis, the deflection c of Caro's eq. 5.1
  // is measured again here with the elastostatic model on the planned joints: the compliance
  // term (the stiff preset) must lower it against a plan without the term, and come within 20 %
  // of the best any tool spin gives in the same posture (a brute force over the spin, 2 deg
  // apart).
  const Cell cell = test::shipped_cell("caro2014_kr270_table");
  const ArmIk ik(cell);
  const Eigen::Vector3d p0 = tcp_pose(cell, cell.home()).translation();
  const Eigen::Vector3d feed = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d z = Eigen::Vector3d(-0.5, 0.0, std::sqrt(0.75));
  std::vector<PlanKeyframe> kf;
  for (int k = 0; k <= 15; ++k) {
    PlanKeyframe f;
    f.target = TcpTarget::axis(p0 + (20.0 * k - 150.0) * feed, z);
    f.s_mm = 20.0 * k;
    f.speed_mm_s = 4000.0 / 60.0;
    f.cl_line = 10 + k;
    kf.push_back(f);
  }
  const auto deflection = [&cell](const JointVector& q, const Eigen::Vector3d& x_feed,
                                  const Eigen::Vector3d& z_tool) {
    Vector6d w = Vector6d::Zero();
    w.tail<3>() = 100.0 * z_tool.cross(x_feed).normalized();
    return normal_tool_deflection_mm(tcp_displacement(cell, q, w).tail<3>(), z_tool, x_feed);
  };
  const auto mean_deflection = [&](const PlanWindowResult& r) {
    double sum = 0.0;
    for (const JointVector& q : r.q)
      sum += deflection(q, feed, z);
    return sum / static_cast<double>(r.q.size());
  };
  PathPlanSettings plain = plan_preset(PlanPreset::smooth);
  plain.w_compliance = 0.0;
  PathPlanSettings stiff = plan_preset(PlanPreset::stiff);
  stiff.normal_deflection_mm = deflection;
  const PlanWindowResult a = PathPlanner(cell, ik, plain).plan(kf, nullptr);
  const PlanWindowResult b = PathPlanner(cell, ik, stiff).plan(kf, nullptr);
  REQUIRE(a.feasible);
  REQUIRE(b.feasible);
  // The best mean c over every tool spin in the stiff plan's posture, keyframe by keyframe.
  const int mu = status_turn(cell, ik.status_model(), b.q[0]).status;
  double best = 0.0;
  for (std::size_t k = 0; k < kf.size(); ++k) {
    double lowest = std::numeric_limits<double>::infinity();
    for (int deg = -180; deg <= 180; deg += 2) {
      JointVector q_other = b.q[k];
      q_other[6] = deg_to_rad(deg);
      Isometry T = Isometry::Identity();
      const Eigen::Vector3d x = (Eigen::Vector3d::UnitX() - z.x() * z).normalized();
      T.linear() << x, z.cross(x), z;
      T.translation() = kf[k].target.p_B_mm;
      const ArmIkSolutions sol = ik.solve(T, q_other, nullptr, mu);
      if (sol.valid[static_cast<std::size_t>(mu)])
        lowest = std::min(lowest, deflection(sol.q[static_cast<std::size_t>(mu)], feed, z));
    }
    best += lowest / static_cast<double>(kf.size());
  }
  const double c_plain = mean_deflection(a), c_stiff = mean_deflection(b);
  INFO("mean normal deflection under 100 N: " << c_plain << " mm without the term, " << c_stiff
                                              << " mm with it, best spin " << best << " mm");
  // (Measured 2026-12-02: 0.109 mm without, 0.076 mm with, 0.066 mm the best spin; the plan
  // still weighs the centring and the conditioning.)
  CHECK(c_stiff < 0.8 * c_plain);
  CHECK(c_stiff < 1.2 * best);
  for (std::size_t k = 0; k < kf.size(); ++k) {
    const Isometry T = tcp_pose(cell, b.q[k]);
    CHECK((T.translation() - kf[k].target.p_B_mm).norm() < 1e-6);
    CHECK((T.linear().col(2) - z).norm() < 1e-9);
  }
}

TEST_CASE(
    "lattice_dp: the heading of a node is the last step of its way in, and a reversal cost "
    "is charged on it as an enumeration of the ways charges it",
    "[path_plan]") {
  // One free joint, a reversal (a step against the last nonzero step) costs `turn`. The DP picks
  // each node's way in by cost to come, so it is a beam search over paths with their last
  // direction; on these small lattices it must still match the enumeration within the cost of
  // one reversal, and every node's heading must be that of its own way in.
  const double turn = 0.7;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    Toy t;
    t.seed = seed;
    t.dims = 1;
    t.R = 3;
    t.layers = 7;
    INFO("seed " << seed);
    const auto reversal = [&](std::int8_t heading, int d) {
      return d != 0 && heading == (d > 0 ? -1 : 1) ? turn : 0.0;
    };
    const LatticeDpResult r = lattice_dp(
        t.layers, t.all_keys(), t.settings(0),
        [&](int layer, const LatticeKey& k, JointVector& q, double& cost) {
          q.setZero(1);
          return t.node(layer, k, cost);
        },
        [&](int layer, const LatticeNode& a, const LatticeNode& b) {
          return t.edge(layer, a.key, b.key) +
                 reversal(a.heading[0], b.key.step[0] - a.key.step[0]);
        });
    // The enumeration of every way, with its reversals.
    double best = std::numeric_limits<double>::infinity();
    std::vector<int> seq(static_cast<std::size_t>(t.layers));
    std::function<void(int, double, std::int8_t)> rec = [&](int layer, double so_far,
                                                            std::int8_t heading) {
      if (layer == t.layers) {
        best = std::min(best, so_far);
        return;
      }
      for (int v = -t.R; v <= t.R; ++v) {
        LatticeKey k;
        k.step[0] = v;
        double c = 0.0;
        if (!t.node(layer, k, c))
          continue;
        double e = 0.0;
        std::int8_t h = heading;
        if (layer > 0) {
          LatticeKey p;
          p.step[0] = seq[static_cast<std::size_t>(layer - 1)];
          const int d = v - p.step[0];
          if (std::abs(d) > t.reach)
            continue;
          e = t.edge(layer, p, k);
          if (!std::isfinite(e))
            continue;
          e += reversal(heading, d);
          h = d > 0 ? 1 : d < 0 ? -1 : heading;
        }
        seq[static_cast<std::size_t>(layer)] = v;
        rec(layer + 1, so_far + c + e, h);
      }
    };
    rec(0, 0.0, 0);
    REQUIRE(r.feasible == std::isfinite(best));
    if (!r.feasible)
      continue;
    CHECK(r.cost >= best - 1e-12);
    CHECK(r.cost <= best + turn + 1e-12);
    // The path's headings and its cost, recomputed along it.
    std::int8_t h = 0;
    double sum = 0.0;
    for (int layer = 0; layer < t.layers; ++layer) {
      const LatticeNode& n = r.path[static_cast<std::size_t>(layer)];
      double c = 0.0;
      REQUIRE(t.node(layer, n.key, c));
      sum += c;
      if (layer > 0) {
        const LatticeNode& p = r.path[static_cast<std::size_t>(layer - 1)];
        const int d = n.key.step[0] - p.key.step[0];
        sum += t.edge(layer, p.key, n.key) + reversal(h, d);
        h = d > 0 ? 1 : d < 0 ? -1 : h;
      }
      CHECK(n.heading[0] == h);
    }
    CHECK(sum == Approx(r.cost).epsilon(1e-12));
  }
}

TEST_CASE("path_plan: update_heading keeps each joint's last change", "[path_plan]") {
  JointHeading h{};
  std::vector<JointVector> q(4, JointVector::Zero(3));
  q[1] << 1.0, 0.0, -1.0;
  q[2] << 1.0, 0.0, -2.0;
  q[3] << 0.5, 0.0, -2.0;
  update_heading(q, h);
  CHECK(h[0] == -1);  // up, then down
  CHECK(h[1] == 0);   // never moved
  CHECK(h[2] == -1);  // down, then held
  std::vector<JointVector> later(2, JointVector::Zero(3));
  later[1] << 0.0, 1e-12, 0.0;  // below the tolerance: no change
  update_heading(later, h);
  CHECK(h[1] == 0);
}
