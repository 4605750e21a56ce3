// Distances between bodies (collision/scene.hpp) against closed forms and brute force, the
// pairs a scene checks, and the motion bound against sampled motions.
#include <random>

#include "catch_compat.hpp"
#include "collision_support.hpp"
#include "redpost/collision/scene.hpp"
#include "redpost/collision/tool_bodies.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

// A one-joint cell whose frame 0 is {B} at q = 0: bodies on it are "moving", so a scene pairs
// them with bodies on {B}; the tests put them anywhere with set_pose.
Cell one_joint_cell() {
  return test::hand_built_cell("one", Isometry::Identity(), Isometry::Identity(),
                               {{JointType::revolute, DhConvention::standard, 0, 0, 0, 0, -3, 3}},
                               {});
}

Shape random_shape(std::mt19937_64& rng, ShapeKind kind) {
  std::uniform_real_distribution<double> size(5.0, 60.0);
  Shape s;
  s.kind = kind;
  s.radius_mm = size(rng);
  s.length_mm = size(rng) * 2.0;
  s.size_mm = Eigen::Vector3d(size(rng), size(rng), size(rng)) * 2.0;
  return s;
}

Isometry random_pose(std::mt19937_64& rng, double spread_mm) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Isometry T = Isometry::Identity();
  T.linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
  T.translation() = spread_mm * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return T;
}

Body body_of(const std::string& name, int frame, const Shape& s) {
  Body b;
  b.name = name;
  b.frame = frame;
  b.shapes.push_back(s);
  return b;
}

// A closed triangle mesh of a box with edges `size` centred at the origin.
std::shared_ptr<TriangleMesh> box_mesh(const Eigen::Vector3d& size) {
  auto m = std::make_shared<TriangleMesh>();
  for (int i = 0; i < 8; ++i) {
    m->vertices.emplace_back((i & 1 ? 0.5 : -0.5) * size.x(), (i & 2 ? 0.5 : -0.5) * size.y(),
                             (i & 4 ? 0.5 : -0.5) * size.z());
  }
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    m->triangles.push_back({f[0], f[1], f[2]});
    m->triangles.push_back({f[0], f[2], f[3]});
  }
  return m;
}

}  // namespace

TEST_CASE("primitive distances agree with closed forms", "[collision]") {
  const Cell cell = one_joint_cell();
  std::mt19937_64 rng(46);
  const ShapeKind movers[] = {ShapeKind::sphere, ShapeKind::capsule};
  const ShapeKind others[] = {ShapeKind::sphere, ShapeKind::capsule, ShapeKind::cylinder,
                              ShapeKind::box};
  int separated = 0, overlapping = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Shape a = random_shape(rng, movers[trial % 2]);
    const Shape b = random_shape(rng, others[(trial / 2) % 4]);
    CollisionScene scene(cell, {body_of("a", 0, a), body_of("b", kFrameBase, b)}, {});
    REQUIRE(scene.pairs().size() == 1);
    ScenePoses poses;
    scene.prepare(poses);
    const Isometry Ta = random_pose(rng, 150.0), Tb = random_pose(rng, 150.0);
    scene.set_pose(0, Ta, poses);
    scene.set_pose(1, Tb, poses);
    // Independent: the sphere's centre, or the capsule's segment (a convex function of t),
    // against the other shape's closed-form point distance.
    const Eigen::Vector3d p0 =
        Ta * Eigen::Vector3d(0, 0, a.kind == ShapeKind::capsule ? -0.5 * a.length_mm : 0.0);
    const Eigen::Vector3d p1 =
        Ta * Eigen::Vector3d(0, 0, a.kind == ShapeKind::capsule ? 0.5 * a.length_mm : 0.0);
    const double expected = test::convex_min([&](double t) {
                              return test::point_to_shape(p0 + t * (p1 - p0), b, Tb);
                            }) -
                            a.radius_mm;
    Proximity near;
    const double got = scene.distance(0, poses, 1e9, &near);
    if (expected > 1e-3) {
      ++separated;
      CHECK(got == Approx(expected).margin(1e-4));
      // The nearest points: that far apart, the first on a's surface, the second on b's.
      CHECK((near.point_a_B - near.point_b_B).norm() == Approx(expected).margin(1e-3));
      CHECK(test::point_to_shape(near.point_b_B, b, Tb) < 1e-3);
    } else {
      ++overlapping;
      CHECK(got <= 1e-4);
    }
    // Above the exact threshold only a lower bound is promised.
    const double bound = scene.distance(0, poses, -1e9);
    CHECK(bound <= std::max(expected, 0.0) + 1e-9);
  }
  CHECK(separated > 100);
  CHECK(overlapping > 20);
}

TEST_CASE("mesh distances agree with a brute force over the triangles", "[collision]") {
  const Cell cell = one_joint_cell();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  // A random triangle soup and a closed box, as an STL would give them.
  auto soup = std::make_shared<TriangleMesh>();
  for (int t = 0; t < 60; ++t) {
    const Eigen::Vector3d c = 100.0 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    for (int k = 0; k < 3; ++k)
      soup->vertices.push_back(c + 30.0 * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    soup->triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  for (const auto& mesh : {soup, box_mesh(Eigen::Vector3d(120, 80, 60))}) {
    Shape m;
    m.kind = ShapeKind::mesh;
    m.mesh = mesh;
    for (int trial = 0; trial < 100; ++trial) {
      const Shape a = random_shape(rng, trial % 2 ? ShapeKind::capsule : ShapeKind::sphere);
      CollisionScene scene(cell, {body_of("a", 0, a), body_of("mesh", kFrameBase, m)}, {});
      ScenePoses poses;
      scene.prepare(poses);
      const Isometry Ta = random_pose(rng, 260.0), Tm = random_pose(rng, 20.0);
      scene.set_pose(0, Ta, poses);
      scene.set_pose(1, Tm, poses);
      const double half = a.kind == ShapeKind::capsule ? 0.5 * a.length_mm : 0.0;
      const Eigen::Vector3d p0 = Ta * Eigen::Vector3d(0, 0, -half),
                            p1 = Ta * Eigen::Vector3d(0, 0, half);
      double expected = 1e300;
      for (const auto& tri : mesh->triangles) {
        const Eigen::Vector3d A = Tm * mesh->vertices[static_cast<std::size_t>(tri[0])];
        const Eigen::Vector3d B = Tm * mesh->vertices[static_cast<std::size_t>(tri[1])];
        const Eigen::Vector3d C = Tm * mesh->vertices[static_cast<std::size_t>(tri[2])];
        expected = std::min(expected, test::convex_min([&](double t) {
                              return test::point_triangle(p0 + t * (p1 - p0), A, B, C);
                            }));
      }
      expected -= a.radius_mm;
      Proximity near;
      const double got = scene.distance(0, poses, 1e9, &near);
      if (expected > 1e-3) {
        CHECK(got == Approx(expected).margin(1e-3));
        CHECK((near.point_a_B - near.point_b_B).norm() == Approx(expected).margin(1e-3));
        // The mesh's point lies on one of its triangles, in {B}.
        double on = 1e300;
        for (const auto& tri : mesh->triangles) {
          on = std::min(
              on, test::point_triangle(near.point_b_B,
                                       Tm * mesh->vertices[static_cast<std::size_t>(tri[0])],
                                       Tm * mesh->vertices[static_cast<std::size_t>(tri[1])],
                                       Tm * mesh->vertices[static_cast<std::size_t>(tri[2])]));
        }
        CHECK(on < 1e-3);
      } else {
        CHECK(got <= 1e-3);
      }
    }
  }
}

TEST_CASE("a body wholly inside a closed mesh is found", "[collision]") {
  const Cell cell = one_joint_cell();
  Shape ball;
  ball.kind = ShapeKind::sphere;
  ball.radius_mm = 10.0;
  // A convex block is one solid for FCL: inside it, the distance says so.
  Shape block;
  block.kind = ShapeKind::mesh;
  block.mesh = box_mesh(Eigen::Vector3d(200, 200, 200));
  {
    CollisionScene scene(cell, {body_of("ball", 0, ball), body_of("block", kFrameBase, block)}, {});
    ScenePoses poses;
    scene.prepare(poses);
    scene.set_pose(1, Isometry::Identity(), poses);
    scene.set_pose(0, Isometry::Identity(), poses);
    CHECK(scene.distance(0, poses, 1e9) <= 0.0);
  }
  // A dented block (one corner pushed in) is a triangle surface: 90 mm from the ball at its
  // centre, which only the inside test finds.
  auto dented = std::make_shared<TriangleMesh>(*box_mesh(Eigen::Vector3d(200, 200, 200)));
  dented->vertices[7] *= 0.5;
  Shape m;
  m.kind = ShapeKind::mesh;
  m.mesh = dented;
  CollisionScene scene(cell, {body_of("ball", 0, ball), body_of("dented", kFrameBase, m)}, {});
  ScenePoses poses;
  scene.prepare(poses);
  scene.set_pose(1, Isometry::Identity(), poses);
  Isometry T = Isometry::Identity();
  T.translation() = Eigen::Vector3d(-20, -20, -20);
  scene.set_pose(0, T, poses);
  CHECK(scene.distance(0, poses, 1e9) == Approx(70.0).margin(1e-6));
  CHECK(scene.inside(0, poses));
  T.translation() = Eigen::Vector3d(0, 0, -150);
  scene.set_pose(0, T, poses);
  CHECK_FALSE(scene.inside(0, poses));
  CHECK(scene.distance(0, poses, 1e9) == Approx(40.0).margin(1e-6));
}

TEST_CASE("a scene pairs the bodies that can move against each other", "[collision]") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  Shape s;
  s.kind = ShapeKind::sphere;
  s.radius_mm = 10.0;
  const int flange = cell.find_joint("theta_6"), upper_arm = cell.find_joint("theta_2");
  std::vector<Body> bodies = {body_of("table", kFrameBase, s), body_of("arm", upper_arm, s),
                              body_of("spindle", flange, s), body_of("arm_too", upper_arm, s)};
  ToolGeometry tool;
  tool.length_mm = 120.0;
  tool.diameter_mm = 10.0;
  tool.flute_length_mm = 30.0;
  tool.holder_diameter_mm = 40.0;
  tool.holder_length_mm = 50.0;
  std::string note;
  for (Body& b : tool_bodies(tool, &note))
    bodies.push_back(b);
  CHECK(note.empty());
  Body part = body_of("part p.stl", kFrameBase, s);
  part.role = BodyRole::part;
  bodies.push_back(part);
  CollisionScene scene(cell, bodies, {{0, 2}});
  std::vector<std::string> names;
  for (std::size_t p = 0; p < scene.pairs().size(); ++p)
    names.push_back(scene.pair_name(static_cast<int>(p)));
  // table-spindle allowed; arm-arm_too on one frame; the tool with the spindle that carries it;
  // tool with tool; cutter with part; table with part (both on {B}).
  const std::vector<std::string> expected = {"table vs arm",
                                             "table vs arm_too",
                                             "table vs the tool cutter",
                                             "table vs the tool shank",
                                             "table vs the tool holder",
                                             "arm vs spindle",
                                             "arm vs the tool cutter",
                                             "arm vs the tool shank",
                                             "arm vs the tool holder",
                                             "arm vs part p.stl",
                                             "spindle vs arm_too",
                                             "spindle vs part p.stl",
                                             "arm_too vs the tool cutter",
                                             "arm_too vs the tool shank",
                                             "arm_too vs the tool holder",
                                             "arm_too vs part p.stl",
                                             "the tool shank vs part p.stl",
                                             "the tool holder vs part p.stl"};
  CHECK(names == expected);
}

TEST_CASE("tool bodies stack cutter, shank and holder along the tool axis", "[collision]") {
  ToolGeometry t;
  t.name = "tool 3";
  t.length_mm = 150.0;
  t.diameter_mm = 12.0;
  t.flute_length_mm = 40.0;
  t.shank_diameter_mm = 11.0;
  t.holder_diameter_mm = 50.0;
  t.holder_length_mm = 60.0;
  std::string note;
  const std::vector<Body> b = tool_bodies(t, &note);
  REQUIRE(b.size() == 3);
  CHECK(note.empty());
  const auto span = [](const Body& body) {
    const Shape& s = body.shapes.front();
    const double z = s.T_frame_shape.translation().z();
    return std::make_pair(z - 0.5 * s.length_mm, z + 0.5 * s.length_mm);
  };
  CHECK(span(b[0]).first == Approx(0.0));
  CHECK(span(b[0]).second == Approx(40.0));
  CHECK(span(b[1]).second == Approx(90.0));
  CHECK(span(b[2]).second == Approx(150.0));
  CHECK(b[1].shapes.front().radius_mm == Approx(5.5));
  CHECK(b[2].shapes.front().radius_mm == Approx(25.0));
  // The CL file's diameter and length alone: one cutter, and a note that says what that leaves.
  ToolGeometry cl;
  cl.length_mm = 100.0;
  cl.diameter_mm = 8.0;
  const std::vector<Body> c = tool_bodies(cl, &note);
  REQUIRE(c.size() == 1);
  CHECK(note.find("no flute length") != std::string::npos);
  CHECK(note.find("no holder") != std::string::npos);
  ToolGeometry none;
  CHECK(tool_bodies(none, &note).empty());
  CHECK(note.find("no diameter") != std::string::npos);
}

// The bound of CollisionScene::motion_bounds against the motion of points of the bodies over
// joint-linear motions, sampled densely, in {B} and against every other body of a pair; and
// halved, it must be broken somewhere (the test can fail).
TEST_CASE("the motion bound holds for every point of every body", "[collision]") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  std::vector<Body> bodies = test::skeleton_bodies(cell, 60.0);
  Shape table;
  table.kind = ShapeKind::sphere;
  table.radius_mm = 300.0;
  bodies.push_back(body_of("table", kFrameBase, table));
  CollisionScene scene(cell, bodies, {});
  ScenePoses p0, ps;
  scene.prepare(p0);
  scene.prepare(ps);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  KinematicsData d0, ds;
  std::vector<double> from;
  const std::size_t row = static_cast<std::size_t>(cell.size()) + 1;
  int broken_when_halved = 0, pair_broken_when_halved = 0;
  long round_pairs = 0;
  for (int trial = 0; trial < 120; ++trial) {
    const JointVector q0 = test::random_posture(cell, rng);
    JointVector q1 = q0;
    const double size = trial % 2 ? 0.02 : 0.3;  // small steps and large ones
    for (int i = 0; i < cell.size(); ++i)
      q1[i] += size * u(rng) * (cell.joint(i).type == JointType::prismatic ? 500.0 : 1.0);
    forward_kinematics(cell, q0, d0);
    scene.place(d0, p0);
    scene.motion_bounds(d0, p0, (q1 - q0).cwiseAbs(), from);
    // Points on the bodies' capsules' surfaces (in their frames), followed along the motion.
    std::vector<std::vector<Eigen::Vector3d>> points(static_cast<std::size_t>(scene.body_count()));
    for (int b = 0; b < scene.body_count(); ++b) {
      for (const Shape& s : scene.body(b).shapes) {
        for (int k = 0; k < 4; ++k) {
          const Eigen::Vector3d dir = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
          points[static_cast<std::size_t>(b)].push_back(
              s.T_frame_shape *
              (Eigen::Vector3d(0, 0, 0.5 * s.length_mm * u(rng)) + s.radius_mm * dir));
        }
      }
    }
    std::vector<double> farthest(static_cast<std::size_t>(scene.body_count()), 0.0);
    std::vector<double> relative(scene.pairs().size(), 0.0);
    for (int j = 1; j <= 48; ++j) {
      forward_kinematics(cell, q0 + (j / 48.0) * (q1 - q0), ds);
      scene.place(ds, ps);
      for (int b = 0; b < scene.body_count(); ++b) {
        const auto bu = static_cast<std::size_t>(b);
        for (const Eigen::Vector3d& local : points[bu]) {
          farthest[bu] =
              std::max(farthest[bu], (ps.T_B_body[bu] * local - p0.T_B_body[bu] * local).norm());
        }
      }
      for (std::size_t p = 0; p < scene.pairs().size(); ++p) {
        // The points of the body later in the chain, seen from the other's frame: their
        // distance changes by no more than they move there. Where the other is round about
        // the next joint's axis (the table sphere, about the table's), from the frame after
        // that joint: its turn moves them about that axis, which changes no distance to it.
        const int a = scene.pairs()[p].a, b = scene.pairs()[p].b;
        const bool b_later = scene.body(b).frame > scene.body(a).frame;
        const auto m = static_cast<std::size_t>(b_later ? b : a);
        const auto o = static_cast<std::size_t>(b_later ? a : b);
        const int seen_from = scene.first_mover(static_cast<int>(p)) - 1;
        const bool round = seen_from > scene.body(static_cast<int>(o)).frame;
        round_pairs += round;
        const auto frame_of = [&](const KinematicsData& d, const ScenePoses& poses) {
          return round ? d.T_B_link[static_cast<std::size_t>(seen_from)] : poses.T_B_body[o];
        };
        for (const Eigen::Vector3d& local : points[m]) {
          const Eigen::Vector3d now = frame_of(ds, ps).inverse() * (ps.T_B_body[m] * local);
          const Eigen::Vector3d then = frame_of(d0, p0).inverse() * (p0.T_B_body[m] * local);
          relative[p] = std::max(relative[p], (now - then).norm());
        }
      }
    }
    for (int b = 0; b < scene.body_count(); ++b) {
      const double bound = from[static_cast<std::size_t>(b) * row];
      CHECK(farthest[static_cast<std::size_t>(b)] <= bound + 1e-9);
      broken_when_halved += farthest[static_cast<std::size_t>(b)] > 0.5 * bound;
    }
    for (std::size_t p = 0; p < scene.pairs().size(); ++p) {
      const double bound = scene.pair_motion(static_cast<int>(p), from);
      CHECK(relative[p] <= bound + 1e-9);
      pair_broken_when_halved += relative[p] > 0.5 * bound;
    }
  }
  CHECK(broken_when_halved > 0);
  CHECK(pair_broken_when_halved > 0);
  CHECK(round_pairs > 0);  // the table sphere about the table's axis, a skeleton capsule
}
