// redpost diff as a library: alignment, deviations, ABC equivalence, statistics and reports.
#include <cmath>
#include <string>

#include "catch_compat.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/krl/diff.hpp"

using namespace redpost;

namespace {

KrlMotionRecord lin(int line, double x, double y, double z, double a = 0, double b = 90,
                    double c = 0, int cl = 0) {
  KrlMotionRecord m;
  m.keyword = "LIN";
  m.target.type = "E6POS";
  m.target.values = {{"X", x}, {"Y", y}, {"Z", z}, {"A", a}, {"B", b}, {"C", c}, {"E1", 10}};
  m.file = "P.src";
  m.line = line;
  m.cl_line = cl;
  return m;
}

// A raster of n LIN motions, lines 10.., with CL lines when `cl`.
KrlProgram raster(int n, bool cl) {
  KrlProgram p;
  p.main_file = "P.src";
  for (int i = 0; i < n; ++i)
    p.motions.push_back(lin(10 + i, (i % 7) * 10.0, i * 2.5, 50.0, 0, 0, 0, cl ? 100 + i : 0));
  return p;
}

}  // namespace

TEST_CASE("diff: a program against itself is equal at tolerance 0") {
  KrlDiffOptions o;
  o.pos_tol_mm = o.ang_tol_deg = o.axis_tol = 0.0;
  for (bool cl : {false, true}) {
    const KrlProgram p = raster(500, cl);
    const KrlDiffResult r = diff_krl_programs(p, p, o);
    CHECK(r.equal);
    CHECK(r.compared == 500);
    CHECK(r.inserted == 0);
    CHECK(r.removed == 0);
    CHECK(r.differences.empty());
    CHECK(r.aligned_by_cl_line == cl);
    const KrlQuantityStats& s = r.statistics[static_cast<int>(KrlQuantity::position)];
    CHECK(s.compared == 500);
    CHECK(s.max == 0.0);
  }
}

TEST_CASE("diff: a coordinate moved by 0.05 mm is found at its line") {
  for (bool cl : {false, true}) {
    const KrlProgram a = raster(200, cl);
    KrlProgram b = a;
    b.motions[57].target.values["Y"] += 0.05;
    KrlDiffOptions o;
    KrlDiffResult r = diff_krl_programs(a, b, o);
    CHECK_FALSE(r.equal);
    CHECK(r.compared == 200);
    CHECK(r.changed == 1);
    CHECK(r.inserted == 0);
    CHECK(r.removed == 0);
    REQUIRE(r.differences.size() == 1);
    const KrlDifference& d = r.differences[0];
    CHECK(d.kind == KrlDifference::Kind::changed);
    CHECK(d.line_a == 67);
    CHECK(d.line_b == 67);
    REQUIRE(d.deviations.size() == 1);
    CHECK(d.deviations[0].quantity == KrlQuantity::position);
    CHECK(d.deviations[0].value == Approx(0.05).margin(1e-9));
    const KrlQuantityStats& s = r.statistics[static_cast<int>(KrlQuantity::position)];
    CHECK(s.over_tolerance == 1);
    CHECK(s.max == Approx(0.05).margin(1e-9));
    CHECK(s.mean() == Approx(0.05 / 200).margin(1e-12));
    o.pos_tol_mm = 0.1;
    r = diff_krl_programs(a, b, o);
    CHECK(r.equal);
  }
}

TEST_CASE("diff: a motion inserted in the middle is one insertion") {
  for (bool cl : {false, true}) {
    const KrlProgram a = raster(300, cl);
    KrlProgram b = a;
    KrlMotionRecord extra = lin(999, 5.0, 5.0, 80.0, 0, 0, 0, cl ? 250 : 0);
    b.motions.insert(b.motions.begin() + 150, extra);
    const KrlDiffResult r = diff_krl_programs(a, b, KrlDiffOptions{});
    CHECK_FALSE(r.equal);
    CHECK(r.inserted == 1);
    CHECK(r.removed == 0);
    CHECK(r.changed == 0);
    CHECK(r.compared == 300);
    REQUIRE(r.differences.size() == 1);
    CHECK(r.differences[0].kind == KrlDifference::Kind::inserted);
    CHECK(r.differences[0].line_b == 999);
    // And the other way round: one removal.
    const KrlDiffResult back = diff_krl_programs(b, a, KrlDiffOptions{});
    CHECK(back.removed == 1);
    CHECK(back.inserted == 0);
    CHECK(back.changed == 0);
  }
}

TEST_CASE("diff: a run of removed motions is one difference; max_shown limits the list") {
  const KrlProgram a = raster(100, false);
  KrlProgram b = a;
  b.motions.erase(b.motions.begin() + 20, b.motions.begin() + 25);
  for (int i = 60; i < 100; i += 2)
    b.motions[static_cast<size_t>(i - 5)].target.values["Z"] += 1.0;
  KrlDiffOptions o;
  o.max_shown = 3;
  const KrlDiffResult r = diff_krl_programs(a, b, o);
  CHECK(r.removed == 5);
  CHECK(r.changed == 20);
  CHECK(r.difference_count == 21);
  REQUIRE(r.differences.size() == 3);
  CHECK(r.differences[0].kind == KrlDifference::Kind::removed);
  CHECK(r.differences[0].count == 5);
  CHECK(r.differences[0].line_a == 30);
  CHECK(r.differences[0].last_line_a == 34);
  CHECK(format_krl_diff_text(r, o).find("18 more difference(s) not shown") != std::string::npos);
}

TEST_CASE("diff: equivalent A, B, C compare equal") {
  // A 180 and A -180 are the same rotation.
  CHECK((rotation_from_abc({180, 20, 30}) - rotation_from_abc({-180, 20, 30})).norm() < 1e-12);
  // At B = 90 only A - C matters: (A 30, C 0) and (A 40, C 10) are one frame.
  CHECK((rotation_from_abc({30, 90, 0}) - rotation_from_abc({40, 90, 10})).norm() < 1e-12);
  // ... but not (A 30, C 0) and (A 40, C 0).
  CHECK((rotation_from_abc({30, 90, 0}) - rotation_from_abc({40, 90, 0})).norm() > 0.1);

  KrlProgram a, b;
  a.motions = {lin(5, 1, 2, 3, 180, 20, 30), lin(6, 1, 2, 4, 30, 90, 0),
               lin(7, 1, 2, 5, 30, 90, 0)};
  b.motions = {lin(5, 1, 2, 3, -180, 20, 30), lin(6, 1, 2, 4, 40, 90, 10),
               lin(7, 1, 2, 5, 40, 90, 0)};
  const KrlDiffResult r = diff_krl_programs(a, b, KrlDiffOptions{});
  CHECK(r.changed == 1);
  REQUIRE(r.differences.size() == 1);
  CHECK(r.differences[0].line_a == 7);
  REQUIRE(r.differences[0].deviations.size() == 1);
  CHECK(r.differences[0].deviations[0].quantity == KrlQuantity::orientation);
  CHECK(r.differences[0].deviations[0].value == Approx(10.0).margin(1e-9));
  const KrlQuantityStats& s = r.statistics[static_cast<int>(KrlQuantity::orientation)];
  CHECK(s.compared == 3);
  CHECK(s.over_tolerance == 1);
}

TEST_CASE("diff: axes, S/T and keyword") {
  KrlMotionRecord p;
  p.keyword = "PTP";
  p.target.type = "E6AXIS";
  p.target.values = {{"A1", 0},  {"A2", -90}, {"A3", 90}, {"A4", 0},
                     {"A5", 45}, {"A6", 0},   {"E1", 100}};
  p.file = "P.src";
  p.line = 3;
  KrlMotionRecord c = lin(4, 1, 2, 3);
  c.target.status = 6;
  c.target.turn = 27;
  KrlProgram a, b;
  a.motions = {p, c};
  b.motions = a.motions;
  b.motions[0].target.values["A2"] = -89.5;
  b.motions[0].target.values["E1"] = 100.2;
  b.motions[1].target.status = 2;
  b.motions[1].keyword = "SLIN";
  const KrlDiffResult r = diff_krl_programs(a, b, KrlDiffOptions{});
  CHECK(r.changed == 2);
  REQUIRE(r.differences.size() == 2);
  REQUIRE(r.differences[0].deviations.size() == 2);
  CHECK(r.differences[0].deviations[0].quantity == KrlQuantity::A2);
  CHECK(r.differences[0].deviations[0].value == Approx(0.5));
  CHECK(r.differences[0].deviations[1].quantity == KrlQuantity::E1);
  CHECK(r.differences[0].deviations[1].value == Approx(0.2));
  bool status = false, keyword = false;
  for (const KrlDeviation& d : r.differences[1].deviations) {
    status = status || d.quantity == KrlQuantity::status;
    keyword = keyword || d.quantity == KrlQuantity::keyword;
  }
  CHECK(status);
  CHECK(keyword);
  CHECK(r.statistics[static_cast<int>(KrlQuantity::turn)].compared == 1);
  CHECK(r.statistics[static_cast<int>(KrlQuantity::turn)].over_tolerance == 0);
}

TEST_CASE("diff: settings and speeds are compared, each said once for the program") {
  KrlProgram a = raster(40, true), b = a;
  for (KrlMotionRecord& m : a.motions) {
    m.vel_cp_m_per_s = 0.015;
    m.tool = "TOOL_DATA[1]";
    m.base = "BASE_DATA[1]";
    m.apo_cdis_mm = 0.5;
    m.ptp_velocity_percent = 20;
  }
  b = a;
  CHECK(diff_krl_programs(a, b, KrlDiffOptions{}).equal);
  // $TOOL written with other blanks and case is the same tool.
  for (KrlMotionRecord& m : b.motions)
    m.tool = "tool_data[ 1 ]";
  CHECK(diff_krl_programs(a, b, KrlDiffOptions{}).equal);

  const auto only = [&](auto change, KrlQuantity q, const std::string& detail) {
    KrlProgram c = a;
    for (size_t i = 10; i < c.motions.size(); ++i)
      change(c.motions[i]);
    const KrlDiffResult r = diff_krl_programs(a, c, KrlDiffOptions{});
    CHECK_FALSE(r.equal);
    CHECK(r.differences.empty());  // nothing listed motion by motion
    REQUIRE(r.summaries.size() == 1);
    CHECK(r.summaries[0].quantity == q);
    CHECK(r.summaries[0].count == 30);
    CHECK(r.summaries[0].line_a == 20);  // the first motion it differs at
    CHECK(r.summaries[0].detail == detail);
    CHECK(format_krl_diff_text(r, KrlDiffOptions{})
              .find(std::string(krl_quantity_name(q)) + " differs at 30 motions") !=
          std::string::npos);
  };
  only([](KrlMotionRecord& m) { m.vel_cp_m_per_s = 0.15; }, KrlQuantity::vel_cp,
       "A 0.015 m/s, B 0.15 m/s");
  only([](KrlMotionRecord& m) { m.tool = "TOOL_DATA[2]"; }, KrlQuantity::tool,
       "A TOOL_DATA[1], B TOOL_DATA[2]");
  only([](KrlMotionRecord& m) { m.base = "BASE_DATA[3]"; }, KrlQuantity::base,
       "A BASE_DATA[1], B BASE_DATA[3]");
  only([](KrlMotionRecord& m) { m.apo_cdis_mm = 2.0; }, KrlQuantity::apo_cdis, "A 0.5 mm, B 2 mm");
  only([](KrlMotionRecord& m) { m.ptp_velocity_percent = 100; }, KrlQuantity::ptp_velocity,
       "A 20 %, B 100 %");
  only([](KrlMotionRecord& m) { m.keyword = "SLIN"; }, KrlQuantity::keyword, "A LIN, B SLIN");
}

TEST_CASE("diff: the same path with other points is equal as curves, within the path tolerance") {
  // A, a polyline of a quarter circle of radius 100 mm in 20 chords; B, the same arc in 57
  // chords (another chordal tolerance). The largest distance between the two polylines is the
  // sagitta of A's chords: r (1 - cos(pi / 80)).
  const auto arc = [](int chords) {
    KrlProgram p;
    for (int i = 0; i <= chords; ++i) {
      const double t = 1.5707963267948966 * i / chords;
      p.motions.push_back(lin(10 + i, 100 * std::cos(t), 100 * std::sin(t), 5.0, 0, 90, 0));
      p.motions.back().target.values.erase("E1");
    }
    return p;
  };
  const KrlProgram a = arc(20), b = arc(57);
  const double sagitta = 100.0 * (1.0 - std::cos(3.14159265358979323846 / 80.0));
  KrlDiffOptions o;
  const KrlDiffResult point_by_point = diff_krl_programs(a, b, o);
  CHECK_FALSE(point_by_point.equal);
  CHECK(point_by_point.path_distance_mm == Approx(sagitta).epsilon(1e-3));
  CHECK(point_by_point.path_exact);

  o.as_curves = true;
  o.path_tol_mm = sagitta * 1.01;
  const KrlDiffResult curves = diff_krl_programs(a, b, o);
  CHECK(curves.equal);
  CHECK(curves.inserted == 0);
  o.path_tol_mm = sagitta * 0.5;
  const KrlDiffResult tight = diff_krl_programs(a, b, o);
  CHECK_FALSE(tight.equal);
  REQUIRE(tight.summaries.size() == 1);
  CHECK(tight.summaries[0].quantity == KrlQuantity::path);

  // A point moved off the path by 0.3 mm is found as curves too, at its line.
  KrlProgram c = b;
  c.motions[30].target.values["Z"] = 5.3;
  o.path_tol_mm = sagitta * 1.01;
  const KrlDiffResult moved = diff_krl_programs(a, c, o);
  CHECK_FALSE(moved.equal);
  // 0.3 mm up from a point of B's arc, which is itself up to the sagitta off A's chords.
  CHECK(moved.path_distance_mm >= 0.3);
  CHECK(moved.path_distance_mm <= std::hypot(0.3, sagitta) + 1e-9);
  CHECK(moved.path_line == 40);
}

TEST_CASE("diff: JSON report escapes strings and carries the expected keys") {
  KrlProgram a = raster(10, false), b = a;
  for (auto& m : b.motions)
    m.file = "dir \"x\"\\P.src";
  b.motions[3].target.values["X"] += 1;
  const KrlDiffResult r = diff_krl_programs(a, b, KrlDiffOptions{});
  const std::string j = format_krl_diff_json(r, KrlDiffOptions{});
  for (const char* key : {"\"equal\": false", "\"compared\": 10", "\"inserted\": 0",
                          "\"removed\": 0", "\"differences\": [", "\"statistics\": {"})
    CHECK(j.find(key) != std::string::npos);
  CHECK(j.find("dir \\\"x\\\"\\\\P.src") != std::string::npos);
  int depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < j.size(); ++i) {
    if (in_string) {
      if (j[i] == '\\')
        ++i;
      else if (j[i] == '"')
        in_string = false;
      continue;
    }
    if (j[i] == '"')
      in_string = true;
    else if (j[i] == '{' || j[i] == '[')
      ++depth;
    else if (j[i] == '}' || j[i] == ']')
      CHECK(--depth >= 0);
  }
  CHECK(depth == 0);
  CHECK_FALSE(in_string);
}

TEST_CASE("diff: large equal programs are compared in linear time") {
  const KrlProgram a = raster(200000, false);
  KrlProgram b = a;
  b.motions.erase(b.motions.begin() + 100000);
  const KrlDiffResult r = diff_krl_programs(a, b, KrlDiffOptions{});
  CHECK(r.removed == 1);
  CHECK(r.compared == 199999);
  CHECK(r.changed == 0);
}

TEST_CASE("diff: completely different programs degrade to pairing in order") {
  KrlProgram a = raster(3000, false), b = raster(3000, false);
  for (auto& m : b.motions)
    m.target.values["Z"] += 7.0;
  const KrlDiffResult r = diff_krl_programs(a, b, KrlDiffOptions{});
  CHECK(r.compared == 3000);
  CHECK(r.changed == 3000);
  CHECK(r.inserted == 0);
}

TEST_CASE("diff: golden program against itself, through the reader") {
  const std::string src =
      std::string(REDPOST_SOURCE_DIR) + "/tests/golden/pocket_arcs/POCKET_ARCS.src";
  KrlDiffOptions o;
  o.pos_tol_mm = o.ang_tol_deg = o.axis_tol = 0.0;
  const KrlDiffResult r = diff_krl_paths(src, src, o);
  CHECK(r.equal);
  CHECK(r.compared > 100);
  const std::string dir = std::string(REDPOST_SOURCE_DIR) + "/tests/golden/long_pass";
  const KrlDiffResult d = diff_krl_paths(dir, dir, o);
  CHECK(d.equal);
  CHECK(d.unmatched.empty());
  CHECK(d.compared > 300);
}

TEST_CASE("diff: main programs of a directory") {
  const std::vector<std::string> mains =
      krl_main_programs(std::string(REDPOST_SOURCE_DIR) + "/tests/golden/long_pass");
  REQUIRE(mains.size() == 1);
  CHECK(mains[0].find("LONG_PASS.src") != std::string::npos);
}
