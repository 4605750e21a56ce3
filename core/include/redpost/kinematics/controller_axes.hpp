// Mapping between DH joint values and controller axes (A1..A6, E1..E6).
//
// value = sign * q + offset, with q in deg for revolute joints and mm for prismatic ones
// (docs/cell-format.md). Virtual joints have no controller axis.
#pragma once

#include <array>
#include <limits>

#include "redpost/kinematics/cell.hpp"

namespace redpost {

// Controller axis values, indexed A1..A6 then E1..E6 (index 0..11). Unmapped entries are NaN.
struct AxisValues {
  std::array<double, 12> value;
  AxisValues() { value.fill(std::numeric_limits<double>::quiet_NaN()); }
  double& arm(int n) { return value[static_cast<size_t>(n - 1)]; }
  double& external(int n) { return value[static_cast<size_t>(6 + n - 1)]; }
  double arm(int n) const { return value[static_cast<size_t>(n - 1)]; }
  double external(int n) const { return value[static_cast<size_t>(6 + n - 1)]; }
};

// DH value of one joint (rad or mm) -> its value in controller units (deg or mm), and back. A
// joint without a controller axis (the virtual joint) converts with sign +1 and offset 0, so
// its "axis units" are plain degrees.
double to_axis_value(const Joint& joint, double q);
double from_axis_value(const Joint& joint, double axis_value);

// Every mapped joint's controller value.
AxisValues to_controller_axes(const Cell& cell, const JointVector& q);

// The DH joint vector from controller values. Joints without a controller axis take their value
// from `unmapped` (chain order, DH units). Throws Error(bad_input) if a mapped axis is NaN.
JointVector from_controller_axes(const Cell& cell, const AxisValues& axes,
                                 const JointVector& unmapped);

}  // namespace redpost
