// The toolpath calls of the C ABI (redpost.h, "Added in 0.6"): drilling cycles, NURBS, MSYS,
// operator text, cutter compensation, the host's warnings, the library's report and the
// pipeline. Each is checked against an independent path to the same program: the CL reader
// expanding the file itself (toolpath_events 0), the reader's toolpath events expanded by the
// session (what convert does), and the calls an NX host makes; all three must give the same bytes.
#include "catch_compat.hpp"

#include <cmath>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "abi_test_support.hpp"
#include "redpost.h"
#include "temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

using namespace redpost::abi_test;

std::string fresh_dir(const std::string& name) {
  return redpost::test::fresh_temp_dir("redpost_abi_toolpath", name);
}

std::map<std::string, std::string> files_of(const std::string& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::ifstream in(e.path(), std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    std::string text = s.str();
    // The report's conversion time is the one line that differs between runs.
    const std::size_t t = text.find("conversion time");
    if (t != std::string::npos)
      text.erase(t, text.find('\n', t) - t);
    out[e.path().filename().string()] = text;
  }
  return out;
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

rp_options options_for(const std::string& out_dir, const std::string& source, int pipeline = 0) {
  rp_options o;
  rp_options_init(&o);
  o.cell_path = kCell.c_str();
  o.output_dir = out_dir.c_str();
  o.program_name = "TP";
  o.pipeline = pipeline;
  static thread_local std::string src;
  src = source;
  o.source_name = src.c_str();
  return o;
}

// A CL file through the reader into a session: the reader's toolpath events (the session
// expands them) or its plain events (the reader expands them).
rp_status convert(const std::string& cl, const std::string& out_dir, int toolpath_events,
                  int pipeline = 0, const char* report = nullptr) {
  rp_options o = options_for(out_dir, cl, pipeline);
  o.report_path = report;
  rp_session* s = nullptr;
  rp_status st = rp_open(&o, &s);
  if (st != RP_OK)
    return st;
  rp_reader_options ro;
  rp_reader_options_init(&ro);
  ro.arcs_as_events = 1;
  ro.toolpath_events = toolpath_events;
  rp_reader* r = nullptr;
  st = rp_reader_open_ex(cl.c_str(), &ro, &r);
  rp_event e;
  int more = 1;
  while (st == RP_OK && (st = rp_reader_next(r, &e, &more)) == RP_OK && more)
    st = rp_session_event(s, &e);
  for (int i = 0; st == RP_OK && rp_reader_warning(r, i); ++i)
    st = rp_warn(s, rp_reader_warning(r, i));
  if (st == RP_OK)
    st = rp_close(s);
  rp_reader_free(r);
  rp_free(s);
  return st;
}

// The job of kToolpath made by the calls an NX host makes (tcl/redpost_post.tcl), each at the
// line of its record, with the numbers NX gives for it.
rp_status by_calls(const std::string& source, const std::string& out_dir, int pipeline = 0) {
  rp_options o = options_for(out_dir, source, pipeline);
  rp_session* s = nullptr;
  rp_status st = rp_open(&o, &s);
  REQUIRE(st == RP_OK);
  const auto line = [&](int n) { REQUIRE(rp_set_line(s, n) == RP_OK); };
  const double origin[3] = {0, 0, 0}, x_axis[3] = {1, 0, 0}, y_axis[3] = {0, 1, 0};
  line(1);
  REQUIRE(rp_operation_start(s, "HOLES") == RP_OK);
  line(2);
  REQUIRE(rp_machine_frame(s, origin, x_axis, y_axis) == RP_OK);
  line(3);
  REQUIRE(rp_tool_change(s, 1, "T1", 0, 0) == RP_OK);
  line(4);
  REQUIRE(rp_spindle(s, 12000, RP_SPINDLE_CW) == RP_OK);
  line(5);
  REQUIRE(rp_operator_text(s, RP_TEXT_INSERT, "KRL: $OUT[7] = TRUE") == RP_OK);
  line(6);
  REQUIRE(rp_operator_text(s, RP_TEXT_PPRINT, "rough the pocket") == RP_OK);
  line(7);
  REQUIRE(rp_rapid(s) == RP_OK);
  line(8);
  REQUIRE(rp_linear_move(s, -100, -450, 110, 0, 0, 1) == RP_OK);
  line(9);
  REQUIRE(rp_feed(s, 1200) == RP_OK);
  line(10);
  rp_cycle_params c;
  rp_cycle_params_init(&c);
  c.peck = 1;
  c.depth_mm = 12;
  c.clearance_mm = 3;
  c.retract_mm = 20;
  c.feed_mm_per_min = 300;
  c.dwell_s = 0.5;
  c.first_peck_mm = 5;
  c.next_peck_mm = 4;
  REQUIRE(rp_cycle_define(s, &c) == RP_OK);
  line(11);
  REQUIRE(rp_cycle_hole(s, -100, -450, 60, 0, 0, 1) == RP_OK);
  line(12);
  REQUIRE(rp_cycle_hole(s, -80, -450, 60, 0, 0, 1) == RP_OK);
  line(13);
  REQUIRE(rp_cycle_off(s) == RP_OK);
  line(14);
  REQUIRE(rp_rapid(s) == RP_OK);
  line(15);
  REQUIRE(rp_linear_move(s, -80, -430, 65, 0, 0, 1) == RP_OK);
  line(16);
  REQUIRE(rp_cutcom(s, 1, "LEFT") == RP_OK);
  line(17);
  REQUIRE(rp_linear_move(s, -80, -430, 60, 0, 0, 1) == RP_OK);
  line(18);
  const double knots[] = {0.25, 0.5, 0.75, 1};
  const double points[] = {-60, -420, 60,  1,    -40, -440, 60, 2,    -20, -420,
                           60,  1,    -10, -430, 60,  1,    0,  -450, 60,  1};
  REQUIRE(rp_nurbs_move(s, knots, 4, points, 5, 0, 0, 1) == RP_OK);
  line(25);
  REQUIRE(rp_cutcom(s, 0, "OFF") == RP_OK);
  line(26);
  REQUIRE(rp_operation_end(s) == RP_OK);
  st = rp_close(s);
  rp_free(s);
  return st;
}

const char* const kToolpath =
    "TOOL PATH/HOLES,TOOL,T1\n"     // 1
    "MSYS/0,0,0,1,0,0,0,1,0\n"      // 2
    "LOAD/TOOL,1\n"                 // 3
    "SPINDL/12000,RPM,CLW\n"        // 4
    "INSERT/KRL: $OUT[7] = TRUE\n"  // 5
    "PPRINT/rough the pocket\n"     // 6
    "RAPID\n"                       // 7
    "GOTO/-100,-450,110,0,0,1\n"    // 8
    "FEDRAT/MMPM,1200\n"            // 9
    "CYCLE/DRILL,DEEP,FEDTO,12,RAPTO,3,RTRCTO,20,MMPM,300,DWELL,0.5,1STPECK,5,SUBPECK,4\n"
    "GOTO/-100,-450,60\n"     // 11
    "GOTO/-80,-450,60\n"      // 12
    "CYCLE/OFF\n"             // 13
    "RAPID\n"                 // 14
    "GOTO/-80,-430,65\n"      // 15
    "CUTCOM/LEFT\n"           // 16
    "GOTO/-80,-430,60\n"      // 17
    "NURBS/\n"                // 18
    "KNOT/0.25,0.5,0.75,1\n"  // 19
    "CNTRL/-60,-420,60\n"
    "CNTRL/-40,-440,60,2\n"
    "CNTRL/-20,-420,60\n"
    "CNTRL/-10,-430,60\n"
    "CNTRL/0,-450,60\n"  // 24
    "CUTCOM/OFF\n"       // 25
    "END-OF-PATH\n";     // 26

}  // namespace

TEST_CASE("abi toolpath: cycles, NURBS, MSYS and texts expanded by the reader or the session") {
  const std::string dir = fresh_dir("expand");
  const std::string cl = dir + "/tp.cls";
  write_file(cl, kToolpath);
  fs::create_directories(dir + "/plain");
  fs::create_directories(dir + "/toolpath");
  REQUIRE(convert(cl, dir + "/plain", 0) == RP_OK);
  REQUIRE(convert(cl, dir + "/toolpath", 1) == RP_OK);
  const auto plain = files_of(dir + "/plain");
  CHECK(plain == files_of(dir + "/toolpath"));
  const std::string& src = plain.at("TP.src");
  // The cycle became pecks and a dwell, the INSERT/KRL: its statement, the PPRINT a comment.
  CHECK(src.find("$OUT[7] = TRUE") != std::string::npos);
  CHECK(src.find("; rough the pocket") != std::string::npos);
  CHECK(src.find("WAIT SEC 0.5") != std::string::npos);
}

TEST_CASE("abi toolpath: the calls of an NX host give the reader's program") {
  const std::string dir = fresh_dir("calls");
  const std::string cl = dir + "/tp.cls";
  write_file(cl, kToolpath);
  for (const char* d : {"/reader", "/calls", "/calls_pipeline"})
    fs::create_directories(dir + d);
  REQUIRE(convert(cl, dir + "/reader", 1) == RP_OK);
  REQUIRE(by_calls(cl, dir + "/calls") == RP_OK);
  REQUIRE(by_calls(cl, dir + "/calls_pipeline", 1) == RP_OK);
  const auto reader = files_of(dir + "/reader");
  CHECK(reader == files_of(dir + "/calls"));
  CHECK(reader == files_of(dir + "/calls_pipeline"));
}

TEST_CASE("abi toolpath: the pipeline gives the same bytes and reports a failure later") {
  const std::string dir = fresh_dir("pipeline");
  const std::string cl = kSource + "/examples/cl/surface_5axis.cls";
  for (const char* d : {"/sync", "/pipe"})
    fs::create_directories(dir + d);
  REQUIRE(convert(cl, dir + "/sync", 1, 0, (dir + "/sync/r.html").c_str()) == RP_OK);
  REQUIRE(convert(cl, dir + "/pipe", 1, 1, (dir + "/pipe/r.html").c_str()) == RP_OK);
  CHECK(files_of(dir + "/sync") == files_of(dir + "/pipe"));

  // A pose beyond the track: the call that sends it returns RP_OK, a later one the failure with
  // the pose's own line; nothing is written.
  const std::string out = dir + "/far";
  fs::create_directories(out);
  rp_options o = options_for(out, "far.apt", 1);
  o.plan = RP_PLAN_LOCAL;
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  REQUIRE(rp_set_line(s, 3) == RP_OK);
  REQUIRE(rp_rapid(s) == RP_OK);
  REQUIRE(rp_linear_move(s, -120, -440, 110, 0, 0, 1) == RP_OK);
  REQUIRE(rp_set_line(s, 5) == RP_OK);
  REQUIRE(rp_feed(s, 1000) == RP_OK);
  CHECK(rp_linear_move(s, 5000, 5000, 110, 0, 0, 1) == RP_OK);
  REQUIRE(rp_set_line(s, 6) == RP_OK);
  const rp_status st = rp_close(s);
  CHECK(st == RP_ERR_JOINT_LIMIT);
  CHECK(std::string(rp_last_error(s)).find("far.apt:5: ") != std::string::npos);
  CHECK(rp_last_error_line(s) == 5);
  CHECK(rp_close(s) == RP_ERR_STATE);
  rp_free(s);
  CHECK(fs::is_empty(out));
}

TEST_CASE("abi toolpath: the host's warnings come first, and only while the session is open") {
  const std::string dir = fresh_dir("warn");
  rp_options o = options_for(dir, "w.apt");
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  REQUIRE(rp_set_line(s, 2) == RP_OK);
  REQUIRE(rp_rapid(s) == RP_OK);
  REQUIRE(rp_linear_move(s, -100, -450, 110, 0, 0, 1) == RP_OK);
  REQUIRE(rp_cutcom(s, 1, "RIGHT") == RP_OK);
  REQUIRE(rp_warn(s, "w.apt:1: unknown word FOO ignored") == RP_OK);
  CHECK(rp_warn(s, nullptr) == RP_ERR_NULL);
  REQUIRE(rp_prepare(s) == RP_OK);
  CHECK(std::string(rp_warning(s, 0)) == "w.apt:1: unknown word FOO ignored");
  CHECK(std::string(rp_warning(s, 1)).find("w.apt:2: CUTCOM/RIGHT ignored") == 0);
  CHECK(rp_warn(s, "late") == RP_ERR_STATE);
  rp_summary sum{};
  REQUIRE(rp_summary_get(s, &sum) == RP_OK);
  CHECK(sum.warnings >= 2);
  REQUIRE(rp_close(s) == RP_OK);
  rp_free(s);
}

TEST_CASE("abi toolpath: bad toolpath calls are refused with the line, nothing written") {
  const std::string dir = fresh_dir("bad");
  const auto refused = [&](auto&& call, rp_status expected, const std::string& fragment) {
    rp_options o = options_for(dir, "bad.cls");
    o.plan = RP_PLAN_LOCAL;
    rp_session* s = nullptr;
    REQUIRE(rp_open(&o, &s) == RP_OK);
    REQUIRE(rp_set_line(s, 7) == RP_OK);
    REQUIRE(rp_linear_move(s, -100, -450, 110, 0, 0, 1) == RP_OK);
    const rp_status st = call(s);
    INFO(rp_last_error(s));
    CHECK(st == expected);
    CHECK(std::string(rp_last_error(s)).find(fragment) != std::string::npos);
    CHECK(rp_close(s) == RP_ERR_STATE);
    rp_free(s);
    CHECK(fs::is_empty(dir));
  };
  rp_cycle_params c;
  rp_cycle_params_init(&c);
  refused([&](rp_session* s) { return rp_cycle_define(s, nullptr); }, RP_ERR_NULL, "NULL");
  refused([&](rp_session* s) { return rp_cycle_define(s, &c); }, RP_ERR_BAD_INPUT,
          "bad.cls:7: CYCLE/DRILL needs FEDTO");
  c.depth_mm = 5;
  c.clearance_mm = 2;
  c.feed_mm_per_min = 200;
  c.dwell_s = 601;
  refused([&](rp_session* s) { return rp_cycle_define(s, &c); }, RP_ERR_BAD_INPUT, "DWELL");
  c.dwell_s = 0;
  c.peck = 1;
  refused([&](rp_session* s) { return rp_cycle_define(s, &c); }, RP_ERR_BAD_INPUT, "no peck depth");
  c.struct_size = 0;
  refused([&](rp_session* s) { return rp_cycle_define(s, &c); }, RP_ERR_BAD_INPUT, "struct_size");
  refused([&](rp_session* s) { return rp_cycle_hole(s, 0, 0, 0, 0, 0, 1); }, RP_ERR_BAD_INPUT,
          "no cycle is on");
  const double knots[] = {0.5, 1};
  const double points[] = {0, 0, 0, 1, 1, 1, 0, 1};
  refused([&](rp_session* s) { return rp_nurbs_move(s, knots, -1, points, 2, 0, 0, 1); },
          RP_ERR_BAD_INPUT, "-1 knots");
  refused([&](rp_session* s) { return rp_nurbs_move(s, nullptr, 2, points, 2, 0, 0, 1); },
          RP_ERR_NULL, "NULL");
  const double nan_points[] = {0, 0, kNaN, 1, 1, 1, 0, 1};
  refused([&](rp_session* s) { return rp_nurbs_move(s, knots, 2, nan_points, 2, 0, 0, 1); },
          RP_ERR_BAD_INPUT, "bad.cls:7: NURBS: a control point");
  const double o3[3] = {0, 0, 0}, x[3] = {1, 0, 0}, y[3] = {1, 0, 0};
  refused([&](rp_session* s) { return rp_machine_frame(s, o3, x, y); }, RP_ERR_BAD_INPUT,
          "orthogonal unit vectors");
  refused([&](rp_session* s) { return rp_machine_frame(s, o3, nullptr, y); }, RP_ERR_NULL, "NULL");
  refused([&](rp_session* s) { return rp_operator_text(s, static_cast<rp_text_kind>(7), "x"); },
          RP_ERR_BAD_INPUT, "text kind 7");
  refused([&](rp_session* s) { return rp_operator_text(s, RP_TEXT_INSERT, "KRL:  "); },
          RP_ERR_BAD_INPUT, "needs a KRL statement");
  refused([&](rp_session* s) { return rp_dwell(s, kNaN); }, RP_ERR_BAD_INPUT, "a dwell of");
}

// Issue 48, item 4: what a call's arguments cannot mean is refused by the call itself, under the
// default whole-path plan too (which buffers the moves it plans and used to find a bad one only
// when it came to plan it, with RP_OK for the call).
TEST_CASE("abi toolpath: arguments that cannot be used are refused by the call, any plan") {
  const std::string dir = fresh_dir("args");
  for (const int plan : {RP_PLAN_GLOBAL, RP_PLAN_LOCAL}) {
    const auto refused = [&](auto&& call, const std::string& fragment) {
      INFO("plan " << plan << ", expecting: " << fragment);
      rp_options o = options_for(dir, "args.cls");
      o.plan = plan;
      rp_session* s = nullptr;
      REQUIRE(rp_open(&o, &s) == RP_OK);
      REQUIRE(rp_set_line(s, 4) == RP_OK);
      REQUIRE(rp_rapid(s) == RP_OK);
      REQUIRE(rp_linear_move(s, -100, -450, 110, 0, 0, 1) == RP_OK);
      REQUIRE(rp_feed(s, 1000) == RP_OK);
      REQUIRE(rp_set_line(s, 9) == RP_OK);
      const rp_status st = call(s);
      INFO(rp_last_error(s));
      CHECK(st == RP_ERR_BAD_INPUT);
      CHECK(std::string(rp_last_error(s)).find("args.cls:9: ") != std::string::npos);
      CHECK(std::string(rp_last_error(s)).find(fragment) != std::string::npos);
      CHECK(rp_close(s) == RP_ERR_STATE);
      rp_free(s);
      CHECK(fs::is_empty(dir));
    };
    refused(
        [](rp_session* s) {
          return rp_circular_move(s, -100, -440, 110, 0, 0, 1, -12, -100, -430, 110, 0, 0, 1);
        },
        "negative radius");
    refused(
        [](rp_session* s) {
          return rp_circular_move(s, -100, -440, kNaN, 0, 0, 1, 0, -100, -430, 110, 0, 0, 1);
        },
        "not a finite number");
    refused(
        [](rp_session* s) {
          return rp_circular_move(s, -100, -440, 110, 0, 0, 0, 0, -100, -430, 110, 0, 0, 1);
        },
        "axis of zero length");
    refused([](rp_session* s) { return rp_linear_move(s, -100, kNaN, 110, 0, 0, 1); },
            "not a finite number");
    refused([](rp_session* s) { return rp_linear_move(s, -100, -440, 110, 0, 0, 0); },
            "tool axis of zero length");
    refused([](rp_session* s) { return rp_feed(s, -5); }, "feed");
    refused([](rp_session* s) { return rp_feed(s, kNaN); }, "feed");
    refused([](rp_session* s) { return rp_spindle(s, -100, RP_SPINDLE_CW); }, "spindle");
    refused([](rp_session* s) { return rp_spindle(s, kNaN, RP_SPINDLE_CW); }, "spindle");
    refused([](rp_session* s) { return rp_tool_change(s, 3, "T3", -10, 100); }, "diameter");
    refused([](rp_session* s) { return rp_tool_change(s, 3, "T3", 10, kNaN); }, "length");
    refused([](rp_session* s) { return rp_tool_change(s, -3, "T3", 10, 100); }, "tool");
    refused([](rp_session* s) { return rp_dwell(s, -1); }, "dwell");
    refused([](rp_session* s) { return rp_dwell(s, 601); }, "dwell");
    const double knots[] = {0, 0, 0, 1, 1, 1};
    const double zero_weight[] = {-90, -440, 110, 1, -80, -440, 110, 0, -70, -440, 110, 1};
    refused([&](rp_session* s) { return rp_nurbs_move(s, knots, 6, zero_weight, 3, 0, 0, 1); },
            "weight");
    const double o3[3] = {0, kNaN, 0}, x[3] = {1, 0, 0}, y[3] = {0, 1, 0};
    refused([&](rp_session* s) { return rp_machine_frame(s, o3, x, y); }, "finite");
  }
}

// Issue 48, item 4: rp_open refuses every option value it cannot use, naming it, and opens
// nothing.
TEST_CASE("abi toolpath: rp_open refuses option values it cannot use") {
  const std::string dir = fresh_dir("open_args");
  int refused_count = 0;
  const auto refused = [&](const char* what, auto&& set) {
    INFO("option: " << what);
    rp_options o = options_for(dir, "open.cls");
    set(o);
    rp_session* s = reinterpret_cast<rp_session*>(&o);  // must be set to NULL on failure
    const rp_status st = rp_open(&o, &s);
    INFO(rp_last_error(nullptr));
    CHECK(st == RP_ERR_BAD_INPUT);
    CHECK(s == nullptr);
    if (st == RP_OK) {
      rp_close(s);
      rp_free(s);
    }
    refused_count += st == RP_ERR_BAD_INPUT ? 1 : 0;
  };
  refused("apo_mm NaN", [](rp_options& o) { o.apo_mm = kNaN; });
  refused("apo_mm -1", [](rp_options& o) { o.apo_mm = -1; });
  refused("chordal_tolerance_mm 0", [](rp_options& o) { o.chordal_tolerance_mm = 0; });
  refused("chordal_tolerance_mm NaN", [](rp_options& o) { o.chordal_tolerance_mm = kNaN; });
  refused("rapid_velocity_m_per_s 0", [](rp_options& o) { o.rapid_velocity_m_per_s = 0; });
  refused("rapid_velocity_m_per_s NaN", [](rp_options& o) { o.rapid_velocity_m_per_s = kNaN; });
  refused("keyframe_spacing_mm 0", [](rp_options& o) { o.keyframe_spacing_mm = 0; });
  refused("keyframe_spacing_mm NaN", [](rp_options& o) { o.keyframe_spacing_mm = kNaN; });
  refused("placement NaN", [](rp_options& o) {
    o.has_placement = 1;
    o.placement[2] = kNaN;
  });
  refused("clearance NaN", [](rp_options& o) {
    o.has_clearance = 1;
    o.clearance_z_mm = kNaN;
  });
  refused("motions_per_file -1", [](rp_options& o) { o.motions_per_file = -1; });
  refused("cl_line_every -1", [](rp_options& o) { o.cl_line_every = -1; });
  refused("max_file_bytes -1", [](rp_options& o) { o.max_file_bytes = -1; });
  refused("plan 7", [](rp_options& o) { o.plan = 7; });
  refused("plan_preset 7", [](rp_options& o) { o.plan_preset = 7; });
  refused("deflection 7", [](rp_options& o) { o.deflection = 7; });
  refused("deflection_tolerance_mm -1", [](rp_options& o) { o.deflection_tolerance_mm = -1; });
  refused("msys 7", [](rp_options& o) { o.msys = 7; });
  refused("fit_tolerance_mm -1", [](rp_options& o) { o.fit_tolerance_mm = -1; });
  refused("fit_angle_tolerance_deg NaN", [](rp_options& o) { o.fit_angle_tolerance_deg = kNaN; });
  refused("plan_threads -1", [](rp_options& o) { o.plan_threads = -1; });
  refused("collision_margin_mm NaN", [](rp_options& o) { o.collision_margin_mm = kNaN; });
  refused("collision_margin_mm 2000", [](rp_options& o) { o.collision_margin_mm = 2000; });
  refused("fixture_count -1", [](rp_options& o) { o.fixture_count = -1; });
  refused("lock_mask bit 9", [](rp_options& o) { o.lock_mask = 1u << 9; });
  CHECK(refused_count == 25);
  CHECK(fs::is_empty(dir));
}

TEST_CASE("abi toolpath: a reader of the 0.5 kinds writes nothing past arc_axis") {
  const std::string cl = kSource + "/examples/cl/pocket_arcs.apt";
  rp_reader_options ro;
  rp_reader_options_init(&ro);
  rp_reader* r = nullptr;
  REQUIRE(rp_reader_open_ex(cl.c_str(), &ro, &r) == RP_OK);
  // A host built against 0.5 has a shorter rp_event: what follows arc_axis is not its.
  std::vector<unsigned char> buffer(sizeof(rp_event), 0xAB);
  int more = 1, events = 0;
  while (rp_reader_next(r, reinterpret_cast<rp_event*>(buffer.data()), &more) == RP_OK && more) {
    ++events;
    for (std::size_t k = offsetof(rp_event, cycle); k < buffer.size(); ++k)
      REQUIRE(buffer[k] == 0xAB);
    REQUIRE(reinterpret_cast<rp_event*>(buffer.data())->kind <= RP_EVENT_ARC);
  }
  CHECK(events > 10);
  rp_reader_free(r);
}

TEST_CASE("abi toolpath: the report is written with the program, never without it") {
  const std::string dir = fresh_dir("report");
  const std::string cl = kSource + "/examples/cl/pocket_arcs.apt";
  const std::string report = dir + "/run.html";
  REQUIRE(convert(cl, dir, 1, 0, report.c_str()) == RP_OK);
  CHECK(fs::file_size(report) > 100000);
  // An abandoned session leaves no report, and keeps an old one whole.
  const auto before = files_of(dir);
  rp_options o = options_for(dir, cl);
  o.program_name = "TP";
  o.report_path = report.c_str();
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  REQUIRE(rp_linear_move(s, -100, -450, 110, 0, 0, 1) == RP_OK);
  REQUIRE(rp_prepare(s) == RP_OK);
  rp_free(s);  // not closed: abandoned
  CHECK(files_of(dir) == before);
}
