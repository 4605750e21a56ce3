// The C ABI (redpost.h) as a host sees it: only the header and libredpost.so, no core headers.
// Misuse gives a status and a message, never a crash; a circular move equals the reader's
// CIRCLE; two sessions on two threads give the bytes of a single-threaded run.
#include "catch_compat.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "abi_test_support.hpp"
#include "redpost.h"  // compiles as C++ too: this file is the check
#include "temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

using namespace redpost::abi_test;

// A fresh, empty directory in the temp area, per process (ctest -j runs the cases in parallel).
std::string fresh_dir(const std::string& name) {
  return redpost::test::fresh_temp_dir("redpost_abi", name);
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every file of a directory, name -> bytes.
std::map<std::string, std::string> files_of(const std::string& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    out[e.path().filename().string()] = slurp(e.path());
  return out;
}

rp_options options_for(const std::string& out_dir, const char* name) {
  rp_options o;
  rp_options_init(&o);
  o.cell_path = kCell.c_str();
  o.output_dir = out_dir.c_str();
  o.program_name = name;
  // Pose by pose (Algorithm 1): every call is tracked and written when it is made, which is what
  // these tests check call by call. The global plan buffers calls (test_abi_plan.cpp).
  o.plan = RP_PLAN_LOCAL;
  return o;
}

// A session with one good first move, ready for more events.
rp_session* open_started(const std::string& out_dir) {
  const rp_options o = options_for(out_dir, "T");
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  REQUIRE(s != nullptr);
  REQUIRE(rp_rapid(s) == RP_OK);
  REQUIRE(rp_linear_move(s, -100, -450, 100, 0, 0, 1) == RP_OK);
  return s;
}

// Converts a CL file through reader + session, as `redpost convert` does. Returns the status of
// the first failing call.
rp_status convert(const std::string& cl, const std::string& out_dir, const char* name,
                  double fit_tolerance_mm = -1.0) {
  rp_options o = options_for(out_dir, name);
  if (fit_tolerance_mm >= 0.0)
    o.fit_tolerance_mm = fit_tolerance_mm;
  o.source_name = cl.c_str();
  rp_session* s = nullptr;
  rp_status st = rp_open(&o, &s);
  if (st != RP_OK)
    return st;
  rp_reader* r = nullptr;
  st = rp_reader_open(cl.c_str(), o.chordal_tolerance_mm, &r);
  rp_event e;
  int more = 1;
  while (st == RP_OK) {
    st = rp_reader_next(r, &e, &more);
    if (st != RP_OK || !more)
      break;
    st = rp_session_event(s, &e);
  }
  if (st == RP_OK)
    st = rp_close(s);
  rp_reader_free(r);
  rp_free(s);
  return st;
}

bool contains(const char* text, const std::string& part) {
  return std::string(text).find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("abi: options defaults and version") {
  rp_options o;
  rp_options_init(&o);
  CHECK(o.struct_size == sizeof(rp_options));
  CHECK(o.apo_mm == 0.5);
  CHECK(o.cl_line_every == 50);
  CHECK(o.chordal_tolerance_mm == 0.01);
  CHECK(o.has_placement == 0);
  for (double v : o.placement)
    CHECK(v == 0.0);
  CHECK(o.cell_path == nullptr);
  CHECK(std::string(rp_version()) == REDPOST_VERSION);
  rp_options_init(nullptr);  // no crash
}

TEST_CASE("abi: a NULL handle is RP_ERR_NULL on every function") {
  rp_session* s = nullptr;
  rp_move_info mi;
  rp_summary su;
  rp_joint_range_info jr;
  rp_event ev{};
  int more = 0;
  CHECK(rp_open(nullptr, &s) == RP_ERR_NULL);
  CHECK(s == nullptr);
  const rp_options o = options_for("/tmp", "T");
  CHECK(rp_open(&o, nullptr) == RP_ERR_NULL);
  CHECK(rp_set_line(s, 1) == RP_ERR_NULL);
  CHECK(rp_tool_change(s, 1, "T1", 10, 50) == RP_ERR_NULL);
  CHECK(rp_spindle(s, 1000, RP_SPINDLE_CW) == RP_ERR_NULL);
  CHECK(rp_feed(s, 100) == RP_ERR_NULL);
  CHECK(rp_rapid(s) == RP_ERR_NULL);
  CHECK(rp_linear_move(s, 0, 0, 0, 0, 0, 1) == RP_ERR_NULL);
  CHECK(rp_circular_move(s, 0, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1) == RP_ERR_NULL);
  CHECK(rp_operation_start(s, "op") == RP_ERR_NULL);
  CHECK(rp_operation_end(s) == RP_ERR_NULL);
  CHECK(rp_coolant(s, 1, "FLOOD") == RP_ERR_NULL);
  CHECK(rp_comment(s, "c") == RP_ERR_NULL);
  CHECK(rp_literal(s, "l") == RP_ERR_NULL);
  CHECK(rp_close(s) == RP_ERR_NULL);
  CHECK(contains(rp_last_error(nullptr), "NULL"));
  CHECK(rp_last_move(s, &mi) == RP_ERR_NULL);
  CHECK(rp_summary_get(s, &su) == RP_ERR_NULL);
  CHECK(rp_joint_range(s, 0, &jr) == RP_ERR_NULL);
  CHECK(rp_warning(s, 0) == nullptr);
  CHECK(rp_output_file(s, 0) == nullptr);
  CHECK(rp_session_event(s, &ev) == RP_ERR_NULL);
  rp_free(s);

  rp_reader* r = nullptr;
  CHECK(rp_reader_open(nullptr, 0.01, &r) == RP_ERR_NULL);
  CHECK(r == nullptr);
  CHECK(rp_reader_open("x.apt", 0.01, nullptr) == RP_ERR_NULL);
  CHECK(rp_reader_next(r, &ev, &more) == RP_ERR_NULL);
  CHECK(rp_reader_warning(r, 0) == nullptr);
  CHECK(rp_reader_last_error(r) != nullptr);
  rp_reader_free(r);
}

TEST_CASE("abi: NULL arguments of an open session are RP_ERR_NULL, and fail it") {
  const std::string dir = fresh_dir("null_args");
  rp_session* s = open_started(dir);
  rp_move_info mi;
  CHECK(rp_last_move(s, nullptr) == RP_ERR_NULL);
  CHECK(rp_summary_get(s, nullptr) == RP_ERR_NULL);
  CHECK(rp_last_move(s, &mi) == RP_OK);  // queries do not fail the session
  CHECK(rp_comment(s, nullptr) == RP_ERR_NULL);
  CHECK(contains(rp_last_error(s), "event 3: "));
  CHECK(rp_linear_move(s, -100, -450, 90, 0, 0, 1) == RP_ERR_STATE);
  rp_free(s);
  CHECK(fs::is_empty(dir));
}

TEST_CASE("abi: rp_open failures: missing cell, missing output dir, bad options") {
  const std::string dir = fresh_dir("open_fail");
  rp_session* s = reinterpret_cast<rp_session*>(&s);  // must be reset to NULL

  rp_options o = options_for(dir, "T");
  const std::string missing = dir + "/no_cell.xml";
  o.cell_path = missing.c_str();
  CHECK(rp_open(&o, &s) == RP_ERR_IO);
  CHECK(s == nullptr);
  CHECK(contains(rp_last_error(nullptr), missing));
  // A session that never opened: every event is RP_ERR_NULL, nothing crashes.
  CHECK(rp_linear_move(s, 0, 0, 0, 0, 0, 1) == RP_ERR_NULL);

  const std::string nowhere = dir + "/not/there";
  o = options_for(nowhere, "T");
  CHECK(rp_open(&o, &s) == RP_ERR_IO);
  CHECK(s == nullptr);
  CHECK(contains(rp_last_error(nullptr), "not/there"));

  o = options_for(dir, nullptr);
  CHECK(rp_open(&o, &s) == RP_ERR_NULL);
  o = options_for(dir, "ABCDEFGHIJKLMNOPQRSTUVWXYZ");
  CHECK(rp_open(&o, &s) == RP_ERR_BAD_INPUT);
  CHECK(contains(rp_last_error(nullptr), "24"));
  o = options_for(dir, "T");
  o.struct_size = 0;
  CHECK(rp_open(&o, &s) == RP_ERR_BAD_INPUT);
  o = options_for(dir, "T");
  o.chordal_tolerance_mm = 0.0;
  CHECK(rp_open(&o, &s) == RP_ERR_BAD_INPUT);
  CHECK(s == nullptr);

  // rp_last_error(NULL) is per thread: another thread's failure does not show here.
  std::string other;
  std::thread([&] {
    rp_options t = options_for(dir, "T");
    t.cell_path = "/nowhere/else.xml";
    rp_session* ts = nullptr;
    rp_open(&t, &ts);
    other = rp_last_error(nullptr);
  }).join();
  CHECK(contains(other.c_str(), "/nowhere/else.xml"));
  CHECK(!contains(rp_last_error(nullptr), "/nowhere/else.xml"));
  CHECK(fs::is_empty(dir));
}

TEST_CASE("abi: NaN coordinates and a zero tool axis are RP_ERR_BAD_INPUT naming the event") {
  const std::string dir = fresh_dir("nan");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  {
    rp_session* s = open_started(dir);  // events 1, 2
    CHECK(rp_feed(s, 500) == RP_OK);    // event 3
    CHECK(rp_linear_move(s, -100, nan, 90, 0, 0, 1) == RP_ERR_BAD_INPUT);
    CHECK(contains(rp_last_error(s), "event 4: "));
    CHECK(contains(rp_last_error(s), "not a finite number"));
    // The session is failed: later events are refused and say where it failed.
    CHECK(rp_linear_move(s, -100, -450, 90, 0, 0, 1) == RP_ERR_STATE);
    CHECK(contains(rp_last_error(s), "event 5: "));
    CHECK(contains(rp_last_error(s), "failed at event 4"));
    CHECK(rp_close(s) == RP_ERR_STATE);
    CHECK(rp_output_file(s, 0) == nullptr);
    rp_summary su;
    CHECK(rp_summary_get(s, &su) == RP_OK);  // diagnostics survive the failure
    CHECK(su.poses == 1);
    rp_free(s);
    CHECK(fs::is_empty(dir));
  }
  {
    rp_session* s = open_started(dir);
    CHECK(rp_linear_move(s, -100, -450, 90, 0, 0, 0) == RP_ERR_BAD_INPUT);
    CHECK(contains(rp_last_error(s), "event 3: "));
    CHECK(contains(rp_last_error(s), "zero length"));
    rp_free(s);
  }
  {
    rp_session* s = open_started(dir);
    CHECK(rp_circular_move(s, nan, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1) == RP_ERR_BAD_INPUT);
    rp_free(s);
    s = open_started(dir);
    CHECK(rp_circular_move(s, -100, -440, 100, 0, 0, 0, 0, -90, -440, 100, 0, 0, 1) ==
          RP_ERR_BAD_INPUT);
    CHECK(contains(rp_last_error(s), "axis of zero length"));
    rp_free(s);
    // The first pose of a rapid far away: the message carries event and line.
    rp_options o = options_for(dir, "T");
    o.source_name = "far.apt";
    REQUIRE(rp_open(&o, &s) == RP_OK);
    CHECK(rp_set_line(s, 42) == RP_OK);
    CHECK(rp_linear_move(s, 0, 0, 10000, 0, 0, 1) == RP_ERR_UNREACHABLE);
    CHECK(contains(rp_last_error(s), "event 1: far.apt:42: pose 1"));
    rp_free(s);
    CHECK(fs::is_empty(dir));
  }
}

TEST_CASE("abi: a feed $VEL.CP cannot say is RP_ERR_BAD_INPUT at its line, nothing written") {
  // 1e300 mm/min once printed a 296-digit $VEL.CP; 1e-4 mm/min printed 0.000000 (issue 18).
  const std::string dir = fresh_dir("feed_range");
  for (const double feed : {1e300, 1.2e5 + 1.0, 1e-4}) {
    INFO("feed " << feed);
    rp_options o = options_for(dir, "T");
    o.source_name = "feeds.apt";
    rp_session* s = nullptr;
    REQUIRE(rp_open(&o, &s) == RP_OK);
    CHECK(rp_set_line(s, 7) == RP_OK);
    CHECK(rp_feed(s, feed) == RP_ERR_BAD_INPUT);
    CHECK(contains(rp_last_error(s), "feeds.apt:7: feed "));
    CHECK(contains(rp_last_error(s), "$VEL.CP"));
    rp_free(s);
  }
  CHECK(fs::is_empty(dir));
  // The limits themselves are feeds: 120 000 mm/min is 2 m/s.
  rp_session* s = open_started(dir);
  CHECK(rp_feed(s, 1.2e5) == RP_OK);
  CHECK(rp_feed(s, 0.06) == RP_OK);
  rp_free(s);
}

TEST_CASE("abi: calls after rp_close are RP_ERR_STATE, the files are in place") {
  const std::string dir = fresh_dir("closed");
  rp_session* s = open_started(dir);
  CHECK(rp_output_file(s, 0) == nullptr);  // nothing written before close
  CHECK(rp_close(s) == RP_OK);
  CHECK(std::string(rp_output_file(s, 0)) == dir + "/T.src");
  CHECK(rp_output_file(s, 1) == nullptr);
  CHECK(fs::exists(dir + "/T.src"));
  CHECK(fs::exists(dir + "/T.dat"));
  CHECK(rp_linear_move(s, -100, -450, 90, 0, 0, 1) == RP_ERR_STATE);
  CHECK(contains(rp_last_error(s), "closed"));
  CHECK(rp_comment(s, "late") == RP_ERR_STATE);
  CHECK(rp_close(s) == RP_ERR_STATE);
  rp_move_info mi;
  REQUIRE(rp_last_move(s, &mi) == RP_OK);
  CHECK(mi.joint_count == 9);
  CHECK(std::isfinite(mi.axes[0]));  // A1
  CHECK(std::isnan(mi.axes[11]));    // E6: not mapped in this cell
  rp_summary su;
  REQUIRE(rp_summary_get(s, &su) == RP_OK);
  CHECK(su.poses == 1);
  CHECK(su.motions == 1);
  rp_joint_range_info jr;
  CHECK(rp_joint_range(s, 0, &jr) == RP_OK);
  CHECK(std::string(jr.name) == "theta_M");
  CHECK(std::string(jr.axis_name) == "E2");
  CHECK(rp_joint_range(s, 9, &jr) == RP_ERR_BAD_INPUT);
  rp_free(s);
}

TEST_CASE("abi: rp_prepare completes the files without renaming; rp_free then leaves nothing") {
  const std::string dir = fresh_dir("prepare");
  // An older program of the same name stays until rp_close renames the new one in.
  { std::ofstream(dir + "/T.src") << "old\n"; }
  const std::string csv = dir + "/joints.csv";
  rp_options o = options_for(dir, "T");
  o.joints_csv_path = csv.c_str();
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  REQUIRE(rp_rapid(s) == RP_OK);
  REQUIRE(rp_linear_move(s, -100, -450, 100, 0, 0, 1) == RP_OK);
  REQUIRE(rp_prepare(s) == RP_OK);
  rp_summary su;
  REQUIRE(rp_summary_get(s, &su) == RP_OK);  // queries work between the two steps
  CHECK(su.motions == 1);
  CHECK(slurp(dir + "/T.src") == "old\n");
  CHECK_FALSE(fs::exists(csv));
  CHECK(rp_linear_move(s, -100, -450, 90, 0, 0, 1) == RP_ERR_STATE);
  CHECK(contains(rp_last_error(s), "prepared"));
  CHECK(rp_prepare(s) == RP_ERR_STATE);
  rp_free(s);  // abandoned after prepare: nothing written, the old program kept
  CHECK(files_of(dir) == std::map<std::string, std::string>{{"T.src", "old\n"}});

  // Prepare and close give the bytes of close alone.
  const std::string a = fresh_dir("prepare_a"), b = fresh_dir("prepare_b");
  for (const std::string& d : {a, b}) {
    rp_session* t = open_started(d);
    if (d == a)
      REQUIRE(rp_prepare(t) == RP_OK);
    REQUIRE(rp_close(t) == RP_OK);
    rp_free(t);
  }
  CHECK(files_of(a) == files_of(b));
  CHECK(files_of(a).count("T.src") == 1);
}

TEST_CASE("abi: a second session writing the same program is refused; outputs may not be inputs") {
  const std::string dir = fresh_dir("second");
  rp_session* first = open_started(dir);
  const rp_options o = options_for(dir, "T");
  rp_session* second = nullptr;
  CHECK(rp_open(&o, &second) == RP_ERR_IO);
  CHECK(second == nullptr);
  CHECK(contains(rp_last_error(nullptr), "is being written into this folder"));
  CHECK(rp_close(first) == RP_OK);
  REQUIRE(rp_open(&o, &second) == RP_OK);  // closed, the first session holds no lock
  rp_free(second);
  rp_free(first);

  rp_options clash = options_for(dir, "T");
  clash.joints_csv_path = kCell.c_str();
  rp_session* s = nullptr;
  CHECK(rp_open(&clash, &s) == RP_ERR_IO);
  CHECK(contains(rp_last_error(nullptr), "the joints CSV names the same file as the cell file"));
}

TEST_CASE("abi: a literal with a CR is refused at its line, the CR shown escaped") {
  const std::string dir = fresh_dir("literal_cr");
  rp_session* s = open_started(dir);
  REQUIRE(rp_set_line(s, 42) == RP_OK);
  CHECK(rp_literal(s, "$OUT[1] = TRUE\rHALT") == RP_ERR_BAD_INPUT);
  const std::string m = rp_last_error(s);
  CHECK(m.find(":42: '$OUT[1] = TRUE\\x0DHALT' cannot be passed") != std::string::npos);
  CHECK(m.find('\r') == std::string::npos);  // nothing that moves a terminal's cursor
  rp_free(s);
  CHECK(fs::is_empty(dir));
}

TEST_CASE("abi: a coordinate beyond 1e7 mm and a tool of 1e300 mm are refused at their event") {
  for (const int plan : {RP_PLAN_LOCAL, RP_PLAN_GLOBAL}) {
    const std::string dir = fresh_dir(plan == RP_PLAN_LOCAL ? "far_local" : "far_global");
    rp_options o = options_for(dir, "T");
    o.plan = static_cast<decltype(o.plan)>(plan);
    rp_session* s = nullptr;
    REQUIRE(rp_open(&o, &s) == RP_OK);
    CHECK(rp_linear_move(s, 1e300, -450, 100, 0, 0, 1) == RP_ERR_BAD_INPUT);
    CHECK(contains(rp_last_error(s), "a move to a coordinate beyond 1e+07 mm"));
    rp_free(s);
    REQUIRE(rp_open(&o, &s) == RP_OK);
    CHECK(rp_tool_change(s, 1, "LONG", 10, 1e300) == RP_ERR_BAD_INPUT);
    CHECK(contains(rp_last_error(s), "a tool length is a number of mm from 0 to 2000"));
    rp_free(s);
    // A diameter too (the fuzzer's: a cutter of 1e300 mm kept the clearance check halving).
    for (const double d : {1e300, -1.0, 501.0, std::numeric_limits<double>::infinity()}) {
      REQUIRE(rp_open(&o, &s) == RP_OK);
      CHECK(rp_tool_change(s, 1, "WIDE", d, 3.0) == RP_ERR_BAD_INPUT);
      CHECK(contains(rp_last_error(s), "a tool diameter is a number of mm from 0 to 500"));
      rp_free(s);
    }
    CHECK(fs::is_empty(dir));
  }
}

TEST_CASE("abi: a session without moves writes nothing at close") {
  const std::string dir = fresh_dir("empty");
  const rp_options o = options_for(dir, "T");
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  rp_move_info mi;
  CHECK(rp_last_move(s, &mi) == RP_ERR_STATE);  // no pose yet
  CHECK(rp_comment(s, "only a comment") == RP_OK);
  CHECK(rp_close(s) == RP_ERR_BAD_INPUT);
  CHECK(contains(rp_last_error(s), "no move"));
  CHECK(rp_close(s) == RP_ERR_STATE);
  rp_free(s);
  CHECK(fs::is_empty(dir));
}

TEST_CASE("abi: a missing CL file fails rp_reader_open with its path") {
  rp_reader* r = nullptr;
  CHECK(rp_reader_open("/nowhere/part.apt", 0.01, &r) == RP_ERR_IO);
  CHECK(r == nullptr);
  CHECK(contains(rp_last_error(nullptr), "/nowhere/part.apt"));
  const std::string cl = kSource + "/examples/cl/pocket_arcs.apt";
  CHECK(rp_reader_open(cl.c_str(), 0.0, &r) == RP_ERR_BAD_INPUT);
}

TEST_CASE("abi: a malformed CL file: the reader's error has file:line:column") {
  const std::string dir = fresh_dir("malformed");
  const std::string cl = dir + "/bad.apt";
  std::ofstream(cl) << "UNITS/MM\nRAPID\nGOTO/-100,-450,100\nGOTO/-100,abc,100\n";
  rp_reader* r = nullptr;
  REQUIRE(rp_reader_open(cl.c_str(), 0.01, &r) == RP_OK);
  rp_event e;
  int more = 1;
  rp_status st = RP_OK;
  while (st == RP_OK && more)
    st = rp_reader_next(r, &e, &more);
  CHECK(st == RP_ERR_BAD_INPUT);
  CHECK(contains(rp_reader_last_error(r), "bad.apt:4:"));
  // A failed reader stays failed (it once answered RP_OK and no more records: a clean end of a
  // half-read file).
  const std::string first = rp_reader_last_error(r);
  for (int k = 0; k < 2; ++k) {
    more = 1;
    CHECK(rp_reader_next(r, &e, &more) == RP_ERR_BAD_INPUT);
    CHECK(more == 0);
    CHECK(rp_reader_last_error(r) == first);
  }
  rp_reader_free(r);
}

TEST_CASE("abi: rp_circular_move gives the bytes of the reader's CIRCLE") {
  const std::string dir = fresh_dir("circle");
  const std::string cl = dir + "/arc.apt";
  // Line 7 ends a quarter arc about (-72,-468,57) by the right-hand rule of +Z; line 9 a helix.
  std::ofstream(cl) << "UNITS/MM\n"
                       "RAPID\n"
                       "GOTO/-72,-480,62\n"
                       "FEDRAT/MMPM,900\n"
                       "GOTO/-72,-480,57\n"
                       "CIRCLE/-72,-468,57,0,0,1,12,0.01,0.5,10,0\n"
                       "GOTO/-60,-468,57\n"
                       "CIRCLE/-72,-468,57,0,0,1\n"
                       "GOTO/-84,-468,56\n"
                       "GOTO/-84,-412,56\n";
  // Without the point reduction: with it, the session draws a CL arc's chords within the
  // chordal tolerance less what the printed decimals may add (docs/timing.md), the reader's
  // chords at the tolerance it is given.
  const std::string by_reader = fresh_dir("circle_reader");
  REQUIRE(convert(cl, by_reader, "ARC", 0.0) == RP_OK);

  // The same events, but the arcs through rp_circular_move.
  const std::string by_calls = fresh_dir("circle_calls");
  rp_options o = options_for(by_calls, "ARC");
  o.fit_tolerance_mm = 0.0;
  o.source_name = cl.c_str();
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  rp_reader* r = nullptr;
  REQUIRE(rp_reader_open(cl.c_str(), 0.01, &r) == RP_OK);
  rp_event e;
  int more = 1;
  int arcs = 0;
  while (rp_reader_next(r, &e, &more) == RP_OK && more) {
    if (e.kind == RP_EVENT_MOVE && (e.line == 7 || e.line == 9)) {
      // The chords of the arcs: once per arc, at its end.
      const bool end = (e.line == 7 && e.p[0] == -60) || (e.line == 9 && e.p[0] == -84);
      if (end) {
        REQUIRE(rp_set_line(s, e.line) == RP_OK);
        const double radius = e.line == 7 ? 12 : 0;
        REQUIRE(rp_circular_move(s, -72, -468, 57, 0, 0, 1, radius, e.p[0], e.p[1], e.p[2],
                                 e.axis[0], e.axis[1], e.axis[2]) == RP_OK);
        ++arcs;
      }
      continue;
    }
    REQUIRE(rp_session_event(s, &e) == RP_OK);
  }
  CHECK(arcs == 2);
  REQUIRE(rp_close(s) == RP_OK);
  rp_reader_free(r);
  rp_free(s);
  CHECK(files_of(by_calls) == files_of(by_reader));

  // An end point off the circle is refused with the event.
  const std::string bad_dir = fresh_dir("circle_bad");
  s = open_started(bad_dir);
  CHECK(rp_circular_move(s, -100, -440, 100, 0, 0, 1, 0, -100, -420, 100, 0, 0, 1) ==
        RP_ERR_BAD_INPUT);
  CHECK(contains(rp_last_error(s), "event 3: "));
  CHECK(contains(rp_last_error(s), "not on the circle"));
  rp_free(s);
  // Before any move there is no start point.
  const std::string first_dir = fresh_dir("circle_first");  // options keep its c_str()
  o = options_for(first_dir, "ARC");
  REQUIRE(rp_open(&o, &s) == RP_OK);
  CHECK(rp_circular_move(s, 0, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1) == RP_ERR_BAD_INPUT);
  CHECK(contains(rp_last_error(s), "start point"));
  rp_free(s);
}

TEST_CASE("abi: two sessions on two threads give the bytes of single-threaded runs") {
  const std::string a = kSource + "/examples/cl/pocket_arcs.apt";
  const std::string b = kSource + "/examples/cl/surface_5axis.cls";
  const std::string a1 = fresh_dir("thread_a1"), b1 = fresh_dir("thread_b1");
  REQUIRE(convert(a, a1, "PROG_A") == RP_OK);
  REQUIRE(convert(b, b1, "PROG_B") == RP_OK);

  for (int round = 0; round < 3; ++round) {
    const std::string a2 = fresh_dir("thread_a2"), b2 = fresh_dir("thread_b2");
    rp_status sa = RP_ERR_INTERNAL, sb = RP_ERR_INTERNAL;
    std::thread ta([&] { sa = convert(a, a2, "PROG_A"); });
    std::thread tb([&] { sb = convert(b, b2, "PROG_B"); });
    ta.join();
    tb.join();
    REQUIRE(sa == RP_OK);
    REQUIRE(sb == RP_OK);
    CHECK(files_of(a2) == files_of(a1));
    CHECK(files_of(b2) == files_of(b1));
  }
  CHECK(files_of(a1).size() == 2);
}
