// Issue 48, item 4: the ABI refuses what it cannot use, call by call, for the calls the event
// tests do not reach: a reader event sent to a session (rp_session_event) is refused as the call
// of the same event would be, the reader's options and queries, the motion observer, and the
// struct_size of every struct a query fills (0 and larger than the library's refused; a smaller
// one, a host built against an older header, filled only as far as it reaches).
#include "catch_compat.hpp"

#include <cmath>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "abi_test_support.hpp"
#include "redpost.h"
#include "temp_dir.hpp"

namespace fs = std::filesystem;

namespace {

using namespace redpost::abi_test;

std::string fresh_dir(const std::string& name) {
  return redpost::test::fresh_temp_dir("redpost_abi_arguments", name);
}

rp_options options_for(const std::string& out_dir) {
  rp_options o;
  rp_options_init(&o);
  o.cell_path = kCell.c_str();
  o.output_dir = out_dir.c_str();
  o.program_name = "ARGS";
  o.source_name = "args.cls";
  return o;
}

// An event as a reader gives it: every field set, as rp_reader_next sets them.
rp_event event_of(rp_event_kind kind, int line) {
  rp_event e;
  std::memset(&e, 0, sizeof e);
  e.kind = kind;
  e.line = line;
  e.p[0] = -100;
  e.p[1] = -440;
  e.p[2] = 110;
  e.axis[2] = 1;
  e.text = "";
  rp_cycle_params_init(&e.cycle);
  return e;
}

}  // namespace

TEST_CASE("abi arguments: rp_session_event refuses what the call of the same event refuses") {
  const std::string dir = fresh_dir("events");
  int refused_count = 0;
  for (const int plan : {RP_PLAN_GLOBAL, RP_PLAN_LOCAL}) {
    const auto refused = [&](const rp_event& bad, rp_status expected, const std::string& fragment) {
      INFO("plan " << plan << ", expecting: " << fragment);
      rp_options o = options_for(dir);
      o.plan = plan;
      rp_session* s = nullptr;
      REQUIRE(rp_open(&o, &s) == RP_OK);
      rp_event e = event_of(RP_EVENT_RAPID, 3);
      REQUIRE(rp_session_event(s, &e) == RP_OK);
      e = event_of(RP_EVENT_MOVE, 4);
      REQUIRE(rp_session_event(s, &e) == RP_OK);
      e = event_of(RP_EVENT_FEED, 5);
      e.value = 1000;
      REQUIRE(rp_session_event(s, &e) == RP_OK);
      const rp_status st = rp_session_event(s, &bad);
      INFO(rp_last_error(s));
      CHECK(st == expected);
      CHECK(std::string(rp_last_error(s)).find("args.cls:9: ") != std::string::npos);
      CHECK(std::string(rp_last_error(s)).find(fragment) != std::string::npos);
      CHECK(rp_close(s) == RP_ERR_STATE);
      rp_free(s);
      CHECK(fs::is_empty(dir));
      refused_count += st == expected ? 1 : 0;
    };
    rp_event e = event_of(static_cast<rp_event_kind>(99), 9);
    refused(e, RP_ERR_BAD_INPUT, "event kind 99");
    e = event_of(RP_EVENT_MOVE, 9);
    e.p[1] = kNaN;
    refused(e, RP_ERR_BAD_INPUT, "not a finite number");
    e = event_of(RP_EVENT_MOVE, 9);
    e.axis[2] = 0;
    refused(e, RP_ERR_BAD_INPUT, "tool axis of zero length");
    e = event_of(RP_EVENT_FROM, 9);
    e.p[0] = kNaN;
    refused(e, RP_ERR_BAD_INPUT, "not a finite number");
    e = event_of(RP_EVENT_FEED, 9);
    e.value = -5;
    refused(e, RP_ERR_BAD_INPUT, "feed");
    e = event_of(RP_EVENT_SPINDLE, 9);
    e.value = -100;
    e.direction = RP_SPINDLE_CW;
    refused(e, RP_ERR_BAD_INPUT, "spindle");
    e = event_of(RP_EVENT_SPINDLE, 9);
    e.value = 100;
    e.direction = static_cast<rp_spindle_direction>(7);
    refused(e, RP_ERR_BAD_INPUT, "spindle direction");
    e = event_of(RP_EVENT_TOOL_CHANGE, 9);
    e.tool_number = 3;
    e.tool_diameter_mm = -10;
    refused(e, RP_ERR_BAD_INPUT, "diameter");
    e = event_of(RP_EVENT_TOOL_CHANGE, 9);
    e.tool_number = -3;
    refused(e, RP_ERR_BAD_INPUT, "tool");
    e = event_of(RP_EVENT_DWELL, 9);
    e.value = 601;
    refused(e, RP_ERR_BAD_INPUT, "dwell");
    e = event_of(RP_EVENT_ARC, 9);
    e.p[1] = -430;
    e.arc_centre[0] = -100;
    e.arc_centre[1] = -435;
    e.arc_centre[2] = 110;
    e.arc_axis[2] = 1;
    e.value = -5;
    refused(e, RP_ERR_BAD_INPUT, "negative radius");
    e.value = 0;
    e.arc_axis[2] = 0;
    refused(e, RP_ERR_BAD_INPUT, "axis of zero length");
    e = event_of(RP_EVENT_CYCLE, 9);
    e.cycle.struct_size = 0;
    refused(e, RP_ERR_BAD_INPUT, "struct_size");
    e = event_of(RP_EVENT_CYCLE, 9);
    refused(e, RP_ERR_BAD_INPUT, "needs FEDTO");
    e = event_of(RP_EVENT_NURBS, 9);
    e.nurbs_knot_count = 2;
    e.nurbs_point_count = 2;
    refused(e, RP_ERR_NULL, "NULL");
    const double knots[] = {0, 0, 0, 1, 1, 1};
    const double zero_weight[] = {-90, -440, 110, 1, -80, -440, 110, 0, -70, -440, 110, 1};
    e.nurbs_knots = knots;
    e.nurbs_knot_count = 6;
    e.nurbs_points = zero_weight;
    e.nurbs_point_count = 3;
    refused(e, RP_ERR_BAD_INPUT, "weight");
    e.nurbs_point_count = -3;
    refused(e, RP_ERR_BAD_INPUT, "-3");
    e = event_of(RP_EVENT_MSYS, 9);
    e.msys_x[0] = 1;
    e.msys_y[0] = 1;
    refused(e, RP_ERR_BAD_INPUT, "orthogonal unit vectors");
    e = event_of(RP_EVENT_OPERATOR_TEXT, 9);
    e.text = nullptr;
    refused(e, RP_ERR_NULL, "NULL");
    e = event_of(RP_EVENT_OPERATOR_TEXT, 9);
    e.text_kind = static_cast<rp_text_kind>(7);
    refused(e, RP_ERR_BAD_INPUT, "text kind 7");
    e = event_of(RP_EVENT_LITERAL, 9);
    e.text = "A\rB";
    refused(e, RP_ERR_BAD_INPUT, "control character");
  }
  CHECK(refused_count == 2 * 21);
  CHECK(rp_session_event(nullptr, nullptr) == RP_ERR_NULL);
}

TEST_CASE("abi arguments: the reader refuses options it cannot use and NULL arguments") {
  const std::string cl = kSource + "/examples/cl/pocket_arcs.apt";
  const auto refused = [&](const char* what, auto&& set, const std::string& fragment) {
    INFO("reader option: " << what);
    rp_reader_options ro;
    rp_reader_options_init(&ro);
    set(ro);
    rp_reader* r = reinterpret_cast<rp_reader*>(&ro);  // must be set to NULL on failure
    CHECK(rp_reader_open_ex(cl.c_str(), &ro, &r) == RP_ERR_BAD_INPUT);
    CHECK(r == nullptr);
    INFO(rp_reader_last_error(nullptr));
    CHECK(std::string(rp_reader_last_error(nullptr)).find(fragment) != std::string::npos);
  };
  refused(
      "struct_size 0", [](rp_reader_options& o) { o.struct_size = 0; }, "struct_size");
  refused(
      "struct_size too large", [](rp_reader_options& o) { o.struct_size = sizeof o + 8; },
      "struct_size");
  refused(
      "chordal tolerance 0", [](rp_reader_options& o) { o.chordal_tolerance_mm = 0; }, "chordal");
  refused(
      "chordal tolerance NaN", [](rp_reader_options& o) { o.chordal_tolerance_mm = kNaN; },
      "chordal");
  refused(
      "msys 7", [](rp_reader_options& o) { o.msys = static_cast<rp_msys_mode>(7); }, "msys");
  CHECK(rp_reader_open(cl.c_str(), -1, nullptr) == RP_ERR_NULL);
  rp_reader* r = nullptr;
  CHECK(rp_reader_open(nullptr, 0.01, &r) == RP_ERR_NULL);
  CHECK(r == nullptr);
  CHECK(rp_reader_open(cl.c_str(), -1, &r) == RP_ERR_BAD_INPUT);
  CHECK(r == nullptr);

  // NULL arguments of an open reader: refused, and the reader goes on where it was.
  REQUIRE(rp_reader_open(cl.c_str(), 0.01, &r) == RP_OK);
  rp_event e;
  int more = 0;
  CHECK(rp_reader_next(r, nullptr, &more) == RP_ERR_NULL);
  CHECK(rp_reader_next(r, &e, nullptr) == RP_ERR_NULL);
  CHECK(rp_reader_next(nullptr, &e, &more) == RP_ERR_NULL);
  REQUIRE(rp_reader_next(r, &e, &more) == RP_OK);
  CHECK(more == 1);
  CHECK(e.line >= 1);
  CHECK(rp_reader_warning(r, -1) == nullptr);
  CHECK(rp_reader_warning(r, 1 << 30) == nullptr);
  CHECK(rp_reader_warning(nullptr, 0) == nullptr);
  rp_reader_free(r);
  rp_reader_free(nullptr);
}

namespace {

// A closed session of a short job (the shipped cell's collision bodies checked), so that every
// query has something to give.
rp_session* closed_session(const std::string& dir) {
  rp_options o = options_for(dir);
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  REQUIRE(rp_rapid(s) == RP_OK);
  REQUIRE(rp_linear_move(s, -100, -450, 110, 0, 0, 1) == RP_OK);
  REQUIRE(rp_feed(s, 1000) == RP_OK);
  REQUIRE(rp_linear_move(s, -60, -450, 110, 0, 0, 1) == RP_OK);
  REQUIRE(rp_close(s) == RP_OK);
  return s;
}

// A query of a struct with struct_size: 0 and one past the library's size are refused; a host's
// older, shorter struct (the first `prefix` bytes) gets those bytes only.
template <class T, class Query>
void check_sized_query(const char* name, std::size_t prefix, Query&& query) {
  INFO(name);
  T t;
  std::memset(&t, 0, sizeof t);
  t.struct_size = 0;
  CHECK(query(&t) == RP_ERR_BAD_INPUT);
  t.struct_size = sizeof(T) + 1;
  CHECK(query(&t) == RP_ERR_BAD_INPUT);
  CHECK(query(static_cast<T*>(nullptr)) == RP_ERR_NULL);
  std::vector<unsigned char> buffer(sizeof(T), 0xAB);
  T* shorter = reinterpret_cast<T*>(buffer.data());
  shorter->struct_size = static_cast<unsigned>(prefix);
  REQUIRE(query(shorter) == RP_OK);
  CHECK(shorter->struct_size == prefix);
  for (std::size_t k = prefix; k < buffer.size(); ++k)
    REQUIRE(buffer[k] == 0xAB);
  t.struct_size = sizeof(T);
  CHECK(query(&t) == RP_OK);
}

}  // namespace

TEST_CASE(
    "abi arguments: every struct_size is checked, and an older host's struct kept to its size") {
  const std::string dir = fresh_dir("sizes");
  rp_session* s = closed_session(dir);
  check_sized_query<rp_timing>("rp_timing", offsetof(rp_timing, plan_windows),
                               [&](rp_timing* t) { return rp_timing_get(s, t); });
  check_sized_query<rp_deflection_summary>(
      "rp_deflection_summary", offsetof(rp_deflection_summary, compensation_iterations),
      [&](rp_deflection_summary* t) { return rp_deflection_summary_get(s, t); });
  check_sized_query<rp_collision_summary>(
      "rp_collision_summary", offsetof(rp_collision_summary, proven_clearance_mm),
      [&](rp_collision_summary* t) { return rp_collision_get(s, t); });
  check_sized_query<rp_cell_info>("rp_cell_info", offsetof(rp_cell_info, coupled_base_joint),
                                  [&](rp_cell_info* t) { return rp_cell_info_get(s, t); });
  check_sized_query<rp_link_info>("rp_link_info", offsetof(rp_link_info, axis_sign),
                                  [&](rp_link_info* t) { return rp_link_get(s, 0, t); });
  rp_link_info link;
  link.struct_size = sizeof link;
  CHECK(rp_link_get(s, -1, &link) == RP_ERR_BAD_INPUT);
  CHECK(rp_link_get(s, 9, &link) == RP_ERR_BAD_INPUT);
  rp_free(s);
  fs::remove_all(dir);
}

TEST_CASE("abi arguments: rp_set_line refuses a negative line and 0 numbers the events again") {
  const std::string dir = fresh_dir("lines");
  rp_options o = options_for(dir);
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  CHECK(rp_set_line(nullptr, 3) == RP_ERR_NULL);
  REQUIRE(rp_set_line(s, 12) == RP_OK);
  CHECK(rp_set_line(s, -4) == RP_ERR_BAD_INPUT);
  CHECK(std::string(rp_last_error(s)).find("line -4 is negative") != std::string::npos);
  // Not an event: the session goes on, at the line it had.
  CHECK(rp_spindle(s, kNaN, RP_SPINDLE_CW) == RP_ERR_BAD_INPUT);
  CHECK(rp_last_error_line(s) == 12);
  CHECK(std::string(rp_last_error(s)).find("event 1: args.cls:12: ") != std::string::npos);
  rp_free(s);

  REQUIRE(rp_open(&o, &s) == RP_OK);
  REQUIRE(rp_set_line(s, 12) == RP_OK);
  REQUIRE(rp_set_line(s, 0) == RP_OK);
  REQUIRE(rp_rapid(s) == RP_OK);
  CHECK(rp_spindle(s, 1000, static_cast<rp_spindle_direction>(9)) == RP_ERR_BAD_INPUT);
  INFO(rp_last_error(s));
  CHECK(std::string(rp_last_error(s)).rfind("event 2: spindle direction 9", 0) == 0);
  rp_free(s);
  CHECK(fs::is_empty(dir));
}

TEST_CASE("abi arguments: the motion observer is set on an open session only") {
  const std::string dir = fresh_dir("observer");
  rp_options o = options_for(dir);
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  long calls = 0;
  const rp_motion_observer count = [](const rp_motion*, void* user) {
    ++*static_cast<long*>(user);
  };
  CHECK(rp_set_motion_observer(nullptr, count, &calls) == RP_ERR_NULL);
  // A NULL function removes it (nothing to refuse), also when none was set.
  CHECK(rp_set_motion_observer(s, nullptr, nullptr) == RP_OK);
  CHECK(rp_set_motion_observer(s, count, &calls) == RP_OK);
  REQUIRE(rp_rapid(s) == RP_OK);
  REQUIRE(rp_linear_move(s, -100, -450, 110, 0, 0, 1) == RP_OK);
  // A failed session takes none.
  CHECK(rp_linear_move(s, kNaN, 0, 0, 0, 0, 1) == RP_ERR_BAD_INPUT);
  CHECK(rp_set_motion_observer(s, count, &calls) == RP_ERR_STATE);
  CHECK(calls == 0);
  rp_free(s);
  CHECK(fs::is_empty(dir));
}
