// rp_set_motion_observer as a host sees it (only redpost.h and libredpost.so): one call per
// written motion, the TCP at the commanded CL point, the feed in force, and no change to the
// program's bytes.
#include "catch_compat.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "abi_test_support.hpp"
#include "redpost.h"
#include "temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

using namespace redpost::abi_test;

std::string fresh_dir(const std::string& name) {
  return redpost::test::fresh_temp_dir("redpost_abi_obs", name);
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Commanded {
  double p[3];
  bool rapid;
  double feed;  // NaN for rapids
};

void record(const rp_motion* m, void* user) {
  static_cast<std::vector<rp_motion>*>(user)->push_back(*m);
}

// A small path: a rapid approach, cuts at two feeds, a rapid retract. Returns what was sent.
std::vector<Commanded> send_path(rp_session* s) {
  const double nan = std::nan("");
  std::vector<Commanded> sent = {
      {{-100, -450, 100}, true, nan}, {{-100, -450, 60}, true, nan},  {{-80, -450, 55}, false, 600},
      {{-80, -430, 55}, false, 600},  {{-60, -430, 55}, false, 1500}, {{-60, -430, 90}, true, nan},
  };
  double feed = nan;
  for (std::size_t k = 0; k < sent.size(); ++k) {
    const Commanded& c = sent[k];
    REQUIRE(rp_set_line(s, static_cast<int>(10 + k)) == RP_OK);
    if (c.rapid) {
      REQUIRE(rp_rapid(s) == RP_OK);
    } else if (c.feed != feed) {
      REQUIRE(rp_feed(s, c.feed) == RP_OK);
      feed = c.feed;
    }
    REQUIRE(rp_linear_move(s, c.p[0], c.p[1], c.p[2], 0, 0, 1) == RP_OK);
  }
  return sent;
}

rp_session* open_session(const std::string& dir) {
  rp_options o;
  rp_options_init(&o);
  o.cell_path = kCell.c_str();
  o.output_dir = dir.c_str();
  o.program_name = "OBS";
  // A clearance plane under the whole path: every rapid may be a PTP (docs/convert.md).
  o.has_clearance = 1;
  o.clearance_z_mm = -1e4;
  o.plan = RP_PLAN_LOCAL;  // one sample per call, as the call is made
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  return s;
}

}  // namespace

TEST_CASE("abi observer: one sample per written motion, at the commanded point", "[abi]") {
  const std::string dir = fresh_dir("samples");
  rp_session* s = open_session(dir);
  std::vector<rp_motion> got;
  REQUIRE(rp_set_motion_observer(s, &record, &got) == RP_OK);
  const std::vector<Commanded> sent = send_path(s);

  rp_move_info last{};
  REQUIRE(rp_last_move(s, &last) == RP_OK);
  REQUIRE(rp_close(s) == RP_OK);
  rp_summary sum{};
  REQUIRE(rp_summary_get(s, &sum) == RP_OK);

  REQUIRE(static_cast<long>(got.size()) == sum.motions);
  REQUIRE(got.size() == sent.size());  // short moves: one written motion per move
  for (std::size_t k = 0; k < got.size(); ++k) {
    const rp_motion& m = got[k];
    CHECK(m.struct_size == sizeof(rp_motion));
    CHECK(m.index == static_cast<long>(k + 1));
    CHECK(m.line == static_cast<int>(10 + k));
    CHECK(m.kind == (k == 0 ? RP_MOTION_PTP : sent[k].rapid ? RP_MOTION_RAPID : RP_MOTION_LIN));
    // The tracker converges to 1e-4 mm: the TCP sits on the point the host commanded.
    for (int i = 0; i < 3; ++i)
      CHECK(std::fabs(m.tcp[i] - sent[k].p[i]) < 1e-3);
    if (sent[k].rapid) {
      CHECK(std::isnan(m.feed_mm_per_min));
    } else {
      CHECK(m.feed_mm_per_min == sent[k].feed);
    }
    CHECK(m.inv_condition > 0.0);
    CHECK(m.inv_condition <= 1.0);
    CHECK(m.conditioning_threshold > 0.0);
    CHECK(m.iterations >= 0);
    CHECK(m.joint_count == last.joint_count);
  }
  // The last sample is the last tracked pose (a short move is tracked in one step).
  const rp_motion& m = got.back();
  CHECK(m.inv_condition == last.inv_condition);
  CHECK(m.iterations == last.iterations);
  for (int i = 0; i < last.joint_count; ++i)
    CHECK(m.joints[i] == last.joints[i]);
  for (int i = 0; i < 12; ++i)
    CHECK((m.axes[i] == last.axes[i] || (std::isnan(m.axes[i]) && std::isnan(last.axes[i]))));
  rp_free(s);
  fs::remove_all(dir);
}

TEST_CASE("abi observer: the program is the same with and without, removal stops the calls",
          "[abi]") {
  const std::string plain = fresh_dir("plain"), watched = fresh_dir("watched");
  rp_session* a = open_session(plain);
  send_path(a);
  REQUIRE(rp_close(a) == RP_OK);
  rp_free(a);

  rp_session* b = open_session(watched);
  std::vector<rp_motion> got;
  REQUIRE(rp_set_motion_observer(b, &record, &got) == RP_OK);
  REQUIRE(rp_rapid(b) == RP_OK);
  REQUIRE(rp_linear_move(b, -100, -450, 100, 0, 0, 1) == RP_OK);
  REQUIRE(got.size() == 1);
  REQUIRE(rp_set_motion_observer(b, nullptr, nullptr) == RP_OK);
  REQUIRE(rp_close(b) == RP_OK);
  CHECK(got.size() == 1);
  rp_free(b);

  rp_session* c = open_session(watched);
  REQUIRE(rp_set_motion_observer(c, &record, &got) == RP_OK);
  send_path(c);
  REQUIRE(rp_close(c) == RP_OK);
  rp_free(c);
  CHECK(slurp(fs::path(plain) / "OBS.src") == slurp(fs::path(watched) / "OBS.src"));
  CHECK(slurp(fs::path(plain) / "OBS.dat") == slurp(fs::path(watched) / "OBS.dat"));
  fs::remove_all(plain);
  fs::remove_all(watched);
}

TEST_CASE("abi observer: misuse gives a status", "[abi]") {
  CHECK(rp_set_motion_observer(nullptr, &record, nullptr) == RP_ERR_NULL);
  const std::string dir = fresh_dir("misuse");
  rp_session* s = open_session(dir);
  REQUIRE(rp_rapid(s) == RP_OK);
  REQUIRE(rp_linear_move(s, -100, -450, 100, 0, 0, 1) == RP_OK);
  REQUIRE(rp_close(s) == RP_OK);
  std::vector<rp_motion> got;
  CHECK(rp_set_motion_observer(s, &record, &got) == RP_ERR_STATE);
  CHECK(std::string(rp_last_error(s)).find("not open") != std::string::npos);
  rp_free(s);
  fs::remove_all(dir);
}
