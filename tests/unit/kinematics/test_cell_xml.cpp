// The cell loader (cell_xml.cpp): every broken definition is refused with a message that names
// the file, the line of the culprit element and what is wrong; the shipped cells load with the
// values their files state.
//
// The error cases start from one small valid cell (kBase) and break exactly one thing in it, so
// that a case can only fail for the reason it names.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/kinematics/types.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

// Seven joints: six revolute arm joints (A1..A6, limits made distinct so that every line of the
// document is unique) and the tool's virtual spin behind a <fixed> frame. <!--EXTRA--> is where a
// case adds elements to <cell>.
const std::string kBase = R"(<?xml version="1.0" encoding="UTF-8"?>
<cell name="mini" format="1" dh="standard">
  <base x="0" y="0" z="400" a="0" b="0" c="0"/>
  <joint name="j1" type="revolute">
    <dh alpha="90" a="100" theta="0" d="400"/>
    <axis name="A1" sign="1" offset="0"/>
    <limits min="-171" max="171"/>
    <home value="1"/>
  </joint>
  <joint name="j2" type="revolute">
    <dh alpha="0" a="500" theta="0" d="0"/>
    <axis name="A2" sign="1" offset="0"/>
    <limits min="-172" max="172"/>
    <home value="2"/>
  </joint>
  <joint name="j3" type="revolute">
    <dh alpha="90" a="50" theta="0" d="0"/>
    <axis name="A3" sign="1" offset="0"/>
    <limits min="-173" max="173"/>
    <home value="3"/>
  </joint>
  <joint name="j4" type="revolute">
    <dh alpha="-90" a="0" theta="0" d="450"/>
    <axis name="A4" sign="1" offset="0"/>
    <limits min="-174" max="174"/>
    <home value="4"/>
  </joint>
  <joint name="j5" type="revolute">
    <dh alpha="90" a="0" theta="0" d="0"/>
    <axis name="A5" sign="1" offset="0"/>
    <limits min="-175" max="175"/>
    <home value="5"/>
  </joint>
  <joint name="j6" type="revolute">
    <dh alpha="0" a="0" theta="0" d="80"/>
    <axis name="A6" sign="1" offset="0"/>
    <limits min="-176" max="176"/>
    <home value="6"/>
  </joint>
  <fixed name="spindle" x="0" y="0" z="120" a="0" b="0" c="0"/>
  <joint name="spin" type="virtual">
    <dh alpha="0" a="0" theta="0" d="30"/>
    <limits min="-180" max="180"/>
    <home value="0"/>
  </joint>
  <conditioning first="j1" last="j6" length="500"/>
  <!--EXTRA-->
</cell>
)";

size_t count_of(const std::string& text, const std::string& needle) {
  size_t n = 0;
  for (size_t p = text.find(needle); p != std::string::npos; p = text.find(needle, p + 1))
    ++n;
  return n;
}

// kBase with the one occurrence of `from` replaced by `to`.
std::string with(const std::string& from, const std::string& to, const std::string& doc = kBase) {
  INFO("substituting '" << from << "'");
  REQUIRE(count_of(doc, from) == 1);
  std::string out = doc;
  out.replace(out.find(from), from.size(), to);
  return out;
}

// kBase with extra elements in <cell>, after all the others.
std::string with_extra(const std::string& elements, const std::string& doc = kBase) {
  return with("<!--EXTRA-->", elements, doc);
}

// 1-based line of the one occurrence of `needle` in `doc`.
int line_of(const std::string& doc, const std::string& needle) {
  INFO("locating '" << needle << "'");
  REQUIRE(count_of(doc, needle) == 1);
  const size_t pos = doc.find(needle);
  return 1 + static_cast<int>(std::count(doc.begin(), doc.begin() + static_cast<long>(pos), '\n'));
}

bool contains(const std::string& s, const std::string& fragment) {
  return s.find(fragment) != std::string::npos;
}

// Parsing `doc` must fail with bad_input at the line where `culprit` (unique in doc) is, with a
// message containing `fragment`.
void expect_bad(const std::string& doc, const std::string& culprit, const std::string& fragment) {
  const int line = line_of(doc, culprit);
  INFO("document:\n" << doc);
  try {
    parse_cell(doc, "bad.xml");
    FAIL("parse_cell accepted the document; expected: " << fragment);
  } catch (const Error& e) {
    INFO("what(): " << e.what());
    CHECK(e.code() == ErrorCode::bad_input);
    CHECK(e.where().file == "bad.xml");
    CHECK(e.where().line == line);
    CHECK(contains(e.message(), fragment));
    // The formatted message leads with "file:line: ".
    CHECK(contains(e.what(), "bad.xml:" + std::to_string(line) + ": "));
  }
}

// The error thrown while loading `path`.
Error load_error(const std::string& path) {
  try {
    load_cell(path);
  } catch (const Error& e) {
    return e;
  }
  FAIL("load_cell(\"" << path << "\") succeeded");
  return Error(ErrorCode::internal, "unreachable");
}

// A cell of n revolute joints k1..kn, one per <joint> line, without controller axes.
std::string cell_of_n_joints(int n) {
  std::string doc = "<cell name=\"many\">\n";
  for (int i = 1; i <= n; ++i) {
    doc += "  <joint name=\"k" + std::to_string(i) +
           "\" type=\"revolute\"><dh alpha=\"0\" a=\"100\" theta=\"0\" d=\"0\"/>"
           "<limits min=\"-90\" max=\"90\"/><home value=\"0\"/></joint>\n";
  }
  return doc + "</cell>\n";
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

double deg(double d) {
  return deg_to_rad(d);
}

const std::string kJ1Dh = R"(<dh alpha="90" a="100" theta="0" d="400"/>)";
const std::string kJ1Axis = R"(<axis name="A1" sign="1" offset="0"/>)";
const std::string kJ1Limits = R"(<limits min="-171" max="171"/>)";
const std::string kJ1Home = R"(<home value="1"/>)";
const std::string kJ3Limits = R"(<limits min="-173" max="173"/>)";
const std::string kJ3Home = R"(<home value="3"/>)";

}  // namespace

// --- the base document ------------------------------------------------------------------------

TEST_CASE("cell_xml: the base document of the error cases is valid") {
  const Cell cell = parse_cell(kBase, "bad.xml");
  REQUIRE(cell.size() == 7);
  CHECK(cell.name == "mini");
  CHECK(cell.source_file == "bad.xml");
  CHECK(cell.joint(0).source_line == line_of(kBase, "<joint name=\"j1\""));
  CHECK(cell.joint(6).type == JointType::virtual_spin);
  CHECK(cell.joint(6).has_fixed_before);
  CHECK(cell.joint(0).home == Approx(deg(1)).epsilon(1e-15));
  CHECK(cell.conditioning.first == 0);
  CHECK(cell.conditioning.last == 5);
}

// --- missing elements and attributes ------------------------------------------------------------

TEST_CASE("cell_xml: a joint without <dh>, <limits> or <home> is refused at the joint's line") {
  SECTION("no <dh>") {
    expect_bad(with(kJ1Dh, ""), "<joint name=\"j1\"", "<joint> needs a <dh> element");
  }
  SECTION("no <limits>") {
    expect_bad(with(kJ3Limits, ""), "<joint name=\"j3\"", "<joint> needs a <limits> element");
  }
  SECTION("no <home>") {
    expect_bad(with(kJ3Home, ""), "<joint name=\"j3\"", "<joint> needs a <home> element");
  }
}

TEST_CASE("cell_xml: an element given twice is refused at the second one") {
  const std::string doc = with(kJ3Home, kJ3Home + "\n    <home value=\"7\"/>");
  expect_bad(doc, "<home value=\"7\"/>", "<home> given twice in <joint>");
}

TEST_CASE("cell_xml: a missing attribute is named") {
  SECTION("dh d") {
    const std::string doc = with(kJ1Dh, R"(<dh alpha="90" a="100" theta="0"/>)");
    expect_bad(doc, R"(<dh alpha="90" a="100" theta="0"/>)", "<dh> needs the attribute 'd'");
  }
  SECTION("limits max") {
    const std::string doc = with(kJ3Limits, R"(<limits min="-173"/>)");
    expect_bad(doc, R"(<limits min="-173"/>)", "<limits> needs the attribute 'max'");
  }
  SECTION("home value") {
    const std::string doc = with(kJ3Home, R"(<home in="axis"/>)");
    expect_bad(doc, R"(<home in="axis"/>)", "<home> needs the attribute 'value'");
  }
  SECTION("joint type") {
    const std::string doc = with(R"(<joint name="j2" type="revolute">)", R"(<joint name="j2">)");
    expect_bad(doc, R"(<joint name="j2">)", "<joint> needs the attribute 'type'");
  }
  SECTION("joint name") {
    const std::string doc =
        with(R"(<joint name="j2" type="revolute">)", R"(<joint type="revolute">)");
    expect_bad(doc, R"(<joint type="revolute">)", "<joint> needs the attribute 'name'");
  }
  SECTION("axis name") {
    const std::string doc = with(kJ1Axis, R"(<axis sign="1" offset="0"/>)");
    expect_bad(doc, R"(<axis sign="1" offset="0"/>)", "<axis> needs the attribute 'name'");
  }
  SECTION("cell name") {
    const std::string doc = with(R"(<cell name="mini" format="1" dh="standard">)", "<cell>");
    expect_bad(doc, "<cell>", "<cell> needs the attribute 'name'");
  }
  SECTION("conditioning length") {
    const std::string doc = with(R"(length="500")", "");
    expect_bad(doc, "<conditioning", "<conditioning> needs the attribute 'length'");
  }
}

// --- numbers ------------------------------------------------------------------------------------

TEST_CASE("cell_xml: a value that is not a number is refused") {
  SECTION("abc in a length") {
    const std::string doc = with(R"(a="500")", R"(a="abc")");
    expect_bad(doc, R"(a="abc")", "<dh> attribute 'a' = \"abc\": not a number");
  }
  SECTION("empty angle") {
    const std::string doc = with(R"(<limits min="-172")", R"(<limits min="")");
    expect_bad(doc, R"(<limits min="")", "<limits> attribute 'min' = \"\": not a number");
  }
  SECTION("blank angle") {
    const std::string doc = with(R"(<limits min="-172")", R"(<limits min="  ")");
    expect_bad(doc, R"(<limits min="  ")", "not a number");
  }
  SECTION("12a in a length: 'a' is no unit") {
    const std::string doc = with(R"(a="500")", R"(a="12a")");
    expect_bad(doc, R"(a="12a")", "<dh> attribute 'a' = \"12a\": unknown unit 'a' (use mm, m)");
  }
  SECTION("12a in an angle") {
    const std::string doc = with(R"(<home value="4"/>)", R"(<home value="12a"/>)");
    expect_bad(doc, R"(<home value="12a"/>)", "unknown unit 'a' (use deg, rad)");
  }
  SECTION("a lone sign") {
    const std::string doc = with(R"(d="450")", R"(d="-")");
    expect_bad(doc, R"(d="-")", "not a number");
  }
}

TEST_CASE("cell_xml: a unitless value with trailing garbage is 'not a number'") {
  // <weight> and <axis sign> take no unit, so "12a" is not a number with an unknown unit.
  SECTION("weight") {
    const std::string doc = with(kJ3Home, kJ3Home + R"(<weight value="12a"/>)");
    expect_bad(doc, R"(<weight value="12a"/>)",
               "<weight> attribute 'value' = \"12a\": not a number");
  }
  SECTION("sign") {
    const std::string doc = with(kJ1Axis, R"(<axis name="A1" sign="1x" offset="0"/>)");
    expect_bad(doc, R"(sign="1x")", "<axis> attribute 'sign' = \"1x\": not a number");
  }
}

TEST_CASE("cell_xml: a doubled sign is not a number") {
  const std::string doc = with(R"(d="450")", R"(d="+-450")");
  expect_bad(doc, R"(d="+-450")", "<dh> attribute 'd' = \"+-450\": not a number");
}

TEST_CASE("cell_xml: NaN and infinities are refused") {
  const char* const texts[] = {"nan", "NaN", "inf", "-inf", "+inf", "infinity", "-nan"};
  for (const char* t : texts) {
    SECTION(std::string("length ") + t) {
      const std::string attr = std::string("d=\"") + t + "\"";
      expect_bad(with(R"(d="450")", attr), attr,
                 "<dh> attribute 'd' = \"" + std::string(t) +
                     "\": must be a finite number (NaN and inf are refused)");
    }
    SECTION(std::string("angle ") + t) {
      const std::string attr = std::string("<home value=\"") + t + "\"/>";
      expect_bad(with(kJ3Home, attr), attr, "must be a finite number");
    }
  }
}

TEST_CASE("cell_xml: magnitudes too large to be meant are refused") {
  SECTION("1e308 mm") {
    expect_bad(with(R"(d="450")", R"(d="1e308")"), R"(d="1e308")",
               "<dh> attribute 'd' = \"1e308\": magnitude too large to be meant");
  }
  SECTION("-1e308 deg") {
    expect_bad(with(R"(<limits min="-172")", R"(<limits min="-1e308")"), R"(min="-1e308")",
               "magnitude too large to be meant");
  }
  SECTION("1e308 m overflows only after the unit") {
    expect_bad(with(R"(d="450")", R"(d="1e308 m")"), R"(d="1e308 m")",
               "magnitude too large to be meant");
  }
  SECTION("1e309 is out of the double range") {
    expect_bad(with(R"(d="450")", R"(d="1e309")"), R"(d="1e309")", "number out of range");
  }
  SECTION("weight 1e308") {
    const std::string doc = with(kJ3Home, kJ3Home + R"(<weight value="1e308"/>)");
    expect_bad(doc, R"(<weight value="1e308"/>)", "magnitude too large to be meant");
  }
  SECTION("stiffness 1e308") {
    const std::string doc = with(kJ3Home, kJ3Home + R"(<stiffness value="1e308"/>)");
    expect_bad(doc, R"(<stiffness value="1e308"/>)", "magnitude too large to be meant");
  }
}

TEST_CASE("cell_xml: the stiffness bound applies after the unit conversion") {
  // 1e10 MNm/rad = 1e19 N*mm/rad, far beyond the 1e15 N*mm/rad the loader means to accept.
  const std::string s = R"(<stiffness value="1e10" unit="MNm/rad"/>)";
  expect_bad(with(kJ3Home, kJ3Home + s), s, "magnitude too large to be meant");
}

TEST_CASE("cell_xml: unknown units are refused with the list of known ones") {
  SECTION("length") {
    expect_bad(with(R"(d="450")", R"(d="12 furlongs")"), R"(d="12 furlongs")",
               "<dh> attribute 'd' = \"12 furlongs\": unknown unit 'furlongs' (use mm, m)");
  }
  SECTION("angle") {
    expect_bad(with(R"(<limits min="-172")", R"(<limits min="-172 grad")"), R"(min="-172 grad")",
               "unknown unit 'grad' (use deg, rad)");
  }
  SECTION("stiffness of a rotary joint") {
    const std::string s = R"(<stiffness value="3" unit="N/mm"/>)";
    expect_bad(with(kJ3Home, kJ3Home + s), s,
               "unknown stiffness unit 'N/mm' for a rotary joint (use Nm/rad, kNm/rad or MNm/rad)");
  }
}

// --- limits and home ----------------------------------------------------------------------------

TEST_CASE("cell_xml: limits with min > max are refused") {
  SECTION("DH units") {
    const std::string l = R"(<limits min="40" max="-155"/>)";
    expect_bad(with(kJ3Limits, l), l, "<limits> of joint 'j3': min 40 > max -155 deg (DH units)");
  }
  SECTION("in axis units, sign +1 with an offset") {
    const std::string doc = with(kJ1Axis, R"(<axis name="A1" sign="1" offset="-180"/>)");
    const std::string l = R"(<limits min="10" max="-10" in="axis"/>)";
    // theta = A1 + 180 deg: [190, 170] deg.
    expect_bad(with(kJ1Limits, l, doc), l, "min 190 > max 170 deg (DH units)");
  }
  SECTION("in axis units, sign -1: the reversed order in the file is what is wrong") {
    const std::string doc = with(kJ1Axis, R"(<axis name="A1" sign="-1" offset="0"/>)");
    const std::string l = R"(<limits min="20" max="-10" in="axis"/>)";
    // q = -A1: the file's min 20 / max -10 give q in [10, -20] deg after the swap.
    expect_bad(with(kJ1Limits, l, doc), l, "min 10 > max -20 deg (DH units)");
  }
  SECTION("prismatic joint, mm") {
    std::string doc =
        with(R"(<joint name="j2" type="revolute">)", R"(<joint name="j2" type="prismatic">)");
    doc = with(R"(<axis name="A2" sign="1" offset="0"/>)", R"(<axis name="E1"/>)", doc);
    const std::string l = R"(<limits min="3000" max="-500"/>)";
    doc = with(R"(<limits min="-172" max="172"/>)", l, doc);
    expect_bad(doc, l, "min 3000 > max -500 mm (DH units)");
  }
}

TEST_CASE("cell_xml: axis-unit limits with sign -1 swap their ends") {
  SECTION("sign -1, in axis units: A1 in [-10, 20] is q in [-20, 10] deg") {
    std::string doc = with(kJ1Axis, R"(<axis name="A1" sign="-1" offset="0"/>)");
    doc = with(kJ1Limits, R"(<limits min="-10" max="20" in="axis"/>)", doc);
    doc = with(kJ1Home, R"(<home value="5" in="axis"/>)", doc);
    const Cell cell = parse_cell(doc, "ok.xml");
    CHECK(cell.joint(0).lower == Approx(deg(-20)).epsilon(1e-15));
    CHECK(cell.joint(0).upper == Approx(deg(10)).epsilon(1e-15));
    CHECK(cell.joint(0).home == Approx(deg(-5)).epsilon(1e-15));
  }
  SECTION("sign -1, offset, prismatic: E1 in [100, 400] mm with E1 = -q + 1000") {
    std::string doc =
        with(R"(<joint name="j2" type="revolute">)", R"(<joint name="j2" type="prismatic">)");
    doc = with(R"(<axis name="A2" sign="1" offset="0"/>)",
               R"(<axis name="E1" sign="-1" offset="1 m"/>)", doc);
    doc = with(R"(<limits min="-172" max="172"/>)", R"(<limits min="100" max="400" in="axis"/>)",
               doc);
    doc = with(R"(<home value="2"/>)", R"(<home value="300" in="axis"/>)", doc);
    const Cell cell = parse_cell(doc, "ok.xml");
    CHECK(cell.joint(1).axis.offset == 1000.0);
    CHECK(cell.joint(1).lower == Approx(600.0).epsilon(1e-15));
    CHECK(cell.joint(1).upper == Approx(900.0).epsilon(1e-15));
    CHECK(cell.joint(1).home == Approx(700.0).epsilon(1e-15));
  }
  SECTION("sign -1 without in=\"axis\": the limits are DH values, not swapped") {
    std::string doc = with(kJ1Axis, R"(<axis name="A1" sign="-1" offset="0"/>)");
    doc = with(kJ1Limits, R"(<limits min="-10" max="20"/>)", doc);
    const Cell cell = parse_cell(doc, "ok.xml");
    CHECK(cell.joint(0).lower == Approx(deg(-10)).epsilon(1e-15));
    CHECK(cell.joint(0).upper == Approx(deg(20)).epsilon(1e-15));
  }
}

TEST_CASE("cell_xml: a home outside the limits is refused at <home>") {
  SECTION("DH units") {
    const std::string h = R"(<home value="200"/>)";
    expect_bad(with(kJ3Home, h), h,
               "home of joint 'j3' is 200 deg, outside its limits [-173, 173] (DH units)");
  }
  SECTION("axis units with an offset") {
    // theta = A1 + 90 deg; A1 = 90 is theta = 180 > 171.
    std::string doc = with(kJ1Axis, R"(<axis name="A1" sign="1" offset="-90"/>)");
    const std::string h = R"(<home value="90" in="axis"/>)";
    expect_bad(with(kJ1Home, h, doc), h, "home of joint 'j1' is 180 deg, outside its limits");
  }
  SECTION("just outside") {
    const std::string h = R"(<home value="173.000001"/>)";
    expect_bad(with(kJ3Home, h), h, "outside its limits");
  }
}

TEST_CASE("cell_xml: a home on a limit is accepted") {
  const Cell cell = parse_cell(with(kJ3Home, R"(<home value="173"/>)"), "ok.xml");
  CHECK(cell.joint(2).home == cell.joint(2).upper);
}

TEST_CASE("cell_xml: an unknown in= is refused") {
  const std::string l = R"(<limits min="-173" max="173" in="axes"/>)";
  expect_bad(with(kJ3Limits, l), l, "<limits> in=\"axes\": use in=\"dh\" or in=\"axis\"");
}

// --- joints -------------------------------------------------------------------------------------

TEST_CASE("cell_xml: an unknown joint type is refused") {
  const std::string j = R"(<joint name="j4" type="rotary">)";
  expect_bad(with(R"(<joint name="j4" type="revolute">)", j), j,
             "unknown joint type 'rotary' (use revolute, prismatic or virtual)");
}

TEST_CASE("cell_xml: at most 16 joints; the 17th is named") {
  SECTION("16 load") {
    const Cell cell = parse_cell(cell_of_n_joints(16), "ok.xml");
    CHECK(cell.size() == 16);
    CHECK(cell.joint(15).name == "k16");
    CHECK(cell.joint(15).source_line == 17);
  }
  SECTION("17 are refused") {
    const std::string doc = cell_of_n_joints(17);
    expect_bad(doc, "<joint name=\"k17\"", "too many joints: redpost handles at most 16");
  }
}

TEST_CASE("cell_xml: a joint name used twice is refused at the second joint") {
  const std::string j = R"(<joint type="revolute" name="j1">)";
  expect_bad(with(R"(<joint name="j2" type="revolute">)", j), j, "joint name 'j1' used twice");
}

TEST_CASE("cell_xml: an empty joint name is refused") {
  const std::string j = R"(<joint name="" type="revolute">)";
  expect_bad(with(R"(<joint name="j5" type="revolute">)", j), j, "a joint needs a non-empty name");
}

// --- controller axes ----------------------------------------------------------------------------

TEST_CASE("cell_xml: a controller axis mapped twice is refused at the second <axis>") {
  const std::string a = R"(<axis name="A1" sign="1" offset="90"/>)";
  const std::string doc = with(R"(<axis name="A4" sign="1" offset="0"/>)", a);
  // The message names the axis and both joints, and points at the second mapping.
  expect_bad(doc, a, "controller axis A1 is mapped to two joints");
  try {
    parse_cell(doc, "bad.xml");
  } catch (const Error& e) {
    CHECK(contains(e.message(), "'j1'"));
    CHECK(contains(e.message(), "'j4'"));
  }
}

TEST_CASE("cell_xml: a virtual joint cannot drive a controller axis") {
  const std::string doc = with(R"(<dh alpha="0" a="0" theta="0" d="30"/>)",
                               R"(<dh alpha="0" a="0" theta="0" d="30"/>
    <axis name="E3"/>)");
  expect_bad(doc, R"(<axis name="E3"/>)",
             "joint 'spin' is virtual (the tool's free spin) and cannot drive axis E3");
}

TEST_CASE("cell_xml: an unknown controller axis name is refused") {
  for (const char* name : {"A7", "X1", "A0", "E7", "a1", "A", "A12", ""}) {
    SECTION(std::string("'") + name + "'") {
      const std::string a = std::string("<axis name=\"") + name + "\" sign=\"1\" offset=\"0\"/>";
      expect_bad(
          with(R"(<axis name="A3" sign="1" offset="0"/>)", a), a,
          std::string("unknown controller axis '") + name + "' (use A1..A6, E1..E6 or none)");
    }
  }
}

TEST_CASE("cell_xml: an axis sign must be +1 or -1") {
  for (const char* sign : {"2", "0", "-1.5", "0.5", "-0"}) {
    SECTION(sign) {
      const std::string a = std::string("<axis name=\"A2\" sign=\"") + sign + "\" offset=\"0\"/>";
      expect_bad(with(R"(<axis name="A2" sign="1" offset="0"/>)", a), a,
                 "<axis> sign must be 1 or -1");
    }
  }
  SECTION("+1 and -1.0 are accepted") {
    std::string doc =
        with(R"(<axis name="A2" sign="1" offset="0"/>)", R"(<axis name="A2" sign="+1"/>)");
    doc = with(R"(<axis name="A3" sign="1" offset="0"/>)", R"(<axis name="A3" sign="-1.0"/>)", doc);
    const Cell cell = parse_cell(doc, "ok.xml");
    CHECK(cell.joint(1).axis.sign == 1.0);
    CHECK(cell.joint(2).axis.sign == -1.0);
  }
}

TEST_CASE("cell_xml: an <axis name=\"none\"> takes no sign or offset") {
  const std::string a = R"(<axis name="none" sign="-1"/>)";
  expect_bad(with(kJ1Axis, a), a, "an <axis name=\"none\"> takes no sign or offset");
}

// --- document structure -------------------------------------------------------------------------

TEST_CASE("cell_xml: malformed XML reports tinyxml2's line") {
  SECTION("an element left open") {
    // <dh ...> without '/': the mismatch is reported at the open element.
    const std::string dh = R"(<dh alpha="90" a="50" theta="0" d="0">)";
    const std::string doc = with(R"(<dh alpha="90" a="50" theta="0" d="0"/>)", dh);
    expect_bad(doc, dh, "not well-formed XML");
  }
  SECTION("an unterminated start tag") {
    const std::string l = R"(<limits min="-174" max="174")";
    const std::string doc = with(R"(<limits min="-174" max="174"/>)", l);
    // tinyxml2 stops in the tag that never ends.
    expect_bad(doc, l, "not well-formed XML");
  }
  SECTION("the root never closed") {
    const std::string doc = with("</cell>\n", "");
    expect_bad(doc, "<cell name=", "not well-formed XML");
  }
}

// Issue 48: what the XML standard refuses and tinyxml2 reads without a word (io/xml_lexical.cpp).
// Each case is checked against xmllint by tests/xml/test_wellformed.sh as well.
TEST_CASE("cell_xml: XML that tinyxml2 takes but the standard refuses, at its line") {
  SECTION("a comment holding two hyphens in a row") {
    const std::string c = "<!-- use --lock E1 here -->";
    expect_bad(with_extra(c), c, "a comment holds '--'");
  }
  SECTION("a comment ending in three hyphens") {
    const std::string c = "<!-- the end --->";
    expect_bad(with_extra(c), c, "a comment holds '--'");
  }
  SECTION("the second line of a comment holds them") {
    const std::string doc = with_extra("<!-- first line\n  second -- line -->");
    expect_bad(doc, "second -- line", "a comment holds '--'");
  }
  SECTION("a bare ampersand in an attribute") {
    const std::string h = R"(<home value="1&2"/>)";
    expect_bad(with(kJ1Home, h), h, "a bare '&'");
  }
  SECTION("an entity XML does not define") {
    const std::string b = R"(<cell name="mini&nbsp;cell" format="1" dh="standard">)";
    expect_bad(with(R"(<cell name="mini" format="1" dh="standard">)", b), b,
               "the entity '&nbsp;' is not defined");
  }
  SECTION("a '<' in an attribute value") {
    const std::string b = R"(<cell name="a<b" format="1" dh="standard">)";
    expect_bad(with(R"(<cell name="mini" format="1" dh="standard">)", b), b, "not well-formed XML");
  }
}

TEST_CASE("cell_xml: what the standard allows stays allowed") {
  // '&', '<' and single hyphens in a comment, the predefined entities and character references
  // in a value: all read as XML reads them.
  const std::string doc =
      with(R"(<cell name="mini" format="1" dh="standard">)",
           R"(<cell name="m&amp;i&#110;&#x69;&lt;&gt;&quot;&apos;" format="1" dh="standard">)",
           with_extra("<!-- a & b < c - d, -x- -->"));
  const Cell cell = parse_cell(doc, "ok.xml");
  CHECK(cell.name == "m&ini<>\"'");
}

TEST_CASE("cell_xml: the root element must be <cell>") {
  std::string doc = with(R"(<cell name="mini" format="1" dh="standard">)",
                         R"(<robot name="mini" format="1" dh="standard">)");
  doc = with("</cell>", "</robot>", doc);
  expect_bad(doc, "<robot", "the root element is <robot>, expected <cell>");
}

TEST_CASE("cell_xml: an unsupported format is refused") {
  const std::string c = R"(<cell name="mini" format="2" dh="standard">)";
  expect_bad(with(R"(<cell name="mini" format="1" dh="standard">)", c), c,
             "unsupported cell format \"2\" (this redpost reads 1)");
}

TEST_CASE("cell_xml: unknown elements are refused") {
  SECTION("in <cell>") {
    expect_bad(with_extra(R"(<joints/>)"), "<joints/>",
               "unknown element <joints> in <cell> (known: base, joint, fixed, tool, conditioning, "
               "controller, tool-table, collision)");
  }
  SECTION("in <joint>") {
    const std::string e = R"(<limit min="-1" max="1"/>)";
    expect_bad(with(kJ3Home, kJ3Home + e), e,
               "unknown element <limit> in joint 'j3' (known: dh, limits, home, weight, axis, "
               "stiffness, speed)");
  }
}

TEST_CASE("cell_xml: a misspelt attribute is refused, not ignored") {
  SECTION("limits") {
    const std::string l = R"(<limits mni="-173" max="173"/>)";
    expect_bad(with(kJ3Limits, l), l,
               "<limits> has an unknown attribute 'mni' (known: min, max, in)");
  }
  SECTION("dh") {
    const std::string d = R"(<dh alpha="90" a="100" theta="0" d="400" thetta="1"/>)";
    expect_bad(with(kJ1Dh, d), d, "<dh> has an unknown attribute 'thetta'");
  }
  SECTION("fixed") {
    const std::string f = R"(<fixed name="spindle" x="0" y="0" z="120" a="0" b="0" cc="0"/>)";
    expect_bad(with(R"(<fixed name="spindle" x="0" y="0" z="120" a="0" b="0" c="0"/>)", f), f,
               "<fixed> has an unknown attribute 'cc'");
  }
  SECTION("joint") {
    const std::string j = R"(<joint name="j2" typ="revolute">)";
    expect_bad(with(R"(<joint name="j2" type="revolute">)", j), j,
               "<joint> has an unknown attribute 'typ' (known: name, type, dh)");
  }
}

TEST_CASE("cell_xml: the chain order is checked") {
  SECTION("a joint after <tool>") {
    const std::string doc = with_extra(R"(<tool z="10"/>
  <joint name="late" type="revolute">)" +
                                       std::string(R"(<dh alpha="0" a="0" theta="0" d="0"/>
    <limits min="-1" max="1"/><home value="0"/></joint>)"));
    expect_bad(doc, R"(<joint name="late")", "<joint> after <tool>: the tool frame ends the chain");
  }
  SECTION("<base> after a joint") {
    const std::string b = R"(<base z="1"/>)";
    expect_bad(with_extra(b), b, "<base> must come once, before the first joint");
  }
}

TEST_CASE("cell_xml: a cell without joints is refused") {
  const std::string doc =
      "<?xml version=\"1.0\"?>\n<cell name=\"none\">\n  <base z=\"1\"/>\n</cell>\n";
  expect_bad(doc, "<cell", "the cell has no <joint>");
}

// --- conditioning -------------------------------------------------------------------------------

TEST_CASE("cell_xml: conditioning must span at least 6 joints") {
  SECTION("five joints") {
    const std::string c = R"(<conditioning first="j2" last="j6" length="500"/>)";
    expect_bad(with(R"(<conditioning first="j1" last="j6" length="500"/>)", c), c,
               "<conditioning> must span at least 6 joints (from 'j2' to 'j6' is 5)");
  }
  SECTION("an unknown joint") {
    const std::string c = R"(<conditioning first="j0" last="j6" length="500"/>)";
    expect_bad(with(R"(<conditioning first="j1" last="j6" length="500"/>)", c), c,
               "<conditioning> first: no joint 'j0'");
  }
  SECTION("a length of zero") {
    const std::string c = R"(<conditioning first="j1" last="j6" length="0"/>)";
    expect_bad(with(R"(<conditioning first="j1" last="j6" length="500"/>)", c), c,
               "<conditioning> length must be > 0 mm");
  }
  SECTION("seven joints, the virtual one included, are accepted") {
    const Cell cell = parse_cell(with(R"(last="j6")", R"(last="spin")"), "ok.xml");
    CHECK(cell.conditioning.count() == 7);
  }
}

TEST_CASE("cell_xml: conditioning with first after last says so, not a negative span") {
  const std::string c = R"(<conditioning first="spin" last="j1" length="500"/>)";
  const std::string doc = with(R"(<conditioning first="j1" last="j6" length="500"/>)", c);
  const int line = line_of(doc, c);
  try {
    parse_cell(doc, "bad.xml");
    FAIL("accepted");
  } catch (const Error& e) {
    INFO("message: " << e.message());
    CHECK(e.code() == ErrorCode::bad_input);
    CHECK(e.where().line == line);
    CHECK(contains(e.message(), "'spin'"));
    CHECK_FALSE(contains(e.message(), "is -"));
  }
}

// --- empty documents and files ------------------------------------------------------------------

TEST_CASE("cell_xml: an empty document is refused as empty") {
  for (const char* text : {"", "\n\n   \n", "<?xml version=\"1.0\"?>\n", "<!-- nothing -->\n"}) {
    SECTION(std::string("text of ") + std::to_string(std::string(text).size()) + " chars") {
      try {
        parse_cell(text, "bad.xml");
        FAIL("accepted");
      } catch (const Error& e) {
        INFO("what(): " << e.what());
        CHECK(e.code() == ErrorCode::bad_input);
        CHECK(e.where().file == "bad.xml");
        CHECK(contains(e.message(), "empty file: no <cell> element"));
      }
    }
  }
}

TEST_CASE("cell_xml: a missing file is an io error naming the path") {
  const std::string path = test::source_path("definitions/cells/no_such_cell.xml");
  const Error e = load_error(path);
  CHECK(e.code() == ErrorCode::io);
  CHECK(e.where().file == path);
  CHECK(contains(e.what(), path));
  CHECK(contains(e.message(), "no such file"));
}

TEST_CASE("cell_xml: a directory given as a cell file is an io error") {
  const std::string path = test::source_path("definitions/cells");
  const Error e = load_error(path);
  CHECK(e.code() == ErrorCode::io);
  CHECK(e.where().file == path);
  CHECK(contains(e.what(), path));
  CHECK(contains(e.message(), "is a directory"));
}

TEST_CASE("cell_xml: errors in a loaded file name that file and the line") {
  namespace fs = std::filesystem;
  const fs::path path =
      fs::temp_directory_path() /
      ("redpost_test_cell_xml_" +
       std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()) + ".xml");
  const std::string h = R"(<home value="200"/>)";
  const std::string doc = with(kJ3Home, h);
  {
    std::ofstream out(path, std::ios::binary);
    out << doc;
  }
  const Error e = load_error(path.string());
  fs::remove(path);
  CHECK(e.code() == ErrorCode::bad_input);
  CHECK(e.where().file == path.string());
  CHECK(e.where().line == line_of(doc, h));
  CHECK(contains(e.what(), path.string() + ":" + std::to_string(line_of(doc, h)) + ": "));
}

// --- values that load ---------------------------------------------------------------------------

TEST_CASE("cell_xml: units convert to mm and rad") {
  std::string doc = with(R"(<dh alpha="90" a="100" theta="0" d="400"/>)",
                         R"(<dh alpha="1.5 rad" a="0.25 m" theta="-30deg" d=" 400 mm "/>)");
  doc =
      with(R"(<base x="0" y="0" z="400" a="0" b="0" c="0"/>)", R"(<base x="1.5 m" z="400"/>)", doc);
  const Cell cell = parse_cell(doc, "ok.xml");
  const Joint& j = cell.joint(0);
  CHECK(j.alpha_rad == 1.5);
  CHECK(j.a_mm == 250.0);
  CHECK(j.theta_rad == Approx(deg(-30)).epsilon(1e-15));
  CHECK(j.d_mm == 400.0);
  CHECK(cell.T_B_0.translation().x() == 1500.0);
}

TEST_CASE("cell_xml: stiffness is stored in N*mm/rad or N/mm") {
  SECTION("rotary") {
    struct Case {
      const char* unit;
      double expected;
    };
    for (const Case& c :
         {Case{"", 2e3}, Case{"Nm/rad", 2e3}, Case{"kNm/rad", 2e6}, Case{"MNm/rad", 2e9}}) {
      const std::string s = std::string("<stiffness value=\"2\"") +
                            (*c.unit ? std::string(" unit=\"") + c.unit + "\"" : "") + "/>";
      const Cell cell = parse_cell(with(kJ3Home, kJ3Home + s), "ok.xml");
      INFO(s);
      REQUIRE(cell.joint(2).stiffness.has_value());
      CHECK(*cell.joint(2).stiffness == c.expected);
      CHECK_FALSE(cell.joint(1).stiffness.has_value());
    }
  }
  SECTION("prismatic") {
    std::string doc =
        with(R"(<joint name="j2" type="revolute">)", R"(<joint name="j2" type="prismatic">)");
    doc = with(R"(<home value="2"/>)", R"(<home value="2"/><stiffness value="5000" unit="N/m"/>)",
               doc);
    const Cell cell = parse_cell(doc, "ok.xml");
    REQUIRE(cell.joint(1).stiffness.has_value());
    CHECK(*cell.joint(1).stiffness == Approx(5.0).epsilon(1e-15));
  }
  SECTION("not positive") {
    const std::string s = R"(<stiffness value="0"/>)";
    expect_bad(with(kJ3Home, kJ3Home + s), s, "the stiffness of joint 'j3' must be > 0");
  }
}

TEST_CASE("cell_xml: <fixed> frames compose onto the next joint; <tool> ends the chain") {
  std::string doc = with(R"(<fixed name="spindle" x="0" y="0" z="120" a="0" b="0" c="0"/>)",
                         R"(<fixed x="10"/>
  <fixed a="90"/>)");
  doc = with_extra(R"(<tool z="25" c="180"/>)", doc);
  const Cell cell = parse_cell(doc, "ok.xml");
  const Joint& spin = cell.joint(6);
  CHECK(spin.has_fixed_before);
  for (int i = 0; i < 6; ++i)
    CHECK_FALSE(cell.joint(i).has_fixed_before);
  // Tx(10) then Rz(90): translation (10, 0, 0), rotation Rz(90).
  const Eigen::Matrix3d Rz90 = Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()).matrix();
  CHECK((spin.T_prev_link.translation() - Eigen::Vector3d(10, 0, 0)).norm() < 1e-12);
  CHECK((spin.T_prev_link.linear() - Rz90).norm() < 1e-12);
  const Eigen::Matrix3d Rx180 = Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX()).matrix();
  CHECK((cell.T_last_tcp.translation() - Eigen::Vector3d(0, 0, 25)).norm() < 1e-12);
  CHECK((cell.T_last_tcp.linear() - Rx180).norm() < 1e-12);
}

// --- the shipped cells --------------------------------------------------------------------------

TEST_CASE("cell_xml: all shipped cells load") {
  for (const char* name : test::kShippedCells) {
    INFO(name);
    const Cell cell = test::shipped_cell(name);
    CHECK(cell.name == name);
    CHECK(cell.source_file == test::source_path(std::string("definitions/cells/") + name + ".xml"));
    CHECK(cell.conditioning.declared());
    CHECK(cell.conditioning.count() == 6);
  }
}

TEST_CASE("cell_xml: andres2011 cell: joints, types, limits in axis units") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  REQUIRE(cell.size() == 9);
  const char* const names[] = {"theta_M", "d_L",     "theta_1", "theta_2", "theta_3",
                               "theta_4", "theta_5", "theta_6", "theta_7"};
  for (int i = 0; i < 9; ++i)
    CHECK(cell.joint(i).name == names[i]);
  CHECK(cell.joint(0).type == JointType::revolute);
  CHECK(cell.joint(1).type == JointType::prismatic);
  for (int i = 2; i < 8; ++i)
    CHECK(cell.joint(i).type == JointType::revolute);
  CHECK(cell.joint(8).type == JointType::virtual_spin);
  for (int i = 0; i < 9; ++i)
    CHECK(cell.joint(i).convention == DhConvention::standard);

  // Axis mapping.
  CHECK(axis_name(cell.joint(0).axis) == "E2");
  CHECK(axis_name(cell.joint(1).axis) == "E1");
  CHECK(axis_name(cell.joint(2).axis) == "A1");
  CHECK(cell.joint(2).axis.offset == -180.0);
  CHECK_FALSE(cell.joint(8).axis.mapped());

  // theta_1: A1 = theta_1 - 180 deg with A1 in [-185, 185] deg, so theta_1 in [-5, 365] deg.
  CHECK(cell.joint(2).lower == Approx(deg(-5)).epsilon(1e-14));
  CHECK(cell.joint(2).upper == Approx(deg(365)).epsilon(1e-14));
  CHECK(cell.joint(2).home == Approx(deg(180)).epsilon(1e-14));
  // theta_3 = A3 - 90 deg, home A3 = 90: theta_3 = 0.
  CHECK(std::fabs(cell.joint(4).home) < 1e-15);
  // Track: mm, no conversion.
  CHECK(cell.joint(1).lower == -500.0);
  CHECK(cell.joint(1).upper == 3000.0);
  CHECK(cell.joint(1).home == 500.0);
  CHECK(cell.joint(1).weight == 1e-6);
  // theta_M limits in DH units.
  CHECK(cell.joint(0).lower == Approx(deg(-720)).epsilon(1e-15));

  // DH: alpha given in rad is taken exactly; deg converted.
  CHECK(cell.joint(7).alpha_rad == 0.3564);
  CHECK(cell.joint(7).d_mm == -443.4);
  CHECK(cell.joint(0).alpha_rad == Approx(kPi / 2).epsilon(1e-15));
  CHECK(cell.joint(0).a_mm == 803.0);
  CHECK(cell.joint(0).d_mm == -305.0);
  CHECK(cell.joint(8).d_mm == -119.7);

  CHECK(cell.joint(2).source_line ==
        line_of(read_file(cell.source_file), "<joint name=\"theta_1\""));
  CHECK_FALSE(cell.joint(8).has_fixed_before);
  CHECK(cell.conditioning.first == 2);
  CHECK(cell.conditioning.last == 7);
}

TEST_CASE("cell_xml: kr15_2 cell: six arm joints between base and tool frames") {
  const Cell cell = test::shipped_cell("kr15_2");
  REQUIRE(cell.size() == 6);
  for (int i = 0; i < 6; ++i) {
    CHECK(cell.joint(i).name == "theta_" + std::to_string(i + 1));
    CHECK(cell.joint(i).type == JointType::revolute);
    CHECK(axis_name(cell.joint(i).axis) == "A" + std::to_string(i + 1));
    // Issue 20: half the KR270-2's of Caro Table 4.1 (docs/cells.md), in N mm/rad.
    static const double kHalfCaro[6] = {0.1185, 1.66, 1.395, 0.243, 0.2605, 0.19};
    REQUIRE(cell.joint(i).stiffness.has_value());
    CHECK(*cell.joint(i).stiffness == Approx(kHalfCaro[i] * 1e9).epsilon(1e-12));
  }
  // theta_2 = A2, home -90 deg; theta_4 = A4 + 180 deg, A4 in [-350, 350].
  CHECK(cell.joint(1).home == Approx(deg(-90)).epsilon(1e-15));
  CHECK(cell.joint(3).lower == Approx(deg(-170)).epsilon(1e-14));
  CHECK(cell.joint(3).upper == Approx(deg(530)).epsilon(1e-14));
  // <base c="180"> and <tool c="180">: Rx(180).
  const Eigen::Matrix3d Rx180 = Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX()).matrix();
  CHECK((cell.T_B_0.linear() - Rx180).norm() < 1e-15);
  CHECK((cell.T_last_tcp.linear() - Rx180).norm() < 1e-15);
}

TEST_CASE("cell_xml: caro2014 cell: modified DH, stiffness, the spindle <fixed> frame") {
  const Cell cell = test::shipped_cell("caro2014_kr270_table");
  REQUIRE(cell.size() == 7);
  const char* const names[] = {"theta_1", "theta_2", "theta_3", "theta_4",
                               "theta_5", "theta_6", "beta"};
  for (int i = 0; i < 7; ++i) {
    CHECK(cell.joint(i).name == names[i]);
    CHECK(cell.joint(i).convention == DhConvention::modified);
  }
  CHECK(cell.joint(6).type == JointType::virtual_spin);
  CHECK_FALSE(cell.joint(6).axis.mapped());
  CHECK_FALSE(cell.joint(6).stiffness.has_value());

  // 0.237 MNm/rad = 0.237e9 N*mm/rad.
  REQUIRE(cell.joint(0).stiffness.has_value());
  CHECK(*cell.joint(0).stiffness == Approx(0.237e9).epsilon(1e-15));
  CHECK(*cell.joint(1).stiffness == Approx(3.32e9).epsilon(1e-15));
  CHECK(*cell.joint(5).stiffness == Approx(0.38e9).epsilon(1e-15));

  // Sign -1 mapping with DH limits: theta_1 = -A1, limits as written, home A1 = 0.
  CHECK(cell.joint(0).axis.sign == -1.0);
  CHECK(cell.joint(0).lower == Approx(deg(-185)).epsilon(1e-15));
  CHECK(cell.joint(0).upper == Approx(deg(185)).epsilon(1e-15));
  // theta_2 = -A2, home A2 = -90: theta_2 = 90 deg.
  CHECK(cell.joint(1).home == Approx(deg(90)).epsilon(1e-15));
  // theta_3 = -A3 - 90 deg, home A3 = 90: theta_3 = -180 deg.
  CHECK(cell.joint(2).home == Approx(deg(-180)).epsilon(1e-15));

  // <base z="750">.
  CHECK((cell.T_B_0.translation() - Eigen::Vector3d(0, 0, 750)).norm() < 1e-12);
  CHECK((cell.T_B_0.linear() - Eigen::Matrix3d::Identity()).norm() < 1e-15);

  // <fixed name="spindle" z="684" a="90" c="45"/> sits before 'beta'.
  for (int i = 0; i < 6; ++i)
    CHECK_FALSE(cell.joint(i).has_fixed_before);
  const Joint& beta = cell.joint(6);
  REQUIRE(beta.has_fixed_before);
  CHECK((beta.T_prev_link.translation() - Eigen::Vector3d(0, 0, 684)).norm() < 1e-12);
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(kPi / 4, Eigen::Vector3d::UnitX()))
                                .matrix();
  CHECK((beta.T_prev_link.linear() - R).norm() < 1e-12);
  // Caro eq. 2.9 column by column: (0,1,0), (-sqrt2/2,0,sqrt2/2), (sqrt2/2,0,sqrt2/2).
  const double h = std::sqrt(0.5);
  Eigen::Matrix3d eq29;
  eq29 << 0, -h, h, 1, 0, 0, 0, h, h;
  CHECK((beta.T_prev_link.linear() - eq29).norm() < 1e-12);
  // The tool frame after the spin turns z to point from the tip to the spindle: Rx(pi), no move.
  CHECK(cell.T_last_tcp.translation().norm() < 1e-12);
  CHECK(
      (cell.T_last_tcp.linear() - Eigen::Matrix3d(Eigen::Vector3d(1, -1, -1).asDiagonal())).norm() <
      1e-12);
}

// --- axis speeds (<speed>, issue 17) -------------------------------------------------------------

namespace {

// kBase with <speed> on every arm joint: joint i gets velocity 100 + i deg/s and acceleration
// 300 + i deg/s2, so that each line stays unique. `replace` swaps one joint's element for another
// text (empty: the joint has none).
std::string with_speeds(int replace_joint = 0, const std::string& replacement = "") {
  std::string doc = kBase;
  for (int i = 1; i <= 6; ++i) {
    const std::string home = "<home value=\"" + std::to_string(i) + "\"/>";
    const std::string speed = "<speed velocity=\"" + std::to_string(100 + i) +
                              " deg/s\" acceleration=\"" + std::to_string(300 + i) + " deg/s2\"/>";
    doc = with(home, home + (i == replace_joint ? replacement : speed), doc);
  }
  return doc;
}

}  // namespace

TEST_CASE("cell_xml: <speed> is stored in DH units per second and per second squared") {
  SECTION("deg/s and deg/s2") {
    const Cell cell = parse_cell(with_speeds(), "ok.xml");
    CHECK(cell.has_axis_speeds());
    for (int i = 0; i < 6; ++i) {
      CHECK(cell.joint(i).max_velocity == Approx(deg(100 + i + 1)).epsilon(1e-14));
      CHECK(cell.joint(i).max_acceleration == Approx(deg(300 + i + 1)).epsilon(1e-14));
    }
    CHECK_FALSE(cell.joint(6).has_speed());  // the virtual spin
  }
  SECTION("rad/s, and a bare number in controller units (deg/s)") {
    const Cell cell =
        parse_cell(with_speeds(2, R"(<speed velocity="2 rad/s" acceleration="150"/>)"), "ok.xml");
    CHECK(cell.joint(1).max_velocity == 2.0);
    CHECK(cell.joint(1).max_acceleration == Approx(deg(150)).epsilon(1e-14));
  }
  SECTION("a prismatic joint in mm/s, m/s, mm/s2 and m/s2") {
    std::string doc = with_speeds(2, R"(<speed velocity="1.5 m/s" acceleration="2 m/s2"/>)");
    doc =
        with(R"(<joint name="j2" type="revolute">)", R"(<joint name="j2" type="prismatic">)", doc);
    const Cell cell = parse_cell(doc, "ok.xml");
    CHECK(cell.joint(1).max_velocity == Approx(1500.0).epsilon(1e-14));
    CHECK(cell.joint(1).max_acceleration == Approx(2000.0).epsilon(1e-14));
  }
  SECTION("a cell without any <speed> has no axis speeds") {
    const Cell cell = parse_cell(kBase, "ok.xml");
    CHECK_FALSE(cell.has_axis_speeds());
  }
}

TEST_CASE("cell_xml: a bad <speed> is refused at its line") {
  SECTION("zero velocity") {
    const std::string s = R"(<speed velocity="0" acceleration="100"/>)";
    expect_bad(with_speeds(3, s), s, "the velocity of joint 'j3' must be > 0");
  }
  SECTION("negative acceleration") {
    const std::string s = R"(<speed velocity="10" acceleration="-5 deg/s2"/>)";
    expect_bad(with_speeds(3, s), s, "the acceleration of joint 'j3' must be > 0");
  }
  SECTION("NaN") {
    const std::string s = R"(<speed velocity="nan" acceleration="100"/>)";
    expect_bad(with_speeds(3, s), s, "NaN and inf are refused");
  }
  SECTION("a linear unit on a revolute joint") {
    const std::string s = R"(<speed velocity="10 mm/s" acceleration="100"/>)";
    expect_bad(with_speeds(3, s), s, "unit");
  }
  SECTION("without acceleration") {
    const std::string s = R"(<speed velocity="10"/>)";
    expect_bad(with_speeds(3, s), s, "acceleration");
  }
  SECTION("on the virtual spin") {
    std::string doc = with_speeds();
    const std::string s = R"(<speed velocity="10" acceleration="100"/>)";
    doc = with(R"(<home value="0"/>)", std::string(R"(<home value="0"/>)") + s, doc);
    expect_bad(doc, s, "joint 'spin' is virtual");
  }
  SECTION("missing on one joint while the others have one: the joint's line") {
    const std::string doc = with_speeds(4, "");
    expect_bad(doc, R"(<joint name="j4" type="revolute">)",
               "joint 'j4' (A4) has no <speed> while joint 'j1' has one");
  }
}

TEST_CASE("cell_xml: the shipped cells give every axis a speed") {
  for (const char* name : {"andres2011_kr15_track_table", "kr15_2", "caro2014_kr270_table"}) {
    INFO(name);
    const Cell cell = test::shipped_cell(name);
    CHECK(cell.has_axis_speeds());
  }
  // The reference cell: table 90 deg/s, track 1000 mm/s, A1 156 deg/s (definitions/cells).
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  CHECK(cell.joint(0).max_velocity == Approx(deg(90)).epsilon(1e-14));
  CHECK(cell.joint(1).max_velocity == Approx(1000.0).epsilon(1e-14));
  CHECK(cell.joint(2).max_velocity == Approx(deg(156)).epsilon(1e-14));
}

// --- <controller> ------------------------------------------------------------------------------

TEST_CASE("cell_xml: <controller> gives the load data and the coupled base's EX_AX_DATA entry") {
  const std::string path =
      std::string(REDPOST_SOURCE_DIR) + "/definitions/cells/andres2011_kr15_track_table.xml";
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string controller = R"(<controller base-data="1">)";
  const std::string base_kinematic = R"(<kinematic axis="E2" type="base" machine-def="2"/>)";
  REQUIRE(text.find(controller) != std::string::npos);
  REQUIRE(text.find(base_kinematic) != std::string::npos);
  const auto edit = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  // The shipped cell: no load given (each tool's own number), ET1.
  Cell cell = parse_cell(text, "cell.xml");
  CHECK(cell.controller.load_data == 0);
  CHECK(cell.controller.ex_ax_data == 1);
  cell = parse_cell(edit(controller, R"(<controller base-data="3" load-data="5">)"), "cell.xml");
  CHECK(cell.controller.base_data == 3);
  CHECK(cell.controller.load_data == 5);
  cell = parse_cell(
      edit(base_kinematic, R"(<kinematic axis="E2" type="base" machine-def="4" ex-ax-data="2"/>)"),
      "cell.xml");
  CHECK(cell.controller.machine_def == 4);
  CHECK(cell.controller.ex_ax_data == 2);
  const auto refused = [&](const std::string& doc, const std::string& words) {
    try {
      parse_cell(doc, "cell.xml");
      FAIL("accepted");
    } catch (const Error& e) {
      INFO(e.what());
      CHECK(e.code() == ErrorCode::bad_input);
      CHECK(e.where().line > 0);
      CHECK(e.message().find(words) != std::string::npos);
    }
  };
  refused(edit(controller, R"(<controller load-data="17">)"), "from 1 to 16");
  refused(edit(base_kinematic, R"(<kinematic axis="E2" type="base" ex-ax-data="7"/>)"),
          "from 1 to 6");
  refused(edit(R"(<kinematic axis="E1" type="robroot"/>)",
               R"(<kinematic axis="E1" type="robroot" ex-ax-data="1"/>)"),
          "belong to a base kinematic");
}
