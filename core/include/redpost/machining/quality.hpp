// The machining-quality criterion of Caro 2014 section 5.1 (issue 8).
#pragma once

#include <cmath>
#include <cstddef>

#include <Eigen/Core>

#include "redpost/io/error.hpp"

namespace redpost {

// Eq. 5.1: c_i = | dd_i . (z_7 x x_Pi) |, the tool displacement normal to both the feed x_Pi
// and the tool axis z_7 (unit vectors), all in the same frame. dd_i is the position part of the
// displacement screw of eq. 5.2 (elastostatic.hpp: tcp_displacement(...).tail<3>()). mm.
inline double normal_tool_deflection_mm(const Eigen::Vector3d& dd_mm, const Eigen::Vector3d& z7,
                                        const Eigen::Vector3d& x_feed) {
  return std::abs(dd_mm.dot(z7.cross(x_feed)));
}

// Eq. 5.3: f_MQC, the mean of the c_i over the n points of the tool path. mm. Throws
// Error(bad_input) for an empty path, since the mean of nothing is not a quality.
inline double machining_quality_criterion_mm(const double* c_mm, std::size_t n) {
  if (n == 0)
    throw Error(ErrorCode::bad_input,
                "machining quality criterion (Caro eq. 5.3): the tool path has no points");
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    sum += c_mm[i];
  return sum / static_cast<double>(n);
}

}  // namespace redpost
