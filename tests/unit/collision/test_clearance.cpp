// The clearance check between poses (collision/clearance.hpp) against dense brute-force
// sampling of the same motions: the least clearance it reports is a lower bound of every
// sampled distance, and a motion that comes closer than the margin anywhere is never called
// clear. Mutation-checked: with the motion bound halved (steps twice too long), the same
// sampling must find a reported clearance that is too high.
#include <iostream>
#include <random>

#include "catch_compat.hpp"
#include "collision_support.hpp"
#include "redpost/collision/clearance.hpp"
#include "redpost/kinematics/arm_ik.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

struct Trial {
  std::unique_ptr<JointPath> path;
  JointVector q0;
};

// Obstacles on {B} around the arm's reach: spheres and boxes.
std::vector<Body> obstacles(std::mt19937_64& rng, const Eigen::Vector3d& around, int count) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Body> out;
  for (int k = 0; k < count; ++k) {
    Shape s;
    s.kind = k % 2 ? ShapeKind::box : ShapeKind::sphere;
    s.radius_mm = 60.0 + 40.0 * u(rng);
    s.size_mm = Eigen::Vector3d(150, 100, 80) + 50.0 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    s.T_frame_shape.translation() = around + 700.0 * Eigen::Vector3d(u(rng), u(rng), 0.6 * u(rng));
    Body b;
    b.name = "obstacle " + std::to_string(k);
    b.role = BodyRole::fixture;
    b.frame = kFrameBase;
    b.shapes.push_back(s);
    out.push_back(b);
  }
  return out;
}

// The least distance over every pair along the path, sampled densely (exact distances).
double sampled_least(const CollisionScene& scene, const JointPath& path, int samples) {
  const Cell& cell = scene.cell();
  ScenePoses poses;
  scene.prepare(poses);
  KinematicsData data;
  double least = 1e300;
  JointVector q;
  for (int k = 0; k <= samples; ++k) {
    if (!path.at(static_cast<double>(k) / samples, q))
      return std::numeric_limits<double>::quiet_NaN();
    for (int i = 0; i < cell.size(); ++i) {
      if (cell.joint(i).type == JointType::virtual_spin)
        q[i] = 0.0;
    }
    forward_kinematics(cell, q, data);
    scene.place(data, poses);
    for (std::size_t p = 0; p < scene.pairs().size(); ++p)
      least = std::min(least, scene.distance(static_cast<int>(p), poses, 1e300));
  }
  return least;
}

struct Outcome {
  int motions = 0, too_high = 0, missed = 0, close = 0;
};

Outcome run(double bound_scale, int seed) {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const ArmIk ik(cell);
  std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Outcome out;
  const int track = cell.find_joint("d_L");
  for (int scene_no = 0; scene_no < 6; ++scene_no) {
    std::vector<Body> bodies = test::skeleton_bodies(cell, 70.0);
    const JointVector home = cell.home();
    const Eigen::Vector3d around = tcp_pose(cell, home).translation();
    // The arm against the obstacles: the skeleton's links overlap where they meet, so its own
    // pairs are allowed.
    const std::vector<std::pair<int, int>> allowed =
        test::all_pairs(static_cast<int>(bodies.size()));
    for (Body& b : obstacles(rng, around, 8))
      bodies.push_back(b);
    CollisionScene scene(cell, bodies, allowed);
    ClearanceSettings settings;
    settings.margin_mm = 5.0;
    settings.bound_scale = bound_scale;
    ClearanceMonitor monitor(scene, settings);
    for (int m = 0; m < 14; ++m) {
      JointVector q0 = home, q1;
      for (int i = 0; i < cell.size(); ++i)
        q0[i] += 0.15 * u(rng) * (cell.joint(i).type == JointType::prismatic ? 1000.0 : 1.0);
      std::unique_ptr<JointPath> path;
      if (m % 3 == 0) {
        // The track alone: a body moving straight at an obstacle, where the bound is tight.
        q1 = q0;
        q1[track] += 400.0 * u(rng);
        path = std::make_unique<JointLinePath>(q0, q1);
      } else if (m % 3 == 1) {
        q1 = q0;
        for (int i = 0; i < cell.size(); ++i)
          q1[i] += 0.3 * u(rng) * (cell.joint(i).type == JointType::prismatic ? 1000.0 : 1.0);
        path = std::make_unique<JointLinePath>(q0, q1);
      } else {
        // A LIN: the TCP moved along a line, the arm solved in its posture.
        const int status = status_turn(cell, ik.status_model(), q0).status;
        Isometry T = tcp_pose(cell, q0);
        T.translation() += 150.0 * Eigen::Vector3d(u(rng), u(rng), u(rng));
        JointVector other = q0;
        other[track] += 100.0 * u(rng);
        const ArmIkSolutions sol = ik.solve(T, other, &q0, status);
        if (!sol.valid[static_cast<std::size_t>(status)])
          continue;
        q1 = sol.q[static_cast<std::size_t>(status)];
        path = std::make_unique<CartesianPath>(ik, cell, q0, q1);
      }
      if (!within_limits(cell, q0) || !within_limits(cell, q1))
        continue;
      const double sampled = sampled_least(scene, *path, 400);
      if (std::isnan(sampled))
        continue;
      JointVector start;
      path->at(0.0, start);
      const MotionClearance first = monitor.start(start);
      const MotionClearance along = monitor.advance(*path);
      const double reported = std::min(first.least_mm, along.least_mm);
      const bool clear = first.clear && along.clear;
      ++out.motions;
      out.close += sampled < 50.0;
      // Called clear: the least reported is a lower bound of every sampled distance (up to
      // FCL's tolerance). Not clear: a distance below the margin was found (or not proven).
      out.too_high += clear ? reported > sampled + 1e-6 : !(reported < settings.margin_mm);
      out.missed += sampled < settings.margin_mm && along.clear && first.clear;
    }
  }
  return out;
}

}  // namespace

TEST_CASE("the clearance between poses never misses what dense sampling finds", "[collision]") {
  const Outcome o = run(1.0, 46);
  INFO("motions " << o.motions << ", close " << o.close);
  CHECK(o.motions > 40);
  CHECK(o.close > 10);  // the scenes bring bodies near each other
  CHECK(o.too_high == 0);
  CHECK(o.missed == 0);
}

TEST_CASE("mutation: a bound that takes steps twice too long is caught", "[collision]") {
  const Outcome o = run(0.5, 46);
  INFO("motions " << o.motions << ", too high " << o.too_high << ", missed " << o.missed);
  CHECK(o.too_high + o.missed > 0);
}

TEST_CASE("a LIN whose A6 bends past its limit between ends within it is not followed",
          "[collision]") {
  // Both ends hold A6 at one value; the orientation slerped between them bends A6 off it. With
  // the limit put between the two, the solver could still take A6's other turn (360 deg away,
  // within the limits) at the middle: the controller's continuous A6 cannot, and stops there.
  Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const int a1 = cell.find_joint("theta_1"), a6 = cell.find_joint("theta_6");
  JointVector q0 = cell.home();
  q0[a6] = from_axis_value(cell.joint(a6), 100.0);
  JointVector q1 = q0;
  q1[a1] += deg_to_rad(20.0);
  q1[cell.find_joint("theta_5")] += deg_to_rad(15.0);
  double bend = 0.0;
  {
    const ArmIk ik(cell);
    const CartesianPath wide(ik, cell, q0, q1);
    JointVector qm;
    REQUIRE(wide.at(0.5, qm));
    bend = qm[a6] - q0[a6];
  }
  REQUIRE(std::abs(bend) > 1e-4);
  // The limit on the bend's side halfway to it; the other side far enough for A6's other turn
  // at the middle, which a solver free to pick the turn within the limits would take.
  Joint& j = cell.joints[static_cast<std::size_t>(a6)];
  const double middle = q0[a6] + bend;
  if (bend > 0.0) {
    j.upper = q0[a6] + 0.5 * bend;
    j.lower = std::min(j.lower, middle - 2.0 * kPi - 0.1);
  } else {
    j.lower = q0[a6] + 0.5 * bend;
    j.upper = std::max(j.upper, middle + 2.0 * kPi + 0.1);
  }
  const ArmIk ik(cell);
  const CartesianPath path(ik, cell, q0, q1);
  JointVector q;
  CHECK(path.at(0.0, q));
  CHECK(path.at(1.0, q));
  CHECK_FALSE(path.at(0.5, q));
  // The monitor calls it lost, not clear.
  const std::vector<Body> bodies = test::skeleton_bodies(cell, 10.0);
  const std::vector<std::pair<int, int>> allowed = test::all_pairs(static_cast<int>(bodies.size()));
  CollisionScene scene(cell, bodies, allowed);
  ClearanceMonitor monitor(scene, ClearanceSettings{});
  monitor.start(q0);
  const MotionClearance c = monitor.advance(path);
  CHECK_FALSE(c.clear);
  CHECK(c.path_lost);
}

TEST_CASE("a bound that never closes ends in bounded work, unproven and not clear", "[collision]") {
  // With the bound scaled past any distance no piece is ever proven: the halving alone would
  // take 2^max_depth pieces (what a tool of 1e300 mm did through the C ABI). The pieces budget
  // ends it, and the motion is called unproven, never clear.
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  std::vector<Body> bodies = test::skeleton_bodies(cell, 70.0);
  const std::vector<std::pair<int, int>> allowed = test::all_pairs(static_cast<int>(bodies.size()));
  // A box 300 mm beside the tool: near enough that its pairs are open, far from touching.
  const JointVector q0 = cell.home();
  Shape box;
  box.kind = ShapeKind::box;
  box.size_mm = Eigen::Vector3d(100, 100, 100);
  box.T_frame_shape.translation() =
      tcp_pose(cell, q0).translation() + Eigen::Vector3d(0.0, 300.0, 0.0);
  Body obstacle;
  obstacle.name = "box";
  obstacle.role = BodyRole::fixture;
  obstacle.frame = kFrameBase;
  obstacle.shapes.push_back(box);
  bodies.push_back(obstacle);
  const CollisionScene scene(cell, bodies, allowed);
  REQUIRE(!scene.pairs().empty());
  JointVector q1 = q0;
  q1[cell.find_joint("d_L")] += 200.0;
  const JointLinePath path(q0, q1);
  for (const int pieces : {64, 4096}) {
    ClearanceSettings settings;
    settings.bound_scale = 1e12;
    settings.max_pieces = pieces;
    ClearanceMonitor monitor(scene, settings);
    REQUIRE(monitor.start(q0).clear);
    const MotionClearance c = monitor.advance(path);
    INFO("pieces " << pieces << ", queries " << c.distance_queries << ", pairs "
                   << scene.pairs().size());
    CHECK_FALSE(c.clear);
    CHECK(c.unproven);
    // The end once, then at most one distance per pair and piece.
    CHECK(c.distance_queries <=
          static_cast<long>(scene.pairs().size()) * (static_cast<long>(pieces) + 1));
    CHECK(c.distance_queries > pieces);  // it did halve up to the budget
    CHECK_FALSE(c.where.exact);          // no contact found: the messages say "cannot be proven"
  }
  // A blended corner's share of the bound does not shrink with halving: no room left is
  // unproven as well, not a contact.
  JointLinePath blended(q0, q1);
  blended.blend_fraction = 0.5;
  ClearanceSettings settings;
  settings.bound_scale = 1e12;
  ClearanceMonitor monitor(scene, settings);
  REQUIRE(monitor.start(q0).clear);
  const MotionClearance c = monitor.advance(blended);
  CHECK_FALSE(c.clear);
  CHECK(c.unproven);
  CHECK_FALSE(c.where.exact);
}

namespace {

// The Andres cell's table top (a cylinder about the table's axis, on {B}, as the shipped cell
// draws it) with its centre moved off the axis by `off_axis_mm`, and spheres on the floor (the
// frame after the table joint, which turns about that axis in {B}) at `gap` from the round
// table's rim, around it at the table top's height.
std::vector<Body> table_and_floor_spheres(const Cell& cell, double off_axis_mm,
                                          std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Shape top;
  top.kind = ShapeKind::cylinder;
  top.radius_mm = 450.0;
  top.length_mm = 150.0;
  top.T_frame_shape.translation() = Eigen::Vector3d(off_axis_mm, 0.0, -325.0);
  Body table;
  table.name = "table";
  table.frame = kFrameBase;
  table.shapes.push_back(top);
  std::vector<Body> out{table};
  // In the floor's frame (Rz(theta) Tz(-305) Tx(803) Rx(90) from {B}) the table's axis is the
  // line x = -803, z = 0 along y, and the table top spans y -95 .. 55.
  const int floor = cell.find_joint("theta_M");
  for (int k = 0; k < 6; ++k) {
    Shape s;
    s.kind = ShapeKind::sphere;
    s.radius_mm = 30.0;
    const double gap_mm = 6.0 + 40.0 * u(rng), azimuth = 2.0 * kPi * u(rng);
    const double rho = 450.0 + s.radius_mm + gap_mm;
    s.T_frame_shape.translation() = Eigen::Vector3d(
        -803.0 + rho * std::cos(azimuth), -95.0 + 150.0 * u(rng), rho * std::sin(azimuth));
    Body b;
    b.name = "floor sphere " + std::to_string(k);
    b.frame = floor;
    b.shapes.push_back(s);
    out.push_back(b);
  }
  return out;
}

}  // namespace

// A round table turning under a body on the floor keeps every distance: the check proves such
// a motion from its ends (the turn is no motion of the pair), where a bound on the floor's
// sweep (3.4 m of track at 1 rad) could never close. Against dense sampling, and against the
// same table 15 mm off its axis, where the turn does move the pair and must be bounded.
TEST_CASE("a table round about its own axis: its turn moves nothing against the floor",
          "[collision]") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const int table = cell.find_joint("theta_M"), track = cell.find_joint("d_L");
  std::mt19937_64 rng(48);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const double off_axis_mm : {0.0, 15.0}) {
    INFO("table off its axis by " << off_axis_mm << " mm");
    int motions = 0, proven_from_ends = 0, too_high = 0, missed = 0;
    for (int scene_no = 0; scene_no < 5; ++scene_no) {
      const CollisionScene scene(cell, table_and_floor_spheres(cell, off_axis_mm, rng), {});
      REQUIRE(scene.pairs().size() == 6);
      ClearanceSettings settings;
      settings.margin_mm = 5.0;
      ClearanceMonitor monitor(scene, settings);
      for (int m = 0; m < 6; ++m) {
        JointVector q0 = cell.home(), q1;
        q0[table] = 3.0 * u(rng);
        q1 = q0;
        q1[table] += 3.0 * u(rng);  // up to 170 deg of the table in one motion
        q1[track] += 300.0 * u(rng);
        const JointLinePath path(q0, q1);
        const double sampled = sampled_least(scene, path, 600);
        const MotionClearance first = monitor.start(q0);
        const MotionClearance along = monitor.advance(path);
        const double reported = std::min(first.least_mm, along.least_mm);
        const bool clear = first.clear && along.clear;
        ++motions;
        // Sound either way: a clear motion's least is a lower bound of every sampled distance;
        // one below the margin is never called clear.
        too_high += clear && reported > sampled + 1e-6;
        missed += sampled < settings.margin_mm && clear;
        // Round: the ends' distances prove it, once per pair, with the least exactly there.
        proven_from_ends +=
            clear && along.distance_queries <= 6 && std::abs(reported - sampled) < 1e-6;
      }
    }
    CHECK(too_high == 0);
    CHECK(missed == 0);
    if (off_axis_mm == 0.0) {
      CHECK(proven_from_ends == motions);
    } else {
      CHECK(proven_from_ends == 0);  // the shortcut is not taken for a table off its axis
    }
  }
}
