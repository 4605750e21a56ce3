// Programs a cell can run safely (issue 16), checked against what the written program and the
// joints log say, independently of the session's own figures: tools (FK of the flange), rapids
// (a brute-force joint interpolation of every PTP through FK), cycles, the coupled base, MSYS
// messages, the byte budget, CIRC (the circle through the written points against the CL arc)
// and the statements passed through.
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "catch_compat.hpp"
#include "redpost/cl/reader.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/kinematics/tool_table.hpp"
#include "redpost/krl/template.hpp"
#include "redpost/post/session.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace redpost;
namespace fs = std::filesystem;

namespace {

const char* const kCell = "andres2011_kr15_track_table";

struct Run {
  std::string src;                     // the main .src
  std::vector<std::vector<double>> q;  // the joints log, chain order (DH units)
  PostSummary summary;
};

struct RunOptions {
  std::string templates = "krc4_lin";
  std::string cell = kCell;
  double clearance_z_mm = std::numeric_limits<double>::quiet_NaN();
  ToolTable tools;
  long max_file_bytes = 0;
  bool arcs_as_events = false;
  double chordal_tolerance_mm = 0.01;
  MsysMode msys = MsysMode::ignore;
  std::string name = "PROG";
  double fit_tolerance_mm = 0.0;  // point reduction off, as PostOptions has it
  RedundancyPlan plan = RedundancyPlan::local;
  int cell_load_data = 0;  // the cell's <controller load-data> (0: none)
};

// Converts CL text as `redpost convert` does (reader -> session), into `dir`.
Run run(const std::string& cl, const fs::path& dir, const RunOptions& ro = {}) {
  Cell cell = test::shipped_cell(ro.cell);
  cell.controller.load_data = ro.cell_load_data;
  const KrlTemplateSet set =
      load_krl_templates(test::source_path("definitions/krl/" + ro.templates + ".xml"));
  const fs::path input = dir / "part.apt";
  std::ofstream(input) << cl;
  PostOptions o;
  o.program.name = ro.name;
  o.program.output_dir = dir.string();
  o.program.max_file_bytes = ro.max_file_bytes;
  o.program.base = "BASE_DATA[1]";
  o.source_name = input.string();
  o.joints_csv_path = (dir / "joints.csv").string();
  o.clearance_z_mm = ro.clearance_z_mm;
  o.tools = ro.tools;
  o.chordal_tolerance_mm = ro.chordal_tolerance_mm;
  o.reduction.tolerance_mm = ro.fit_tolerance_mm;
  o.plan = ro.plan;
  std::ifstream in = open_text_stream(input.string());
  ClReaderOptions read;
  read.arcs_as_events = ro.arcs_as_events;
  read.chordal_tolerance_mm = ro.chordal_tolerance_mm;
  read.msys = ro.msys;
  ClReader reader(in, input.string(), read);
  PostSession session(cell, set, o);
  ClEvent e;
  while (reader.next(e))
    session.handle(e);
  Run out;
  out.summary = session.finish();
  out.src = read_text_file((dir / (ro.name + ".src")).string());
  std::ifstream csv(dir / "joints.csv");
  std::string line;
  std::getline(csv, line);
  while (std::getline(csv, line)) {
    for (char& c : line)
      c = c == ',' ? ' ' : c;
    std::istringstream s(line);
    int pose = 0, cl_line = 0;
    double time_s = 0.0;
    s >> pose >> cl_line >> time_s;
    std::vector<double> q(static_cast<size_t>(cell.size()));
    for (double& v : q)
      s >> v;
    out.q.push_back(q);
  }
  return out;
}

JointVector to_q(const Cell& cell, const std::vector<double>& v) {
  JointVector q = cell.home();
  for (int i = 0; i < cell.size(); ++i)
    q[i] = v[static_cast<size_t>(i)];
  return q;
}

// The motion statements of a program, in order: the keyword of each.
std::vector<std::string> motion_keywords(const std::string& src) {
  std::vector<std::string> out;
  static const std::regex motion(R"((^|\n)(PTP|LIN|SLIN|CIRC) )");
  for (auto it = std::sregex_iterator(src.begin(), src.end(), motion); it != std::sregex_iterator();
       ++it)
    out.push_back((*it)[2]);
  return out;
}

// The lowest TCP height (z in the part frame, which is {B} here) along the joint-space line
// from q0 to q1, sampled every 0.1 deg / 0.1 mm of the largest joint move: what a synchronous
// PTP does between the two postures.
double lowest_z_along(const Cell& cell, const JointVector& q0, const JointVector& q1) {
  double largest = 0.0;
  for (int i = 0; i < cell.size(); ++i) {
    const double d = std::fabs(q1[i] - q0[i]);
    largest = std::max(largest,
                       cell.joint(i).type == JointType::prismatic ? d / 0.1 : rad_to_deg(d) / 0.1);
  }
  const int n = std::max(50, static_cast<int>(std::ceil(largest)));
  double lowest = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= n; ++k) {
    JointVector q = q0;
    for (int i = 0; i < cell.size(); ++i)
      q[i] = q0[i] + (q1[i] - q0[i]) * k / n;
    lowest = std::min(lowest, tcp_pose(cell, q).translation().z());
  }
  return lowest;
}

// A drilling job like the SolidWorks drill files: two tools, cycles with RAPTO 3 and RTRCTO
// 25 over holes on the part's top at z = 0.
std::string drill_job(double length1_mm, double length2_mm) {
  return "UNITS/MM\n"
         "CUTTER/14.,0,7.,4.2,31.,0," +
         std::to_string(length1_mm) +
         "\n"
         "LOAD/TOOL,15\n"
         "SPINDL/4948,RPM,CLW\n"
         "RAPID/\n"
         "GOTO/-120.,-450.,25.\n"
         "CYCLE/DRILL,FEDTO,7.85,MMPM,326.77,RAPTO,3.,RTRCTO,25.,DWELL,0.5\n"
         "GOTO/-120.,-450.,0\n"
         "GOTO/-90.,-450.,0\n"
         "GOTO/-60.,-470.,0\n"
         "CYCLE/OFF\n"
         "CUTTER/6.7,0,3.35,2.0,31.,0," +
         std::to_string(length2_mm) +
         "\n"
         "LOAD/TOOL,16\n"
         "SPINDL/5155,RPM,CLW\n"
         "RAPID/\n"
         "GOTO/-120.,-450.,25.\n"
         "CYCLE/DEEP2,FEDTO,20.,1STPECK,5.,SUBPECK,5.,MMPM,432.1,RAPTO,3.,RTRCTO,25.\n"
         "GOTO/-120.,-450.,0\n"
         "GOTO/-90.,-450.,0\n"
         "CYCLE/OFF\n"
         "FINI\n";
}

}  // namespace

// --- tools ------------------------------------------------------------------------------------

TEST_CASE(
    "machine: the same hole with two tool lengths puts the flange exactly the difference "
    "further along the tool axis (FK)",
    "[machine]") {
  const Cell cell = test::shipped_cell(kCell);
  const std::string hole =
      "UNITS/MM\nCUTTER/10.,0,5.,0,0,0,@L\nLOADTL/1\nRAPID/\nGOTO/-100.,-450.,40.\n"
      "FEDRAT/300,MMPM\nGOTO/-100.,-450.,-5.\n";
  std::vector<Eigen::Vector3d> flange;
  for (double length : {69.0, 105.0}) {
    test::TempDir dir;
    std::string cl = hole;
    cl.replace(cl.find("@L"), 2, std::to_string(length));
    const Run r = run(cl, dir.path);
    REQUIRE(!r.q.empty());
    // The frame before the tool's spin: the spindle mount, on the tool axis.
    KinematicsData data;
    forward_kinematics(cell, to_q(cell, r.q.back()), data);
    flange.push_back(data.T_B_link[static_cast<size_t>(cell.size() - 2)].translation());
    // And the tool's own TCP (the chain's, moved by the length) is on the hole's bottom.
    const Cell tool = cell_for_tool(cell, length);
    const Isometry tcp = tcp_pose(tool, to_q(tool, r.q.back()));
    CHECK((tcp.translation() - Eigen::Vector3d(-100, -450, -5)).norm() < 2e-4);
    CHECK(tcp.linear().col(2).z() > 1.0 - 1e-9);
  }
  // The tool axis is +z: the longer tool's flange is 36 mm higher, nothing else.
  CHECK((flange[1] - flange[0] - Eigen::Vector3d(0, 0, 36.0)).norm() < 1e-3);
}

TEST_CASE(
    "machine: back to the first tool under the whole-path plan, the TCP is that tool's again "
    "(FK)",
    "[machine]") {
  // Tool 1, tool 2, tool 1 again: the session goes back to the first tool's cell, whose planner
  // must be built on that cell's IK (it once kept one that the second cell's replay had freed).
  const Cell cell = test::shipped_cell(kCell);
  std::string cl = "UNITS/MM\n";
  const double lengths[] = {69.0, 40.0, 69.0};
  const int numbers[] = {1, 2, 1};
  for (int k = 0; k < 3; ++k) {
    cl += fmt::format("CUTTER/10.,0,5.,0,0,0,{:.1f}\nLOADTL/{}\n", lengths[k], numbers[k]);
    // The second, shorter tool is loaded and put back without a move: the retract before the
    // third change (by the 29 mm the next tool is longer) is the only motion on its cell.
    if (k != 1) {
      cl +=
          "RAPID/\nGOTO/-100.,-450.,40.\nFEDRAT/600,MMPM\nGOTO/-100.,-450.,-2.\n"
          "GOTO/-60.,-450.,-2.\nGOTO/-60.,-470.,-2.\nRAPID/\nGOTO/-60.,-470.,40.\n";
    }
  }
  cl += "FINI\n";
  test::TempDir dir;
  RunOptions ro;
  ro.plan = RedundancyPlan::global;
  const Run r = run(cl, dir.path, ro);
  REQUIRE(!r.q.empty());
  // The last motion (the third tool's retract) puts that tool's own TCP at its point.
  const Cell tool1 = cell_for_tool(cell, 69.0);
  const Isometry tcp = tcp_pose(tool1, to_q(tool1, r.q.back()));
  CHECK((tcp.translation() - Eigen::Vector3d(-60, -470, 40)).norm() < 2e-4);
  CHECK(r.src.find("$TOOL = TOOL_DATA[2]") != std::string::npos);
  CHECK(r.src.rfind("$TOOL = TOOL_DATA[1]") > r.src.find("$TOOL = TOOL_DATA[2]"));
}

TEST_CASE("machine: the drill job writes a $TOOL per CL tool, the coupled base and safe PTPs",
          "[machine]") {
  const Cell cell = test::shipped_cell(kCell);
  test::TempDir dir;
  const Run r = run(drill_job(69.0, 105.0), dir.path);
  // Without a tool table CL tool n is TOOL_DATA[n], with a warning naming the line.
  CHECK(r.src.find("$TOOL = TOOL_DATA[15]") != std::string::npos);
  CHECK(r.src.find("$TOOL = TOOL_DATA[16]") != std::string::npos);
  CHECK(r.src.find("HALT ; mount tool T16") != std::string::npos);
  CHECK(r.src.find("$BASE = EK(MACHINE_DEF[2].ROOT, MACHINE_DEF[2].MECH_TYPE, BASE_DATA[1])") !=
        std::string::npos);
  CHECK(r.src.find("$ACT_EX_AX = 2") != std::string::npos);
  CHECK(r.src.find("WAIT SEC 0.500") != std::string::npos);  // the first cycle's DWELL
  int warned = 0;
  for (const std::string& w : r.summary.warnings)
    warned += w.find("no tool table, so TOOL_DATA[1") != std::string::npos;
  CHECK(warned == 2);

  // Every PTP after the first motion, interpolated in joint space (brute force, FK of the
  // tool's own TCP): the tool never goes below the cycles' clearance plane z = 3 on a PTP, let
  // alone into the part (top z = 0).
  const Cell tool15 = cell_for_tool(cell, 69.0), tool16 = cell_for_tool(cell, 105.0);
  std::istringstream lines(r.src);
  std::string line;
  const Cell* tool = &tool15;
  bool after_change = false;
  size_t k = 0;
  int ptps = 0, lins_below = 0;
  while (std::getline(lines, line)) {
    if (line.find("$TOOL = TOOL_DATA[16]") == 0) {
      tool = &tool16;
      after_change = true;
    }
    const bool ptp = line.rfind("PTP ", 0) == 0, lin = line.rfind("LIN ", 0) == 0;
    if (!ptp && !lin)
      continue;
    REQUIRE(k < r.q.size());
    if (k > 0 && ptp && !after_change) {
      ++ptps;
      // The ends are where the tracker put them, within its 1e-4 mm.
      CHECK(lowest_z_along(*tool, to_q(*tool, r.q[k - 1]), to_q(*tool, r.q[k])) >= 3.0 - 2e-4);
    }
    if (lin && tcp_pose(*tool, to_q(*tool, r.q[k])).translation().z() < 3.0 - 1e-6)
      ++lins_below;  // the feeds into the holes and the retracts out of them
    // The approach after the tool change starts at the changer, not at the last hole.
    after_change = after_change && !ptp;
    ++k;
  }
  CHECK(k == r.q.size());
  CHECK(ptps >= 8);
  CHECK(lins_below >= 10);
}

TEST_CASE(
    "machine: a tool table maps tools, warns on a length that disagrees, refuses a "
    "missing tool with its line",
    "[machine]") {
  test::TempDir dir;
  const fs::path table = dir.path / "tools.xml";
  std::ofstream(table) << "<tool-table>\n"
                          "  <tool number=\"15\" data=\"3\" length=\"70\" name=\"centre drill\"/>\n"
                          "  <tool number=\"16\" data=\"4\" load-data=\"11\" length=\"105\"/>\n"
                          "</tool-table>\n";
  RunOptions ro;
  ro.tools = load_tool_table(table.string());
  const Run r = run(drill_job(69.0, 105.0), dir.path, ro);
  // $TOOL, then the load and the number the pendant shows: the table's load for tool 16, the
  // tool's own number for tool 15, which the table gives none.
  CHECK(
      r.src.find("$TOOL = TOOL_DATA[3]\r\n$LOAD = LOAD_DATA[3]\r\nCONTINUE\r\n$ACT_TOOL = 3\r\n") !=
      std::string::npos);
  CHECK(r.src.find(
            "$TOOL = TOOL_DATA[4]\r\n$LOAD = LOAD_DATA[11]\r\nCONTINUE\r\n$ACT_TOOL = 4\r\n") !=
        std::string::npos);
  // The cell's load for every tool the table gives none.
  {
    test::TempDir other;
    RunOptions with_cell_load = ro;
    with_cell_load.cell_load_data = 6;
    const Run c = run(drill_job(69.0, 105.0), other.path, with_cell_load);
    CHECK(c.src.find("$TOOL = TOOL_DATA[3]\r\n$LOAD = LOAD_DATA[6]\r\n") != std::string::npos);
    CHECK(c.src.find("$TOOL = TOOL_DATA[4]\r\n$LOAD = LOAD_DATA[11]\r\n") != std::string::npos);
  }
  // SolidWorks CAM names no tool on LOAD/TOOL: the table's name is written.
  CHECK(r.src.find("; TOOL CHANGE: T15 centre drill") != std::string::npos);
  bool mismatch = false;
  for (const std::string& w : r.summary.warnings) {
    mismatch = mismatch || (w.find("part.apt:3: tool 15: the CL file gives a length of 69.000 mm, "
                                   "the tool table (") != std::string::npos &&
                            w.find("tools.xml:2) 70.000 mm") != std::string::npos);
  }
  CHECK(mismatch);

  std::ofstream(table) << "<tool-table>\n  <tool number=\"15\" data=\"3\" length=\"70\"/>\n"
                          "</tool-table>\n";
  ro.tools = load_tool_table(table.string());
  test::TempDir failed;
  try {
    run(drill_job(69.0, 105.0), failed.path, ro);
    FAIL("tool 16 was accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::bad_input);
    CHECK(e.where().line == 13);  // LOAD/TOOL,16
    CHECK(e.message().find("tool 16 is not in the tool table of") != std::string::npos);
  }
  for (const auto& e : fs::directory_iterator(failed.path))
    CHECK(e.path().extension() != ".src");
}

// --- rapids -----------------------------------------------------------------------------------

TEST_CASE("machine: without a clearance every rapid is a straight LIN; with one, PTP above it",
          "[machine]") {
  const std::string cl =
      "UNITS/MM\nLOADTL/1\nRAPID/\nGOTO/-120.,-440.,110.\nRAPID/\nGOTO/-120.,-440.,62.\n"
      "FEDRAT/200,MMPM\nGOTO/-120.,-440.,57.\nGOTO/-72.,-480.,57.\nRAPID/\nGOTO/-72.,-480.,110.\n"
      "RAPID/\nGOTO/-150.,-420.,110.\n";
  test::TempDir a, b;
  const Run none = run(cl, a.path);
  CHECK(motion_keywords(none.src) ==
        std::vector<std::string>{"PTP", "LIN", "LIN", "LIN", "LIN", "LIN"});
  RunOptions ro;
  ro.clearance_z_mm = 100.0;
  const Run with = run(cl, b.path, ro);
  // 110 -> 62 crosses z = 100: PTP to the plane, LIN below it; 57 -> 110 likewise upwards; the
  // last rapid stays above the plane: one PTP.
  CHECK(motion_keywords(with.src) ==
        std::vector<std::string>{"PTP", "PTP", "LIN", "LIN", "LIN", "LIN", "PTP", "PTP"});
  const Cell cell = test::shipped_cell(kCell);
  const std::vector<std::string> kinds = motion_keywords(with.src);
  for (size_t k = 1; k < kinds.size(); ++k) {
    if (kinds[k] == "PTP")
      CHECK(lowest_z_along(cell, to_q(cell, with.q[k - 1]), to_q(cell, with.q[k])) >= 100.0 - 1e-6);
  }
  CHECK(with.src.find("$VEL.CP = 0.250000") != std::string::npos);  // the rapid LINs' speed
}

// --- messages, MSYS ---------------------------------------------------------------------------

TEST_CASE(
    "machine: an unreachable first pose names --placement, the MSYS when it is z-down, and "
    "track and table only where the cell has them",
    "[machine]") {
  const std::string cl = "TOOL PATH/OP,TOOL,T\nMSYS/0,0,0,0,1,0,1,0,0\nGOTO/0,0,-3000,0,0,-1\n";
  test::TempDir a, b;
  try {
    run(cl, a.path);
    FAIL("accepted");
  } catch (const Error& e) {
    INFO(e.what());
    CHECK(e.message().find("--placement") != std::string::npos);
    CHECK(e.message().find("track and table") != std::string::npos);
    CHECK(e.message().find("MSYS (line 2)") != std::string::npos);
    CHECK(e.message().find("--msys apply") != std::string::npos);
  }
  RunOptions kr15;
  kr15.cell = "kr15_2";
  try {
    run("GOTO/0,0,-9000\n", b.path, kr15);
    FAIL("accepted");
  } catch (const Error& e) {
    INFO(e.what());
    CHECK(e.message().find("--placement") != std::string::npos);
    CHECK(e.message().find("track") == std::string::npos);
    CHECK(e.message().find("table") == std::string::npos);
    CHECK(e.message().find("MSYS") == std::string::npos);
  }
}

// --- program size -----------------------------------------------------------------------------

TEST_CASE(
    "machine: a program over the byte budget is split into parts within it, each continuing the "
    "cut",
    "[machine]") {
  std::string cl = "UNITS/MM\nLOADTL/1\nFEDRAT/600,MMPM\nGOTO/-150.,-450.,40.\n";
  for (int k = 0; k < 600; ++k)
    cl += "GOTO/" + std::to_string(-150.0 + 0.2 * k) + ",-450.," + (k % 2 ? "40." : "39.") + "\n";
  test::TempDir dir;
  RunOptions ro;
  ro.max_file_bytes = 16 * 1024;
  const Run r = run(cl, dir.path, ro);
  int parts = 0;
  for (const auto& e : fs::directory_iterator(dir.path)) {
    if (e.path().extension() != ".src")
      continue;
    INFO(e.path());
    CHECK(fs::file_size(e.path()) <= static_cast<std::uintmax_t>(ro.max_file_bytes));
    parts += e.path().stem().string().rfind("PROG_P", 0) == 0;
  }
  CHECK(parts >= 3);
  CHECK(r.src.find("PROG_P001( )") != std::string::npos);
  // The zigzag never leaves the material: every part after the first continues the cut, with
  // the tool set and no PTP (which would stop the tool on the surface).
  const std::string p2 = read_text_file((dir.path / "PROG_P002.src").string());
  CHECK(p2.find("$TOOL = TOOL_DATA[1]") < p2.find("LIN {E6POS"));
  CHECK(p2.find("PTP {") == std::string::npos);
  CHECK(p2.find("; continues the cut") != std::string::npos);
  // The whole program has every motion once.
  size_t motions = 0;
  for (int p = 1; p <= parts; ++p) {
    const std::string text =
        read_text_file((dir.path / ("PROG_P00" + std::to_string(p) + ".src")).string());
    motions += motion_keywords(text).size();
  }
  CHECK(motions == r.q.size());

  ro.max_file_bytes = 100;
  CHECK_THROWS_WITH(run(cl, dir.path, ro), Catch::Contains("must be at least 16384"));
  ro.max_file_bytes = 16 * 1024;
  ro.name = "A_NAME_OF_22_CHARACTERS";
  CHECK_THROWS_WITH(run(cl, dir.path, ro), Catch::Contains("must be split, but its name"));
}

// --- CIRC -------------------------------------------------------------------------------------

// A CIRC as the controller reads it: its start (the last position printed before it), the
// auxiliary and the end point, and the circle through the three (closed form).
struct PrintedCirc {
  Eigen::Vector3d start, aux, end, centre, normal;  // normal: unit, by the right-hand rule a->b->c
  double radius_mm = 0.0;
  double sweep_rad = 0.0;  // from the start through the auxiliary point to the end
};

std::vector<PrintedCirc> printed_circs(const std::string& src) {
  static const std::regex circ(
      R"(CIRC \{X (-?[0-9.]+), Y (-?[0-9.]+), Z (-?[0-9.]+)\}, \{E6POS: X (-?[0-9.]+), Y (-?[0-9.]+), Z (-?[0-9.]+),)");
  static const std::regex any(R"(\{E6POS: X (-?[0-9.]+), Y (-?[0-9.]+), Z (-?[0-9.]+),)");
  std::vector<PrintedCirc> out;
  for (auto it = std::sregex_iterator(src.begin(), src.end(), circ); it != std::sregex_iterator();
       ++it) {
    PrintedCirc c;
    const std::string before = src.substr(0, static_cast<size_t>(it->position()));
    for (auto jt = std::sregex_iterator(before.begin(), before.end(), any);
         jt != std::sregex_iterator(); ++jt)
      c.start = Eigen::Vector3d(std::stod((*jt)[1]), std::stod((*jt)[2]), std::stod((*jt)[3]));
    c.aux = Eigen::Vector3d(std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3]));
    c.end = Eigen::Vector3d(std::stod((*it)[4]), std::stod((*it)[5]), std::stod((*it)[6]));
    const Eigen::Vector3d ab = c.aux - c.start, ac = c.end - c.start;
    const Eigen::Vector3d n = ab.cross(ac);
    c.centre = c.start + (ac.squaredNorm() * n.cross(ab) + ab.squaredNorm() * ac.cross(n)) /
                             (2.0 * n.squaredNorm());
    c.normal = n.normalized();
    c.radius_mm = (c.start - c.centre).norm();
    const Eigen::Vector3d u = c.start - c.centre, w = c.end - c.centre;
    c.sweep_rad = std::atan2(c.normal.dot(u.cross(w)), u.dot(w));
    if (c.sweep_rad <= 0.0)
      c.sweep_rad += 2.0 * kPi;
    out.push_back(c);
  }
  return out;
}

TEST_CASE(
    "machine: arcs become CIRCs whose circle through the written points stays on the CL "
    "arc; arcs that cannot be proven stay chords",
    "[machine]") {
  const std::string cl = read_text_file(test::source_path("examples/cl/pocket_arcs.apt"));
  test::TempDir dir;
  RunOptions ro;
  ro.templates = "krc4_circ";
  ro.arcs_as_events = true;
  const Run r = run(cl, dir.path, ro);
  // Each CIRC's circle through its printed points must have the CL arc's radius 12 mm and lie
  // in the pocket's plane (independent of redpost).
  const std::vector<PrintedCirc> circs = printed_circs(r.src);
  for (const PrintedCirc& c : circs) {
    CHECK(c.radius_mm == Approx(12.0).margin(0.01));
    CHECK(std::fabs(c.normal.z()) > 1.0 - 1e-6);
  }
  CHECK(circs.size() == 8);  // every arc of the pocket
  CHECK(motion_keywords(r.src).size() == r.q.size());

  // A chordal tolerance finer than the printed decimals cannot be proven: chords, with a note.
  test::TempDir fine;
  ro.chordal_tolerance_mm = 0.0002;
  const Run chords = run(cl, fine.path, ro);
  CHECK(chords.src.find("\nCIRC ") == std::string::npos);
  bool noted = false;
  for (const std::string& w : chords.summary.warnings)
    noted = noted || w.find("written as chords, not as a CIRC") != std::string::npos;
  CHECK(noted);
}

TEST_CASE("machine: a full circle becomes two CIRCs of half a turn that close the circle",
          "[machine]") {
  // A full turn (the CIRCLE's GOTO back at its start, as APT writes a circle) has no circle
  // through its start, middle and end; two CIRCs of half a turn do. Checked from the printed
  // points: radius, plane, the half-turns, and the second one ending where the first began.
  const std::string cl =
      "UNITS/MM\nCUTTER/10.,0\nLOADTL/1\nSPINDL/12000,RPM,CLW\nRAPID\n"
      "GOTO/-100,-440,110\nRAPID\nGOTO/-100,-440,62\nFEDRAT/MMPM,900\nGOTO/-100,-440,57\n"
      "GOTO/-82,-440,57\nCIRCLE/-100,-440,57,0,0,1,18\nGOTO/-82,-440,57\n"
      "GOTO/-100,-440,57\nRAPID\nGOTO/-100,-440,110\nFINI\n";
  test::TempDir dir;
  RunOptions ro;
  ro.templates = "krc4_circ";
  ro.arcs_as_events = true;
  const Run r = run(cl, dir.path, ro);
  const std::vector<PrintedCirc> circs = printed_circs(r.src);
  REQUIRE(circs.size() == 2);
  for (const PrintedCirc& c : circs) {
    CHECK(c.radius_mm == Approx(18.0).margin(0.002));
    CHECK(c.normal.z() > 1.0 - 1e-6);  // counter-clockwise about +z, as the CIRCLE's axis says
    CHECK(c.sweep_rad == Approx(kPi).margin(0.1));  // half a turn (a chord's angle either way)
  }
  CHECK(circs[0].normal.dot(circs[1].normal) > 1.0 - 1e-9);  // the same way round
  CHECK((circs[1].end - circs[0].start).norm() < 2e-3);      // back at the start
  CHECK(circs[0].sweep_rad + circs[1].sweep_rad == Approx(2.0 * kPi).margin(1e-3));
  CHECK(motion_keywords(r.src).size() == r.q.size());
  // The same circle without CIRCs: chords only.
  test::TempDir lin;
  ro.templates = "krc4_lin";
  CHECK(run(cl, lin.path, ro).src.find("\nCIRC ") == std::string::npos);
}

// --- the Caro cell ----------------------------------------------------------------------------

TEST_CASE("machine: the Caro cell's TCP z points from the tip to the spindle, as in placement",
          "[machine]") {
  // At home the KR270-2 holds the spindle above the tool pointing down: the TCP z (the CL tool
  // axis convention) must point up, as placement's F_Pi z (towards the robot) does.
  const Cell cell = test::shipped_cell("caro2014_kr270_table");
  CHECK(tcp_pose(cell, cell.home()).linear().col(2).z() > 0.99);
  const Cell andres = test::shipped_cell(kCell);
  CHECK(tcp_pose(andres, andres.home()).linear().col(2).z() > 0.5);
}

// --- statements passed through ----------------------------------------------------------------

TEST_CASE("machine: INSERT/KRL: passes a checked statement, free text never reaches the code",
          "[machine]") {
  test::TempDir dir;
  const Run r =
      run("UNITS/MM\nLOADTL/1\nINSERT/[HOLDER=C40] 14MM X 60DEG\nINSERT/KRL: $OUT[17] = TRUE\n"
          "RAPID/\nGOTO/-120.,-440.,110.\n",
          dir.path);
  CHECK(r.src.find("\r\n; [HOLDER=C40] 14MM X 60DEG\r\n") != std::string::npos);
  CHECK(r.src.find("\r\n$OUT[17] = TRUE\r\n") != std::string::npos);
  test::TempDir bad;
  try {
    run("UNITS/MM\nINSERT/KRL: LIN {X 0}\nGOTO/-120.,-440.,110.\n", bad.path);
    FAIL("a motion passed through");
  } catch (const Error& e) {
    CHECK(e.where().line == 2);
    CHECK(e.message().find("cannot be passed to the KRL program") != std::string::npos);
  }
  for (const auto& e : fs::directory_iterator(bad.path))
    CHECK(e.path().extension() != ".src");
}

TEST_CASE("machine: a merged move written as its tracked steps puts every step on the CL line",
          "[machine][point_reduction]") {
  // 301 points 1 mm apart on a straight line while the tool tilts 20 deg about y: each merged
  // move of 100 points turns the whole frame (tilt and spin) further off the tool axis's great
  // circle than the angular tolerance allows, so it is written as the steps the tracker took.
  // Each step must be where the tracker took it, on the line (a regression: every step was
  // once written at the merged move's end point).
  std::string cl =
      "UNITS/MM\nLOADTL/1\nSPINDL/RPM,8000,CLW\nRAPID\nGOTO/-100,-500,100,0,0,1\n"
      "FEDRAT/MMPM,2000\n";
  for (int i = 0; i <= 300; ++i) {
    const double tilt = deg_to_rad(20.0 * i / 300.0);
    cl += fmt::format("GOTO/{:.4f},-500.0000,40.0000,{:.7f},0.0000000,{:.7f}\n", -100.0 + i,
                      std::sin(tilt), std::cos(tilt));
  }
  test::TempDir dir;
  RunOptions ro;
  ro.fit_tolerance_mm = 0.01;
  const Run r = run(cl, dir.path, ro);
  CHECK(r.summary.reducible_points == 300);
  CHECK(r.summary.reduced_moves < 10);
  static const std::regex lin(
      R"(LIN \{E6POS: X (\S+), Y (\S+), Z (\S+), A (\S+), B (\S+), C (\S+),)");
  int lins = 0;
  double last_x = -1e9;
  for (auto it = std::sregex_iterator(r.src.begin(), r.src.end(), lin);
       it != std::sregex_iterator(); ++it) {
    const double x = std::stod((*it)[1]), y = std::stod((*it)[2]), z = std::stod((*it)[3]);
    const KukaAbc abc{std::stod((*it)[4]), std::stod((*it)[5]), std::stod((*it)[6])};
    INFO("LIN at X " << x);
    CHECK(std::fabs(y + 500.0) <= 0.0015);
    CHECK(std::fabs(z - 40.0) <= 0.0015);
    CHECK(x > last_x);  // each step further along, none repeated at the end
    last_x = x;
    // Its tool axis: the CL file's at that x (the tilt is linear in x), within the tolerance.
    const double tilt = deg_to_rad(20.0 * (x + 100.0) / 300.0);
    const Eigen::Vector3d expected(std::sin(tilt), 0.0, std::cos(tilt));
    const Eigen::Vector3d axis = rotation_from_abc(abc).col(2);
    CHECK(rad_to_deg(std::acos(std::min(1.0, axis.dot(expected)))) <= 0.1);
    ++lins;
  }
  // The steps, not one LIN per point and not one per merged move.
  CHECK(lins > 10);
  CHECK(lins < 150);
  CHECK(last_x == Approx(200.0).margin(0.001));
}

TEST_CASE(
    "machine: with the point reduction, a small circle's chords at 10 m/min are written at the "
    "motion rate: each lasts one 12 ms cycle at its printed $VEL.CP",
    "[machine]") {
  // A 3 mm circle as LIN chords (krc4_lin): 0.49 mm chords, 3 ms each at 10 m/min, which no
  // reduction can lengthen within 0.01 mm. Checked from the printed text alone: every LIN's
  // length between printed positions over the $VEL.CP in force is at least one cycle; the
  // straight lead-in, long enough, keeps the feed.
  const std::string cl =
      "UNITS/MM\nCUTTER/6.,0\nLOADTL/1\nSPINDL/12000,RPM,CLW\nRAPID\nGOTO/-100,-440,110\n"
      "RAPID\nGOTO/-100,-440,62\nFEDRAT/MMPM,10000\nGOTO/-100,-440,57\nGOTO/-97,-440,57\n"
      "CIRCLE/-100,-440,57,0,0,1,3\nGOTO/-97,-440,57\nGOTO/-100,-440,57\nRAPID\n"
      "GOTO/-100,-440,110\nFINI\n";
  for (const double fit : {0.01, 0.0}) {
    test::TempDir dir;
    RunOptions ro;
    ro.fit_tolerance_mm = fit;
    const Run r = run(cl, dir.path, ro);
    std::istringstream text(r.src);
    std::string line;
    double vel_mm_s = 0.0;
    bool have = false;
    Eigen::Vector3d last;
    int short_motions = 0, lins = 0, at_feed = 0;
    static const std::regex pos(R"(X (-?[0-9.]+), Y (-?[0-9.]+), Z (-?[0-9.]+))");
    while (std::getline(text, line)) {
      if (line.rfind("$VEL.CP = ", 0) == 0)
        vel_mm_s = 1000.0 * std::stod(line.substr(10));
      std::smatch m;
      if (line.rfind("LIN ", 0) != 0 || !std::regex_search(line, m, pos))
        continue;
      const Eigen::Vector3d p(std::stod(m[1]), std::stod(m[2]), std::stod(m[3]));
      if (have && (p - last).norm() > 1e-6 && vel_mm_s < 200.0) {  // the cutting LINs
        ++lins;
        short_motions += (p - last).norm() / vel_mm_s < 0.012 * (1.0 - 1e-4) ? 1 : 0;
        at_feed += std::fabs(vel_mm_s - 10000.0 / 60.0) < 1e-3 ? 1 : 0;
      }
      last = p;
      have = true;
    }
    INFO("fit-tol " << fit << ", " << r.summary.slowed_motions << " lowered for an axis");
    CHECK(lins > 30);
    if (fit > 0.0) {
      CHECK(short_motions == 0);
      CHECK(at_feed >= 2);  // the lead-in and the way back to the centre
      CHECK(r.summary.rate_slowed_motions + r.summary.slowed_motions == lins - at_feed);
      CHECK(r.summary.below_cycle_motions == 0);
    } else {
      CHECK(short_motions > 20);  // 0.7's program: the chords at the feed
      CHECK(r.summary.rate_slowed_motions == 0);
    }
  }
}

TEST_CASE(
    "machine: CL points on a circle become CIRCs with the point reduction, and every point lies "
    "on the circle through the printed points",
    "[machine]") {
  // A CAM circle as GOTOs (no CIRCLE record): 3/4 of a 9 mm circle in 0.15 mm steps, then a
  // straight exit. krc4_circ writes arcs; from the printed text alone, every CL point must lie
  // within 0.01 mm (and the printed decimals) of a written CIRC's circle or LIN.
  std::string cl =
      "UNITS/MM\nCUTTER/6.,0\nLOADTL/1\nSPINDL/12000,RPM,CLW\nRAPID\nGOTO/-91,-440,110\n"
      "RAPID\nGOTO/-91,-440,62\nFEDRAT/MMPM,6000\nGOTO/-91,-440,57\n";
  std::vector<Eigen::Vector3d> points;
  const int steps = static_cast<int>(1.5 * kPi * 9.0 / 0.15);
  for (int k = 1; k <= steps; ++k) {
    const double phi = 1.5 * kPi * k / steps;
    points.emplace_back(-100.0 + 9.0 * std::cos(phi), -440.0 + 9.0 * std::sin(phi), 57.0);
    cl += fmt::format("GOTO/{:.4f},{:.4f},57\n", points.back().x(), points.back().y());
  }
  cl += "GOTO/-80,-449,57\nRAPID\nGOTO/-80,-449,110\nFINI\n";
  for (const char* set : {"krc4_circ", "krc4_lin"}) {
    test::TempDir dir;
    RunOptions ro;
    ro.templates = set;
    ro.fit_tolerance_mm = 0.01;
    const Run r = run(cl, dir.path, ro);
    const std::vector<PrintedCirc> circs = printed_circs(r.src);
    INFO(set);
    if (std::string(set) == "krc4_lin") {
      CHECK(circs.empty());
      continue;
    }
    REQUIRE(!circs.empty());
    CHECK(motion_keywords(r.src).size() < 20);  // 140 points as a few CIRCs
    // Every CL point on the arc within the tolerance of some written circle (its own arc).
    int on = 0;
    for (const Eigen::Vector3d& p : points) {
      for (const PrintedCirc& c : circs) {
        const Eigen::Vector3d rel = p - c.centre;
        const double h = rel.dot(c.normal);
        if (std::hypot(h, (rel - h * c.normal).norm() - c.radius_mm) <= 0.011) {
          ++on;
          break;
        }
      }
    }
    CHECK(on == static_cast<int>(points.size()));
    for (const PrintedCirc& c : circs)
      CHECK(c.radius_mm == Approx(9.0).margin(0.01));
  }
}
