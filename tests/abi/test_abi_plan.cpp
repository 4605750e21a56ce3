// The whole-path plan through the C ABI (docs/redundancy.md, docs/c-abi.md): its defaults, the
// options refused, an external axis held at a value, checked on the written program, and the
// same bytes and warnings on several threads (run under ThreadSanitizer in CI).
#include "catch_compat.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "abi_test_support.hpp"
#include "redpost.h"
#include "temp_dir.hpp"

namespace {

using namespace redpost::abi_test;

rp_options options_for(const std::string& dir) {
  rp_options o;
  rp_options_init(&o);
  o.cell_path = kCell.c_str();
  o.output_dir = dir.c_str();
  o.program_name = "PLAN";
  // The test counts one motion per CL point: point reduction (rp_options 0.8) off.
  o.fit_tolerance_mm = 0.0;
  return o;
}

}  // namespace

TEST_CASE("abi plan: the defaults are the global plan, smooth, 20 mm keyframes, nothing held",
          "[abi]") {
  rp_options o;
  rp_options_init(&o);
  CHECK(o.plan == RP_PLAN_GLOBAL);
  CHECK(o.plan_preset == RP_PLAN_SMOOTH);
  CHECK(o.keyframe_spacing_mm == 20.0);
  CHECK(o.lock_mask == 0u);
  for (double v : o.lock_value)
    CHECK(std::isnan(v));
}

TEST_CASE("abi plan: bad plan options are refused by rp_open", "[abi]") {
  const std::string dir = redpost::test::fresh_temp_dir("redpost_abi_plan", "bad");
  rp_session* s = nullptr;
  rp_options o = options_for(dir);
  o.plan = 7;
  CHECK(rp_open(&o, &s) == RP_ERR_BAD_INPUT);
  o = options_for(dir);
  o.keyframe_spacing_mm = 0.0;
  CHECK(rp_open(&o, &s) == RP_ERR_BAD_INPUT);
  CHECK(std::string(rp_last_error(nullptr)).find("keyframe spacing") != std::string::npos);
  o = options_for(dir);
  o.lock_mask = 1u << 4;  // E5: the reference cell maps no joint to it
  CHECK(rp_open(&o, &s) == RP_ERR_BAD_INPUT);
  CHECK(std::string(rp_last_error(nullptr)).find("E5") != std::string::npos);
  o = options_for(dir);
  o.plan = RP_PLAN_LOCAL;
  o.lock_mask = 1u;
  o.lock_value[0] = 500.0;  // a value needs the global plan
  CHECK(rp_open(&o, &s) == RP_ERR_BAD_INPUT);
  CHECK(s == nullptr);
}

TEST_CASE("abi plan: E1 held at 500 mm is 500 in every written motion", "[abi]") {
  const std::string dir = redpost::test::fresh_temp_dir("redpost_abi_plan", "lock");
  rp_options o = options_for(dir);
  o.lock_mask = 1u;  // E1
  o.lock_value[0] = 500.0;
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  REQUIRE(rp_rapid(s) == RP_OK);
  REQUIRE(rp_linear_move(s, -100, -450, 100, 0, 0, 1) == RP_OK);
  REQUIRE(rp_feed(s, 3000) == RP_OK);
  for (int k = 0; k <= 40; ++k)
    REQUIRE(rp_linear_move(s, -100 + 5 * k, -450, 60, 0, 0, 1) == RP_OK);
  REQUIRE(rp_close(s) == RP_OK);
  rp_free(s);
  std::ifstream in(dir + "/PLAN.src");
  std::string line;
  int motions = 0;
  while (std::getline(in, line)) {
    if (line.rfind("LIN ", 0) != 0 && line.rfind("PTP ", 0) != 0)
      continue;
    ++motions;
    const std::size_t at = line.find("E1 ");
    REQUIRE(at != std::string::npos);
    INFO(line);
    CHECK(std::stod(line.substr(at + 3)) == Approx(500.0).margin(1e-3));
  }
  CHECK(motions >= 40);
}

namespace {

struct PlanSeen {
  int motions = 0, planned = 0;
  double largest_gap = 0.0;  // |written - planned| over every joint, DH units
};

void count_planned(const rp_motion* m, void* user) {
  auto& seen = *static_cast<PlanSeen*>(user);
  ++seen.motions;
  if (!m->planned)
    return;
  ++seen.planned;
  for (int i = 0; i < m->joint_count && i < 16; ++i)
    seen.largest_gap = std::max(seen.largest_gap, std::fabs(m->joints[i] - m->planned_joints[i]));
}

// A 400 mm pass along the track, observed; the plan's counters after rp_close.
PlanSeen observe_pass(int plan, rp_timing& t) {
  const std::string dir = redpost::test::fresh_temp_dir("redpost_abi_plan", "observed");
  rp_options o = options_for(dir);
  o.plan = plan;
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  PlanSeen seen;
  REQUIRE(rp_set_motion_observer(s, &count_planned, &seen) == RP_OK);
  REQUIRE(rp_rapid(s) == RP_OK);
  REQUIRE(rp_linear_move(s, -100, -450, 100, 0, 0, 1) == RP_OK);
  REQUIRE(rp_feed(s, 3000) == RP_OK);
  for (int k = 0; k <= 80; ++k)
    REQUIRE(rp_linear_move(s, -100, -450 - 5 * k, 60, 0, 0, 1) == RP_OK);
  REQUIRE(rp_close(s) == RP_OK);
  t = rp_timing{};
  t.struct_size = sizeof t;
  REQUIRE(rp_timing_get(s, &t) == RP_OK);
  rp_free(s);
  return seen;
}

}  // namespace

TEST_CASE("abi plan: the observer sees the planned posture, rp_timing the plan's counters",
          "[abi]") {
  rp_timing t{};
  const PlanSeen global = observe_pass(RP_PLAN_GLOBAL, t);
  CHECK(global.motions > 80);
  CHECK(global.planned >= 80);  // every cutting motion followed the plan
  // The tracker stays near the plan (it is pulled towards it, not onto it): below 30 mm on the
  // track, and far below 30 rad on the rotary joints.
  CHECK(global.largest_gap > 0.0);
  CHECK(global.largest_gap < 30.0);
  CHECK(t.plan_windows >= 1);
  CHECK(t.plan_fallback_windows == 0);
  CHECK(t.plan_ik_evaluations > 1000);

  const PlanSeen local = observe_pass(RP_PLAN_LOCAL, t);
  CHECK(local.motions > 80);
  CHECK(local.planned == 0);
  CHECK(t.plan_windows == 0);
  CHECK(t.plan_ik_evaluations == 0);
}

namespace {

// Every file of a folder, name and bytes.
std::string files_in(const std::string& dir) {
  std::vector<std::filesystem::path> files;
  for (const auto& f : std::filesystem::directory_iterator(dir))
    files.push_back(f.path());
  std::sort(files.begin(), files.end());
  std::string all;
  for (const auto& f : files) {
    std::ifstream in(f, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    all += f.filename().string() + "\n" + s.str();
  }
  return all;
}

// A CL file of the test's own: three tools without a tool table (the tracking side warns), a
// zigzag each, and a PPRINT every 300 lines (the reading side warns).
std::string threads_cl(const std::string& dir) {
  std::ostringstream s;
  s << "UNITS/MM\nMULTAX/ON\n";
  int line = 2;
  for (int tool = 1; tool <= 3; ++tool) {
    const double y0 = -450.0 - 20.0 * tool;
    s << "LOADTL/" << tool << "\nSPINDL/9000,RPM,CLW\nRAPID\nGOTO/-100," << y0
      << ",100,0,0.2,0.9797959\nFEDRAT/MMPM,3000\n";
    line += 5;
    for (int l = 0; l < 6; ++l) {
      for (int k = 0; k < 250; ++k) {
        if (++line % 300 == 0)
          s << "PPRINT/ NOTE " << line++ << "\n";
        const int i = l % 2 == 0 ? k : 249 - k;
        s << "GOTO/" << (-100.0 + 0.5 * i) << "," << (y0 - 3.0 * l) << ",60,0,0.2,0.9797959\n";
      }
    }
  }
  const std::string path = dir + "/threads.apt";
  std::ofstream(path) << s.str();
  return path;
}

struct Converted {
  rp_status status = RP_OK;
  std::string files;
  std::vector<std::string> warnings;
};

Converted convert_threads(const std::string& cl, const std::string& dir, int threads,
                          int pipeline) {
  rp_options o = options_for(dir);
  o.fit_tolerance_mm = 0.01;
  o.plan_threads = threads;
  o.pipeline = pipeline;
  o.source_name = cl.c_str();
  Converted out;
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  rp_reader_options ro;
  rp_reader_options_init(&ro);
  ro.toolpath_events = 1;
  rp_reader* r = nullptr;
  REQUIRE(rp_reader_open_ex(cl.c_str(), &ro, &r) == RP_OK);
  rp_event e;
  int more = 1;
  while (out.status == RP_OK) {
    out.status = rp_reader_next(r, &e, &more);
    if (out.status != RP_OK || !more)
      break;
    out.status = rp_session_event(s, &e);
  }
  if (out.status == RP_OK)
    out.status = rp_prepare(s);
  for (int i = 0; rp_warning(s, i) != nullptr; ++i)
    out.warnings.push_back(rp_warning(s, i));
  if (out.status == RP_OK)
    out.status = rp_close(s);
  rp_reader_free(r);
  rp_free(s);
  out.files = files_in(dir);
  return out;
}

}  // namespace

TEST_CASE("abi plan: plan_threads 2 and 3 give the bytes and warnings of one thread", "[abi]") {
  const std::string cl = threads_cl(redpost::test::fresh_temp_dir("redpost_abi", "threads_cl"));
  const Converted one =
      convert_threads(cl, redpost::test::fresh_temp_dir("redpost_abi", "threads_1"), 1, 0);
  REQUIRE(one.status == RP_OK);
  CHECK(one.warnings.size() >= 6);  // three tools, PPRINTs
  for (int threads : {2, 3}) {
    for (int pipeline = 0; pipeline <= (threads == 2 ? 1 : 0); ++pipeline) {
      INFO(threads << " threads, pipeline " << pipeline);
      const Converted many = convert_threads(
          cl,
          redpost::test::fresh_temp_dir(
              "redpost_abi", "threads_" + std::to_string(threads) + "_" + std::to_string(pipeline)),
          threads, pipeline);
      CHECK(many.status == RP_OK);
      CHECK(many.files == one.files);
      CHECK(many.warnings == one.warnings);
    }
  }
}

namespace {

// A session into `dir` (with or without the pipeline) with tool 1 loaded and a feed: ready for
// moves.
rp_session* open_for_moves(const std::string& dir, int pipeline) {
  rp_options o = options_for(dir);
  o.pipeline = pipeline;
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  REQUIRE(rp_tool_change(s, 1, "T1", 10.0, 100.0) == RP_OK);
  REQUIRE(rp_feed(s, 3000.0) == RP_OK);
  return s;
}

}  // namespace

TEST_CASE("abi plan: rp_sync tells an event that failed on the pipeline's thread", "[abi]") {
  // A host that stops sending for a reason of its own (redpost convert at a broken CL line)
  // must hear of an earlier event's failure first. A pose 5 m out among 600 good ones: the
  // events after it return at once under the pipeline; rp_sync waits and tells the pose.
  for (int pipeline : {0, 1}) {
    INFO("pipeline " << pipeline);
    const std::string dir =
        redpost::test::fresh_temp_dir("redpost_abi", "sync_" + std::to_string(pipeline));
    rp_session* s = open_for_moves(dir, pipeline);
    rp_status sent = RP_OK;
    int failed_at = 0;
    for (int k = 0; k < 600 && sent == RP_OK; ++k) {
      REQUIRE(rp_set_line(s, 10 + k) == RP_OK);
      const double x = k == 300 ? 5000.0 : -100.0 + 0.5 * k;
      sent = rp_linear_move(s, x, -450.0, 60.0, 0.0, 0.0, 1.0);
      failed_at = sent == RP_OK ? 0 : k;
    }
    CHECK(rp_sync(nullptr) == RP_ERR_NULL);
    const rp_status synced = rp_sync(s);
    // Without the pipeline an event fails when it is sent (or a few later under the plan's
    // windows); with it, at rp_sync at the latest.
    CHECK((sent != RP_OK || synced != RP_OK));
    if (sent != RP_OK)
      CHECK(failed_at >= 300);
    const std::string message = rp_last_error(s);
    INFO(message);
    CHECK(message.find("would have to leave its limits") != std::string::npos);
    CHECK(message.find(":310: ") != std::string::npos);
    CHECK(rp_last_error_line(s) == 310);
    CHECK(rp_close(s) != RP_OK);
    rp_free(s);
    CHECK(files_in(dir).empty());
  }
}

TEST_CASE("abi plan: rp_sync on a session whose events all went through is RP_OK", "[abi]") {
  const std::string dir = redpost::test::fresh_temp_dir("redpost_abi", "sync_ok");
  rp_session* s = open_for_moves(dir, 1);
  for (int k = 0; k < 200; ++k)
    REQUIRE(rp_linear_move(s, -100.0 + 0.5 * k, -450.0, 60.0, 0.0, 0.0, 1.0) == RP_OK);
  CHECK(rp_sync(s) == RP_OK);
  CHECK(rp_sync(s) == RP_OK);
  CHECK(rp_close(s) == RP_OK);
  rp_free(s);
  CHECK(files_in(dir).find("PLAN.src") != std::string::npos);
}

TEST_CASE(
    "abi plan: under the pipeline an error of the expansion comes at once, after an "
    "earlier failure of the tracking",
    "[abi]") {
  // The expansion (a hole without a cycle) runs on the host's thread and refuses the event
  // itself; a pose out of reach sent before it, still queued for the session's thread, is the
  // error all the same, as without the pipeline.
  for (const bool far_first : {false, true}) {
    INFO("pose out of reach first: " << far_first);
    const std::string dir =
        redpost::test::fresh_temp_dir("redpost_abi", far_first ? "front_after_far" : "front_alone");
    rp_session* s = open_for_moves(dir, 1);
    for (int k = 0; k < 300; ++k) {
      REQUIRE(rp_set_line(s, 10 + k) == RP_OK);
      const double x = far_first && k == 100 ? 5000.0 : -100.0 + 0.5 * k;
      REQUIRE(rp_linear_move(s, x, -450.0, 60.0, 0.0, 0.0, 1.0) == RP_OK);
    }
    REQUIRE(rp_set_line(s, 400) == RP_OK);
    rp_status st = rp_cycle_hole(s, -50.0, -450.0, 60.0, 0.0, 0.0, 1.0);
    if (!far_first)
      CHECK(st != RP_OK);  // at once
    if (st == RP_OK)
      st = rp_sync(s);
    CHECK(st != RP_OK);
    const std::string message = rp_last_error(s);
    INFO(message);
    if (far_first) {
      CHECK(message.find(":110: ") != std::string::npos);
      CHECK(message.find("would have to leave its limits") != std::string::npos);
    } else {
      CHECK(message.find(":400: ") != std::string::npos);
      CHECK(message.find("no cycle is on") != std::string::npos);
    }
    CHECK(rp_close(s) != RP_OK);
    rp_free(s);
    CHECK(files_in(dir).empty());
  }
}
