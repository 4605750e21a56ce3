// The APT/CLDATA and NX CLSF reader (core/src/cl/): every record it accepts, checked on small
// inline inputs whose expected events are worked out by hand; arcs and NURBS checked against
// the geometry they stand for (points on the curve, sagitta, direction) with an independent
// evaluation; every refused input checked for its line, column and message; and the real CL
// files of /work/shared/evaldata read to the end (or to a located error).
#include <charconv>
#include <cmath>
#include <cstddef>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "catch_compat.hpp"
#include "redpost/cl/reader.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/types.hpp"
#include "test_support.hpp"

using namespace redpost;
using Eigen::Vector3d;

namespace {

struct ReadResult {
  std::vector<ClEvent> events;
  std::deque<std::string> warnings;
};

ReadResult read_all(const std::string& text, const ClReaderOptions& options = {}) {
  std::istringstream in(text);
  ClReader reader(in, "t.apt", options);
  ReadResult r;
  ClEvent e;
  while (reader.next(e))
    r.events.push_back(e);
  r.warnings = reader.warnings();
  return r;
}

std::vector<ClEvent> of_kind(const std::vector<ClEvent>& events, ClEventKind kind) {
  std::vector<ClEvent> out;
  for (const ClEvent& e : events) {
    if (e.kind == kind)
      out.push_back(e);
  }
  return out;
}

std::vector<ClEvent> moves_of(const std::string& text, const ClReaderOptions& options = {}) {
  return of_kind(read_all(text, options).events, ClEventKind::move);
}

// The Error that reading `text` throws; fails the test when there is none.
Error error_of(const std::string& text, const ClReaderOptions& options = {}) {
  try {
    read_all(text, options);
  } catch (const Error& e) {
    return e;
  }
  FAIL("no error for:\n" << text);
  return Error(ErrorCode::internal, "unreachable");
}

// Column 0: the whole record is at fault, as what the expander (cl/expander.hpp) refuses is:
// what a cycle, an MSYS or an operator text means, not one of its values.
void check_error(const std::string& text, int line, int column, const std::string& fragment,
                 const ClReaderOptions& options = {}) {
  INFO("input:\n" << text);
  const Error e = error_of(text, options);
  INFO("message: " << e.what());
  CHECK(e.code() == ErrorCode::bad_input);
  CHECK(e.where().file == "t.apt");
  CHECK(e.where().line == line);
  CHECK(e.where().column == column);
  CHECK(e.message().find(fragment) != std::string::npos);
}

bool near(const Vector3d& a, const Vector3d& b, double tol = 1e-12) {
  return (a - b).norm() <= tol;
}

// Exact decimal text of a double, so that the reader parses back the very same number.
std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

std::string xyz(const Vector3d& p) {
  return num(p.x()) + "," + num(p.y()) + "," + num(p.z());
}

// Checks a linearised arc about the line through `centre` along the unit `axis`: every point at
// `radius` from the axis within 1e-9, height along the axis linear from h0 to h1, every chord's
// sagitta within the tolerance, every chord turning positively about `axis` (right-hand rule),
// the total turn equal to `sweep`, and the last point exactly `end`.
void check_arc(const std::vector<ClEvent>& pieces, const Vector3d& start, const Vector3d& centre,
               const Vector3d& axis, double radius, double sweep, const Vector3d& end,
               double tolerance) {
  REQUIRE(!pieces.empty());
  Vector3d prev = start;
  double turned = 0.0;
  for (const ClEvent& e : pieces) {
    CHECK(e.origin == MoveOrigin::arc);
    const Vector3d r = e.p_mm - centre;
    const Vector3d radial = r - r.dot(axis) * axis;
    CHECK(std::fabs(radial.norm() - radius) <= 1e-9);
    const Vector3d r_prev = prev - centre;
    const Vector3d radial_prev = r_prev - r_prev.dot(axis) * axis;
    const double turn = std::atan2(axis.dot(radial_prev.cross(radial)), radial_prev.dot(radial));
    CHECK(turn > 0.0);  // right-hand rule about axis
    turned += turn;
    const double half_chord = 0.5 * (radial - radial_prev).norm();
    const double sagitta = radius - std::sqrt(radius * radius - half_chord * half_chord);
    CHECK(sagitta <= tolerance * (1.0 + 1e-9));
    prev = e.p_mm;
  }
  CHECK(std::fabs(turned - sweep) <= 1e-9);
  CHECK(pieces.back().p_mm == end);  // exact
}

// Cox-de Boor basis functions: an evaluation independent of the reader's de Boor algorithm.
double basis(const std::vector<double>& u, int i, int p, double t) {
  if (p == 0) {
    const bool last_span = t == u.back() && u[i] < u[i + 1] && u[i + 1] == u.back();
    return (u[i] <= t && t < u[i + 1]) || last_span ? 1.0 : 0.0;
  }
  double a = 0.0, b = 0.0;
  if (u[i + p] > u[i])
    a = (t - u[i]) / (u[i + p] - u[i]) * basis(u, i, p - 1, t);
  if (u[i + p + 1] > u[i + 1])
    b = (u[i + p + 1] - t) / (u[i + p + 1] - u[i + 1]) * basis(u, i + 1, p - 1, t);
  return a + b;
}

Vector3d nurbs_point(const std::vector<double>& u, int p, const std::vector<Vector3d>& points,
                     const std::vector<double>& weights, double t) {
  Vector3d num_sum = Vector3d::Zero();
  double den = 0.0;
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    const double nw = basis(u, i, p, t) * weights[static_cast<std::size_t>(i)];
    num_sum += nw * points[static_cast<std::size_t>(i)];
    den += nw;
  }
  return num_sum / den;
}

double distance_to_polyline(const Vector3d& q, const std::vector<Vector3d>& line) {
  double best = (q - line.front()).norm();
  for (std::size_t i = 1; i < line.size(); ++i) {
    const Vector3d d = line[i] - line[i - 1];
    const double len2 = d.squaredNorm();
    const double u = len2 > 0.0 ? std::clamp((q - line[i - 1]).dot(d) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, (q - (line[i - 1] + u * d)).norm());
  }
  return best;
}

// The reader's polyline of a NURBS (start point + chord ends) against the curve sampled densely
// with the independent evaluation: every chord end lies on the curve, and the curve nowhere
// strays from the polyline by more than the tolerance.
void check_nurbs(const Vector3d& start, const std::vector<ClEvent>& pieces,
                 const std::vector<double>& knots, int degree, const std::vector<Vector3d>& points,
                 const std::vector<double>& weights, double tolerance) {
  REQUIRE(!pieces.empty());
  std::vector<Vector3d> polyline{start};
  for (const ClEvent& e : pieces) {
    CHECK(e.origin == MoveOrigin::nurbs);
    polyline.push_back(e.p_mm);
  }
  const double t0 = knots[static_cast<std::size_t>(degree)];
  const double t1 = knots[points.size()];
  std::vector<Vector3d> dense;
  const int samples = 20000;
  for (int s = 0; s <= samples; ++s)
    dense.push_back(nurbs_point(knots, degree, points, weights, t0 + (t1 - t0) * s / samples));
  CHECK(near(polyline.front(), dense.front(), 1e-12));
  CHECK(near(polyline.back(), dense.back(), 1e-9));
  double on_curve = 0.0, off_polyline = 0.0;
  for (const Vector3d& p : polyline)
    on_curve = std::max(on_curve, distance_to_polyline(p, dense));
  for (const Vector3d& q : dense)
    off_polyline = std::max(off_polyline, distance_to_polyline(q, polyline));
  CHECK(on_curve <= 1e-5);  // the dense sampling's own chords are that far from the curve
  CHECK(off_polyline <= tolerance);
}

const char* const kEvaldata = "/work/shared/evaldata";

}  // namespace

// ---------------------------------------------------------------------------------------------
// Syntax

TEST_CASE("cl_reader: comments, blank lines, case, spaces and number forms") {
  const auto moves = moves_of(
      "$$ a comment line\n"
      "\n"
      "goto/1,2,3\n"
      "GoTo / 3. , .5 , -.5   $$ a comment after the record\n"
      "GOTO/1e3,+2,-1E-1\r\n"
      "   \t\n"
      "  GOTO/0,0,10,0,0,2\n");
  REQUIRE(moves.size() == 4);
  CHECK(moves[0].p_mm == Vector3d(1, 2, 3));
  CHECK(moves[0].line == 3);
  CHECK(moves[1].p_mm == Vector3d(3.0, 0.5, -0.5));
  CHECK(moves[1].line == 4);
  CHECK(moves[2].p_mm == Vector3d(1000.0, 2.0, -0.1));
  CHECK(moves[2].line == 5);
  CHECK(moves[3].line == 7);
  CHECK(moves[3].tool_axis == Vector3d(0, 0, 1));  // (0,0,2) normalised
  for (const ClEvent& m : moves) {
    CHECK(m.origin == MoveOrigin::goto_point);
    CHECK_FALSE(m.rapid);
  }
}

TEST_CASE("cl_reader: a continued record has its first line; errors name the physical line") {
  const auto moves = moves_of(
      "GOTO/1,$\n"
      "  2,3\n"
      "GOTO/4,5,$ $$ a comment after the continuation mark\n"
      "6\n"
      "GOTO/7,8,9\n");
  REQUIRE(moves.size() == 3);
  CHECK(moves[0].p_mm == Vector3d(1, 2, 3));
  CHECK(moves[0].line == 1);
  CHECK(moves[1].p_mm == Vector3d(4, 5, 6));
  CHECK(moves[1].line == 3);
  CHECK(moves[2].line == 5);

  check_error("GOTO/1,$\n  2,x\n", 2, 5, "not a number");
  check_error("GOTO/1,2,3\nGOTO/1,2,3$\n", 2, 0, "continuation");
}

TEST_CASE("cl_reader: $$ comments are kept on request; PPRINT always gives a comment") {
  const std::string text = "$$ hello\nGOTO/1,2,3 $$ there\nPPRINT/Keep This\n";
  ClReaderOptions keep;
  keep.keep_comments = true;
  const auto kept = read_all(text, keep).events;
  REQUIRE(kept.size() == 4);
  CHECK(kept[0].kind == ClEventKind::comment);
  CHECK(kept[0].text == "hello");
  CHECK(kept[0].line == 1);
  CHECK(kept[1].kind == ClEventKind::move);
  CHECK(kept[2].kind == ClEventKind::comment);
  CHECK(kept[2].text == "there");
  CHECK(kept[2].line == 2);
  CHECK(kept[3].kind == ClEventKind::comment);
  CHECK(kept[3].text == "Keep This");

  const auto dropped = read_all(text).events;
  REQUIRE(dropped.size() == 2);
  CHECK(dropped[0].kind == ClEventKind::move);
  CHECK(dropped[1].text == "Keep This");
}

TEST_CASE("cl_reader: PARTNO, INSERT, PPRINT, END and FINI") {
  const auto r = read_all(
      "PARTNO/ Bracket 7 \n"
      "INSERT/[HOLDER=C40] Lin_Rel {X 5} $VEL.CP=0.2  \n"
      "PPRINT  old style, no slash\n"
      "PARTNO OLD STYLE\n"
      "INSERT/krl:  $OUT[17] = TRUE \n"
      "END\n"
      "FINI\n");
  const auto& events = r.events;
  REQUIRE(events.size() == 7);
  CHECK(events[0].kind == ClEventKind::part_name);
  CHECK(events[0].text == "Bracket 7");
  // Operator text is never code: a comment, with a warning naming its line.
  CHECK(events[1].kind == ClEventKind::comment);
  CHECK(events[1].text == "[HOLDER=C40] Lin_Rel {X 5} $VEL.CP=0.2");  // case kept
  CHECK(events[1].line == 2);
  CHECK(events[2].kind == ClEventKind::comment);
  CHECK(events[2].text == "old style, no slash");
  CHECK(events[3].kind == ClEventKind::part_name);
  CHECK(events[3].text == "OLD STYLE");
  // The explicit pass-through form gives the statement after "KRL:" (any case).
  CHECK(events[4].kind == ClEventKind::literal);
  CHECK(events[4].text == "$OUT[17] = TRUE");
  CHECK(events[4].line == 5);
  CHECK(events[5].kind == ClEventKind::end_of_program);
  CHECK(events[6].kind == ClEventKind::end_of_program);
  CHECK(events[6].line == 7);
  REQUIRE(r.warnings.size() == 2);
  CHECK(r.warnings[0].find("t.apt:2: INSERT/ text written as a comment") == 0);
  CHECK(r.warnings[0].find("INSERT/KRL:") != std::string::npos);
  CHECK(r.warnings[1].find("t.apt:3: PPRINT/ text written as a comment") == 0);

  check_error("INSERT/KRL:   \n", 1, 0, "needs a KRL statement");
}

TEST_CASE("cl_reader: operator-text warnings are capped, each names its line") {
  std::string text;
  for (int i = 0; i < 30; ++i)
    text += "INSERT/note " + std::to_string(i) + "\n";
  const auto r = read_all(text);
  CHECK(of_kind(r.events, ClEventKind::comment).size() == 30);
  REQUIRE(r.warnings.size() == 21);
  CHECK(r.warnings[19].find("t.apt:20: INSERT/") == 0);
  CHECK(r.warnings[20].find("t.apt:21: more INSERT/PPRINT text") == 0);
}

// ---------------------------------------------------------------------------------------------
// Units, axes, motion

TEST_CASE("cl_reader: an INCHES file gives mm and mm/min") {
  const auto events = read_all(
                          "UNITS/INCHES\n"
                          "CUTTER/.5,0.125\n"
                          "LOADTL/3\n"
                          "GOTO/1,2,-.5\n"
                          "FEDRAT/10,IPM\n"
                          "FEDRAT/4\n"
                          "GODLTA/0,0,1\n"
                          "FEDRAT/100,MMPM\n"
                          "UNIT/MM\n"
                          "GOTO/1,2,3\n"
                          "FEDRAT/100\n"
                          "UNIT/INCH\n"
                          "GOTO/1,0,0\n")
                          .events;
  const auto tools = of_kind(events, ClEventKind::tool_change);
  REQUIRE(tools.size() == 1);
  CHECK(tools[0].tool_diameter_mm == Approx(12.7).epsilon(1e-15));
  const auto moves = of_kind(events, ClEventKind::move);
  REQUIRE(moves.size() == 4);
  CHECK(near(moves[0].p_mm, Vector3d(25.4, 50.8, -12.7)));
  CHECK(near(moves[1].p_mm, Vector3d(25.4, 50.8, 12.7)));
  CHECK(moves[2].p_mm == Vector3d(1, 2, 3));
  CHECK(moves[3].p_mm == Vector3d(25.4, 0, 0));
  const auto feeds = of_kind(events, ClEventKind::feed);
  REQUIRE(feeds.size() == 4);
  CHECK(feeds[0].value == Approx(254.0).epsilon(1e-15));
  CHECK(feeds[1].value == Approx(101.6).epsilon(1e-15));
  CHECK(feeds[2].value == 100.0);  // MMPM in an inch file is still mm/min
  CHECK(feeds[3].value == 100.0);
}

TEST_CASE("cl_reader: the tool axis is set, kept, normalised, and +Z without MULTAX") {
  const auto moves = moves_of(
      "GOTO/0,0,0\n"
      "TLAXIS/0,3,4\n"
      "GOTO/1,0,0\n"
      "GOTO/2,0,0,1,0,0\n"
      "GOTO/3,0,0\n"
      "MULTAX/ON\n"
      "GOTO/4,0,0\n");
  REQUIRE(moves.size() == 5);
  CHECK(moves[0].tool_axis == Vector3d(0, 0, 1));
  CHECK(near(moves[1].tool_axis, Vector3d(0, 0.6, 0.8)));
  CHECK(moves[2].tool_axis == Vector3d(1, 0, 0));
  CHECK(moves[3].tool_axis == Vector3d(1, 0, 0));  // persists when omitted
  CHECK(moves[4].tool_axis == Vector3d(1, 0, 0));

  // MULTAX/ON: a GOTO needs an axis first; TLAXIS or a GOTO with i,j,k gives one.
  check_error("MULTAX/ON\nGOTO/1,2,3\n", 2, 1, "before any tool axis is known");
  CHECK(moves_of("MULTAX\nTLAXIS/0,0,1\nGOTO/1,2,3\n").size() == 1);
  CHECK(moves_of("MULTAX/ON\nGOTO/1,2,3,0,1,0\nGOTO/1,2,4\n").back().tool_axis ==
        Vector3d(0, 1, 0));
}

TEST_CASE("cl_reader: FROM and GODLTA") {
  const auto moves = moves_of(
      "FROM/0,0,100,0,0,1\n"
      "GODLTA/0,0,-10\n"
      "TLAXIS/1,0,0\n"
      "GODLTA/5\n");
  REQUIRE(moves.size() == 3);
  CHECK(moves[0].origin == MoveOrigin::from_point);
  CHECK(moves[0].p_mm == Vector3d(0, 0, 100));
  CHECK(moves[1].origin == MoveOrigin::goto_point);
  CHECK(moves[1].p_mm == Vector3d(0, 0, 90));
  CHECK(moves[2].p_mm == Vector3d(5, 0, 90));  // along the tool axis
  CHECK(moves[2].tool_axis == Vector3d(1, 0, 0));
  check_error("GODLTA/1,2,3\n", 1, 1, "needs a known position");
  check_error("GOTO/0,0,0\nGODLTA/1,2\n", 2, 1, "GODLTA takes 1 value");
}

TEST_CASE("cl_reader: RAPID applies to the next move only, with or without the slash") {
  const auto events = read_all(
                          "RAPID\n"
                          "GOTO/0,0,10\n"
                          "GOTO/0,0,5\n"
                          "rapid/\n"
                          "FEDRAT/100\n"
                          "GOTO/1,0,5\n"
                          "GOTO/2,0,5\n")
                          .events;
  std::vector<ClEventKind> kinds;
  for (const ClEvent& e : events)
    kinds.push_back(e.kind);
  CHECK(kinds == std::vector<ClEventKind>{ClEventKind::rapid, ClEventKind::move, ClEventKind::move,
                                          ClEventKind::rapid, ClEventKind::feed, ClEventKind::move,
                                          ClEventKind::move});
  const auto moves = of_kind(events, ClEventKind::move);
  CHECK(moves[0].rapid);
  CHECK_FALSE(moves[1].rapid);
  CHECK(moves[2].rapid);
  CHECK_FALSE(moves[3].rapid);
  check_error("RAPID/ON\n", 1, 7, "RAPID takes no values");
}

// ---------------------------------------------------------------------------------------------
// Feed, spindle, coolant, tools

TEST_CASE("cl_reader: FEDRAT in both orders, per minute and per revolution") {
  const auto events = read_all(
                          "FEDRAT/250,MMPM\n"
                          "FEDRAT/MMPM,300\n"
                          "FEDRAT/120\n"
                          "SPINDL/1000,RPM,CLW\n"
                          "FEDRAT/0.1,MMPR\n"
                          "SPINDL/2000\n"
                          "FEDRAT/IPM,10\n"
                          "FEDRAT/0.01,IPR\n")
                          .events;
  const auto feeds = of_kind(events, ClEventKind::feed);
  REQUIRE(feeds.size() == 7);
  CHECK(feeds[0].value == 250.0);
  CHECK(feeds[1].value == 300.0);
  CHECK(feeds[2].value == 120.0);
  CHECK(feeds[3].value == Approx(100.0).epsilon(1e-15));
  CHECK(feeds[4].value == Approx(200.0).epsilon(1e-15));  // a feed per rev follows SPINDL
  CHECK(feeds[4].line == 6);
  CHECK(feeds[5].value == Approx(254.0).epsilon(1e-15));
  CHECK(feeds[6].value == Approx(0.254 * 2000.0).epsilon(1e-14));

  check_error("FEDRAT/0.1,MMPR\n", 1, 8, "spindle speed is not known");
  check_error("SPINDL/OFF\nFEDRAT/MMPR,0.1\n", 2, 13, "spindle speed is not known");
  check_error("FEDRAT/100,MMPS\n", 1, 12, "unknown feed unit");
  check_error("FEDRAT/0\n", 1, 8, "must be > 0");
}

TEST_CASE("cl_reader: SPINDL and COOLNT forms") {
  const auto events = read_all(
                          "SPINDL/4948,RPM,CLW\n"
                          "SPINDL/RPM,1200,CCLW\n"
                          "SPINDL/OFF\n"
                          "SPINDL/ON\n"
                          "SPINDL/800\n"
                          "COOLNT/FLOOD\n"
                          "COOLNT/mist\n"
                          "COOLNT/OFF\n"
                          "COOLNT/ON\n"
                          "COOLNT/THRU\n"
                          "COOLNT/TAP\n")
                          .events;
  const auto s = of_kind(events, ClEventKind::spindle);
  REQUIRE(s.size() == 5);
  CHECK((s[0].value == 4948.0 && s[0].direction == SpindleDirection::clockwise));
  CHECK((s[1].value == 1200.0 && s[1].direction == SpindleDirection::counter_clockwise));
  CHECK((s[2].value == 0.0 && s[2].direction == SpindleDirection::off));
  CHECK((s[3].value == 1200.0 && s[3].direction == SpindleDirection::counter_clockwise));
  CHECK((s[4].value == 800.0 && s[4].direction == SpindleDirection::clockwise));
  const auto c = of_kind(events, ClEventKind::coolant);
  REQUIRE(c.size() == 6);
  CHECK((c[0].flag && c[0].text == "FLOOD"));
  CHECK((c[1].flag && c[1].text == "MIST"));
  CHECK((!c[2].flag && c[2].text == "OFF"));
  CHECK((c[3].flag && c[3].text == "ON"));
  CHECK((c[4].flag && c[4].text == "THRU"));
  CHECK((c[5].flag && c[5].text == "TAP"));
  check_error("COOLNT/FOG\n", 1, 8, "unknown mode");
  check_error("SPINDL/100,SFM\n", 1, 12, "surface speed");
}

TEST_CASE("cl_reader: LOAD/TOOL and LOADTL change tools; SELECT/TOOL only preselects") {
  // SolidWorks CAM: CUTTER, LOAD/TOOL, then SELECT/TOOL with the *next* tool's number.
  const std::string sw =
      "CUTTER/14.,0,7.,4.206024,31.,0,69.\n"
      "LOAD/TOOL,15\n"
      "SELECT/TOOL,16\n"
      "CUTTER/6.7\n"
      "LOADTL/16,ADJUST,16\n";
  const auto tools = of_kind(read_all(sw).events, ClEventKind::tool_change);
  REQUIRE(tools.size() == 2);
  CHECK(tools[0].tool_number == 15);
  CHECK(tools[0].tool_diameter_mm == 14.0);
  CHECK(tools[0].tool_length_mm == 69.0);  // h of the 7-value CUTTER
  CHECK(tools[0].line == 2);
  CHECK(tools[1].tool_number == 16);
  CHECK(tools[1].tool_diameter_mm == 6.7);
  CHECK(tools[1].tool_length_mm == 0.0);

  ClReaderOptions loads;
  loads.select_tool_loads = true;
  const auto with_select = of_kind(read_all(sw, loads).events, ClEventKind::tool_change);
  REQUIRE(with_select.size() == 3);
  CHECK(with_select[1].tool_number == 16);
  CHECK(with_select[1].line == 3);

  // NX: TOOL PATH names the operation and the tool, TLDATA gives its size, LOAD/TOOL changes.
  const auto nx = read_all(
                      "TOOL PATH/BOK_7,TOOL,R390-25A25L-17L\n"
                      "TLDATA/MILL,25.0000,0.0000,75.0000,0.0000,0.0000\n"
                      "LOAD/TOOL,1,ADJUST,1 \n"
                      "END-OF-PATH\n")
                      .events;
  REQUIRE(nx.size() == 3);
  CHECK(nx[0].kind == ClEventKind::operation_start);
  CHECK(nx[0].text == "BOK_7");
  CHECK(nx[1].kind == ClEventKind::tool_change);
  CHECK(nx[1].tool_number == 1);
  CHECK(nx[1].text == "R390-25A25L-17L");
  CHECK(nx[1].tool_diameter_mm == 25.0);
  CHECK(nx[1].tool_length_mm == 75.0);
  CHECK(nx[2].kind == ClEventKind::operation_end);
  CHECK(nx[2].line == 4);

  check_error("LOAD/TOOL,2.5\n", 1, 11, "whole number");
  check_error("LOAD/SPINDLE,2\n", 1, 6, "LOAD/TOOL,n");
}

TEST_CASE("cl_reader: MSYS, PAINT, CSYS, TRNTYP and CUTCOM are read and give no motion") {
  const auto r = read_all(
      "UNITS/MM\n"
      "MSYS/393.0000,-297.5000,3.0000,0.0000000,1.0000000,0.0000000,1.0000000,0.0000000,0."
      "0000000\n"
      "PAINT/COLOR,186\n"
      "TRNTYP/WORLD,0,0,0\n"
      "CSYS/1.,0,0,0,0,1.,0,0,0,0,1.,0\n"
      "CUTCOM/LEFT,XYPLAN\n"
      "GOTO/1,2,3\n"
      "CUTCOM/OFF\n"
      "CUTCOM/RIGHT\n");
  REQUIRE(r.events.size() == 2);
  // MSYS gives its frame (for messages) and, by default, leaves the data in the MCS.
  CHECK(r.events[0].kind == ClEventKind::machine_frame);
  CHECK(r.events[0].line == 2);
  CHECK_FALSE(r.events[0].flag);
  CHECK(r.events[0].p_mm.isApprox(Eigen::Vector3d(393, -297.5, 3)));
  CHECK(r.events[0].tool_axis.isApprox(Eigen::Vector3d(0, 0, -1)));  // X = y, Y = x: z down
  CHECK(r.events[1].kind == ClEventKind::move);
  CHECK(r.events[1].p_mm.isApprox(Eigen::Vector3d(1, 2, 3)));
  REQUIRE(r.warnings.size() == 1);  // once per file
  CHECK(r.warnings[0].find("t.apt:6: CUTCOM/LEFT ignored") == 0);

  check_error("CSYS/1,0,0,5,0,1,0,0,0,0,1,0\n", 1, 1, "identity");
  check_error("TRNTYP/WORLD,0,0,10\n", 1, 1, "TRNTYP/WORLD,0,0,0");
  check_error("MSYS/0,0,0,1,0,0,1,0,0\n", 1, 0, "orthogonal");
  // With the MCS as the workpiece frame, a second, different MCS cannot be placed: refused.
  check_error("MSYS/0,0,0,1,0,0,0,1,0\nGOTO/1,2,3\nMSYS/0,0,5,1,0,0,0,1,0\n", 3, 0,
              "differs from the one at line 1");
}

TEST_CASE("cl_reader: --msys apply turns points, tool axes and circles into NX's absolute frame") {
  // A z-down MCS as in NX 5-axis samples: X_mcs = (0,1,0), Y_mcs = (1,0,0), origin (10,20,30).
  const std::string text =
      "TOOL PATH/OP1,TOOL,T1\n"
      "MSYS/10,20,30,0,1,0,1,0,0\n"
      "GOTO/1,2,3,0,0,-1\n"
      "GODLTA/0,0,-2\n"
      "CIRCLE/1,4,1,0,0,1,2,0.01,0.5,10,0\n"
      "GOTO/3,4,1\n";
  ClReaderOptions apply;
  apply.msys = MsysMode::apply;
  apply.chordal_tolerance_mm = 0.001;
  const auto r = read_all(text, apply);
  const auto moves = of_kind(r.events, ClEventKind::move);
  REQUIRE(moves.size() >= 3);
  // p_abs = o + R p with R = [X Y Z], Z = X x Y = (0,0,-1).
  CHECK(moves[0].p_mm.isApprox(Eigen::Vector3d(10 + 2, 20 + 1, 30 - 3)));
  CHECK(moves[0].tool_axis.isApprox(Eigen::Vector3d(0, 0, 1)));  // the tool points up now
  CHECK(moves[1].p_mm.isApprox(Eigen::Vector3d(12, 21, 29)));    // the delta turned too
  // The arc from MCS (1,2,1) to (3,4,1) about the centre (1,4,1): every chord point is 2 from
  // the centre, turned into the absolute frame (14, 21, 29).
  const Eigen::Vector3d centre_abs(10 + 4, 20 + 1, 30 - 1);
  for (std::size_t i = 2; i < moves.size(); ++i) {
    CHECK(std::fabs((moves[i].p_mm - centre_abs).norm() - 2.0) < 1e-3);
    CHECK(std::fabs(moves[i].p_mm.z() - 29.0) < 1e-9);
  }
  CHECK(moves.back().p_mm.isApprox(Eigen::Vector3d(14, 23, 29)));
  const auto frames = of_kind(r.events, ClEventKind::machine_frame);
  REQUIRE(frames.size() == 1);
  CHECK(frames[0].flag);

  // Under apply, each operation may have its own MCS.
  ClReaderOptions apply2 = apply;
  CHECK_NOTHROW(
      read_all("MSYS/0,0,0,1,0,0,0,1,0\nGOTO/1,2,3\nMSYS/0,0,5,1,0,0,0,1,0\n"
               "GOTO/1,2,3\n",
               apply2));
}

TEST_CASE("cl_reader: unknown words give one event and one warning per word") {
  const auto r = read_all(
      "UNITS/MM\n"
      "CSI_SET_FLUTE_LENGTH/5.\n"
      "LINTOL/0.01\n"
      "CSI_SET_FLUTE_LENGTH/73.\n"
      "OPSTOP\n"
      "GOTO/1,2,3\n"
      "LINTOL/ anything ,, goes\n");
  const auto unknown = of_kind(r.events, ClEventKind::unknown_word);
  REQUIRE(unknown.size() == 3);
  CHECK(unknown[0].text == "CSI_SET_FLUTE_LENGTH");
  CHECK(unknown[1].text == "LINTOL");
  CHECK(unknown[2].text == "OPSTOP");
  CHECK(unknown[2].line == 5);
  REQUIRE(r.warnings.size() == 3);
  CHECK(r.warnings[0] == "t.apt:2: unknown word CSI_SET_FLUTE_LENGTH ignored");
  CHECK(r.warnings[1] == "t.apt:3: unknown word LINTOL ignored");
  CHECK(r.warnings[2] == "t.apt:5: unknown word OPSTOP ignored");
  CHECK(of_kind(r.events, ClEventKind::move).size() == 1);

  // Reporting stops after 1000 different words, with one more warning saying so.
  std::string many;
  for (int i = 0; i < 1500; ++i)
    many += "VENDOR_WORD_" + std::to_string(i) + "/1\n";
  const auto flood = read_all(many);
  CHECK(of_kind(flood.events, ClEventKind::unknown_word).size() == 1000);
  REQUIRE(flood.warnings.size() == 1001);
  CHECK(flood.warnings.back() ==
        "t.apt:1001: more than 1000 different unknown words; the others are ignored without a "
        "warning");
}

// ---------------------------------------------------------------------------------------------
// Arcs

TEST_CASE("cl_reader: 6-value CIRCLE arcs lie on the circle, within tolerance, turning right") {
  ClReaderOptions opt;
  opt.chordal_tolerance_mm = 0.01;
  // A quarter turn about +Z from (10,0) to (0,10), then the same pair about -Z (three quarters).
  const auto ccw = moves_of("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1.\nGOTO/0,10,0\n", opt);
  REQUIRE(ccw.size() > 2);
  const std::vector<ClEvent> ccw_arc(ccw.begin() + 1, ccw.end());
  check_arc(ccw_arc, Vector3d(10, 0, 0), Vector3d::Zero(), Vector3d::UnitZ(), 10.0, kPi / 2,
            Vector3d(0, 10, 0), opt.chordal_tolerance_mm);
  CHECK(ccw_arc.back().line == 3);  // the GOTO that ends the arc

  const auto cw = moves_of("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,-1.\nGOTO/0,10,0\n", opt);
  const std::vector<ClEvent> cw_arc(cw.begin() + 1, cw.end());
  check_arc(cw_arc, Vector3d(10, 0, 0), Vector3d::Zero(), -Vector3d::UnitZ(), 10.0, 1.5 * kPi,
            Vector3d(0, 10, 0), opt.chordal_tolerance_mm);
  CHECK(cw_arc.size() > 2 * ccw_arc.size());

  // A GOTO back to the start point closes a full circle (SolidWorks CAM writes circles so).
  const auto full = moves_of("GOTO/15.,-3.,-5.\nCIRCLE/15.,15.,-5.,0,0,-1.\nGOTO/15.,-3.,-5.\n");
  const std::vector<ClEvent> full_arc(full.begin() + 1, full.end());
  check_arc(full_arc, Vector3d(15, -3, -5), Vector3d(15, 15, -5), -Vector3d::UnitZ(), 18.0, 2 * kPi,
            Vector3d(15, -3, -5), 0.01);

  // An arc that turns through almost all of the circle.
  const double a = 2 * kPi - 1e-3;
  const Vector3d almost(10 * std::cos(a), 10 * std::sin(a), 0);
  const auto most = moves_of("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1\nGOTO/" + xyz(almost) + "\n");
  const std::vector<ClEvent> most_arc(most.begin() + 1, most.end());
  check_arc(most_arc, Vector3d(10, 0, 0), Vector3d::Zero(), Vector3d::UnitZ(), 10.0,
            std::atan2(almost.y(), almost.x()) + 2 * kPi, almost, 0.01);
}

TEST_CASE("cl_reader: random arcs in any plane meet every arc property") {
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Vector3d centre(300 * unit(rng), 300 * unit(rng), 300 * unit(rng));
    Vector3d n(unit(rng), unit(rng), unit(rng));
    n.normalize();
    const double radius = 0.5 + 200 * u01(rng);
    const double sweep = 0.01 + (2 * kPi - 0.02) * u01(rng);
    ClReaderOptions opt;
    opt.chordal_tolerance_mm = std::pow(10.0, -4.0 + 3.0 * u01(rng));
    // Start and end on the circle, written with 17 digits.
    const Vector3d u = n.unitOrthogonal();
    const Vector3d v = n.cross(u);
    const double a0 = 2 * kPi * u01(rng);
    const Vector3d start = centre + radius * (std::cos(a0) * u + std::sin(a0) * v);
    const Vector3d end = centre + radius * (std::cos(a0 + sweep) * u + std::sin(a0 + sweep) * v);
    const Vector3d parsed_start(std::stod(num(start.x())), std::stod(num(start.y())),
                                std::stod(num(start.z())));
    const Vector3d r0 = parsed_start - centre;
    const double parsed_radius = (r0 - r0.dot(n) * n).norm();
    // The axis as written is n, but the reader keeps the unit vector of what it parses.
    const bool flip = u01(rng) < 0.5;  // write -n and go the other way round
    const std::string text = "GOTO/" + xyz(start) + "\nCIRCLE/" + xyz(centre) + "," +
                             xyz(flip ? Vector3d(-n) : n) + "\nGOTO/" + xyz(end) + "\n";
    INFO("trial " << trial << ":\n" << text);
    const auto moves = moves_of(text, opt);
    const std::vector<ClEvent> arc(moves.begin() + 1, moves.end());
    check_arc(arc, parsed_start, centre, flip ? Vector3d(-n) : n, parsed_radius,
              flip ? 2 * kPi - sweep : sweep, arc.back().p_mm, opt.chordal_tolerance_mm);
    CHECK(near(arc.back().p_mm, end, 1e-9));
  }
}

TEST_CASE("cl_reader: 11-value NX CIRCLE gives its axis for clockwise travel") {
  // NX's CLSF manual: "i,j,k is the circle axis vector ... assuming a clockwise direction".
  // The NX files in evaldata agree: with the right-hand rule every arc would reverse the tool.
  const std::string nx =
      "TOOL PATH/CONTOUR,TOOL,MILL_10\n"
      "GOTO/10,0,0,0,0,1\n"
      "CIRCLE/0,0,0,0.0000000,0.0000000,1.0000000,10.0000,0.0600,0.5000,40.0000,1.0000\n"
      "GOTO/0,10,0\n";
  const auto moves = moves_of(nx);
  const std::vector<ClEvent> arc(moves.begin() + 1, moves.end());
  check_arc(arc, Vector3d(10, 0, 0), Vector3d::Zero(), -Vector3d::UnitZ(), 10.0, 1.5 * kPi,
            Vector3d(0, 10, 0), 0.01);

  // The same records read as APT turn the short way.
  ClReaderOptions apt;
  apt.dialect = ClDialect::apt;
  const auto apt_moves = moves_of(nx, apt);
  const std::vector<ClEvent> apt_arc(apt_moves.begin() + 1, apt_moves.end());
  check_arc(apt_arc, Vector3d(10, 0, 0), Vector3d::Zero(), Vector3d::UnitZ(), 10.0, kPi / 2,
            Vector3d(0, 10, 0), 0.01);

  // The 7-value form (radius only) and a radius that contradicts the start point.
  CHECK(moves_of("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nGOTO/0,10,0\n").size() > 2);
  check_error("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,12\nGOTO/0,12,0\n", 2, 0,
              "CIRCLE gives the radius 12");
}

TEST_CASE("cl_reader: arc helix, tool axis along the arc, and arc errors") {
  const auto helix = moves_of("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1\nGOTO/0,10,5\n");
  const std::vector<ClEvent> arc(helix.begin() + 1, helix.end());
  REQUIRE(arc.size() > 2);
  double prev_z = 0.0, prev_turn = 0.0;
  for (const ClEvent& e : arc) {
    const double turn = std::atan2(e.p_mm.y(), e.p_mm.x());
    CHECK(std::hypot(e.p_mm.x(), e.p_mm.y()) == Approx(10.0).epsilon(1e-12));
    CHECK(e.p_mm.z() > prev_z);
    CHECK((e.p_mm.z() - prev_z) / (turn - prev_turn) == Approx(5.0 / (kPi / 2)).epsilon(1e-9));
    prev_z = e.p_mm.z();
    prev_turn = turn;
  }
  CHECK(arc.back().p_mm == Vector3d(0, 10, 5));

  // Arc points keep the current tool axis; the GOTO's own axis applies at its point.
  const auto tilted = moves_of("GOTO/10,0,0,0,0,1\nCIRCLE/0,0,0,0,0,1\nGOTO/0,10,0,0,1,1\n");
  for (std::size_t i = 1; i + 1 < tilted.size(); ++i)
    CHECK(tilted[i].tool_axis == Vector3d(0, 0, 1));
  CHECK(near(tilted.back().tool_axis, Vector3d(0, 1, 1).normalized()));

  check_error("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1\nGOTO/0,10.5,0\n", 3, 6, "not on the circle");
  check_error("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,0\nGOTO/0,10,0\n", 2, 14, "circle axis");
  check_error("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10,0.06\nGOTO/0,10,0\n", 2, 23, "CIRCLE takes 6");
  check_error("CIRCLE/0,0,0,0,0,1\nGOTO/0,10,0\n", 1, 1, "needs a start point");
  check_error("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1\nGODLTA/1,0,0\n", 3, 1, "must be followed by");
  check_error("GOTO/10,0,0\nCIRCLE/0,0,0,0,0,1\n", 2, 0, "without the GOTO");
  check_error("GOTO/0,0,0\nCIRCLE/0,0,5,0,0,1\nGOTO/1,0,0\n", 2, 0, "lies on the circle's axis");
}

// ---------------------------------------------------------------------------------------------
// NURBS

TEST_CASE("cl_reader: a rational quadratic NURBS in NX form is a quarter circle") {
  // NX writes the knots without the leading zeros and all but one of the trailing ends, and
  // leaves out the first control point (the current position): 1 knot and 2 CNTRL give
  // order 2 + 2 - 1 = 3, knot vector (0,0,0,1,1,1), points (10,0) (10,10 w=sqrt2/2) (0,10).
  const double w = std::sqrt(0.5);
  ClReaderOptions opt;
  opt.chordal_tolerance_mm = 0.001;
  const auto events = read_all(
                          "GOTO/10,0,0\n"
                          "NURBS/\n"
                          "KNOT/1.0000000\n"
                          "CNTRL/10,10,0," +
                              num(w) +
                              "\n"
                              "CNTRL/0,10,0\n"
                              "GOTO/0,20,0\n",
                          opt)
                          .events;
  const auto moves = of_kind(events, ClEventKind::move);
  REQUIRE(moves.size() > 3);
  const std::vector<ClEvent> curve(moves.begin() + 1, moves.end() - 1);
  Vector3d prev(10, 0, 0);
  for (const ClEvent& e : curve) {
    CHECK(e.origin == MoveOrigin::nurbs);
    CHECK(e.line == 2);
    CHECK(std::fabs(e.p_mm.norm() - 10.0) <= 1e-9);  // on the circle
    const double half = 0.5 * (e.p_mm - prev).norm();
    CHECK(10.0 - std::sqrt(100.0 - half * half) <= opt.chordal_tolerance_mm);
    CHECK(prev.cross(e.p_mm).z() > 0.0);
    prev = e.p_mm;
  }
  CHECK(curve.back().p_mm == Vector3d(0, 10, 0));
  CHECK(moves.back().p_mm == Vector3d(0, 20, 0));
  CHECK(moves.back().origin == MoveOrigin::goto_point);
  check_nurbs(Vector3d(10, 0, 0), curve, {0, 0, 0, 1, 1, 1}, 2,
              {Vector3d(10, 0, 0), Vector3d(10, 10, 0), Vector3d(0, 10, 0)}, {1.0, w, 1.0},
              opt.chordal_tolerance_mm);
}

TEST_CASE("cl_reader: a cubic NURBS matches an independent evaluation, in both knot forms") {
  const std::vector<Vector3d> p{{0, 0, 0},   {10, 20, 5}, {30, -10, 5},
                                {45, 25, 0}, {60, 0, 10}, {80, 5, 0}};
  const std::vector<double> knots{0, 0, 0, 0, 0.3, 0.6, 1, 1, 1, 1};
  std::string cntrl;
  for (std::size_t i = 1; i < p.size(); ++i)
    cntrl += "CNTRL/" + xyz(p[i]) + "\n";
  ClReaderOptions opt;
  opt.chordal_tolerance_mm = 0.005;

  // Complete knot vector, every control point written (the first is where the tool is).
  const auto full = moves_of(
      "GOTO/0,0,0\nNURBS/\nKNOT/0,0,0,0,0.3,0.6,1,1,1,1\nCNTRL/0,0,0\n" + cntrl + "GOTO/80,5,20\n",
      opt);
  const std::vector<ClEvent> full_curve(full.begin() + 1, full.end() - 1);
  check_nurbs(p[0], full_curve, knots, 3, p, std::vector<double>(p.size(), 1.0),
              opt.chordal_tolerance_mm);

  // NX form: 3 knots and 5 CNTRL give order 5 + 2 - 3 = 4; the same curve point for point.
  const auto nx = moves_of("GOTO/0,0,0\nNURBS/\nKNOT/0.3,0.6,1\n" + cntrl, opt);
  const std::vector<ClEvent> nx_curve(nx.begin() + 1, nx.end());
  REQUIRE(nx_curve.size() == full_curve.size());
  for (std::size_t i = 0; i < nx_curve.size(); ++i)
    CHECK(nx_curve[i].p_mm == full_curve[i].p_mm);

  // Complete knot vector without the first control point (it is the current position).
  const auto implicit = moves_of("GOTO/0,0,0\nNURBS/\nKNOT/0,0,0,0,0.3,0.6,1,1,1,1\n" + cntrl, opt);
  CHECK(implicit.size() == nx.size());

  // One NURBS after another starts where the first ended.
  const auto two =
      moves_of("GOTO/0,0,0\nNURBS/\nKNOT/0.3,0.6,1\n" + cntrl + "NURBS/\nKNOT/1\nCNTRL/90,10,0\n");
  CHECK(two.back().p_mm == Vector3d(90, 10, 0));
  CHECK(two.back().line == 9);  // the NURBS/ record
}

TEST_CASE("cl_reader: NURBS data that do not fit are refused") {
  const std::string start = "GOTO/0,0,0\nNURBS/\n";
  check_error(start + "KNOT/0.2,0.1,1\nCNTRL/1,1,0\nCNTRL/2,0,0\nCNTRL/3,1,0\n", 3, 10,
              "must not decrease");
  check_error(start +
                  "KNOT/1\nCNTRL/1,1,0\nCNTRL/2,0,0\nCNTRL/3,1,0\nCNTRL/4,1,0\nCNTRL/5,1,0\n"
                  "CNTRL/6,1,0\nCNTRL/7,1,0\nCNTRL/8,1,0\nCNTRL/9,1,0\nCNTRL/10,1,0\n",
              2, 0, "give order 11");
  check_error(start + "KNOT/0.5,0.9\nCNTRL/1,1,0\nCNTRL/2,0,0\nGOTO/3,0,0\n", 2, 0,
              "cannot tell the curve's order");
  check_error(start + "KNOT/0,0,0,1,1,1\nCNTRL/0,1,0\nCNTRL/1,1,0\nCNTRL/2,0,0\n", 2, 0,
              "starts 1 mm away");
  check_error(start + "KNOT/0,0,0,1,1,1\nCNTRL/1,1,0\n", 2, 0, "do not fit");
  check_error(start +
                  "KNOT/0.5,0.5,0.5,1\nCNTRL/1,1,0\nCNTRL/2,0,0\nCNTRL/3,1,0\nCNTRL/4,1,0\n"
                  "CNTRL/5,1,0\n",
              2, 0, "");
  check_error(start + "KNOT/1\nCNTRL/1,1,0,0\nCNTRL/2,0,0\n", 4, 13, "weight must be > 0");
  check_error(start + "KNOT/1\nCNTRL/1,1,0\nKNOT/1\n", 5, 1, "KNOT/ after CNTRL/");
  check_error("GOTO/0,0,0\nCNTRL/1,1,0\n", 2, 1, "outside a NURBS");
  check_error(start + "GOTO/1,1,1\n", 2, 0, "needs KNOT/ and CNTRL/");
}

TEST_CASE(
    "cl_reader: a NURBS beyond the chord bound, or a tolerance below the finest, is refused") {
  // A cubic zigzag 1e5 mm high, control points 9e4 mm apart: some 2e4 chords per span at the
  // finest tolerance, 2e6 in all. The reader stops at the bound, reading one event at a time.
  std::string text = "GOTO/0,0,0\nNURBS/\nKNOT/";
  const int spans = 100;
  for (int k = 1; k <= spans; ++k)
    text += (k > 1 ? "," : "") + num(static_cast<double>(k) / spans);
  text += "\n";
  for (int i = 1; i <= spans + 2; ++i)
    text += "CNTRL/" + num(9e4 * i) + "," + (i % 2 ? "100000" : "0") + ",0\n";
  ClReaderOptions opt;
  opt.chordal_tolerance_mm = kMinChordalToleranceMm;
  std::istringstream in(text);
  ClReader reader(in, "t.apt", opt);
  ClEvent e;
  long moves = 0;
  try {
    while (reader.next(e))
      moves += e.kind == ClEventKind::move ? 1 : 0;
    FAIL("no error after " << moves << " moves");
  } catch (const Error& err) {
    CHECK(err.where().line == 2);  // the NURBS/ record
    CHECK(err.message().find("more than the 1000000 chords a curve may have") != std::string::npos);
    CHECK(err.message().find("raise --chordal-tol") != std::string::npos);
  }
  CHECK(moves <= kMaxCurveChords + 1);
  // At 1 mm the same curve needs some 2e4 chords, and is read.
  opt.chordal_tolerance_mm = 1.0;
  CHECK_NOTHROW(read_all(text, opt));

  // Below the finest tolerance: refused before reading (an arc of the largest coordinates
  // needs 7e5 chords at the finest one, so its own bound is a backstop).
  ClReaderOptions tiny;
  tiny.chordal_tolerance_mm = 1e-300;
  std::istringstream empty("GOTO/0,0,0\n");
  try {
    ClReader r(empty, "t.apt", tiny);
    FAIL("no error");
  } catch (const Error& err) {
    CHECK(err.message().find("must be a number of mm of at least 0.0001") != std::string::npos);
    CHECK(err.message().find("--chordal-tol") != std::string::npos);
  }
}

TEST_CASE("cl_reader: a byte order mark is skipped, and a CR inside a line is refused at it") {
  const auto plain = moves_of("GOTO/1,2,3\nGOTO/4,5,6\n");
  const auto bom = moves_of("\xEF\xBB\xBFGOTO/1,2,3\r\nGOTO/4,5,6\r\n");
  REQUIRE(bom.size() == plain.size());
  for (size_t i = 0; i < bom.size(); ++i)
    CHECK(bom[i].p_mm == plain[i].p_mm);
  // CR-only line endings (the whole file would be one line), and a stray CR in a record.
  check_error("GOTO/1,2,3\rGOTO/4,5,6\r", 1, 11, "the file's lines end in CR alone");
  check_error("GOTO/1,2,3\nINSERT/A\rB\n", 2, 9, "a record holds a stray CR");
}

TEST_CASE("cl_reader: a pecking cycle beyond 10 000 pecks per hole is refused at its line") {
  check_error(
      "GOTO/8.,15.,25.\n"
      "CYCLE/DEEP2,FEDTO,10,1STPECK,1e-6,SUBPECK,1e-6,MMPM,100,RAPTO,3.,RTRCTO,25.\n"
      "GOTO/8.,15.,0\n",
      2, 0, "needs 10000000 pecks per hole, more than the 10000 redpost writes");
  // 10 000 exactly is written.
  const auto moves = moves_of(
      "GOTO/8.,15.,25.\n"
      "CYCLE/DEEP2,FEDTO,10,1STPECK,0.001,SUBPECK,0.001,MMPM,100,RAPTO,3.,"
      "RTRCTO,25.\n"
      "GOTO/8.,15.,0\n"
      "CYCLE/OFF\n");
  long cuts = 0;
  for (size_t i = 1; i < moves.size(); ++i)  // after the GOTO before the cycle
    cuts += moves[i].rapid ? 0 : 1;
  CHECK(cuts == 10000);
}

// ---------------------------------------------------------------------------------------------
// Drilling cycles

namespace {

struct Step {
  bool is_move;
  double z_or_feed;
  bool rapid;
};

std::vector<Step> steps_of(const std::vector<ClEvent>& events) {
  std::vector<Step> out;
  for (const ClEvent& e : events) {
    if (e.kind == ClEventKind::move)
      out.push_back({true, e.p_mm.z(), e.rapid});
    else if (e.kind == ClEventKind::feed)
      out.push_back({false, e.value, false});
  }
  return out;
}

}  // namespace

TEST_CASE("cl_reader: a drill cycle expands to rapid, feed to depth, rapid out") {
  const auto events = read_all(
                          "FEDRAT/500,MMPM\n"
                          "RAPID/\n"
                          "GOTO/8.,15.,25.\n"
                          "CYCLE/INIT\n"
                          "CYCLE/DRILL,FEDTO,7.5,MMPM,300,RAPTO,3.,RTRCTO,25.,DWELL,0\n"
                          "GOTO/8.,15.,0\n"
                          "GOTO/27.,15.,0\n"
                          "CYCLE/OFF\n"
                          "GOTO/27,15,50\n")
                          .events;
  const auto moves = of_kind(events, ClEventKind::move);
  // The approach GOTO, hole 1 (already above it at the retract height: 3 moves), hole 2
  // (travel at the retract height first: 4 moves), the GOTO after CYCLE/OFF.
  REQUIRE(moves.size() == 1 + 3 + 4 + 1);
  const std::vector<Vector3d> expected{{8, 15, 25},    {8, 15, 3},   {8, 15, -7.5},
                                       {8, 15, 25},    {27, 15, 25}, {27, 15, 3},
                                       {27, 15, -7.5}, {27, 15, 25}, {27, 15, 50}};
  const std::vector<bool> rapid{true, true, false, true, true, true, false, true, false};
  for (std::size_t i = 0; i < moves.size(); ++i) {
    INFO("move " << i);
    CHECK(moves[i].p_mm == expected[i]);
    CHECK(moves[i].rapid == rapid[i]);
    CHECK(moves[i].origin == (i == 0 || i == 8 ? MoveOrigin::goto_point : MoveOrigin::cycle));
  }
  CHECK(moves[1].line == 6);
  CHECK(moves[5].line == 7);
  // The cycle's feed before each cut, the programme's feed restored after it.
  const auto steps = steps_of(events);
  std::vector<double> feeds;
  for (const Step& s : steps) {
    if (!s.is_move)
      feeds.push_back(s.z_or_feed);
  }
  CHECK(feeds == std::vector<double>{500, 300, 500, 300, 500});
  REQUIRE(steps.size() == 14);
  CHECK((!steps[3].is_move && steps[3].z_or_feed == 300));  // just before the first cut
  CHECK((steps[4].is_move && steps[4].z_or_feed == -7.5));
  CHECK((!steps[5].is_move && steps[5].z_or_feed == 500));  // right after it
}

TEST_CASE("cl_reader: a cycle's moves carry its clearance plane; DWELL gives a dwell") {
  const auto events = read_all(
                          "FEDRAT/500,MMPM\n"
                          "CYCLE/DRILL,FEDTO,7.5,MMPM,300,RAPTO,3.,RTRCTO,25.,DWELL,1.5\n"
                          "GOTO/8.,15.,0\n"
                          "GOTO/27.,15.,2\n"
                          "CYCLE/OFF\n"
                          "GOTO/27,15,50\n")
                          .events;
  const auto moves = of_kind(events, ClEventKind::move);
  for (const ClEvent& m : moves) {
    INFO("move at " << m.p_mm.transpose());
    if (m.origin == MoveOrigin::cycle) {
      REQUIRE(m.has_clearance);
      // RAPTO above the hole's point, along the tool axis.
      const double hole_z = m.p_mm.x() < 20 ? 0.0 : 2.0;
      CHECK(m.clearance_p_mm == Vector3d(m.p_mm.x(), 15, hole_z + 3));
    } else {
      CHECK_FALSE(m.has_clearance);
    }
  }
  // One dwell per hole, at its bottom: right after the cut, before the retract.
  std::vector<std::size_t> dwell_at;
  for (std::size_t i = 0; i < events.size(); ++i) {
    if (events[i].kind == ClEventKind::dwell) {
      CHECK(events[i].value == 1.5);
      dwell_at.push_back(i);
    }
  }
  REQUIRE(dwell_at.size() == 2);
  for (std::size_t i : dwell_at) {
    REQUIRE(i > 0);
    CHECK(events[i - 1].kind == ClEventKind::move);
    CHECK_FALSE(events[i - 1].rapid);  // the cut
  }
  check_error("CYCLE/DRILL,FEDTO,5,RAPTO,2,MMPM,100,DWELL,-1\n", 1, 44, "DWELL must be 0 to 600");
  check_error("CYCLE/DRILL,FEDTO,5,RAPTO,2,MMPM,100,DWELL,2000\n", 1, 44, "DWELL must be 0");
}

TEST_CASE("cl_reader: a DEEP cycle pecks with full retracts") {
  // SolidWorks CAM: first peck 5, then 2 more each, to 42.01108: 1 + ceil(37.01108 / 2) = 20.
  const auto events = read_all(
                          "GOTO/8.,15.,25.\n"
                          "CYCLE/DEEP2,FEDTO,42.01108,1STPECK,5.,SUBPECK,2.,MMPM,432.1,RAPTO,3.,"
                          "RTRCTO,25.\n"
                          "GOTO/8.,15.,0\n"
                          "CYCLE/OFF\n")
                          .events;
  const auto moves = of_kind(events, ClEventKind::move);
  std::vector<double> bottoms, reentries;
  int retracts_to_clearance = 0;
  for (std::size_t i = 1; i < moves.size(); ++i) {
    const ClEvent& m = moves[i];
    CHECK(m.p_mm.head<2>() == Eigen::Vector2d(8, 15));
    if (!m.rapid) {
      bottoms.push_back(-m.p_mm.z());
      CHECK(moves[i - 1].rapid);  // every cut starts from a rapid
    } else if (m.p_mm.z() == 3.0) {
      ++retracts_to_clearance;
    } else if (m.p_mm.z() < 3.0) {
      reentries.push_back(m.p_mm.z());
    }
  }
  REQUIRE(bottoms.size() == 20);
  for (std::size_t k = 0; k + 1 < bottoms.size(); ++k)
    CHECK(bottoms[k] == Approx(5.0 + 2.0 * static_cast<double>(k)).epsilon(1e-15));
  CHECK(bottoms.back() == 42.01108);
  CHECK(retracts_to_clearance == 1 + 19);  // the approach, then out after each peck but the last
  REQUIRE(reentries.size() == 19);         // back down to 3 mm above the previous bottom
  CHECK(reentries[0] == Approx(-2.0).epsilon(1e-15));
  CHECK(moves.back().p_mm.z() == 25.0);
  CHECK(moves.back().rapid);
}

TEST_CASE("cl_reader: NX cycles: RAPTO without RTRCTO, any tool axis, DEEP needs its pecks") {
  const auto moves = moves_of(
      "TOOL PATH/DRILLING,TOOL,DRILL_8\n"
      "CYCLE/DRILL,RAPTO,3.0000,FEDTO,10.0000,MMPM,250.0000\n"
      "GOTO/0,0,0,1,0,0\n"
      "GOTO/0,20,0\n"
      "CYCLE/OFF\n");
  const std::vector<Vector3d> expected{{3, 0, 0},  {-10, 0, 0},  {3, 0, 0},
                                       {3, 20, 0}, {-10, 20, 0}, {3, 20, 0}};
  REQUIRE(moves.size() == expected.size());
  for (std::size_t i = 0; i < moves.size(); ++i) {
    CHECK(moves[i].p_mm == expected[i]);
    CHECK(moves[i].tool_axis == Vector3d(1, 0, 0));
  }
  check_error("CYCLE/DRILL,DEEP,RAPTO,3.0000,FEDTO,10.0000,MMPM,250.0000\n", 1, 0, "no peck depth");
  // FEDTO 0 (as in NX's sample) needs no pecks: the holes are touched, with a warning.
  const auto r =
      read_all("UNITS/MM\nCYCLE/DRILL,DEEP,RAPTO,3,FEDTO,0,MMPM,250\nGOTO/1,2,3\nCYCLE/OFF\n");
  CHECK(of_kind(r.events, ClEventKind::move).size() == 3);
  REQUIRE(r.warnings.size() == 1);
  CHECK(r.warnings[0].find("FEDTO 0") != std::string::npos);
}

TEST_CASE("cl_reader: cycles that cannot be expanded safely are refused") {
  check_error("GOTO/0,0,0\nCYCLE/TAP,FEDTO,5,RAPTO,2,MMPM,100\n", 2, 7,
              "CYCLE/TAP is not supported");
  check_error("CYCLE/BORE,FEDTO,5,RAPTO,2,MMPM,100\n", 1, 7, "CYCLE/BORE is not supported");
  check_error("CYCLE/DRILL,FEDTO,5,RAPTO,2,MMPM,100,CAM,3\n", 1, 38, "unknown parameter CAM");
  check_error("CYCLE/DRILL,5,IPM,10,.1\n", 1, 13, "positional");
  check_error("CYCLE/DRILL,FEDTO,5,MMPM,100\n", 1, 0, "RAPTO");
  check_error("CYCLE/DRILL,FEDTO,5,RAPTO,2\n", 1, 0, "gives no feed");
  check_error("CYCLE/DRILL,FEDTO,-5,RAPTO,2,MMPM,100\n", 1, 19, "must be >= 0");
  check_error("CYCLE/DRILL,FEDTO,5,RAPTO,2,MMPM,100\nGOTO/0,0,0\nGODLTA/0,0,1\n", 3, 0,
              "only GOTO");
  // A tool change with the cycle still on: the GOTOs after it could be holes or moves.
  check_error(
      "CYCLE/DRILL,FEDTO,5,RAPTO,2,MMPM,100\nGOTO/0,0,0\nLOAD/TOOL,2\nRAPID/\nGOTO/0,0,100\n", 5, 0,
      "cannot tell whether this GOTO is a hole");
  // ... and the advice is the safe one: end the cycle at its last hole, not just CYCLE/OFF.
  check_error(
      "CYCLE/DRILL,FEDTO,5,RAPTO,2,MMPM,100\nGOTO/0,0,0\nLOAD/TOOL,2\nRAPID/\nGOTO/0,0,100\n", 5, 0,
      "Do not only insert CYCLE/OFF before the tool change");
  CHECK(moves_of("CYCLE/DRILL,FEDTO,5,RAPTO,2,MMPM,100\nGOTO/0,0,0\nCYCLE/OFF\nLOAD/TOOL,2\n"
                 "GOTO/0,0,100\n")
            .back()
            .origin == MoveOrigin::goto_point);
}

// ---------------------------------------------------------------------------------------------
// Errors

TEST_CASE("cl_reader: malformed records and bad numbers name line, column and cause") {
  check_error("GOTO 1,2,3\n", 1, 5, "GOTO needs '/'");
  check_error("GOTO/1,,3\n", 1, 8, "empty value");
  check_error("GOTO/1,2,\n", 1, 10, "empty value");
  check_error("GOTO/1,abc,3\n", 1, 8, "not a number");
  check_error("GOTO/1,2,3x\n", 1, 10, "not a number");
  check_error("GOTO/1,nan,3\n", 1, 8, "NaN and inf are refused");
  check_error("GOTO/1,2,-inf\n", 1, 10, "NaN and inf are refused");
  check_error("GOTO/1,2,3e8\n", 1, 10, "out of range");
  check_error("GOTO/1,2,1e999\n", 1, 10, "out of range");
  check_error("UNITS/INCHES\nGOTO/0,0,5e6\n", 2, 10, "out of range");
  check_error("GOTO/1,2,3,0,0,0\n", 1, 12, "zero length");
  check_error("GOTO/1,2,3,0,0\n", 1, 12, "takes 3 values (x,y,z) or 6");
  check_error("GOTO/1,2,3,1\n", 1, 12, "got 4 values");
  check_error("GOTO/1,2\n", 1, 1, "got 2 values");
  check_error("GOTO/1,2,3\n%%garbage\n", 2, 1, "malformed record");
  check_error("12/3\n", 1, 1, "malformed record");
  check_error("  /3\n", 1, 3, "no major word");
  check_error("UNITS/FURLONGS\n", 1, 7, "unknown unit");
  check_error("ORIGIN/1,2,3\n", 1, 1, "ORIGIN is not supported");
  check_error("TLAXIS/NORMPS\n", 1, 1, "TLAXIS takes 3 values");
}

TEST_CASE("cl_reader: a physical line longer than max_line_bytes is refused") {
  ClReaderOptions opt;
  opt.max_line_bytes = 16;
  CHECK(moves_of("GOTO/1,2,3\r\nGOTO/1.00000,2,3\r\n", opt).size() == 2);  // 16 bytes + CR
  const Error e = error_of("GOTO/1,2,3\nGOTO/1.00000000000000,2,3\n", opt);
  CHECK(e.where().line == 2);
  CHECK(e.message().find("line longer than 16 bytes") != std::string::npos);
  CHECK(std::string(e.what()).find("t.apt:2: line longer") == 0);

  // A megabyte line without a newline stops at the limit (the reader never holds more).
  opt.max_line_bytes = 1000;
  CHECK(error_of(std::string(1 << 20, 'A'), opt).where().line == 1);
}

// ---------------------------------------------------------------------------------------------
// Real files and volume

TEST_CASE("cl_reader: the real CL files of evaldata are read to the end or to a located error") {
  namespace fs = std::filesystem;
  if (!fs::is_directory(kEvaldata)) {
    SUCCEED("evaldata not present at " << kEvaldata << ": skipped");
    return;
  }
  struct Summary {
    std::map<MoveOrigin, long> moves;
    std::map<ClEventKind, long> kinds;
    long axis_changes = 0;
    int error_line = 0;
    std::string error;
  };
  std::map<std::string, Summary> seen;
  for (const char* dir : {"apt", "clsf"}) {
    for (const auto& entry : fs::directory_iterator(fs::path(kEvaldata) / dir)) {
      std::ifstream in(entry.path(), std::ios::binary);
      ClReader reader(in, entry.path().string());
      Summary s;
      ClEvent e;
      Vector3d last_axis(0, 0, 0);
      try {
        while (reader.next(e)) {
          ++s.kinds[e.kind];
          if (e.kind == ClEventKind::move) {
            ++s.moves[e.origin];
            CHECK(e.p_mm.allFinite());
            CHECK(std::fabs(e.tool_axis.norm() - 1.0) <= 1e-12);
            s.axis_changes += e.tool_axis != last_axis;
            last_axis = e.tool_axis;
          }
        }
      } catch (const Error& err) {
        s.error_line = err.where().line;
        s.error = err.what();
        CHECK(err.where().line > 0);
      }
      seen[entry.path().filename().string()] = s;
    }
  }
  auto check_file = [&](const std::string& name, auto&& check) {
    if (seen.count(name)) {
      INFO(name << (seen[name].error.empty() ? "" : ": " + seen[name].error));
      check(seen[name]);
    }
  };
  check_file("nx_variable_contour_5axis.cls", [](const Summary& s) {
    CHECK(s.error.empty());
    CHECK(s.moves.at(MoveOrigin::goto_point) == 546);  // 120 of them with i,j,k
    CHECK(s.axis_changes > 10);
    CHECK(s.axis_changes <= 120);
    CHECK(s.kinds.at(ClEventKind::tool_change) == 1);  // LOAD/TOOL,2; SELECT/TOOL,2 preselects
  });
  check_file("swcam_drill_cycles.apt", [](const Summary& s) {
    CHECK(s.error.empty());
    // 8 drilled holes (3 moves for the first, 4 for the others) and 8 holes of 20 pecks
    // (60 moves each, plus the travel to holes 2..8).
    CHECK(s.moves.at(MoveOrigin::cycle) == (3 + 7 * 4) + (8 * 60 + 7));
    CHECK(s.kinds.at(ClEventKind::tool_change) == 2);
    CHECK(s.kinds.at(ClEventKind::unknown_word) == 2);
  });
  check_file("swcam_gasket_circles.apt", [](const Summary& s) {
    CHECK(s.error.empty());
    CHECK(s.moves.at(MoveOrigin::arc) > 100);
    CHECK(s.kinds.at(ClEventKind::end_of_program) == 1);
  });
  check_file("swcam_cutcom_multi_op.apt", [](const Summary& s) {
    // The spot-drill cycle is never switched off before the next tools (see docs).
    CHECK(s.error_line == 479);
    CHECK(s.error.find("cannot tell whether this GOTO is a hole") != std::string::npos);
    CHECK(s.moves.at(MoveOrigin::arc) > 100);
  });
  check_file("nx_kontur_nar_40_circle.cls", [](const Summary& s) {
    CHECK(s.error.empty());
    CHECK(s.moves.at(MoveOrigin::goto_point) == 27);
    CHECK(s.moves.at(MoveOrigin::arc) > 19);  // 19 CIRCLE records
  });
  check_file("nx_cutcom_load_tool.clsf", [](const Summary& s) {
    CHECK(s.error.empty());
    CHECK(s.moves.at(MoveOrigin::arc) > 140);  // 140 CIRCLE records
    CHECK(s.kinds.at(ClEventKind::operation_start) == 1);
    CHECK(s.kinds.at(ClEventKind::operation_end) == 1);
  });
  check_file("nx_nurbs_fixed_contour.clsf", [](const Summary& s) {
    CHECK(s.error.empty());
    CHECK(s.moves.at(MoveOrigin::nurbs) > 1413);  // at least one chord per CNTRL
    CHECK(s.moves.at(MoveOrigin::goto_point) == 78);
  });
  check_file("nx_cycle_drill_deep.clsf", [](const Summary& s) {
    CHECK(s.error.empty());
    CHECK(s.moves.at(MoveOrigin::cycle) == 6);  // two holes, FEDTO 0
  });
}

TEST_CASE("cl_reader: a 200000-record stream is read in one pass") {
  std::string text = "PARTNO/VOLUME\nUNITS/MM\nMULTAX/ON\nFEDRAT/1000,MMPM\n";
  text.reserve(200000 * 64);
  char buf[32];
  auto fixed4 = [&buf](double v) {
    return std::string(buf,
                       std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, 4).ptr);
  };
  for (int i = 0; i < 200000; ++i) {
    const double x = 0.001 * i;
    text +=
        "GOTO/" + fixed4(x) + ",-12.5000," + fixed4(0.5 * x) + ",0.0000000,0.0000000,1.0000000\n";
  }
  text += "FINI\n";
  std::istringstream in(text);
  ClReader reader(in, "volume.cls");
  ClEvent e;
  long moves = 0;
  double last_x = -1.0;
  while (reader.next(e)) {
    if (e.kind == ClEventKind::move) {
      ++moves;
      last_x = e.p_mm.x();
    }
  }
  CHECK(moves == 200000);
  CHECK(last_x == 199.999);
  CHECK(reader.warnings().empty());
}

TEST_CASE("cl_reader: a file without UNITS is read as mm, with one warning at the first motion") {
  // Real CAM output rarely has UNITS (NX CLSF never); a file in inches without it would come
  // out 25.4 times too small, so the reader says what it assumed.
  const auto r = read_all("PARTNO/P\nFEDRAT/100\nGOTO/1,2,3\nGOTO/4,5,6\n");
  REQUIRE(r.warnings.size() == 1);
  CHECK(r.warnings[0].find("t.apt:3: no UNITS record before the first motion") == 0);
  CHECK(r.warnings[0].find("UNITS/INCHES") != std::string::npos);
  const auto moves = of_kind(r.events, ClEventKind::move);
  REQUIRE(moves.size() == 2);
  CHECK(moves[0].p_mm == Vector3d(1, 2, 3));
  // With UNITS/INCHES: no warning, coordinates scaled by 25.4.
  const auto in = read_all("UNITS/INCHES\nGOTO/1,2,3\n");
  CHECK(in.warnings.empty());
  REQUIRE(of_kind(in.events, ClEventKind::move).size() == 1);
  CHECK(of_kind(in.events, ClEventKind::move)[0].p_mm.isApprox(Vector3d(25.4, 50.8, 76.2)));
}
