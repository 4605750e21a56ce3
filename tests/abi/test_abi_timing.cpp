// The time model through the C ABI (rp_timing_get, rp_feed_limit, the timed fields of rp_motion)
// as a host sees it: the cycle time is where the last motion ends, the time at the CL feeds is
// the closed form sum of length / feed, every motion takes at least its length at its $VEL.CP,
// and the struct_size rules hold as for the other info structs.
#include "catch_compat.hpp"

#include <cmath>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
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
  return redpost::test::fresh_temp_dir("redpost_abi_timing", name);
}

void record(const rp_motion* m, void* user) {
  static_cast<std::vector<rp_motion>*>(user)->push_back(*m);
}

rp_session* open_session(const std::string& dir, const char* name, int plan = RP_PLAN_LOCAL,
                         double fit_tolerance_mm = 0.01) {
  rp_options o;
  rp_options_init(&o);
  o.plan = plan;
  o.fit_tolerance_mm = fit_tolerance_mm;
  o.cell_path = kCell.c_str();
  o.output_dir = dir.c_str();
  o.program_name = name;
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  return s;
}

// Every event of the CL file through the library's reader into the session, then rp_close.
void convert_file(rp_session* s, const std::string& cl) {
  rp_reader* r = nullptr;
  REQUIRE(rp_reader_open(cl.c_str(), 0.01, &r) == RP_OK);
  rp_event e;
  int more = 1;
  while (more) {
    REQUIRE(rp_reader_next(r, &e, &more) == RP_OK);
    if (more)
      REQUIRE(rp_session_event(s, &e) == RP_OK);
  }
  rp_reader_free(r);
  REQUIRE(rp_close(s) == RP_OK);
}

struct Cut {
  double p[3];
  double feed_mm_per_min;  // 0: a rapid
};

// A rapid approach, three cuts at two feeds, a rapid out.
const std::vector<Cut> kPath = {
    {{-100, -450, 100}, 0}, {{-100, -450, 60}, 0},   {{-80, -450, 55}, 600},
    {{-80, -430, 55}, 600}, {{-60, -430, 55}, 1500}, {{-60, -430, 90}, 0},
};

void send(rp_session* s, const std::vector<Cut>& path) {
  for (std::size_t k = 0; k < path.size(); ++k) {
    REQUIRE(rp_set_line(s, static_cast<int>(10 + k)) == RP_OK);
    if (path[k].feed_mm_per_min > 0.0)
      REQUIRE(rp_feed(s, path[k].feed_mm_per_min) == RP_OK);
    else
      REQUIRE(rp_rapid(s) == RP_OK);
    REQUIRE(rp_linear_move(s, path[k].p[0], path[k].p[1], path[k].p[2], 0, 0, 1) == RP_OK);
  }
}

double distance(const double* a, const double* b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

}  // namespace

TEST_CASE("abi timing: the cycle time, the time at the CL feeds and every motion's duration",
          "[abi]") {
  const std::string dir = fresh_dir("path");
  rp_session* s = open_session(dir, "TIMED");
  std::vector<rp_motion> got;
  REQUIRE(rp_set_motion_observer(s, &record, &got) == RP_OK);
  send(s, kPath);
  REQUIRE(rp_close(s) == RP_OK);

  rp_timing t{};
  t.struct_size = sizeof t;
  REQUIRE(rp_timing_get(s, &t) == RP_OK);
  REQUIRE(got.size() >= kPath.size());
  CHECK(t.axis_speeds_known == 1);
  CHECK(t.cycle_time_s == Approx(got.back().time_s).margin(1e-9));
  CHECK(t.peak_speed_fraction > 0.0);
  CHECK(t.peak_speed_fraction <= 1.0);
  CHECK(t.slowed_motions == 0);
  CHECK(t.untimed_tool_changes == 0);

  // The cuts at exactly their feeds, in closed form: 20.616 mm at 10 mm/s, 20 mm at 10 mm/s,
  // 20 mm at 25 mm/s.
  double feed_time_s = 0.0;
  for (std::size_t k = 2; k < 5; ++k)
    feed_time_s += distance(kPath[k - 1].p, kPath[k].p) / (kPath[k].feed_mm_per_min / 60.0);
  CHECK(t.feed_time_s == Approx(feed_time_s).epsilon(1e-9));
  // Accelerating and braking only add time; at these feeds and 2 m/s^2, well under 1 %.
  CHECK(t.cutting_time_s >= t.feed_time_s - 1e-9);
  CHECK(t.cutting_time_s <= 1.01 * t.feed_time_s);

  // Motion by motion: ends in order, each at least its TCP length at its $VEL.CP.
  double end_s = 0.0;
  for (std::size_t k = 0; k < got.size(); ++k) {
    const rp_motion& m = got[k];
    INFO("motion " << k);
    CHECK(m.duration_s >= 0.0);
    CHECK(m.time_s == Approx(end_s + m.duration_s).margin(1e-9));
    end_s = m.time_s;
    if (k > 0 && m.kind != RP_MOTION_PTP && std::isfinite(m.command_mm_s)) {
      const double length = distance(got[k - 1].tcp, m.tcp);
      CHECK(m.duration_s >= length / m.command_mm_s - 1e-9);
      CHECK(m.speed_mm_s <= m.command_mm_s * (1.0 + 1e-9));
      // The controller's clock: a CP motion that moves lasts at least one 12 ms cycle.
      if (length > 1e-6)
        CHECK(m.duration_s >= 0.012 - 1e-12);
    }
    for (int j = 0; j < m.joint_count && j < 16; ++j)
      CHECK(m.speed_fraction[j] <= 1.0);
    REQUIRE(m.limit != nullptr);
  }
  rp_free(s);
}

TEST_CASE("abi timing: struct_size rules and the feed limits list", "[abi]") {
  // The pocket example with every feed at 10 000 mm/min, every CL point kept (--fit-tol 0): the
  // track limits the feed somewhere, and most arc chords last less than a cycle.
  // (No std::regex: GCC 12 warns inside <regex> under the sanitizers, and warnings fail here.)
  std::ifstream in(kSource + "/examples/cl/pocket_arcs.apt");
  std::string fast, line;
  while (std::getline(in, line))
    fast += (line.rfind("FEDRAT/", 0) == 0 ? std::string("FEDRAT/MMPM,10000") : line) + "\n";
  const std::string dir = fresh_dir("fast");
  const std::string cl = dir + "/fast.apt";
  std::ofstream(cl) << fast;
  const std::string out = dir + "/out";
  fs::create_directories(out);

  rp_session* s = open_session(out, "FAST", RP_PLAN_LOCAL, 0.0);
  convert_file(s, cl);

  rp_timing t{};
  t.struct_size = sizeof t;
  REQUIRE(rp_timing_get(s, &t) == RP_OK);
  CHECK(t.slowed_motions > 0);
  CHECK(t.rate_slowed_motions == 0);  // written at the feed: the clock slows them unasked
  CHECK(t.peak_speed_fraction <= 1.0);
  REQUIRE(t.feed_limits > 0);
  REQUIRE(t.feed_limits_listed > 0);
  CHECK(t.feed_limits_listed <= t.feed_limits);
  // The clock of the shipped krc4_lin set (0.7).
  CHECK(t.interpolation_cycle_s == 0.012);
  CHECK(t.cp_motions > 0);
  CHECK(t.below_cycle_motions <= t.cp_motions);
  CHECK(t.below_cycle_motions > 0);
  CHECK(t.rate_limited_motions <= t.below_cycle_motions);
  CHECK(t.shortest_motion_s > 0.0);
  CHECK(t.shortest_motion_line > 0);

  SECTION("with the point reduction, every motion lasts a cycle at its $VEL.CP") {
    const std::string out_fit = dir + "/fit";
    fs::create_directories(out_fit);
    rp_session* f = open_session(out_fit, "FAST", RP_PLAN_LOCAL, 0.01);
    convert_file(f, cl);
    rp_timing r{};
    r.struct_size = sizeof r;
    REQUIRE(rp_timing_get(f, &r) == RP_OK);
    rp_free(f);
    CHECK(r.below_cycle_motions == 0);
    CHECK(r.rate_slowed_motions > 0);
    // The clock keeps them at the speed written: the motion rate (not an axis) limits those
    // that reach it (the others are kept lower still by their corners).
    CHECK(r.rate_limited_motions > 0);
    CHECK(r.rate_limited_motions <= r.rate_slowed_motions);
    // The same time as without the reduction, or less: the time model ran the chords at one
    // per cycle there too.
    CHECK(r.cutting_time_s <= t.cutting_time_s * 1.001);
  }

  SECTION("every listed stretch") {
    for (int i = 0; i < t.feed_limits_listed; ++i) {
      rp_feed_limit_info f{};
      f.struct_size = sizeof f;
      REQUIRE(rp_feed_limit(s, i, &f) == RP_OK);
      INFO("stretch " << i);
      CHECK(f.first_line <= f.last_line);
      CHECK(f.motions >= 1);
      CHECK(f.lowest_mm_per_min < 0.95 * f.asked_mm_per_min);
      const std::string limit = f.limit;
      if (limit == "motion rate" || limit == "look-ahead" || limit == "curvature") {
        // The controller's clock (0.7), a CIRC's radius (0.8): not an axis.
        CHECK(f.joint == -1);
        CHECK(std::string(f.axis_name) == "-");
        CHECK(std::string(f.joint_name).empty());
      } else {
        CHECK((limit == "axis velocity" || limit == "axis acceleration" || limit == "corner"));
        CHECK(std::string(f.axis_name).size() == 2);
        CHECK(std::string(f.joint_name).size() > 0);
      }
    }
    rp_feed_limit_info past{};
    past.struct_size = sizeof past;
    CHECK(rp_feed_limit(s, t.feed_limits_listed, &past) == RP_ERR_BAD_INPUT);
    CHECK(rp_feed_limit(s, -1, &past) == RP_ERR_BAD_INPUT);
  }
  SECTION("struct_size: zero and too large are refused, a smaller one fills only its part") {
    rp_timing bad{};
    CHECK(rp_timing_get(s, &bad) == RP_ERR_BAD_INPUT);
    bad.struct_size = sizeof bad + 8;
    CHECK(rp_timing_get(s, &bad) == RP_ERR_BAD_INPUT);
    CHECK(rp_timing_get(s, nullptr) == RP_ERR_NULL);
    rp_timing part;
    std::memset(&part, 0x7f, sizeof part);
    part.struct_size = offsetof(rp_timing, feed_time_s);
    REQUIRE(rp_timing_get(s, &part) == RP_OK);
    CHECK(part.cycle_time_s == t.cycle_time_s);
    unsigned char untouched[sizeof(double)];
    std::memset(untouched, 0x7f, sizeof untouched);
    CHECK(std::memcmp(&part.feed_time_s, untouched, sizeof untouched) == 0);
  }
  rp_free(s);
}

TEST_CASE("abi timing: the point reduction's defaults, bounds, counters and a 0.7 host", "[abi]") {
  rp_options o;
  rp_options_init(&o);
  CHECK(o.fit_tolerance_mm == 0.01);
  CHECK(o.fit_angle_tolerance_deg == 0.1);
  const std::string dir = fresh_dir("fit");
  o.cell_path = kCell.c_str();
  o.output_dir = dir.c_str();
  o.program_name = "FIT";
  rp_session* s = nullptr;
  for (double bad : {-1.0, 1e-4, 2.0, std::nan("")}) {
    o.fit_tolerance_mm = bad;
    CHECK(rp_open(&o, &s) == RP_ERR_BAD_INPUT);
    CHECK(std::string(rp_last_error(nullptr)).find("--fit-tol") != std::string::npos);
  }
  o.fit_tolerance_mm = 0.01;
  for (double bad : {0.0, 10.0, std::nan("")}) {
    o.fit_angle_tolerance_deg = bad;
    CHECK(rp_open(&o, &s) == RP_ERR_BAD_INPUT);
    CHECK(std::string(rp_last_error(nullptr)).find("--fit-ang-tol") != std::string::npos);
  }
  o.fit_angle_tolerance_deg = 0.1;

  // The long pass (403 CL points on straight lines): merged with the defaults, one motion per
  // point with 0, and for a host whose rp_options ends before the 0.8 fields.
  const auto run = [&](const rp_options& options, const char* name) {
    const std::string out = dir + "/" + name;
    fs::create_directories(out);
    rp_options copy = options;
    copy.output_dir = out.c_str();
    copy.program_name = name;
    rp_session* session = nullptr;
    REQUIRE(rp_open(&copy, &session) == RP_OK);
    convert_file(session, kSource + "/examples/cl/long_pass.apt");
    rp_timing t{};
    t.struct_size = sizeof t;
    REQUIRE(rp_timing_get(session, &t) == RP_OK);
    rp_free(session);
    return t;
  };
  const rp_timing reduced = run(o, "FIT_ON");
  CHECK(reduced.reducible_points > 300);
  CHECK(reduced.reduced_moves * 10 < reduced.reducible_points);
  rp_options off = o;
  off.fit_tolerance_mm = 0.0;
  const rp_timing every = run(off, "FIT_OFF");
  CHECK(every.reduced_moves == 0);  // nothing reduced
  CHECK(every.reducible_points == 0);
  CHECK(every.cp_motions > 10 * reduced.cp_motions);
  rp_options old_host = o;
  old_host.struct_size = offsetof(rp_options, fit_tolerance_mm);
  const rp_timing old = run(old_host, "FIT_07");
  CHECK(old.reduced_moves == every.reduced_moves);
  CHECK(old.cp_motions == every.cp_motions);
  // The long pass's merged moves all last a cycle at its feed: nothing written at the motion rate.
  CHECK(reduced.rate_slowed_motions == 0);
  CHECK(reduced.below_cycle_motions == 0);
  CHECK(every.rate_slowed_motions == 0);
}
