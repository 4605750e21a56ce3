// KRL template sets and the KRL writer: the shipped sets load, bad sets are refused with
// file:line, and what the writer puts on disk is read back by a minimal reader written here
// (string scanning, independent of the writer's code) and compared with the motions given.
#include <stdlib.h>

#include <algorithm>
#include <charconv>
#include <clocale>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <locale>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "redpost/krl/motion_rate.hpp"
#include "redpost/krl/reader.hpp"
#include "redpost/krl/template.hpp"
#include "redpost/krl/writer.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace redpost;
namespace fs = std::filesystem;

namespace {

std::string template_path(const std::string& name) {
  return test::source_path("definitions/krl/" + name + ".xml");
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A fresh directory under /tmp, removed at the end of the test, with its listing.
struct TempDir : test::TempDir {
  TempDir() : test::TempDir("redpost_krl") {}
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(path))
      out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }
  std::map<std::string, std::string> contents() const {
    std::map<std::string, std::string> out;
    for (const std::string& n : names())
      out[n] = read_bytes(path / n);
    return out;
  }
};

// --- the minimal independent reader -----------------------------------------------------------

std::vector<std::string> split_lines(const std::string& bytes) {
  std::vector<std::string> lines;
  size_t pos = 0;
  while (pos < bytes.size()) {
    const size_t nl = bytes.find('\n', pos);
    std::string l = bytes.substr(pos, nl == std::string::npos ? std::string::npos : nl - pos);
    if (!l.empty() && l.back() == '\r')
      l.pop_back();
    lines.push_back(l);
    if (nl == std::string::npos)
      break;
    pos = nl + 1;
  }
  return lines;
}

double parse_number(const std::string& s) {
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  REQUIRE(ec == std::errc());
  REQUIRE(ptr == s.data() + s.size());
  return v;
}

// A motion line: "PTP {E6AXIS: A1 0.0, ...}", "LIN {E6POS: X 1, ...} C_DIS", "SLIN {...}".
struct MotionLine {
  std::string command, type;
  std::map<std::string, double> value;
  std::vector<std::string> keys;  // in order
  size_t line_index = 0;
};

std::vector<MotionLine> motion_lines(const std::vector<std::string>& lines) {
  static const std::regex motion(
      R"(^(PTP|LIN|SLIN|SPL) \{(E6POS|E6AXIS): ([^}]*)\}( C_DIS| WITH \$VEL\.CP = [0-9.]+)?$)");
  static const std::regex item(R"(^\s*([A-Z][A-Z0-9]*) (-?[0-9]+(\.[0-9]+)?)$)");
  std::vector<MotionLine> out;
  for (size_t i = 0; i < lines.size(); ++i) {
    std::smatch m;
    if (!std::regex_match(lines[i], m, motion))
      continue;
    MotionLine ml;
    ml.command = m[1];
    ml.type = m[2];
    ml.line_index = i;
    std::stringstream items(m[3].str());
    std::string it;
    while (std::getline(items, it, ',')) {
      std::smatch im;
      REQUIRE(std::regex_match(it, im, item));
      ml.keys.push_back(im[1]);
      ml.value[im[1]] = parse_number(im[2]);
    }
    out.push_back(ml);
  }
  return out;
}

Eigen::Matrix3d rotation_zyx_deg(double a, double b, double c) {
  const double k = 3.14159265358979323846 / 180.0;
  return (Eigen::AngleAxisd(a * k, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(b * k, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(c * k, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// --- motions ----------------------------------------------------------------------------------

std::vector<KrlMotion> make_motions(const Cell& cell, int count, uint64_t seed,
                                    int rapid_every = 0) {
  const ArmStatusModel model = make_arm_status_model(cell);
  std::mt19937_64 rng(seed);
  std::vector<KrlMotion> out;
  for (int i = 0; i < count; ++i) {
    const JointVector q = test::random_posture(cell, rng);
    KrlMotion m;
    m.kind = rapid_every > 0 && i % rapid_every == rapid_every - 1 ? KrlMotionKind::rapid
                                                                   : KrlMotionKind::lin;
    m.axes = to_controller_axes(cell, q);
    m.T_base_tcp = tcp_pose(cell, q);
    m.status_turn = status_turn(cell, model, q);
    m.cl_line = 1000 + 3 * i;
    out.push_back(m);
  }
  return out;
}

KrlProgramInfo info_for(const TempDir& dir, const std::string& name) {
  KrlProgramInfo info;
  info.name = name;
  info.output_dir = dir.path.string();
  info.header_comment = "redpost test";
  return info;
}

std::vector<std::string> write_program(const KrlTemplateSet& set, const KrlProgramInfo& info,
                                       const std::vector<KrlMotion>& motions,
                                       double feed_mm_per_min = 1200.0) {
  KrlWriter w(set, info);
  w.velocity(feed_mm_per_min / 60000.0);
  for (const KrlMotion& m : motions)
    w.motion(m);
  return w.finish();
}

void check_axes(const MotionLine& ml, const AxisValues& axes, bool with_arm) {
  if (with_arm) {
    for (int n = 1; n <= 6; ++n) {
      const std::string key = "A" + std::to_string(n);
      REQUIRE(ml.value.count(key));
      CHECK(ml.value.at(key) == Approx(axes.arm(n)).margin(0.5e-4 + 1e-12));
    }
  }
  for (int n = 1; n <= 6; ++n) {
    const std::string key = "E" + std::to_string(n);
    if (std::isnan(axes.external(n))) {
      CHECK(ml.value.count(key) == 0);  // only the axes the cell has
    } else {
      REQUIRE(ml.value.count(key));
      CHECK(ml.value.at(key) == Approx(axes.external(n)).margin(0.5e-4 + 1e-12));
    }
  }
}

void check_pose(const MotionLine& ml, const KrlMotion& m) {
  const Eigen::Vector3d p = m.T_base_tcp.translation();
  CHECK(ml.value.at("X") == Approx(p.x()).margin(0.5e-3 + 1e-9));
  CHECK(ml.value.at("Y") == Approx(p.y()).margin(0.5e-3 + 1e-9));
  CHECK(ml.value.at("Z") == Approx(p.z()).margin(0.5e-3 + 1e-9));
  const Eigen::Matrix3d R = rotation_zyx_deg(ml.value.at("A"), ml.value.at("B"), ml.value.at("C"));
  CHECK((R - m.T_base_tcp.linear()).norm() < 1e-5);
}

int line_of(const std::string& text, const std::string& needle) {
  const size_t at = text.find(needle);
  REQUIRE(at != std::string::npos);
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

}  // namespace

// --- template sets ------------------------------------------------------------------------------

TEST_CASE("krl_writer: the shipped template sets load") {
  const KrlTemplateSet lin = load_krl_templates(template_path("krc4_lin"));
  CHECK(lin.name == "krc4_lin");
  CHECK_FALSE(lin.spline);
  CHECK(lin.statements.at("lin").find("C_DIS") != std::string::npos);
  const KrlTemplateSet spline = load_krl_templates(template_path("krc4_spline"));
  CHECK(spline.spline);
  CHECK(spline.max_spline_points == 100);
  CHECK(spline.statements.count("lin") == 0);
  const KrlTemplateSet krc2 = load_krl_templates(template_path("krc2_lin"));
  CHECK(krc2.statements.at("rapid").find("{s}") != std::string::npos);
  // A KR C4 holds about 4 MB of programs in all; the parts' size is the writer's default.
  CHECK(lin.program_memory_bytes == 3000000);
  CHECK(spline.program_memory_bytes == 3000000);
  CHECK(lin.max_file_bytes == 0);
  CHECK(krc2.program_memory_bytes == 0);  // not known for KSS 5
  CHECK(krc2.src_file.find("&PARAM") == std::string::npos);
  for (const KrlTemplateSet* s : {&lin, &spline, &krc2}) {
    INFO(s->name);
    CHECK(s->src_file.find("BAS (#INITMOV,0 )") != std::string::npos);
    CHECK(s->src_file.find("{date}") == std::string::npos);  // deterministic output
    CHECK(s->src_file.rfind("&ACCESS", 0) == 0);             // the layout line break is dropped
  }
}

TEST_CASE("krl_writer: the time model's clock comes from the set and its skeleton") {
  // The shipped KR C4 sets write $ADVANCE = 3 and say nothing else: a 12 ms cycle, look-ahead 3.
  const KrlTemplateSet lin = load_krl_templates(template_path("krc4_lin"));
  CHECK(lin.timing.interpolation_cycle_ms == 12.0);
  CHECK(lin.timing.advance == 3);
  // The skeleton's $ADVANCE wins over the default; the attribute sets it where none is written.
  const std::string good = read_bytes(template_path("krc4_lin"));
  const KrlTemplateSet five =
      parse_krl_templates(replaced(good, "$ADVANCE = 3", "$ADVANCE = 5"), "5.xml");
  CHECK(five.timing.advance == 5);
  const KrlTemplateSet none = parse_krl_templates(
      replaced(replaced(good, "$ADVANCE = 3\n", ""), "<timing ptp-velocity=\"20\"/>",
               "<timing ptp-velocity=\"20\" advance=\"1\" interpolation-cycle=\"4\"/>"),
      "1.xml");
  CHECK(none.timing.advance == 1);
  CHECK(none.timing.interpolation_cycle_ms == 4.0);
}

TEST_CASE("krl_writer: the example of docs/krl-templates.md loads and writes") {
  const std::string doc = read_bytes(test::source_path("docs/krl-templates.md"));
  const size_t begin = doc.find("```xml\n");
  REQUIRE(begin != std::string::npos);
  const size_t end = doc.find("\n```", begin + 7);
  REQUIRE(end != std::string::npos);
  const KrlTemplateSet set =
      parse_krl_templates(doc.substr(begin + 7, end - begin - 7), "krl-templates.md");
  TempDir dir;
  const Cell cell = test::shipped_cell("caro2014_kr270_table");
  write_program(set, info_for(dir, "DOC_EXAMPLE"), make_motions(cell, 5, 8));
  CHECK(motion_lines(split_lines(read_bytes(dir.path / "DOC_EXAMPLE.src"))).size() == 5);
}

TEST_CASE("krl_writer: bad template files are refused with file:line") {
  const std::string good = read_bytes(template_path("krc4_lin"));
  const auto expect_error = [](const std::string& text, int line, const std::string& words) {
    try {
      parse_krl_templates(text, "bad.xml");
      FAIL("accepted");
    } catch (const Error& e) {
      INFO(e.what());
      CHECK(e.code() == ErrorCode::bad_input);
      CHECK(e.where().file == "bad.xml");
      if (line > 0)
        CHECK(e.where().line == line);
      CHECK(e.message().find(words) != std::string::npos);
    }
  };
  REQUIRE_NOTHROW(parse_krl_templates(good, "good.xml"));

  SECTION("a look-ahead other than the skeleton's $ADVANCE") {
    const std::string bad = replaced(good, "<timing ptp-velocity=\"20\"/>",
                                     "<timing ptp-velocity=\"20\" advance=\"2\"/>");
    expect_error(bad, line_of(bad, "advance=\"2\""), "sets $ADVANCE = 3");
  }
  SECTION("a program memory too small to be meant, and one given twice") {
    std::string bad =
        replaced(good, "<limits program-memory=\"3000000\"/>", "<limits program-memory=\"1000\"/>");
    expect_error(bad, line_of(bad, "program-memory=\"1000\""), "program-memory");
    bad = replaced(good, "<limits program-memory=\"3000000\"/>",
                   "<limits program-memory=\"3000000\"/><limits max-bytes=\"65536\"/>");
    expect_error(bad, 0, "<limits> given twice");
  }
  SECTION("a continued part that would stop the advance run or move") {
    const std::string marker = "; continues the cut where the part before it ended";
    std::string bad = replaced(good, marker, "WAIT SEC 0\n" + marker);
    expect_error(bad, line_of(bad, "WAIT SEC 0"), "may not hold WAIT");
    bad = replaced(good, marker, "BAS (#INITMOV,1 )\n" + marker);
    expect_error(bad, line_of(bad, "#INITMOV,1"), "#INITMOV");
    bad = replaced(good, marker, "  ptp {E6AXIS: A1 0}\n" + marker);
    expect_error(bad, line_of(bad, "ptp {E6AXIS"), "may not hold PTP");
  }
  SECTION("an interpolation cycle out of range") {
    const std::string bad = replaced(good, "<timing ptp-velocity=\"20\"/>",
                                     "<timing ptp-velocity=\"20\" interpolation-cycle=\"0\"/>");
    expect_error(bad, line_of(bad, "interpolation-cycle"), "interpolation-cycle");
  }
  SECTION("unknown placeholder in a statement") {
    const std::string bad = replaced(good, "Y {y}, Z {z}, A {a}, B {b}, C {c}{ext}} C_DIS",
                                     "Y {y}, Z {zz}, A {a}, B {b}, C {c}{ext}} C_DIS");
    expect_error(bad, line_of(bad, "{zz}"), "{zz}");
  }
  SECTION("a placeholder of another statement") {
    const std::string bad = replaced(good, "{c}{ext}} C_DIS", "{c}, S {s}{ext}} C_DIS");
    expect_error(bad, line_of(bad, "S {s}"), "{s}");
  }
  SECTION("unknown placeholder deep in a skeleton") {
    const std::string bad = replaced(good, "$APO.CDIS = {apo_mm}", "$APO.CDIS = {apo}");
    expect_error(bad, line_of(bad, "{apo}"), "{apo}");
  }
  SECTION("{body} not alone on its line") {
    const std::string bad = replaced(good, "\n{body}\n", "\nX {body}\n");
    expect_error(bad, line_of(bad, "X {body}"), "alone");
  }
  SECTION("unknown statement") {
    const std::string bad =
        replaced(good, "  <statement name=\"vel\">",
                 "  <statement name=\"arc\">CIRC {x}</statement>\n  <statement name=\"vel\">");
    expect_error(bad, line_of(bad, "name=\"arc\""), "arc");
  }
  SECTION("a spline statement in a set without <spline>") {
    const std::string bad =
        replaced(good, "  <statement name=\"vel\">",
                 "  <statement name=\"spline_end\">ENDSPLINE</statement>\n  <statement "
                 "name=\"vel\">");
    expect_error(bad, line_of(bad, "spline_end"), "spline");
  }
  SECTION("a segment's own speed in one form only, or without SPL") {
    const std::string spline = read_bytes(template_path("krc4_spline"));
    REQUIRE_NOTHROW(parse_krl_templates(spline, "good.xml"));
    const std::string lin_only =
        std::regex_replace(spline, std::regex("  <statement name=\"spline_spl_vel\">[^\n]*\n"), "");
    expect_error(lin_only, line_of(lin_only, "name=\"spline_lin_vel\""), "go together");
    const std::string no_spl =
        std::regex_replace(spline, std::regex("  <statement name=\"spline_spl\">[^\n]*\n"), "");
    expect_error(no_spl, line_of(no_spl, "name=\"spline_lin_vel\""), "only with spline_spl");
  }
  SECTION("fixed text that redpost check would reject (issue 31)") {
    // A 25-character name in the skeleton: refused at its line, as check reports it.
    const std::string long_name =
        replaced(good, "$ADVANCE = 3", "$ADVANCE = 3\nABCDEFGHIJKLMNOPQRSTUVWXY = 1");
    expect_error(long_name, line_of(long_name, "ABCDEFGHIJKLMNOPQRSTUVWXY"),
                 "has 25 characters, more than 24");
    // One of 24 is a KRL name: accepted.
    REQUIRE_NOTHROW(parse_krl_templates(
        replaced(good, "$ADVANCE = 3", "$ADVANCE = 3\nABCDEFGHIJKLMNOPQRSTUVWX = 1"), "ok.xml"));
    // A statement that is not KRL, on the second line of a statement.
    const std::string not_krl =
        replaced(good, "HALT ; mount tool T{number} by hand", "MOUNT THE TOOL ; T{number} by hand");
    expect_error(not_krl, line_of(not_krl, "MOUNT THE TOOL"),
                 "<statement name=\"tool_change_manual\">: not a KRL statement");
    // A declaration after the skeleton's first statement.
    const std::string late_decl = replaced(good, "$ADVANCE = 3", "$ADVANCE = 3\nDECL INT COUNT");
    expect_error(late_decl, line_of(late_decl, "DECL INT COUNT"), "declaration after");
    // A FOLD left open in the dat skeleton.
    const std::string open_fold = replaced(good, "DEFDAT {name}\n", "DEFDAT {name}\n;FOLD DATA\n");
    expect_error(open_fold, line_of(open_fold, ";FOLD DATA"), "FOLD without a matching ENDFOLD");
  }
  SECTION("a statement missing") {
    const std::string bad =
        replaced(good, "<statement name=\"vel\">$VEL.CP = {vel}</statement>", "");
    expect_error(bad, line_of(bad, "<krl-templates"), "vel");
  }
  SECTION("decimals out of range") {
    const std::string bad = replaced(good, "angle=\"4\"", "angle=\"four\"");
    expect_error(bad, line_of(bad, "<numbers"), "angle");
  }
  SECTION("malformed XML") {
    const std::string bad = replaced(good, "</statement>\n  <statement name=\"comment\">",
                                     "</statment>\n  <statement name=\"comment\">");
    try {
      parse_krl_templates(bad, "bad.xml");
      FAIL("accepted");
    } catch (const Error& e) {
      CHECK(e.where().file == "bad.xml");
      CHECK(e.where().line > 0);
      CHECK(std::string(e.what()).find("not well-formed") != std::string::npos);
    }
  }
  SECTION("a file on disk: the message starts with path:line") {
    TempDir dir;
    const fs::path p = dir.path / "t.xml";
    const std::string bad = replaced(good, "{apo_mm}", "{apo}");
    std::ofstream(p, std::ios::binary) << bad;
    try {
      load_krl_templates(p.string());
      FAIL("accepted");
    } catch (const Error& e) {
      CHECK(std::string(e.what()).rfind(
                p.string() + ":" + std::to_string(line_of(bad, "{apo}")) + ":", 0) == 0);
    }
  }
  SECTION("missing file") {
    try {
      load_krl_templates("/nonexistent/redpost/krc9.xml");
      FAIL("accepted");
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::io);
      CHECK(e.where().file == "/nonexistent/redpost/krc9.xml");
    }
  }
}

// --- the writer -----------------------------------------------------------------------------

TEST_CASE("krl_writer: a small program reads back as the motions given") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");  // E1 track, E2 table
  const KrlTemplateSet set = load_krl_templates(template_path("krc4_lin"));
  TempDir dir;
  KrlProgramInfo info = info_for(dir, "MILL_TEST");
  info.cl_line_every = 10;
  info.base = "BASE_DATA[3]";
  info.tool = "TOOL_DATA[2]";
  std::vector<KrlMotion> motions = make_motions(cell, 60, 42, 20);
  motions[17].T_base_tcp.translation().x() = -0.0002;  // prints as 0.000, not -0.000

  const double feed1 = 1500.0, feed2 = 700.0;  // mm/min
  {
    KrlWriter w(set, info);
    w.velocity(feed1 / 60000.0);
    for (size_t i = 0; i < motions.size(); ++i) {
      if (i == 30)
        w.velocity(feed2 / 60000.0);
      w.motion(motions[i]);
    }
    CHECK(w.motions() == 60);
    const std::vector<std::string> paths = w.finish();
    REQUIRE(paths.size() == 1);
    CHECK(paths[0] == (dir.path / "MILL_TEST.src").string());
  }
  CHECK(dir.names() == std::vector<std::string>{"MILL_TEST.dat", "MILL_TEST.src"});
  const std::string src = read_bytes(dir.path / "MILL_TEST.src");
  const std::string dat = read_bytes(dir.path / "MILL_TEST.dat");

  // Line endings: CRLF everywhere, no bare LF, and a final CRLF.
  for (const std::string* bytes : {&src, &dat}) {
    size_t bare = 0;
    for (size_t i = 0; i < bytes->size(); ++i)
      bare += (*bytes)[i] == '\n' && (i == 0 || (*bytes)[i - 1] != '\r');
    CHECK(bare == 0);
    CHECK(bytes->size() >= 2);
    CHECK(bytes->substr(bytes->size() - 2) == "\r\n");
  }
  const std::vector<std::string> lines = split_lines(src);
  const auto has = [&](const std::string& l) {
    return std::find(lines.begin(), lines.end(), l) != lines.end();
  };
  CHECK(lines[0] == "&ACCESS RVP");
  CHECK(has("DEF MILL_TEST( )"));
  CHECK(has("END"));
  CHECK(has("    BAS (#INITMOV,0 )"));
  CHECK(has("$BASE = BASE_DATA[3]"));
  CHECK(has("$TOOL = TOOL_DATA[2]"));
  CHECK(has("$APO.CDIS = 0.500"));
  CHECK(dat.find("DEFDAT MILL_TEST\r\n") != std::string::npos);
  CHECK(dat.find("ENDDAT\r\n") != std::string::npos);
  CHECK(src.find("-0.000") == std::string::npos);

  const std::vector<MotionLine> ml = motion_lines(lines);
  REQUIRE(ml.size() == motions.size());
  // The first motion, although given as a LIN, is a PTP to the full E6AXIS.
  CHECK(ml[0].command == "PTP");
  CHECK(ml[0].type == "E6AXIS");
  check_axes(ml[0], motions[0].axes, true);
  CHECK(ml[0].keys == std::vector<std::string>{"A1", "A2", "A3", "A4", "A5", "A6", "E1", "E2"});
  for (size_t i = 1; i < motions.size(); ++i) {
    INFO("motion " << i);
    if (motions[i].kind == KrlMotionKind::rapid) {
      CHECK(ml[i].command == "PTP");
      CHECK(ml[i].type == "E6AXIS");
      check_axes(ml[i], motions[i].axes, true);
    } else {
      CHECK(ml[i].command == "LIN");
      CHECK(ml[i].type == "E6POS");
      CHECK(ml[i].keys == std::vector<std::string>{"X", "Y", "Z", "A", "B", "C", "E1", "E2"});
      check_pose(ml[i], motions[i]);
      check_axes(ml[i], motions[i].axes, false);
    }
  }

  // $VEL.CP in m/s = feed / 60000, printed before the first feed move and at the change.
  std::vector<std::pair<size_t, double>> vel;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].rfind("$VEL.CP = ", 0) == 0)
      vel.emplace_back(i, parse_number(lines[i].substr(10)));
  }
  REQUIRE(vel.size() == 2);
  CHECK(vel[0].second == Approx(feed1 / 60000.0).margin(0.5e-6));
  CHECK(vel[1].second == Approx(feed2 / 60000.0).margin(0.5e-6));
  CHECK(vel[0].first < ml[1].line_index);
  CHECK(vel[0].first > ml[0].line_index);
  CHECK(vel[1].first > ml[29].line_index);
  CHECK(vel[1].first < ml[30].line_index);

  // The first motion is the BCO run (bco_ptp): said in a comment, slower, then the rapids'
  // velocity again.
  REQUIRE(ml[0].line_index >= 2);
  CHECK(lines[ml[0].line_index - 2].rfind("; BCO run: PTP from where the robot stands", 0) == 0);
  CHECK(lines[ml[0].line_index - 1] == "BAS (#VEL_PTP,10)");
  CHECK(lines[ml[0].line_index + 1] == "BAS (#VEL_PTP,20)");

  // A CL line comment before every 10th motion, carrying that motion's CL line (before the
  // BCO run's two lines at the first).
  int cl_comments = 0;
  for (size_t i = 0; i < motions.size(); ++i) {
    const size_t at = ml[i].line_index - (i == 0 ? 2 : 0);
    const std::string expected = "; CL line " + std::to_string(motions[i].cl_line);
    const bool present =
        at > 0 && (lines[at - 1] == expected || (at > 1 && lines[at - 2] == expected));
    CHECK(present == (i % 10 == 0));
    cl_comments += present;
  }
  CHECK(cl_comments == 6);
}

TEST_CASE("krl_writer: a cell without external axes writes no E values") {
  const Cell cell = test::shipped_cell("caro2014_kr270_table");
  const KrlTemplateSet set = load_krl_templates(template_path("krc4_lin"));
  TempDir dir;
  const std::vector<KrlMotion> motions = make_motions(cell, 20, 5);
  write_program(set, info_for(dir, "CARO"), motions);
  const std::vector<MotionLine> ml = motion_lines(split_lines(read_bytes(dir.path / "CARO.src")));
  REQUIRE(ml.size() == motions.size());
  CHECK(ml[0].keys == std::vector<std::string>{"A1", "A2", "A3", "A4", "A5", "A6"});
  for (size_t i = 1; i < ml.size(); ++i) {
    CHECK(ml[i].keys == std::vector<std::string>{"X", "Y", "Z", "A", "B", "C"});
    check_pose(ml[i], motions[i]);
  }
}

TEST_CASE("krl_writer: KRC2 rapids are Cartesian PTPs with Status and Turn") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const KrlTemplateSet set = load_krl_templates(template_path("krc2_lin"));
  TempDir dir;
  const std::vector<KrlMotion> motions = make_motions(cell, 40, 9, 4);
  write_program(set, info_for(dir, "KRC2_PROG"), motions);
  const std::string src = read_bytes(dir.path / "KRC2_PROG.src");
  CHECK(src.find("&PARAM") == std::string::npos);
  CHECK(read_bytes(dir.path / "KRC2_PROG.dat").find("EXT BAS (BAS_COMMAND :IN,REAL :IN )") !=
        std::string::npos);
  const std::vector<MotionLine> ml = motion_lines(split_lines(src));
  REQUIRE(ml.size() == motions.size());
  CHECK(ml[0].type == "E6AXIS");
  int rapids = 0, seen_status = 0;
  for (size_t i = 1; i < motions.size(); ++i) {
    if (motions[i].kind != KrlMotionKind::rapid)
      continue;
    ++rapids;
    INFO("motion " << i);
    CHECK(ml[i].command == "PTP");
    REQUIRE(ml[i].type == "E6POS");
    CHECK(ml[i].keys ==
          std::vector<std::string>{"X", "Y", "Z", "A", "B", "C", "S", "T", "E1", "E2"});
    check_pose(ml[i], motions[i]);
    check_axes(ml[i], motions[i].axes, false);
    CHECK(ml[i].value.at("S") == motions[i].status_turn.status);
    CHECK(ml[i].value.at("T") == motions[i].status_turn.turn);
    seen_status |= motions[i].status_turn.status;
  }
  CHECK(rapids == 10);
  CHECK(seen_status != 0);
}

TEST_CASE("krl_writer: spline blocks hold at most max-points SLINs") {
  const Cell cell = test::shipped_cell("kr15_2");
  const KrlTemplateSet set = load_krl_templates(template_path("krc4_spline"));
  TempDir dir;
  const std::vector<KrlMotion> motions = make_motions(cell, 251, 13, 0);
  {
    KrlWriter w(set, info_for(dir, "SPLINED"));
    w.velocity(0.02);
    for (size_t i = 0; i < motions.size(); ++i) {
      if (i == 150)
        w.velocity(0.01);  // ends the block: no system variable inside a spline block
      w.motion(motions[i]);
    }
    w.finish();
  }
  const std::vector<std::string> lines = split_lines(read_bytes(dir.path / "SPLINED.src"));
  bool inside = false;
  int in_block = 0, blocks = 0, slins = 0;
  std::vector<int> sizes;
  for (const std::string& l : lines) {
    if (l == "SPLINE") {
      CHECK_FALSE(inside);
      inside = true;
      in_block = 0;
      ++blocks;
    } else if (l == "ENDSPLINE C_SPL") {
      CHECK(inside);
      inside = false;
      sizes.push_back(in_block);
    } else if (l.rfind("SLIN ", 0) == 0) {
      CHECK(inside);
      ++in_block;
      ++slins;
    } else if (inside) {
      CHECK(l.rfind(";", 0) == 0);  // only comments inside a block
    }
  }
  CHECK_FALSE(inside);
  CHECK(slins == 250);  // the first motion is the PTP
  // 149 SLINs before the velocity change (100 + 49), then 101 (100 + 1).
  CHECK(sizes == std::vector<int>{100, 49, 100, 1});
  CHECK(blocks == 4);
  const std::vector<MotionLine> ml = motion_lines(lines);
  REQUIRE(ml.size() == motions.size());
  for (size_t i = 1; i < ml.size(); ++i)
    check_pose(ml[i], motions[i]);
}

TEST_CASE("krl_writer: SPL where the path is smooth, a new block at every corner") {
  // A quarter circle of 60 segments (smooth), then a corner, a straight line of two segments
  // (collinear points pass smoothly too), another corner and a last segment alone (an SLIN
  // between two corners). The blocks' segments are read back from the text.
  const Cell cell = test::shipped_cell("kr15_2");
  const KrlTemplateSet set = load_krl_templates(template_path("krc4_spline"));
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k <= 60; ++k) {
    const double phi = 0.5 * M_PI * k / 60.0;
    points.emplace_back(600.0 + 40.0 * std::cos(phi), 40.0 * std::sin(phi), 500.0);
  }
  points.emplace_back(600.0, 40.0, 540.0);  // up: a 90 deg corner (the arc ends along -x)
  points.emplace_back(600.0, 40.0, 580.0);
  points.emplace_back(600.0, 80.0, 580.0);  // another corner
  std::vector<KrlMotion> motions = make_motions(cell, static_cast<int>(points.size()), 5, 0);
  for (size_t i = 0; i < points.size(); ++i)
    motions[i].T_base_tcp.translation() = points[i];
  for (const double tolerance : {0.0, 0.009}) {
    TempDir dir;
    KrlProgramInfo info = info_for(dir, "SMOOTH");
    info.spline_tolerance_mm = tolerance;
    std::vector<bool> smooth;
    {
      KrlWriter w(set, info);
      w.velocity(0.1);
      for (size_t i = 0; i < motions.size(); ++i) {
        // Slower for two segments in the middle of the arc (an axis limits them).
        w.velocity(i == 30 || i == 31 ? 0.05 : 0.1);
        w.motion(motions[i]);
        smooth.push_back(w.joined_smoothly());
      }
      CHECK(w.has_spl() == (tolerance > 0.0));
      w.finish();
    }
    std::vector<std::string> kinds;  // per block: "SPL"/"SLIN" per segment
    std::string block;
    int own_speed = 0;  // segments with their own $VEL.CP
    for (const std::string& l : split_lines(read_bytes(dir.path / "SMOOTH.src"))) {
      if (l.find(" WITH $VEL.CP = 0.050000") != std::string::npos)
        ++own_speed;
      if (l == "SPLINE")
        block.clear();
      else if (l == "ENDSPLINE C_SPL")
        kinds.push_back(block);
      else if (l.rfind("SPL ", 0) == 0)
        block += "S";
      else if (l.rfind("SLIN ", 0) == 0)
        block += "L";
    }
    if (tolerance == 0.0) {
      // Every feed move an SLIN; the speed changes end the blocks: the program of 0.7.
      CHECK(kinds == std::vector<std::string>{std::string(29, 'L'), "LL",
                                              std::string(points.size() - 32, 'L')});
      CHECK(own_speed == 0);
      CHECK(std::none_of(smooth.begin(), smooth.end(), [](bool b) { return b; }));
    } else {
      // The arc's 60 segments and its corner end one block; the line of two, then the last.
      // The two slower segments keep the block, with their own speed.
      CHECK(kinds == std::vector<std::string>{std::string(60, 'S'), "SS", "L"});
      CHECK(own_speed == 2);
      // The arc's inner points are smooth knots; the corners and the block starts are not.
      for (size_t i = 0; i < smooth.size(); ++i) {
        INFO("motion " << i);
        CHECK(smooth[i] == (i >= 2 && i <= 60 || i == 62));
      }
    }
    // The positions are the points given, whatever the keyword (and a WITH after them).
    const std::vector<MotionLine> ml =
        motion_lines(split_lines(read_bytes(dir.path / "SMOOTH.src")));
    REQUIRE(ml.size() == motions.size());
    for (size_t i = 1; i < ml.size(); ++i)
      check_pose(ml[i], motions[i]);
  }
}

TEST_CASE("krl_writer: an SLIN alone between corners shorter than a cycle runs at the rate") {
  // A zigzag of 1 mm steps turning 90 deg at every point: every step a block of its own. At
  // 0.2 m/s a step lasts 5 ms; with a 12 ms cycle each is written with the speed at which it
  // lasts one (its length short by the printed decimals), and the reader's count of motions
  // below a cycle, from the text, is 0. Without the cycle, at 0.2 m/s, all are below.
  const Cell cell = test::shipped_cell("kr15_2");
  const KrlTemplateSet set = load_krl_templates(template_path("krc4_spline"));
  std::vector<KrlMotion> motions = make_motions(cell, 21, 9, 0);
  for (size_t i = 0; i < motions.size(); ++i) {
    // One orientation: the steps only move (a turn would take its own time at $VEL.ORI1).
    motions[i].T_base_tcp.linear() = motions[0].T_base_tcp.linear();
    motions[i].T_base_tcp.translation() = Eigen::Vector3d(600.0 + static_cast<double>((i + 1) / 2),
                                                          static_cast<double>(i / 2), 500.0);
  }
  for (const double cycle : {0.0, 0.012}) {
    TempDir dir;
    KrlProgramInfo info = info_for(dir, "ZIGZAG");
    info.spline_tolerance_mm = 0.009;
    info.interpolation_cycle_s = cycle;
    std::vector<double> rates;
    {
      KrlWriter w(set, info);
      w.velocity(0.2);
      for (const KrlMotion& m : motions)
        w.motion(m);
      w.end_block();
      for (long k = 1; k <= static_cast<long>(motions.size()); ++k) {
        double v = 0.0;
        if (w.take_rate_segment(k, v))
          rates.push_back(v);
      }
      w.finish();
    }
    const KrlProgram program = read_krl_program((dir.path / "ZIGZAG.src").string());
    const KrlMotionRate rate = krl_motion_rate(program, KrlMotionRateOptions{});
    CHECK(rate.cp_motions == 19);  // the first step starts after a PTP to axes: not measured
    CHECK(rate.unmeasured == 1);
    CHECK(rate.spline_joined == 0);
    if (cycle == 0.0) {
      CHECK(rates.empty());
      CHECK(rate.below_cycle == 19);
    } else {
      // (1 - sqrt(3) 0.001) mm / 0.012 s = 83.18899 mm/s, floored to the set's 6 decimals of
      // m/s.
      REQUIRE(rates.size() == 20);
      for (const double v : rates)
        CHECK(v == Approx(0.083188).margin(1e-12));
      CHECK(rate.below_cycle == 0);
      for (std::size_t k = 1; k < program.motions.size(); ++k)
        CHECK(program.motions[k].vel_cp_m_per_s == Approx(0.083188).margin(1e-12));
    }
  }
}

TEST_CASE("krl_writer: splitting into a main program and parts") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const KrlTemplateSet set = load_krl_templates(template_path("krc4_lin"));
  TempDir dir;
  KrlProgramInfo info = info_for(dir, "BIGJOB");
  info.motions_per_file = 1000;
  std::vector<KrlMotion> motions = make_motions(cell, 2500, 77, 0);
  // Each part ends out of the material: the next runs alone (the test below: in the cut).
  motions[999].in_air = motions[1999].in_air = true;
  const std::vector<std::string> paths = write_program(set, info, motions);

  CHECK(dir.names() == std::vector<std::string>{"BIGJOB.dat", "BIGJOB.src", "BIGJOB_P001.dat",
                                                "BIGJOB_P001.src", "BIGJOB_P002.dat",
                                                "BIGJOB_P002.src", "BIGJOB_P003.dat",
                                                "BIGJOB_P003.src"});
  REQUIRE(paths.size() == 4);
  CHECK(fs::path(paths[0]).filename() == "BIGJOB.src");
  std::vector<std::string> part_files;
  for (size_t i = 1; i < paths.size(); ++i)
    part_files.push_back(fs::path(paths[i]).filename().string());
  CHECK(std::is_sorted(part_files.begin(), part_files.end()));

  // The main calls the parts, in order, and moves nothing itself.
  const std::vector<std::string> main = split_lines(read_bytes(dir.path / "BIGJOB.src"));
  std::vector<std::string> calls;
  const std::regex call(R"(^([A-Za-z][A-Za-z0-9_]*)\( \)$)");
  for (const std::string& l : main) {
    std::smatch m;
    if (std::regex_match(l, m, call))
      calls.push_back(m[1]);
  }
  CHECK(calls == std::vector<std::string>{"BIGJOB_P001", "BIGJOB_P002", "BIGJOB_P003"});
  CHECK(motion_lines(main).empty());
  CHECK(std::find(main.begin(), main.end(), "DEF BIGJOB( )") != main.end());

  size_t next = 0;  // index of the next given motion
  for (int part = 1; part <= 3; ++part) {
    INFO("part " << part);
    const std::string name = "BIGJOB_P00" + std::to_string(part);
    const std::vector<std::string> lines = split_lines(read_bytes(dir.path / (name + ".src")));
    CHECK(std::find(lines.begin(), lines.end(), "DEF " + name + "( )") != lines.end());
    CHECK(read_bytes(dir.path / (name + ".dat")).find("DEFDAT " + name + "\r\n") !=
          std::string::npos);
    // Its own $VEL.CP before its first feed move: it runs alone.
    CHECK(std::count_if(lines.begin(), lines.end(),
                        [](const std::string& l) { return l.rfind("$VEL.CP = ", 0) == 0; }) == 1);
    const std::vector<MotionLine> ml = motion_lines(lines);
    REQUIRE(!ml.empty());
    CHECK(ml[0].command == "PTP");
    CHECK(ml[0].type == "E6AXIS");
    if (part == 1) {
      check_axes(ml[0], motions[0].axes, true);
      CHECK(ml.size() == 1000);
    } else {
      // The posture where the previous part ended, then this part's own motions.
      check_axes(ml[0], motions[next - 1].axes, true);
      CHECK(ml.size() == (part == 3 ? 501u : 1001u));
    }
    for (size_t k = part == 1 ? 1 : 1; k < ml.size(); ++k) {
      const size_t given = part == 1 ? k : next + k - 1;
      CHECK(ml[k].command == "LIN");
      check_pose(ml[k], motions[given]);
    }
    next += part == 1 ? ml.size() : ml.size() - 1;
  }
  CHECK(next == motions.size());
}

TEST_CASE("krl_writer: a part ends after a rapid once three quarters full; else the cut is said") {
  // A seeded property: motions with a rapid (in_air) every `every`-th, 16 KiB parts. Every part
  // boundary the writer reports outside the cut follows a rapid, read back from the parts' text
  // (each part's last motion line against the motions given); the others are counted and their
  // CL lines named; the files' bytes are the report's.
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const KrlTemplateSet set = load_krl_templates(template_path("krc4_lin"));
  for (const int every : {7, 40, 0}) {
    INFO("a rapid every " << every << " motions");
    TempDir dir;
    KrlProgramInfo info = info_for(dir, "AIR");
    info.max_file_bytes = 16 * 1024;
    std::vector<KrlMotion> motions = make_motions(cell, 900, 11, every);
    for (KrlMotion& m : motions)
      m.in_air = m.kind == KrlMotionKind::rapid;
    long report_bytes = 0, mid_cut = 0;
    std::vector<int> mid_cut_lines;
    {
      KrlWriter w(set, info);
      w.velocity(0.02);
      for (const KrlMotion& m : motions)
        w.motion(m);
      w.prepare();
      report_bytes = w.split().program_bytes;
      mid_cut = w.split().mid_cut;
      mid_cut_lines = w.split().mid_cut_lines;
      REQUIRE(w.split().parts >= 3);
      w.finish();
    }
    long file_bytes = 0;
    for (const std::string& name : dir.names())
      file_bytes += static_cast<long>(fs::file_size(dir.path / name));
    CHECK(report_bytes == file_bytes);
    // Each part but the last: its last motion is motion k of those given (by its CL line
    // comment-free text: the part's motion lines counted in order).
    int parts = 0, after_rapid = 0, in_cut = 0;
    std::vector<int> cut_lines;
    size_t given = 0;
    bool continues = false;  // the part continues the cut of the one before (no restating PTP)
    for (int p = 1;; ++p) {
      const fs::path src = dir.path / fmt::format("AIR_P{:03}.src", p);
      if (!fs::exists(src))
        break;
      const std::vector<std::string> lines = split_lines(read_bytes(src));
      CHECK(static_cast<long>(fs::file_size(src)) <= info.max_file_bytes);
      const auto ml = motion_lines(lines);
      // A part after the first starts with the PTP that restates where the last one ended,
      // unless it continues a cut.
      CHECK(continues == std::any_of(lines.begin(), lines.end(), [](const std::string& l) {
              return l.rfind("; continues the cut", 0) == 0;
            }));
      given += ml.size() - (p > 1 && !continues ? 1 : 0);
      ++parts;
      if (given >= motions.size())
        break;
      const KrlMotion& last = motions[given - 1];
      continues = !last.in_air;
      if (last.in_air) {
        ++after_rapid;
      } else {
        ++in_cut;
        cut_lines.push_back(last.cl_line);
      }
    }
    CHECK(given == motions.size());
    CHECK(in_cut == mid_cut);
    CHECK(std::vector<int>(cut_lines.begin(),
                           cut_lines.begin() + std::min<size_t>(cut_lines.size(), 10)) ==
          mid_cut_lines);
    if (every == 7)
      CHECK(in_cut == 0);  // a rapid in every quarter of a part
    if (every == 0)
      CHECK(after_rapid == 0);
    if (every == 40)
      CHECK(after_rapid > 0);
    CHECK(parts >= 3);
  }
}

TEST_CASE("krl_writer: a part that starts in the cut continues it without a stop") {
  // Every motion in the cut, parts of 16 KiB (or of 150 motions): each part after the first has
  // no INI fold, no BCO run and no restated spindle or coolant; its first motion is the next
  // motion given, and the part before ends on a blended motion. A set without continued_src
  // writes the old exact-stop PTP instead.
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  for (const char* set_name : {"krc4_lin", "krc2_lin", "krc4_circ", "krc4_spline"}) {
    for (const bool by_count : {false, true}) {
      for (const bool without : {false, true}) {
        INFO(set_name << (by_count ? ", 150 motions a part" : ", 16 KiB a part")
                      << (without ? ", no continued_src" : ""));
        KrlTemplateSet set = load_krl_templates(template_path(set_name));
        if (without)
          set.continued_src_file.clear();
        TempDir dir;
        KrlProgramInfo info = info_for(dir, "CUT");
        info.max_file_bytes = by_count ? 0 : 16 * 1024;
        info.motions_per_file = by_count ? 150 : 0;
        const std::vector<KrlMotion> motions = make_motions(cell, 500, 5);
        KrlSplitReport report;
        {
          KrlWriter w(set, info);
          w.spindle(9000, true);
          w.coolant(true, "FLOOD");
          w.velocity(0.02);
          for (const KrlMotion& m : motions)
            w.motion(m);
          w.prepare();
          report = w.split();
          w.finish();
        }
        REQUIRE(report.parts >= 3);
        CHECK(report.mid_cut == report.parts - 1);
        CHECK(report.continued == (without ? 0 : report.mid_cut));
        size_t given = 0;
        for (int p = 1; p <= report.parts; ++p) {
          INFO("part " << p);
          const std::string text = read_bytes(dir.path / fmt::format("CUT_P{:03}.src", p));
          const std::vector<std::string> lines = split_lines(text);
          std::vector<MotionLine> ml = motion_lines(lines);
          REQUIRE(!ml.empty());
          const bool continues = p > 1 && !without;
          CHECK((text.find("BAS (#INITMOV") == std::string::npos) == continues);
          CHECK((text.find("; SPINDLE ON 9000 rpm") == std::string::npos) == continues);
          CHECK((text.find("; BCO run") == std::string::npos) == continues);
          CHECK(text.find("$TOOL = TOOL_DATA[1]") != std::string::npos);
          if (p > 1 && without) {
            // The restating PTP to where the part before ended, then the next motion.
            CHECK(ml[0].command == "PTP");
            check_axes(ml[0], motions[given - 1].axes, true);
            ml.erase(ml.begin());
          }
          if (p == 1) {
            CHECK(ml[0].command == "PTP");
            ml.erase(ml.begin());
            ++given;
          }
          // CIRC lines are not among motion_lines(): the shipped circ set writes a LIN where
          // no arc was fitted, as here (random postures).
          for (const MotionLine& l : ml) {
            REQUIRE(given < motions.size());
            CHECK(l.command != "PTP");
            check_pose(l, motions[given++]);
          }
          if (p < report.parts) {
            // The last statement of the part is blended: C_DIS, or the spline block's end with
            // its approximation.
            const auto end = std::find(lines.rbegin(), lines.rend(), "END");
            REQUIRE(end != lines.rend());
            const std::string& last = *std::next(end);
            INFO(last);
            CHECK((last.size() > 6 &&
                   (last.substr(last.size() - 6) == " C_DIS" || last == "ENDSPLINE C_SPL")));
          }
        }
        CHECK(given == motions.size());
      }
    }
  }
}

TEST_CASE("krl_writer: files appear only complete") {
  const Cell cell = test::shipped_cell("kr15_2");
  const KrlTemplateSet set = load_krl_templates(template_path("krc4_lin"));
  const std::vector<KrlMotion> motions = make_motions(cell, 30, 3);

  SECTION("destroyed without finish(): nothing is left") {
    TempDir dir;
    {
      KrlProgramInfo info = info_for(dir, "ABORTED");
      info.motions_per_file = 10;
      KrlWriter w(set, info);
      w.velocity(0.01);
      for (const KrlMotion& m : motions)
        w.motion(m);
      CHECK_FALSE(dir.names().empty());  // temporaries while writing
      for (const std::string& n : dir.names()) {
        // .NAME.src.XXXXXXXX.part~ (and the lock .ABORTED.lock~): hidden, no final name yet
        CHECK(n.front() == '.');
        REQUIRE(n.size() > 6);
        CHECK((n.substr(n.size() - 6) == ".part~" || n == ".ABORTED.lock~"));
      }
    }
    CHECK(dir.names().empty());
  }
  SECTION("a failure half-way leaves nothing either") {
    TempDir dir;
    {
      KrlWriter w(set, info_for(dir, "FAILED"));
      w.velocity(0.01);
      w.motion(motions[0]);
      KrlMotion bad = motions[1];
      bad.T_base_tcp.translation().y() = std::nan("");
      CHECK_THROWS_AS(w.motion(bad), Error);
    }
    CHECK(dir.names().empty());
  }
  SECTION("finish() leaves no temporaries") {
    TempDir dir;
    KrlProgramInfo info = info_for(dir, "DONE");
    info.motions_per_file = 10;
    write_program(set, info, motions);
    for (const std::string& n : dir.names()) {
      CHECK(n.front() != '.');
      CHECK(n.find('~') == std::string::npos);
    }
    CHECK(dir.names().size() == 8);  // main + 3 parts, .src and .dat each
  }
}

TEST_CASE("krl_writer: identical input gives identical bytes, whatever the locale") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const std::vector<KrlMotion> motions = make_motions(cell, 300, 21, 7);
  for (const char* set_name : {"krc4_lin", "krc4_spline", "krc2_lin"}) {
    INFO(set_name);
    const KrlTemplateSet set = load_krl_templates(template_path(set_name));
    const auto run = [&]() {
      TempDir dir;
      KrlProgramInfo info = info_for(dir, "SAME");
      info.motions_per_file = 120;
      write_program(set, info, motions, 1234.5);
      return dir.contents();
    };
    const auto first = run();
    REQUIRE(first.size() == 8);
    CHECK(run() == first);

    // A C++ global locale with ',' as decimal point (always available).
    struct CommaDecimal : std::numpunct<char> {
      char do_decimal_point() const override { return ','; }
      char do_thousands_sep() const override { return '.'; }
      std::string do_grouping() const override { return "\3"; }
    };
    std::locale::global(std::locale(std::locale::classic(), new CommaDecimal));
    const auto comma = run();
    std::locale::global(std::locale::classic());
    CHECK(comma == first);

    // The C and C++ locales of a German system, where installed.
    if (std::setlocale(LC_ALL, "de_DE.UTF-8") != nullptr) {
      std::locale::global(std::locale("de_DE.UTF-8"));
      const auto german = run();
      std::locale::global(std::locale::classic());
      std::setlocale(LC_ALL, "C");
      CHECK(german == first);
    } else {
      WARN("locale de_DE.UTF-8 is not installed: the C-locale part of this test did not run");
    }
  }
}

TEST_CASE("krl_writer: program names are KRL identifiers of at most 24 characters") {
  const KrlTemplateSet set = load_krl_templates(template_path("krc4_lin"));
  TempDir dir;
  const auto refused = [&](const std::string& name, int per_file, const std::string& words) {
    KrlProgramInfo info = info_for(dir, name);
    info.motions_per_file = per_file;
    try {
      KrlWriter w(set, info);
      FAIL("accepted " << name);
    } catch (const Error& e) {
      INFO(e.what());
      CHECK(e.code() == ErrorCode::bad_input);
      CHECK(e.message().find(words) != std::string::npos);
    }
  };
  refused(std::string(25, 'A'), 0, "at most 24");
  refused("1ABC", 0, "letter");
  refused("MILL-1", 0, "letters");
  refused("LIN", 0, "keyword");
  refused("", 0, "empty");
  // Splitting appends _P001: the name must leave room for it.
  refused(std::string(20, 'B'), 1000, "too long to split");
  CHECK_NOTHROW(KrlWriter(set, info_for(dir, std::string(24, 'C'))));
  KrlProgramInfo split = info_for(dir, std::string(19, 'D'));
  split.motions_per_file = 1000;
  CHECK_NOTHROW(KrlWriter(set, split));
  CHECK(dir.names().empty());  // the writers above were not finished
}

TEST_CASE("krl_writer: what cannot be written is refused") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  const KrlTemplateSet set = load_krl_templates(template_path("krc4_lin"));
  const std::vector<KrlMotion> motions = make_motions(cell, 3, 1);
  TempDir dir;

  SECTION("a missing output directory") {
    KrlProgramInfo info = info_for(dir, "X");
    info.output_dir = (dir.path / "not_there").string();
    try {
      KrlWriter w(set, info);
      FAIL("accepted");
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::io);
    }
  }
  SECTION("an axis value the template needs is NaN") {
    KrlWriter w(set, info_for(dir, "NAN_AXIS"));
    KrlMotion m = motions[0];
    m.axes.arm(3) = std::nan("");
    try {
      w.motion(m);
      FAIL("accepted");
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::internal);
      CHECK(e.message().find("A3") != std::string::npos);
    }
  }
  SECTION("a feed move before any feed rate") {
    KrlWriter w(set, info_for(dir, "NO_FEED"));
    w.motion(motions[0]);  // the PTP needs none
    try {
      w.motion(motions[1]);
      FAIL("accepted");
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::bad_input);
    }
  }
  SECTION("external axes that change from motion to motion") {
    KrlWriter w(set, info_for(dir, "EXT_CHANGE"));
    w.velocity(0.01);
    w.motion(motions[0]);
    KrlMotion m = motions[1];
    m.axes.external(2) = std::nan("");
    CHECK_THROWS_AS(w.motion(m), Error);
  }
  SECTION("a literal of two lines") {
    KrlWriter w(set, info_for(dir, "LITERAL"));
    CHECK_THROWS_AS(w.literal("WAIT SEC 1\nHALT"), Error);
  }
  SECTION("a $BASE or $TOOL that redpost check would reject (issue 31)") {
    for (const bool base : {true, false}) {
      for (const std::string bad :
           {std::string(10000, 'B'), std::string("BASE@1"), std::string("BASE_DATA[1")}) {
        KrlProgramInfo info = info_for(dir, "BAD_FRAME");
        (base ? info.base : info.tool) = bad;
        try {
          KrlWriter w(set, info);
          FAIL("accepted");
        } catch (const Error& e) {
          CHECK(e.code() == ErrorCode::bad_input);
          CHECK(e.message().find(base ? "$BASE = " : "$TOOL = ") == 0);
        }
      }
    }
    KrlProgramInfo info = info_for(dir, "GOOD_FRAME");
    info.base = "{FRAME: X 0, Y 0, Z 10, A 0, B 0, C 0}";
    info.tool = "TOOL_DATA[3]";
    CHECK_NOTHROW(KrlWriter(set, info));
  }
}

TEST_CASE("krl_writer: process statements, and their restatement at the start of a part") {
  const Cell cell = test::shipped_cell("kr15_2");
  const KrlTemplateSet set = load_krl_templates(template_path("krc4_lin"));
  TempDir dir;
  KrlProgramInfo info = info_for(dir, "PROC");
  info.motions_per_file = 5;
  std::vector<KrlMotion> motions = make_motions(cell, 8, 2);
  motions[4].in_air = true;  // part 1 ends out of the material: part 2 runs alone
  {
    KrlWriter w(set, info);
    KrlToolChange change;
    change.number = 3;
    change.name = "D12 ball\nmill";
    change.tool_data = 3;
    change.load_data = 7;
    change.tool = "TOOL_DATA[3]";
    w.tool_change(change);
    w.spindle(12000, true);
    w.coolant(true, "FLOOD");
    w.comment("roughing; pass 1\r\n");
    w.velocity(0.02);
    for (const KrlMotion& m : motions)
      w.motion(m);
    w.literal("WAIT SEC 0.5");
    w.spindle(0, true);
    w.finish();
  }
  const std::vector<std::string> p1 = split_lines(read_bytes(dir.path / "PROC_P001.src"));
  const std::vector<std::string> p2 = split_lines(read_bytes(dir.path / "PROC_P002.src"));
  const auto index = [](const std::vector<std::string>& lines, const std::string& l) {
    return static_cast<long>(std::find(lines.begin(), lines.end(), l) - lines.begin());
  };
  for (const std::string& l :
       {std::string("$TOOL = TOOL_DATA[3]"), std::string("$LOAD = LOAD_DATA[7]"),
        std::string("$ACT_TOOL = 3"), std::string("; SPINDLE ON 12000 rpm CW"),
        std::string("; COOLANT ON FLOOD")}) {
    INFO(l);
    CHECK(index(p1, l) < static_cast<long>(p1.size()));
    // Restated in part 2 before its first PTP, so that it runs alone.
    CHECK(index(p2, l) < static_cast<long>(motion_lines(p2).at(0).line_index));
  }
  // The change itself (a HALT without a tool change routine) is not repeated: the tool is on.
  CHECK(index(p1, "; TOOL CHANGE: T3 D12 ball mill") < static_cast<long>(p1.size()));
  CHECK(index(p1, "HALT ; mount tool T3 by hand (TOOL_DATA[3]), then start the program again") <
        static_cast<long>(p1.size()));
  CHECK(index(p2, "; TOOL CHANGE: T3 D12 ball mill") == static_cast<long>(p2.size()));
  CHECK(index(p1, "; roughing; pass 1") < static_cast<long>(p1.size()));
  CHECK(index(p2, "WAIT SEC 0.5") < index(p2, "; SPINDLE OFF"));
  CHECK(index(p2, "; SPINDLE OFF") < static_cast<long>(p2.size()));
}

TEST_CASE("krl_writer: the base, the tool and its load by number, and the KR C2 coupled base") {
  const Cell cell = test::shipped_cell("kr15_2");
  const std::vector<KrlMotion> motions = make_motions(cell, 3, 2);
  const auto header = [&](const std::string& set_name, const KrlProgramInfo& info) {
    const KrlTemplateSet set = load_krl_templates(template_path(set_name));
    {
      KrlWriter w(set, info);
      w.velocity(0.02);
      for (const KrlMotion& m : motions)
        w.motion(m);
      w.finish();
    }
    std::vector<std::string> lines =
        split_lines(read_bytes(std::filesystem::path(info.output_dir) / (info.name + ".src")));
    // The lines between the header comment and $ADVANCE: what {frames} wrote.
    const auto from = std::find_if(lines.begin(), lines.end(), [](const std::string& l) {
      return l.rfind("; redpost", 0) == 0 || l == "; test";
    });
    const auto to = std::find(lines.begin(), lines.end(), "$ADVANCE = 3");
    REQUIRE(from < to);
    return std::vector<std::string>(from + 1, to);
  };
  TempDir dir;
  KrlProgramInfo info = info_for(dir, "FRAMES");
  info.header_comment = "test";
  info.base = "BASE_DATA[4]";
  info.base_data = 4;
  info.tool = "TOOL_DATA[2]";
  info.tool_data = 2;
  // KR C4, a static base; the load is the tool's own number unless given.
  CHECK(header("krc4_lin", info) ==
        std::vector<std::string>{"$BASE = BASE_DATA[4]", "CONTINUE", "$ACT_BASE = 4",
                                 "$TOOL = TOOL_DATA[2]", "$LOAD = LOAD_DATA[2]", "CONTINUE",
                                 "$ACT_TOOL = 2"});
  info.load_data = 9;
  info.base_coupled = true;
  info.machine_def = 3;
  info.ex_ax_data = 2;
  info.ex_axes = 1;
  CHECK(header("krc4_spline", info) ==
        std::vector<std::string>{
            "$BASE = EK(MACHINE_DEF[3].ROOT, MACHINE_DEF[3].MECH_TYPE, BASE_DATA[4])", "CONTINUE",
            "$ACT_EX_AX = 1", "CONTINUE", "$ACT_BASE = 4", "$TOOL = TOOL_DATA[2]",
            "$LOAD = LOAD_DATA[9]", "CONTINUE", "$ACT_TOOL = 2"});
  // KR C2: the coupled base through EK of the kinematic's EX_AX_DATA entry, not BAS (#BASE, n),
  // which selects a base that does not turn with the table.
  const std::vector<std::string> coupled = header("krc2_lin", info);
  CHECK(coupled == std::vector<std::string>{
                       "$BASE = EK(EX_AX_DATA[2].ROOT, EX_AX_DATA[2].EX_KIN, BASE_DATA[4])",
                       "CONTINUE", "$ACT_EX_AX = 1", "$TOOL = TOOL_DATA[2]"});
  // As KUKA's BAS.SRC writes them, every $ACT_* assignment follows a CONTINUE: without it the
  // assignment stops the advance run, and a part that continues a cut would stop in it.
  for (const char* set_name : {"krc4_lin", "krc4_circ", "krc4_spline", "krc2_lin"}) {
    for (const bool coupled_base : {true, false}) {
      info.base_coupled = coupled_base;
      const std::vector<std::string> lines = header(set_name, info);
      for (size_t k = 0; k < lines.size(); ++k) {
        INFO(set_name << ": " << lines[k]);
        if (lines[k].rfind("$ACT_", 0) == 0)
          CHECK((k > 0 && lines[k - 1] == "CONTINUE"));
      }
    }
  }
  info.base_coupled = false;
  const std::vector<std::string> fixed = header("krc2_lin", info);
  CHECK(fixed == std::vector<std::string>{"$BASE = BASE_DATA[4]", "$TOOL = TOOL_DATA[2]"});
  CHECK(coupled.front() != fixed.front());

  // A $TOOL or $BASE given as an expression has no number: a set that writes one is refused
  // before anything is written, naming the option to give.
  const KrlTemplateSet krc4 = load_krl_templates(template_path("krc4_lin"));
  info.tool = "MY_SPINDLE_TOOL";
  info.tool_data = 0;
  info.name = "NO_NUMBER";
  try {
    KrlWriter w(krc4, info);
    FAIL("a tool without a number was accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::bad_input);
    CHECK(e.message().find("the tool is not a TOOL_DATA[n] entry: give --tool TOOL_DATA[n]") !=
          std::string::npos);
  }
  CHECK(!std::filesystem::exists(dir.path / "NO_NUMBER.src"));
  info.tool = "TOOL_DATA[2]";
  info.tool_data = 2;
  info.base_data = 0;
  CHECK_THROWS_WITH(KrlWriter(krc4, info), Catch::Contains("give --base BASE_DATA[n]"));
}

TEST_CASE("krl_writer: a hand-built template set is checked too, and {date} only on request") {
  const KrlTemplateSet shipped = load_krl_templates(template_path("krc4_lin"));
  TempDir dir;
  {
    KrlTemplateSet set = shipped;
    set.statements["lin"] = "LIN {E6POS: X {x}, Q {q}}";
    CHECK_THROWS_AS(KrlWriter(set, info_for(dir, "HAND")), Error);
    set = shipped;
    set.statements["ptp_axes"] = "PTP {E6AXIS: A1 {a1}, X {x}}";  // not a PTP-axes value
    CHECK_THROWS_AS(KrlWriter(set, info_for(dir, "HAND")), Error);
    set = shipped;
    set.statements.erase("vel");
    CHECK_THROWS_AS(KrlWriter(set, info_for(dir, "HAND")), Error);
    set = shipped;
    set.src_file = "DEF {name}( )\nEND";  // no {body}
    CHECK_THROWS_AS(KrlWriter(set, info_for(dir, "HAND")), Error);
    set = shipped;
    set.continued_src_file = "DEF {name}( )\n  wait sec 0\n{body}\nEND";  // stops the advance run
    CHECK_THROWS_WITH(KrlWriter(set, info_for(dir, "HAND")),
                      Catch::Contains("line 2") && Catch::Contains("may not hold WAIT"));
  }
  CHECK(dir.names().empty());
  KrlTemplateSet dated = shipped;
  dated.dat_file = "DEFDAT {name}\n; written {date}\nENDDAT";
  const Cell cell = test::shipped_cell("kr15_2");
  write_program(dated, info_for(dir, "DATED"), make_motions(cell, 2, 4));
  const std::string dat = read_bytes(dir.path / "DATED.dat");
  CHECK(std::regex_search(
      dat, std::regex(R"(; written 2[0-9]{3}-[0-9]{2}-[0-9]{2} [0-9:]{8} UTC\r\n)")));
  CHECK(read_bytes(dir.path / "DATED.src").find("UTC") == std::string::npos);
}
