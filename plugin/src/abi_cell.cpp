// The C ABI's view of the session's cell model (redpost.h, "The cell's model"): what a host needs
// to draw the cell from its DH chain and to redo its forward kinematics (the report's 3D view).
#include <cstring>
#include <string>

#include "abi_internal.hpp"
#include "redpost.h"
#include "redpost/kinematics/cell.hpp"

using namespace redpost::abi;

namespace {

// Row-major 3x4: the layout of every transform in redpost.h.
void copy_transform(const redpost::Isometry& T, double out[12]) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c)
      out[4 * r + c] = T.linear()(r, c);
    out[4 * r + 3] = T.translation()(r);
  }
}

rp_joint_type joint_type_of(redpost::JointType type) {
  switch (type) {
    case redpost::JointType::prismatic:
      return RP_JOINT_PRISMATIC;
    case redpost::JointType::virtual_spin:
      return RP_JOINT_VIRTUAL;
    case redpost::JointType::revolute:
      break;
  }
  return RP_JOINT_REVOLUTE;
}

}  // namespace

extern "C" {

RP_API rp_status rp_cell_info_get(const rp_session* session, rp_cell_info* info) {
  if (!session)
    return null_handle("the session");
  return guard(session->error, "", [&] {
    if (!info)
      throw AbiError{RP_ERR_NULL, "rp_cell_info_get: info is NULL"};
    check_struct_size(info, "rp_cell_info_get", "rp_cell_info");
    const redpost::Cell& c = session->cell;
    rp_cell_info out;
    std::memset(&out, 0, sizeof out);
    out.joint_count = c.size();
    copy_transform(c.T_B_0, out.T_B_0);
    copy_transform(c.T_last_tcp, out.T_last_tcp);
    copy_transform(session->T_B_part, out.T_B_part);
    out.reference_tool_length_mm = c.tools.reference_length_mm;
    out.coupled_base_joint = c.controller.coupled_base_joint;
    out.robroot_joint = c.controller.robroot_joint;
    copy_sized(info, out);
  });
}

RP_API rp_status rp_link_get(const rp_session* session, int index, rp_link_info* info) {
  if (!session)
    return null_handle("the session");
  return guard(session->error, "", [&] {
    if (!info)
      throw AbiError{RP_ERR_NULL, "rp_link_get: info is NULL"};
    check_struct_size(info, "rp_link_get", "rp_link_info");
    const redpost::Cell& c = session->cell;
    if (index < 0 || index >= c.size()) {
      throw AbiError{RP_ERR_BAD_INPUT, "rp_link_get: no link " + std::to_string(index) +
                                           " (the cell has " + std::to_string(c.size()) + ")"};
    }
    const redpost::Joint& j = c.joint(index);
    rp_link_info out;
    std::memset(&out, 0, sizeof out);
    out.name = j.name.c_str();
    out.axis_name = static_axis_name(j.axis);
    out.type = joint_type_of(j.type);
    out.modified_dh = j.convention == redpost::DhConvention::modified ? 1 : 0;
    out.alpha_rad = j.alpha_rad;
    out.a_mm = j.a_mm;
    out.theta_rad = j.theta_rad;
    out.d_mm = j.d_mm;
    copy_transform(j.T_prev_link, out.T_prev_link);
    out.lower = j.lower;
    out.upper = j.upper;
    if (j.axis.mapped()) {
      out.axis_sign = j.axis.sign;
      out.axis_offset = j.axis.offset;
    }
    copy_sized(info, out);
  });
}

}  // extern "C"
