// The convex hull of a <convex> body (collision/convex_hull.hpp), checked against what a hull
// is: a closed surface of outward triangles with every point behind every face (brute force
// over all points and faces), made of the points themselves; and a <convex> body's distance
// against the closed form of the box its points are the corners of.
#include <cmath>
#include <fstream>
#include <map>
#include <random>

#include "catch_compat.hpp"
#include "redpost/collision/cell_bodies.hpp"
#include "redpost/collision/convex_hull.hpp"
#include "redpost/collision/scene.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

// Every edge in exactly two triangles, once each way (a closed, consistently wound surface);
// Euler's V - E + F = 2 for a surface like a sphere's.
void check_closed(const TriangleMesh& m) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k)
      ++directed[{t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)]}];
  }
  for (const auto& [e, n] : directed) {
    CHECK(n == 1);
    CHECK(directed.count({e.second, e.first}) == 1);
  }
  const auto V = static_cast<long>(m.vertices.size());
  const auto E = static_cast<long>(directed.size() / 2);
  const auto F = static_cast<long>(m.triangles.size());
  CHECK(V - E + F == 2);
}

// The volume the triangles enclose (divergence theorem): positive when they face outward.
double volume(const TriangleMesh& m) {
  double v = 0.0;
  for (const auto& t : m.triangles) {
    v += m.vertices[static_cast<std::size_t>(t[0])].dot(
             m.vertices[static_cast<std::size_t>(t[1])].cross(
                 m.vertices[static_cast<std::size_t>(t[2])])) /
         6.0;
  }
  return v;
}

// The largest height of any point above any face's plane (mm): at most rounding for a hull.
double worst_outside(const TriangleMesh& m, const std::vector<Eigen::Vector3d>& points) {
  double worst = -1e300;
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d& a = m.vertices[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d n = (m.vertices[static_cast<std::size_t>(t[1])] - a)
                                  .cross(m.vertices[static_cast<std::size_t>(t[2])] - a);
    if (n.norm() < 1e-12)
      continue;  // a sliver of a split face: its plane is its neighbours'
    for (const Eigen::Vector3d& p : points)
      worst = std::max(worst, n.normalized().dot(p - a));
  }
  return worst;
}

// A one-joint cell file with `collision` (its <collision> element) after the joint: lines 1-6
// are the cell and its joint, so the element starts at line 7.
std::string one_joint_cell(const std::string& collision) {
  return R"(<?xml version="1.0"?>
<cell name="t" format="1">
  <joint name="j1" type="revolute">
    <dh alpha="0" a="0" theta="0" d="0"/>
    <limits min="-170" max="170"/><home value="0"/>
  </joint>
)" + collision +
         "</cell>\n";
}

std::string error_of(const std::vector<Eigen::Vector3d>& points) {
  try {
    convex_hull(points, "<convex>");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::bad_input);
    return e.message();
  }
  return "";
}

}  // namespace

TEST_CASE("convex hull: a box's corners and points inside it give the box", "[collision]") {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 8; ++i)
    points.emplace_back(i & 1 ? 40.0 : -40.0, i & 2 ? 25.0 : -25.0, i & 4 ? 60.0 : 0.0);
  std::mt19937_64 rng(46);
  std::uniform_real_distribution<double> u(-0.99, 0.99);
  for (int i = 0; i < 50; ++i)
    points.emplace_back(40.0 * u(rng), 25.0 * u(rng), 30.0 + 30.0 * u(rng));
  const TriangleMesh hull = convex_hull(points, "<convex>");
  CHECK(hull.vertices.size() == 8);
  CHECK(hull.triangles.size() == 12);  // six squares, two triangles each
  check_closed(hull);
  CHECK(volume(hull) == Approx(80.0 * 50.0 * 60.0).epsilon(1e-12));
  CHECK(worst_outside(hull, points) <= 1e-9);
}

TEST_CASE("convex hull: seeded random clouds, every point behind every face", "[collision]") {
  std::mt19937_64 rng(4646);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 30; ++trial) {
    std::vector<Eigen::Vector3d> points;
    const int n = 4 + trial * 7;
    const Eigen::Vector3d scale(10.0 + 200.0 * u(rng), 10.0 + 200.0 * u(rng), 1.0 + 50.0 * u(rng));
    for (int i = 0; i < n; ++i)
      points.emplace_back(Eigen::Vector3d(g(rng), g(rng), g(rng)).cwiseProduct(scale));
    const TriangleMesh hull = convex_hull(points, "<convex>");
    check_closed(hull);
    CHECK(volume(hull) > 0.0);
    CHECK(worst_outside(hull, points) <= 1e-9 * scale.maxCoeff());
    // The hull's vertices are points of the cloud, not new ones.
    for (const Eigen::Vector3d& v : hull.vertices) {
      bool found = false;
      for (const Eigen::Vector3d& p : points)
        found = found || p == v;
      CHECK(found);
    }
  }
}

TEST_CASE("convex hull: points that span no volume are refused", "[collision]") {
  CHECK(error_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).find("3 point(s) span no volume") !=
        std::string::npos);
  CHECK(error_of({{0, 0, 0}, {100, 0, 0}, {0, 100, 0}, {100, 100, 1e-9}}).find("span no volume") !=
        std::string::npos);
  CHECK(error_of({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {4, 4, 4}}).find("span no volume") !=
        std::string::npos);
  CHECK(error_of({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, std::nan("")}}).find("not finite") !=
        std::string::npos);
}

TEST_CASE("a <convex> body is as far from a ball as the box its points span", "[collision]") {
  const std::string text = one_joint_cell(R"(  <collision>
    <body name="hull" link="base">
      <convex x="100" z="10" c="30">
        <point x="-50" y="-20" z="-30"/><point x="50" y="-20" z="-30"/>
        <point x="-50" y="20" z="-30"/><point x="50" y="20" z="-30"/>
        <point x="-50" y="-20" z="30"/><point x="50" y="-20" z="30"/>
        <point x="-50" y="20" z="30"/><point x="50" y="20" z="30"/>
        <point x="0" y="0" z="0"/>
      </convex>
    </body>
    <body name="ball" link="j1">
      <sphere radius="5"/>
    </body>
  </collision>
)");
  const Cell cell = parse_cell(text, "t.xml");
  const CellBodies cb = parse_cell_bodies(cell, text, "t.xml");
  REQUIRE(cb.bodies.size() == 2);
  CollisionScene scene(cell, cb.bodies, cb.allowed);
  REQUIRE(scene.pairs().size() == 1);
  ScenePoses poses;
  scene.prepare(poses);
  // The box: centre (100, 0, 10), turned 30 deg about x (KUKA C), half edges 50, 20, 30.
  const Isometry T_B_box = cb.bodies[0].shapes[0].T_frame_shape;
  scene.set_pose(0, Isometry::Identity(), poses);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-150.0, 150.0);
  const Eigen::Vector3d half(50, 20, 30);
  int compared = 0;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p_B(100 + u(rng), u(rng), 10 + u(rng));
    const Eigen::Vector3d p_box = T_B_box.inverse() * p_B;
    const double outside = (p_box.cwiseAbs() - half).cwiseMax(0.0).norm();
    Isometry T = Isometry::Identity();
    T.translation() = p_B;
    scene.set_pose(1, T, poses);
    if (outside < 5.0) {
      CHECK(scene.distance(0, poses, 1e9) <= 0.0);  // the ball reaches into the hull
      continue;
    }
    CHECK(scene.distance(0, poses, 1e9) == Approx(outside - 5.0).margin(1e-6));
    ++compared;
  }
  CHECK(compared > 100);
}

TEST_CASE("a <convex> that spans no volume is refused at its line", "[collision]") {
  const std::string text = one_joint_cell(R"(  <collision>
    <body name="flat" link="base">
      <convex>
        <point x="0" y="0" z="0"/><point x="10" y="0" z="0"/><point x="0" y="10" z="0"/>
        <point x="10" y="10" z="0"/>
      </convex>
    </body>
  </collision>
)");
  const Cell cell = parse_cell(text, "t.xml");
  try {
    parse_cell_bodies(cell, text, "t.xml");
    FAIL("a flat <convex> was read");
  } catch (const Error& e) {
    CHECK(e.where().line == 9);
    CHECK(e.message().find("span no volume") != std::string::npos);
  }
}

TEST_CASE("<convex file> is the hull of an STL's vertices, open or not", "[collision]") {
  test::TempDir dir;
  {
    // Two triangles of a roof: an open surface, whose four corners span a tetrahedron.
    std::ofstream stl((dir.path / "roof.stl").string());
    stl << "solid r\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 100 0 0\n"
           "vertex 0 100 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 100 0 0\n"
           "vertex 0 100 0\nvertex 0 0 80\nendloop\nendfacet\nendsolid r\n";
  }
  const std::string path = (dir.path / "t.xml").string();
  {
    std::ofstream f(path);
    f << one_joint_cell(R"(  <collision>
    <body name="roof" link="j1"><convex file="roof.stl" z="5"/></body>
  </collision>
)");
  }
  const CellBodies b = load_cell_bodies(load_cell(path));
  REQUIRE(b.bodies.size() == 1);
  const Shape& s = b.bodies[0].shapes[0];
  REQUIRE(s.mesh);
  CHECK(s.mesh->vertices.size() == 4);
  CHECK(s.mesh->triangles.size() == 4);
  check_closed(*s.mesh);
  CHECK(volume(*s.mesh) == Approx(100.0 * 100.0 / 2.0 * 80.0 / 3.0).epsilon(1e-12));
  CHECK(s.T_frame_shape.translation().z() == Approx(5.0));
}
