// The machining-quality criterion of Caro 2014 section 5.1 (issue 8).
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace redpost {

// Eq. 5.1: c_i = | dd_i . (z_7 x x_Pi) |, the tool displacement normal to both the feed x_Pi
// and the tool axis z_7, all in the same frame. mm.
inline double normal_tool_deflection_mm(const Eigen::Vector3d& dd_mm, const Eigen::Vector3d& z7,
                                        const Eigen::Vector3d& x_feed) {
  return std::abs(dd_mm.dot(z7.cross(x_feed)));
}

}  // namespace redpost
