#include "scene_cell.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "redpost/io/error.hpp"
#include "redpost/kinematics/controller_axes.hpp"

namespace redpost::run_report {

namespace {

report::Transform34 from_rows(const double* v) {
  report::Transform34 t;
  for (int i = 0; i < 12; ++i)
    t[static_cast<std::size_t>(i)] = v[i];
  return t;
}

}  // namespace

report::Transform34 from_isometry(const Isometry& T) {
  report::Transform34 t;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      t[static_cast<std::size_t>(4 * r + c)] = T.linear()(r, c);
    t[static_cast<std::size_t>(4 * r + 3)] = T.translation()(r);
  }
  return t;
}

LimitMargin closest_limit(const Cell& cell, const JointVector& q) {
  LimitMargin m{std::numeric_limits<double>::quiet_NaN(), -1};
  for (int j = 0; j < cell.size(); ++j) {
    const Joint& jt = cell.joint(j);
    if (jt.type == JointType::virtual_spin || !(jt.upper > jt.lower))
      continue;
    const double share = 100.0 * std::min(q[j] - jt.lower, jt.upper - q[j]) / (jt.upper - jt.lower);
    if (m.joint < 0 || share < m.percent)
      m = {share, j};
  }
  return m;
}

int positioner_joints(int coupled_base_joint) {
  return coupled_base_joint >= 0 ? coupled_base_joint + 1 : 0;
}

report::SceneCell scene_cell_of(const rp_session* session) {
  rp_cell_info info{};
  info.struct_size = sizeof info;
  if (rp_cell_info_get(session, &info) != RP_OK)
    throw Error(ErrorCode::internal, std::string("the cell's model: ") + rp_last_error(session));
  report::SceneCell c;
  c.T_B_0 = from_rows(info.T_B_0);
  c.T_last_tcp = from_rows(info.T_last_tcp);
  c.T_B_part = from_rows(info.T_B_part);
  c.reference_tool_length_mm = info.reference_tool_length_mm;
  c.positioner_joints = positioner_joints(info.coupled_base_joint);
  for (int i = 0; i < info.joint_count; ++i) {
    rp_link_info l{};
    l.struct_size = sizeof l;
    if (rp_link_get(session, i, &l) != RP_OK)
      throw Error(ErrorCode::internal, std::string("the cell's model: ") + rp_last_error(session));
    report::SceneLink s;
    s.name = l.name;
    s.axis = l.axis_name;
    s.type = l.type == RP_JOINT_PRISMATIC ? report::SceneLink::Type::prismatic
             : l.type == RP_JOINT_VIRTUAL ? report::SceneLink::Type::virtual_spin
                                          : report::SceneLink::Type::revolute;
    s.modified_dh = l.modified_dh != 0;
    s.alpha_rad = l.alpha_rad;
    s.a_mm = l.a_mm;
    s.theta_rad = l.theta_rad;
    s.d_mm = l.d_mm;
    s.T_prev_link = from_rows(l.T_prev_link);
    s.lower = l.lower;
    s.upper = l.upper;
    s.axis_sign = l.axis_sign;
    s.axis_offset = l.axis_offset;
    c.links.push_back(std::move(s));
  }
  return c;
}

report::SceneCell scene_cell_of(const Cell& cell, const Isometry& T_B_part) {
  report::SceneCell c;
  c.name = cell.name;
  c.T_B_0 = from_isometry(cell.T_B_0);
  c.T_last_tcp = from_isometry(cell.T_last_tcp);
  c.T_B_part = from_isometry(T_B_part);
  c.reference_tool_length_mm = cell.tools.reference_length_mm;
  c.positioner_joints = positioner_joints(cell.controller.coupled_base_joint);
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    report::SceneLink s;
    s.name = j.name;
    s.axis = axis_name(j.axis);
    s.type = j.type == JointType::prismatic      ? report::SceneLink::Type::prismatic
             : j.type == JointType::virtual_spin ? report::SceneLink::Type::virtual_spin
                                                 : report::SceneLink::Type::revolute;
    s.modified_dh = j.convention == DhConvention::modified;
    s.alpha_rad = j.alpha_rad;
    s.a_mm = j.a_mm;
    s.theta_rad = j.theta_rad;
    s.d_mm = j.d_mm;
    s.T_prev_link = from_isometry(j.T_prev_link);
    s.lower = j.lower;
    s.upper = j.upper;
    if (j.axis.mapped()) {
      s.axis_sign = j.axis.sign;
      s.axis_offset = j.axis.offset;
    }
    c.links.push_back(std::move(s));
  }
  return c;
}

}  // namespace redpost::run_report
