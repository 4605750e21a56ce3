// The whole-path plan through the C ABI (docs/redundancy.md, docs/c-abi.md): its defaults, the
// options refused, and an external axis held at a value, checked on the written program.
#include "catch_compat.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "redpost.h"
#include "temp_dir.hpp"

namespace {

const std::string kSource = REDPOST_SOURCE_DIR;
const std::string kCell = kSource + "/definitions/cells/andres2011_kr15_track_table.xml";

rp_options options_for(const std::string& dir) {
  rp_options o;
  rp_options_init(&o);
  o.cell_path = kCell.c_str();
  o.output_dir = dir.c_str();
  o.program_name = "PLAN";
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
