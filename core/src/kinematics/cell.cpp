#include "redpost/kinematics/cell.hpp"

#include <cmath>

#include "redpost/io/error.hpp"

namespace redpost {

std::string axis_name(const ControllerAxis& axis) {
  switch (axis.kind) {
    case AxisKind::arm:
      return "A" + std::to_string(axis.number);
    case AxisKind::external:
      return "E" + std::to_string(axis.number);
    case AxisKind::none:
      break;
  }
  return "none";
}

namespace {
template <class Get>
JointVector collect(const Cell& cell, Get get) {
  JointVector v(cell.size());
  for (int i = 0; i < cell.size(); ++i)
    v[i] = get(cell.joint(i));
  return v;
}
}  // namespace

JointVector Cell::home() const {
  return collect(*this, [](const Joint& j) { return j.home; });
}
JointVector Cell::lower_limits() const {
  return collect(*this, [](const Joint& j) { return j.lower; });
}
JointVector Cell::upper_limits() const {
  return collect(*this, [](const Joint& j) { return j.upper; });
}
JointVector Cell::weights() const {
  return collect(*this, [](const Joint& j) { return j.weight; });
}

int Cell::find_joint(const std::string& joint_name) const {
  for (int i = 0; i < joint_count; ++i) {
    if (joints[static_cast<size_t>(i)].name == joint_name)
      return i;
  }
  return -1;
}

bool Cell::has_axis_speeds() const {
  bool any = false;
  for (int i = 0; i < joint_count; ++i) {
    const Joint& j = joints[static_cast<size_t>(i)];
    if (j.type == JointType::virtual_spin)
      continue;
    if (!j.has_speed())
      return false;
    any = true;
  }
  return any;
}

void finalize_cell(Cell& cell) {
  if (cell.joint_count < 1 || cell.joint_count > kMaxJoints) {
    throw Error(ErrorCode::internal, "a cell needs 1.." + std::to_string(kMaxJoints) +
                                         " joints, this one has " +
                                         std::to_string(cell.joint_count));
  }
  for (int i = 0; i < cell.joint_count; ++i) {
    const Joint& j = cell.joint(i);
    auto& c = cell.link[static_cast<size_t>(i)];
    c.cos_alpha = std::cos(j.alpha_rad);
    c.sin_alpha = std::sin(j.alpha_rad);
    // 90 deg read from XML is pi/2 to the last bit; a tolerance of a few ulp catches it.
    using Twist = Cell::LinkConstants::Twist;
    c.twist = j.alpha_rad == 0.0                         ? Twist::zero
              : std::fabs(j.alpha_rad - kPi / 2) < 1e-15 ? Twist::plus_quarter
              : std::fabs(j.alpha_rad + kPi / 2) < 1e-15 ? Twist::minus_quarter
                                                         : Twist::general;
    c.cos_theta0 = std::cos(j.theta_rad);
    c.sin_theta0 = std::sin(j.theta_rad);
    if (!(j.lower <= j.upper) || !(j.home >= j.lower && j.home <= j.upper) || !(j.weight > 0.0) ||
        !std::isfinite(j.weight)) {
      throw Error(ErrorCode::internal, "joint '" + j.name + "' breaks the cell invariants");
    }
  }
  cell.has_tcp_frame = !cell.T_last_tcp.matrix().isIdentity(0.0);
  const ConditioningSpec& cs = cell.conditioning;
  if (cs.declared() && (cs.last < cs.first || cs.last >= cell.joint_count || cs.count() < 6 ||
                        !(cs.characteristic_length_mm > 0.0))) {
    throw Error(ErrorCode::internal, "the cell's conditioning block is inconsistent");
  }
}

bool within_limits(const Cell& cell, const JointVector& q, double tolerance) {
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    if (!(q[i] >= j.lower - tolerance && q[i] <= j.upper + tolerance))
      return false;
  }
  return true;
}

}  // namespace redpost
