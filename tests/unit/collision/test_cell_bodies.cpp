// The <collision> element of cell files (collision/cell_bodies.hpp): what it reads, what it
// refuses (with the line), and the shipped cells' bodies.
#include <fstream>

#include "catch_compat.hpp"
#include "redpost/collision/cell_bodies.hpp"
#include "redpost/collision/scene.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

const char* kChain = R"(<?xml version="1.0"?>
<cell name="t" format="1">
  <joint name="j1" type="revolute">
    <dh alpha="90" a="100" theta="0" d="400"/>
    <limits min="-170" max="170"/><home value="0"/>
  </joint>
  <joint name="j2" type="revolute">
    <dh alpha="0" a="500" theta="0" d="0"/>
    <limits min="-170" max="170"/><home value="0"/>
  </joint>
  <joint name="spin" type="virtual">
    <dh alpha="0" a="0" theta="0" d="100"/>
    <limits min="-180" max="180"/><home value="0"/>
  </joint>
)";

std::string cell_text(const std::string& collision) {
  return std::string(kChain) + collision + "</cell>\n";
}

// The error's line and message for a <collision> body (the chain is lines 1..14).
std::pair<int, std::string> refusal(const std::string& collision) {
  const std::string text = cell_text(collision);
  const Cell cell = parse_cell(text, "t.xml");
  try {
    parse_cell_bodies(cell, text, "t.xml");
  } catch (const Error& e) {
    return {e.where().line, e.message()};
  }
  return {0, ""};
}

}  // namespace

TEST_CASE("cell bodies are read in their link's frame", "[collision]") {
  const std::string text = cell_text(R"(  <collision>
    <body name="base" link="base">
      <cylinder x1="0" y1="0" z1="0" x2="0" y2="0" z2="400" radius="120"/>
    </body>
    <body name="upper" link="j2">
      <capsule x1="-500" y1="0" z1="0" x2="0" y2="0" z2="0" radius="0.08 m"/>
      <box x="10" y="20" z="30" a="90" b="0" c="0" dx="10" dy="20" dz="30"/>
      <sphere x="0" y="0" z="0" radius="90"/>
    </body>
    <allow a="base" b="upper"/>
  </collision>
)");
  const Cell cell = parse_cell(text, "t.xml");
  const CellBodies b = parse_cell_bodies(cell, text, "t.xml");
  REQUIRE(b.declared);
  REQUIRE(b.bodies.size() == 2);
  CHECK(b.bodies[0].frame == kFrameBase);
  CHECK(b.bodies[1].frame == 1);
  const Shape& cyl = b.bodies[0].shapes.front();
  CHECK(cyl.kind == ShapeKind::cylinder);
  CHECK(cyl.length_mm == Approx(400.0));
  CHECK(cyl.T_frame_shape.translation().z() == Approx(200.0));
  const Shape& cap = b.bodies[1].shapes[0];
  CHECK(cap.radius_mm == Approx(80.0));
  // The capsule's z axis runs from its first point to its second.
  CHECK((cap.T_frame_shape.linear().col(2) - Eigen::Vector3d::UnitX()).norm() < 1e-12);
  CHECK(b.bodies[1].shapes[1].size_mm.y() == Approx(20.0));
  REQUIRE(b.allowed.size() == 1);
  CHECK(b.allowed.front() == std::make_pair(0, 1));
  // The allowed pair is not checked.
  CollisionScene scene(cell, b.bodies, b.allowed);
  CHECK(scene.pairs().empty());
}

TEST_CASE("a cell without <collision> has no bodies", "[collision]") {
  const std::string text = cell_text("");
  const Cell cell = parse_cell(text, "t.xml");
  const CellBodies b = parse_cell_bodies(cell, text, "t.xml");
  CHECK_FALSE(b.declared);
  CHECK(b.bodies.empty());
}

TEST_CASE("mistakes in <collision> are refused at their line", "[collision]") {
  const auto [line1, what1] = refusal(
      "  <collision>\n    <body name=\"x\" link=\"spin\">\n"
      "      <sphere radius=\"5\"/>\n    </body>\n  </collision>\n");
  CHECK(line1 == 16);
  CHECK(what1.find("virtual joint 'spin'") != std::string::npos);
  const auto [line2, what2] = refusal(
      "  <collision>\n    <body name=\"x\" link=\"nope\">\n"
      "      <sphere radius=\"5\"/>\n    </body>\n  </collision>\n");
  CHECK(line2 == 16);
  CHECK(what2.find("no joint of that name") != std::string::npos);
  const auto [line3, what3] = refusal(
      "  <collision>\n    <body name=\"x\" link=\"j1\">\n"
      "      <sphere radius=\"-5\"/>\n    </body>\n  </collision>\n");
  CHECK(line3 == 17);
  CHECK(what3.find("must be > 0") != std::string::npos);
  const auto [line4, what4] = refusal(
      "  <collision>\n    <body name=\"x\" link=\"j1\">\n"
      "      <cone radius=\"5\"/>\n    </body>\n  </collision>\n");
  CHECK(line4 == 17);
  CHECK(what4.find("unknown element <cone>") != std::string::npos);
  const auto [line5, what5] =
      refusal("  <collision>\n    <allow a=\"x\" b=\"y\"/>\n  </collision>\n");
  CHECK(line5 == 16);
  CHECK(what5.find("no <body> of that name") != std::string::npos);
  const auto [line6, what6] = refusal(
      "  <collision>\n    <body name=\"x\" link=\"j1\">\n      <sphere radius=\"5\"/>\n"
      "    </body>\n    <body name=\"x\" link=\"j2\">\n      <sphere radius=\"5\"/>\n"
      "    </body>\n  </collision>\n");
  CHECK(line6 == 19);
  CHECK(what6.find("used twice") != std::string::npos);
  const auto [line7, what7] = refusal(
      "  <collision>\n    <body name=\"x\" link=\"j1\">\n"
      "      <mesh file=\"missing.stl\"/>\n    </body>\n"
      "  </collision>\n");
  CHECK(line7 == 17);
  CHECK(what7.find("missing.stl") != std::string::npos);
  const auto [line8, what8] = refusal(
      "  <collision>\n    <body name=\"x\" link=\"j1\">\n"
      "      <sphere radius=\"nan\"/>\n    </body>\n"
      "  </collision>\n");
  CHECK(line8 == 17);
  CHECK(what8.find("finite") != std::string::npos);
}

TEST_CASE("a mesh body's STL is read beside the cell file", "[collision]") {
  test::TempDir dir;
  {
    std::ofstream stl((dir.path / "block.stl").string());
    stl << "solid b\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\nvertex 0 10 0\n"
           "endloop\nendfacet\nendsolid b\n";
  }
  const std::string text = cell_text(
      "  <collision>\n    <body name=\"m\" link=\"j1\">\n      <mesh file=\"block.stl\" z=\"5\"/>\n"
      "    </body>\n  </collision>\n");
  const std::string path = (dir.path / "t.xml").string();
  {
    std::ofstream f(path);
    f << text;
  }
  const Cell cell = load_cell(path);
  const CellBodies b = load_cell_bodies(cell);
  REQUIRE(b.bodies.size() == 1);
  REQUIRE(b.bodies[0].shapes.front().mesh);
  CHECK(b.bodies[0].shapes.front().mesh->triangles.size() == 1);
  CHECK(b.bodies[0].shapes.front().T_frame_shape.translation().z() == Approx(5.0));
}
