// The deflection through the C ABI (issue 20) as a host sees it: the options, the fields of
// rp_motion, rp_deflection_summary_get and rp_deflection_get, and their struct_size rules. A
// compensated cut ends where the uncompensated one does, moved by the deflection it predicts.
#include "catch_compat.hpp"

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "abi_test_support.hpp"
#include "redpost.h"
#include "temp_dir.hpp"

namespace {

using namespace redpost::abi_test;

void record(const rp_motion* m, void* user) {
  static_cast<std::vector<rp_motion>*>(user)->push_back(*m);
}

struct Run {
  std::vector<rp_motion> motions;
  rp_deflection_summary summary{};
  std::vector<rp_deflection_info> operations;
  std::vector<std::string> names;  // rp_deflection_info::operation lives with the session only
};

// Two operations of straight cuts along -y, 16 mm tool at 8000 rpm and 2000 mm/min.
Run run(int mode, const std::string& dir) {
  rp_options o;
  rp_options_init(&o);
  o.plan = RP_PLAN_LOCAL;
  o.cell_path = kCell.c_str();
  o.output_dir = dir.c_str();
  o.program_name = "DEFL";
  // The test counts one motion per CL point: point reduction (rp_options 0.8) off.
  o.fit_tolerance_mm = 0.0;
  o.deflection = mode;
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  Run out;
  REQUIRE(rp_set_motion_observer(s, record, &out.motions) == RP_OK);
  REQUIRE(rp_tool_change(s, 1, "MILL", 16.0, 0.0) == RP_OK);
  REQUIRE(rp_spindle(s, 8000.0, RP_SPINDLE_CW) == RP_OK);
  REQUIRE(rp_rapid(s) == RP_OK);
  REQUIRE(rp_linear_move(s, -100, -300, 100, 0, 0, 1) == RP_OK);
  REQUIRE(rp_feed(s, 2000.0) == RP_OK);
  REQUIRE(rp_linear_move(s, -100, -300, 60, 0, 0, 1) == RP_OK);  // a plunge: no load
  for (const char* op : {"ROUGH", "FINISH"}) {
    REQUIRE(rp_operation_start(s, op) == RP_OK);
    for (int k = 1; k <= 10; ++k) {
      REQUIRE(rp_set_line(s, 100 + k) == RP_OK);
      REQUIRE(rp_linear_move(s, -100, -300 - 5.0 * k, 60, 0, 0, 1) == RP_OK);
    }
    REQUIRE(rp_operation_end(s) == RP_OK);
    REQUIRE(rp_linear_move(s, -90, -350, 60, 0, 0, 1) == RP_OK);
    REQUIRE(rp_linear_move(s, -90, -300, 60, 0, 0, 1) == RP_OK);
  }
  REQUIRE(rp_prepare(s) == RP_OK);
  out.summary.struct_size = sizeof out.summary;
  REQUIRE(rp_deflection_summary_get(s, &out.summary) == RP_OK);
  for (int i = 0; i < out.summary.operations; ++i) {
    rp_deflection_info info{};
    info.struct_size = sizeof info;
    REQUIRE(rp_deflection_get(s, i, &info) == RP_OK);
    out.operations.push_back(info);
    out.names.emplace_back(info.operation);
  }
  rp_deflection_info past{};
  past.struct_size = sizeof past;
  CHECK(rp_deflection_get(s, out.summary.operations, &past) == RP_ERR_BAD_INPUT);
  past.struct_size = 0;
  CHECK(rp_deflection_get(s, 0, &past) == RP_ERR_BAD_INPUT);
  CHECK(rp_deflection_get(s, 0, nullptr) == RP_ERR_NULL);
  rp_deflection_summary small{};
  small.struct_size = sizeof(unsigned) + sizeof(int);  // a host with an older, shorter struct
  CHECK(rp_deflection_summary_get(s, &small) == RP_OK);
  CHECK(small.mode == mode);
  CHECK(small.tolerance_mm == 0.0);  // beyond its size: not written
  REQUIRE(rp_close(s) == RP_OK);
  rp_free(s);
  return out;
}

}  // namespace

TEST_CASE("abi deflection: off reports nothing, predict and compensate report every cut",
          "[abi][deflection]") {
  const std::string dir = redpost::test::fresh_temp_dir("redpost_abi_deflection", "modes");
  const Run off = run(RP_DEFLECTION_OFF, dir);
  CHECK(off.summary.mode == RP_DEFLECTION_OFF);
  CHECK(off.summary.operations == 0);
  for (const rp_motion& m : off.motions)
    CHECK(m.has_deflection == 0);

  const Run pred = run(RP_DEFLECTION_PREDICT, dir);
  const Run comp = run(RP_DEFLECTION_COMPENSATE, dir);
  REQUIRE(pred.motions.size() == comp.motions.size());
  // ROUGH, the link moves after its end (no operation), FINISH, the link moves after it.
  REQUIRE(pred.summary.operations == 4);
  CHECK(pred.names[0] == "ROUGH");
  CHECK(pred.operations[0].motions == 10);
  CHECK(pred.operations[0].first_line == 101);
  CHECK(pred.operations[0].last_line == 110);
  CHECK(pred.names[1].empty());
  CHECK(pred.operations[1].motions == 2);
  CHECK(pred.names[2] == "FINISH");
  CHECK(pred.operations[0].max_normal_mm > 0.0);
  CHECK(pred.operations[0].rms_normal_mm <= pred.operations[0].max_normal_mm);
  CHECK(pred.operations[0].max_residual_mm == Approx(pred.operations[0].max_mm).margin(2e-4));
  CHECK(pred.summary.unloaded_moves >= 1);  // the plunge
  CHECK(comp.summary.mode == RP_DEFLECTION_COMPENSATE);
  CHECK(comp.summary.max_compensation_iterations >= 1);
  CHECK(comp.summary.max_compensation_iterations <= 8);
  int loaded = 0;
  for (std::size_t k = 0; k < pred.motions.size(); ++k) {
    const rp_motion& p = pred.motions[k];
    const rp_motion& c = comp.motions[k];
    REQUIRE(p.has_deflection == c.has_deflection);
    if (!p.has_deflection)
      continue;
    ++loaded;
    // Without compensation the residual is the deflection; with it, the target moved by the
    // deflection and the model's residual is below the fixed point's tolerance.
    CHECK(p.compensation_mm == 0.0);
    CHECK(p.residual_mm ==
          Approx(std::hypot(p.deflection_mm[0], p.deflection_mm[1], p.deflection_mm[2]))
              .margin(2e-4));
    CHECK(c.residual_mm < 1e-3);
    CHECK(c.compensation_iterations >= 1);
    // The compensated TCP is the CL point moved back by the deflection.
    for (int i = 0; i < 3; ++i)
      CHECK(c.tcp[i] == Approx(p.tcp[i] - c.deflection_mm[i]).margin(2e-3));
    CHECK(c.cutting_force_N == Approx(p.cutting_force_N).epsilon(1e-9));
    CHECK(c.cutting_force_N > 10.0);
  }
  CHECK(loaded == 24);
}

TEST_CASE("abi deflection: bad options are refused at rp_open", "[abi][deflection]") {
  const std::string dir = redpost::test::fresh_temp_dir("redpost_abi_deflection", "bad");
  rp_options o;
  rp_options_init(&o);
  CHECK(o.deflection == RP_DEFLECTION_OFF);
  CHECK(o.deflection_tolerance_mm == 0.05);
  o.cell_path = kCell.c_str();
  o.output_dir = dir.c_str();
  o.program_name = "BAD";
  rp_session* s = nullptr;
  o.deflection = 7;
  CHECK(rp_open(&o, &s) == RP_ERR_BAD_INPUT);
  CHECK(std::string(rp_last_error(nullptr)).find("options.deflection is 7") != std::string::npos);
  o.deflection = RP_DEFLECTION_PREDICT;
  o.deflection_tolerance_mm = std::nan("");
  CHECK(rp_open(&o, &s) == RP_ERR_BAD_INPUT);
  o.deflection_tolerance_mm = 0.05;
  const std::string cutting = kSource + "/examples/placement/caro2014_cutting.xml";
  o.cutting_path = cutting.c_str();
  o.deflection = RP_DEFLECTION_OFF;
  CHECK(rp_open(&o, &s) == RP_ERR_BAD_INPUT);
  o.deflection = RP_DEFLECTION_PREDICT;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  rp_free(s);
}
