// The cell's model through the C ABI (issue 21: what the report's 3D view draws from): with the
// DH numbers rp_link_get gives and the frames of rp_cell_info_get, a host's own forward
// kinematics, written here from the conventions redpost.h states, must land on the TCP every
// motion reports (rp_motion::tcp), the tool in force included (tool_length_mm, tcp_shift_mm).
// Checked on the standard-DH reference cell with a placement and a tool longer than its
// reference, and on the modified-DH Caro cell with a fixed spindle transform and a <tool> frame.
#include "catch_compat.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "abi_test_support.hpp"
#include "redpost.h"
#include "temp_dir.hpp"

namespace {

using namespace redpost::abi_test;

// A rigid transform as a C host holds it: the 3x4 rows of redpost.h and an implicit 0 0 0 1.
struct Mat4 {
  std::array<double, 12> v{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
  double& operator()(int r, int c) { return v[static_cast<std::size_t>(4 * r + c)]; }
  double operator()(int r, int c) const { return v[static_cast<std::size_t>(4 * r + c)]; }
};

Mat4 from34(const double* v) {
  Mat4 m;
  for (int i = 0; i < 12; ++i)
    m.v[static_cast<std::size_t>(i)] = v[i];
  return m;
}

Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      double x = c == 3 ? a(r, 3) : 0.0;
      for (int k = 0; k < 3; ++k)
        x += a(r, k) * b(k, c);
      m(r, c) = x;
    }
  }
  return m;
}

// The inverse of a rigid transform: R^T and -R^T t.
Mat4 rigid_inverse(const Mat4& a) {
  Mat4 m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      m(r, c) = a(c, r);
    m(r, 3) = -(a(0, r) * a(0, 3) + a(1, r) * a(1, 3) + a(2, r) * a(2, 3));
  }
  return m;
}

Mat4 rows(std::array<double, 12> v) {
  Mat4 m;
  m.v = v;
  return m;
}

// The link transforms as redpost.h states them, written out element by element.
Mat4 link_transform(const rp_link_info& l, double q) {
  const double th = l.theta_rad + (l.type == RP_JOINT_PRISMATIC ? 0.0 : q);
  const double d = l.d_mm + (l.type == RP_JOINT_PRISMATIC ? q : 0.0);
  const double ct = std::cos(th), st = std::sin(th), ca = std::cos(l.alpha_rad),
               sa = std::sin(l.alpha_rad);
  if (l.modified_dh)  // Rx(alpha) Tx(a) Rz(theta) Tz(d)
    return rows({ct, -st, 0, l.a_mm, st * ca, ct * ca, -sa, -d * sa, st * sa, ct * sa, ca, d * ca});
  // Rz(theta) Tz(d) Tx(a) Rx(alpha)
  return rows(
      {ct, -st * ca, st * sa, l.a_mm * ct, st, ct * ca, -ct * sa, l.a_mm * st, 0, sa, ca, d});
}

struct Model {
  rp_cell_info cell{};
  std::vector<rp_link_info> links;
};

Model read_model(const rp_session* s) {
  Model m;
  m.cell.struct_size = sizeof m.cell;
  REQUIRE(rp_cell_info_get(s, &m.cell) == RP_OK);
  for (int i = 0; i < m.cell.joint_count; ++i) {
    rp_link_info l{};
    l.struct_size = sizeof l;
    REQUIRE(rp_link_get(s, i, &l) == RP_OK);
    m.links.push_back(l);
  }
  return m;
}

// The TCP in the CL frame for the motion's joints and tool.
std::array<double, 3> tcp_in_part(const Model& m, const rp_motion& mo) {
  Mat4 T = from34(m.cell.T_B_0);
  for (int i = 0; i < m.cell.joint_count; ++i)
    T = T * from34(m.links[i].T_prev_link) * link_transform(m.links[i], mo.joints[i]);
  T = T * from34(m.cell.T_last_tcp);
  Mat4 shift;
  shift(2, 3) = -mo.tcp_shift_mm;
  const Mat4 T_part_tcp = rigid_inverse(from34(m.cell.T_B_part)) * T * shift;
  return {T_part_tcp(0, 3), T_part_tcp(1, 3), T_part_tcp(2, 3)};
}

void record(const rp_motion* m, void* user) {
  static_cast<std::vector<rp_motion>*>(user)->push_back(*m);
}

double worst_fk_error(const Model& m, const std::vector<rp_motion>& motions) {
  double worst = 0.0;
  for (const rp_motion& mo : motions) {
    const std::array<double, 3> p = tcp_in_part(m, mo);
    worst = std::max(worst, std::hypot(p[0] - mo.tcp[0], p[1] - mo.tcp[1], p[2] - mo.tcp[2]));
  }
  return worst;
}

// A session on `cell` with the CL frame placed at x, y, z, A, B, C (mm, deg) in {B}.
rp_session* open_placed(const std::string& cell, const std::string& dir, const char* name,
                        std::array<double, 6> placement) {
  rp_options o;
  rp_options_init(&o);
  o.plan = RP_PLAN_LOCAL;
  o.cell_path = cell.c_str();
  o.output_dir = dir.c_str();
  o.program_name = name;
  // The test counts one motion per CL point: point reduction (rp_options 0.8) off.
  o.fit_tolerance_mm = 0.0;
  o.has_placement = 1;
  for (int i = 0; i < 6; ++i)
    o.placement[i] = placement[static_cast<std::size_t>(i)];
  rp_session* s = nullptr;
  REQUIRE(rp_open(&o, &s) == RP_OK);
  return s;
}

}  // namespace

TEST_CASE("abi.cell: a host's own FK from rp_link_get lands on every motion's TCP, tool included",
          "[abi][cell]") {
  const std::string dir = redpost::test::fresh_temp_dir("redpost_abi_cell", "andres");
  const std::string cell = kSource + "/definitions/cells/andres2011_kr15_track_table.xml";
  rp_session* s = open_placed(cell, dir, "CELL", {20.0, -15.0, 5.0, 10.0, 0.0, 0.0});
  const Model m = read_model(s);
  REQUIRE(m.cell.joint_count == 9);
  CHECK(m.cell.reference_tool_length_mm == 119.7);
  CHECK(m.cell.coupled_base_joint == 0);
  CHECK(m.cell.robroot_joint == 1);
  CHECK(m.links[1].type == RP_JOINT_PRISMATIC);
  CHECK(m.links[8].type == RP_JOINT_VIRTUAL);
  CHECK(std::string(m.links[2].name) == "theta_1");
  CHECK(std::string(m.links[2].axis_name) == "A1");
  CHECK(m.links[2].axis_sign == 1.0);
  CHECK(m.links[2].axis_offset == -180.0);
  CHECK(std::string(m.links[8].axis_name) == "none");
  CHECK(m.links[8].axis_sign == 0.0);
  // The placement: 10 deg about z, then the offset.
  CHECK(std::fabs(m.cell.T_B_part[3] - 20.0) < 1e-12);
  CHECK(std::fabs(m.cell.T_B_part[0] - std::cos(10.0 * M_PI / 180.0)) < 1e-12);

  std::vector<rp_motion> motions;
  REQUIRE(rp_set_motion_observer(s, record, &motions) == RP_OK);
  // A tool 30.3 mm longer than the chain's reference: its TCP lies beyond the chain's.
  REQUIRE(rp_tool_change(s, 1, "MILL", 16.0, 150.0) == RP_OK);
  REQUIRE(rp_spindle(s, 8000.0, RP_SPINDLE_CW) == RP_OK);
  REQUIRE(rp_rapid(s) == RP_OK);
  REQUIRE(rp_linear_move(s, -100, -300, 100, 0, 0, 1) == RP_OK);
  REQUIRE(rp_feed(s, 2000.0) == RP_OK);
  for (int k = 0; k <= 20; ++k) {
    const double a = 0.3 * k;
    REQUIRE(rp_linear_move(s, -100 + 60 * std::cos(a), -300 + 60 * std::sin(a), 60,
                           0.1 * std::sin(a), 0, 1) == RP_OK);
  }
  REQUIRE(rp_prepare(s) == RP_OK);
  REQUIRE(motions.size() > 10);
  for (const rp_motion& mo : motions) {
    CHECK(mo.tool_length_mm == 150.0);
    CHECK(std::fabs(mo.tcp_shift_mm - 30.3) < 1e-9);
  }
  CHECK(worst_fk_error(m, motions) < 1e-6);

  // Misuse: past the last link, no struct size, NULL.
  rp_link_info l{};
  l.struct_size = sizeof l;
  CHECK(rp_link_get(s, 9, &l) == RP_ERR_BAD_INPUT);
  CHECK(std::string(rp_last_error(s)).find("no link 9") != std::string::npos);
  CHECK(rp_link_get(s, -1, &l) == RP_ERR_BAD_INPUT);
  l.struct_size = 0;
  CHECK(rp_link_get(s, 0, &l) == RP_ERR_BAD_INPUT);
  CHECK(rp_link_get(s, 0, nullptr) == RP_ERR_NULL);
  CHECK(rp_link_get(nullptr, 0, &l) == RP_ERR_NULL);
  rp_cell_info c{};
  CHECK(rp_cell_info_get(s, &c) == RP_ERR_BAD_INPUT);  // struct_size 0
  // A host with an older, shorter struct gets its own fields only.
  c.struct_size = sizeof(unsigned) + sizeof(int);
  CHECK(rp_cell_info_get(s, &c) == RP_OK);
  CHECK(c.joint_count == 9);
  CHECK(c.T_B_0[0] == 0.0);
  REQUIRE(rp_close(s) == RP_OK);
  rp_free(s);
}

TEST_CASE("abi.cell: the modified-DH Caro cell, its spindle transform and tool frame",
          "[abi][cell]") {
  const std::string dir = redpost::test::fresh_temp_dir("redpost_abi_cell", "caro");
  const std::string cell = kSource + "/definitions/cells/caro2014_kr270_table.xml";
  const std::string cl = kSource + "/examples/placement/caro2014_contour.apt";
  // The best placement of docs/placement.md's Case 1.
  rp_session* s = open_placed(cell, dir, "CARO", {-300.0, -1640.0, 536.0, -178.2, 0.0, 0.0});
  const Model m = read_model(s);
  REQUIRE(m.cell.joint_count == 7);
  CHECK(m.links[0].modified_dh == 1);
  CHECK(m.cell.T_B_0[11] == 750.0);                             // <base z="750">
  CHECK(std::fabs(m.links[6].T_prev_link[11] - 684.0) < 1e-9);  // the spindle, Caro eq. 2.9
  CHECK(m.cell.coupled_base_joint == -1);
  std::vector<rp_motion> motions;
  REQUIRE(rp_set_motion_observer(s, record, &motions) == RP_OK);
  rp_reader* r = nullptr;
  REQUIRE(rp_reader_open(cl.c_str(), 0.01, &r) == RP_OK);
  rp_event e;
  int more = 1;
  while (rp_reader_next(r, &e, &more) == RP_OK && more)
    REQUIRE(rp_session_event(s, &e) == RP_OK);
  rp_reader_free(r);
  REQUIRE(rp_prepare(s) == RP_OK);
  REQUIRE(motions.size() > 50);
  CHECK(worst_fk_error(m, motions) < 1e-6);
  REQUIRE(rp_close(s) == RP_OK);
  rp_free(s);
}
