#include "redpost/kinematics/controller_axes.hpp"

#include <cmath>

#include "redpost/io/error.hpp"

namespace redpost {

namespace {
double to_controller_units(const Joint& j, double q) {
  return j.type == JointType::prismatic ? q : rad_to_deg(q);
}
double from_controller_units(const Joint& j, double v) {
  return j.type == JointType::prismatic ? v : deg_to_rad(v);
}
}  // namespace

double to_axis_value(const Joint& joint, double q) {
  return joint.axis.sign * to_controller_units(joint, q) + joint.axis.offset;
}

double from_axis_value(const Joint& joint, double axis_value) {
  return from_controller_units(joint, (axis_value - joint.axis.offset) / joint.axis.sign);
}

AxisValues to_controller_axes(const Cell& cell, const JointVector& q) {
  AxisValues out;
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    if (j.axis.kind == AxisKind::arm)
      out.arm(j.axis.number) = to_axis_value(j, q[i]);
    if (j.axis.kind == AxisKind::external)
      out.external(j.axis.number) = to_axis_value(j, q[i]);
  }
  return out;
}

JointVector from_controller_axes(const Cell& cell, const AxisValues& axes,
                                 const JointVector& unmapped) {
  JointVector q(cell.size());
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    if (!j.axis.mapped()) {
      q[i] = unmapped[i];
      continue;
    }
    const double v =
        j.axis.kind == AxisKind::arm ? axes.arm(j.axis.number) : axes.external(j.axis.number);
    if (!std::isfinite(v)) {
      throw Error(ErrorCode::bad_input, "no finite value for controller axis " + axis_name(j.axis) +
                                            " of joint '" + j.name + "'");
    }
    q[i] = from_axis_value(j, v);
  }
  return q;
}

}  // namespace redpost
