// Tool tables (redpost/kinematics/tool_table.hpp): the file and the cell element, their checks
// with file:line, and the TCP of a tool of another length, checked by forward kinematics.
#include <cmath>
#include <random>
#include <string>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/tool_table.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

void expect_bad(const std::string& xml, int line, const std::string& words) {
  try {
    parse_tool_table(xml, "tools.xml");
    FAIL("accepted: " << xml);
  } catch (const Error& e) {
    INFO(e.what());
    CHECK(e.code() == ErrorCode::bad_input);
    CHECK(e.where().file == "tools.xml");
    CHECK(e.where().line == line);
    CHECK(e.message().find(words) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("tool_table: a file maps CL tools to TOOL_DATA and lengths", "[tool_table]") {
  const ToolTable t = parse_tool_table(
      "<tool-table>\n"
      "  <tool number=\"15\" data=\"3\" length=\"69\" name=\"centre drill\"/>\n"
      "  <tool number=\"16\" data=\"4\" load-data=\"12\" length=\"0.105 m\"/>\n"
      "</tool-table>\n",
      "tools.xml");
  REQUIRE(t.tools.size() == 2);
  REQUIRE(t.find(16));
  CHECK(t.find(16)->tool_data == 4);
  CHECK(t.find(16)->load_data == 12);
  CHECK(t.find(15)->load_data == 0);  // not given: the cell's, else the tool's own number
  CHECK(t.find(16)->length_mm == Approx(105.0));
  CHECK(t.find(15)->name == "centre drill");
  CHECK(t.find(15)->line == 2);
  CHECK(t.find(17) == nullptr);
  CHECK_FALSE(t.has_reference());
}

TEST_CASE("tool_table: bad entries are refused with file:line", "[tool_table]") {
  expect_bad("<tool-table>\n<tool number=\"1\" data=\"1\" length=\"nan\"/>\n</tool-table>", 2,
             "finite");
  expect_bad("<tool-table>\n<tool number=\"1\" data=\"1\" length=\"-5\"/>\n</tool-table>", 2,
             "length must be > 0");
  expect_bad("<tool-table>\n<tool number=\"1\" data=\"17\" length=\"50\"/>\n</tool-table>", 2,
             "from 1 to 16");
  expect_bad("<tool-table>\n<tool number=\"1.5\" data=\"1\" length=\"50\"/>\n</tool-table>", 2,
             "whole number");
  expect_bad(
      "<tool-table>\n<tool number=\"1\" data=\"1\" load-data=\"0\" length=\"50\"/>\n"
      "</tool-table>",
      2, "from 1 to 16");
  expect_bad(
      "<tool-table>\n<tool number=\"1\" data=\"1\" load-data=\"17\" length=\"50\"/>\n"
      "</tool-table>",
      2, "from 1 to 16");
  expect_bad(
      "<tool-table>\n<tool number=\"1\" data=\"1\" length=\"50\"/>\n"
      "<tool number=\"1\" data=\"2\" length=\"60\"/>\n</tool-table>",
      3, "given twice (first at line 2)");
  expect_bad("<tool-table>\n<tool number=\"1\" data=\"1\"/>\n</tool-table>", 2, "length");
  expect_bad("<tool-table>\n<cutter number=\"1\" data=\"1\" length=\"5\"/>\n</tool-table>", 2,
             "unknown element <cutter>");
  expect_bad("<tool-table reference-length=\"100\">\n</tool-table>", 1, "belongs in the cell");
  expect_bad("<tools/>", 1, "expected <tool-table>");
}

TEST_CASE(
    "tool_table: a tool L mm longer puts the TCP L mm further along -z of the TCP, for "
    "every posture and cell form",
    "[tool_table]") {
  std::mt19937_64 rng(11);
  for (const char* name : {"andres2011_kr15_track_table", "caro2014_kr270_table"}) {
    Cell cell = test::shipped_cell(name);
    if (!cell.tools.has_reference())
      cell.tools.reference_length_mm = 100.0;
    const Cell longer = cell_for_tool(cell, cell.tools.reference_length_mm + 36.0);
    const Cell shorter = cell_for_tool(cell, cell.tools.reference_length_mm - 50.0);
    for (int k = 0; k < 200; ++k) {
      const JointVector q = test::random_posture(cell, rng);
      const Isometry T = tcp_pose(cell, q);
      const Eigen::Vector3d z = T.linear().col(2);
      INFO(name);
      CHECK((tcp_pose(longer, q).translation() - (T.translation() - 36.0 * z)).norm() < 1e-9);
      CHECK((tcp_pose(shorter, q).translation() - (T.translation() + 50.0 * z)).norm() < 1e-9);
      CHECK((tcp_pose(longer, q).linear() - T.linear()).norm() < 1e-12);
    }
  }
}

TEST_CASE("tool_table: a tool's geometry for the collision check", "[tool_table]") {
  const ToolTable t = parse_tool_table(
      "<tool-table>\n"
      "  <tool number=\"3\" data=\"3\" length=\"150\" diameter=\"12\" flute-length=\"40\"\n"
      "        shank-diameter=\"11\" holder-diameter=\"50\" holder-length=\"0.06 m\"/>\n"
      "  <tool number=\"4\" data=\"4\" length=\"100\"/>\n"
      "</tool-table>\n",
      "tools.xml");
  const ToolEntry* e = t.find(3);
  REQUIRE(e);
  CHECK(e->diameter_mm == Approx(12.0));
  CHECK(e->flute_length_mm == Approx(40.0));
  CHECK(e->shank_diameter_mm == Approx(11.0));
  CHECK(e->holder_diameter_mm == Approx(50.0));
  CHECK(e->holder_length_mm == Approx(60.0));
  CHECK(std::isnan(t.find(4)->diameter_mm));  // not given: the CL file's
  expect_bad(
      "<tool-table>\n<tool number=\"1\" data=\"1\" length=\"50\" diameter=\"0\"/>\n"
      "</tool-table>",
      2, "diameter must be > 0");
  expect_bad(
      "<tool-table>\n<tool number=\"1\" data=\"1\" length=\"50\" diameter=\"8\"\n"
      "holder-diameter=\"40\"/>\n</tool-table>",
      2, "needs both holder-diameter and holder-length");
  expect_bad(
      "<tool-table>\n<tool number=\"1\" data=\"1\" length=\"50\" diameter=\"8\"\n"
      "flute-length=\"30\" holder-diameter=\"40\" holder-length=\"30\"/>\n</tool-table>",
      2, "do not fit in its length");
  expect_bad(
      "<tool-table>\n<tool number=\"1\" data=\"1\" length=\"50\" flute-length=\"30\"/>\n"
      "</tool-table>",
      2, "need the cutter's diameter");
  expect_bad(
      "<tool-table>\n<tool number=\"1\" data=\"1\" length=\"50\" flute=\"30\"/>\n"
      "</tool-table>",
      2, "unknown attribute 'flute'");
}
