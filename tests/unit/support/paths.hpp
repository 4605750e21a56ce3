// Seeded test paths for the tracker, shared by the unit tests and the benchmarks.
#pragma once

#include <cmath>
#include <vector>

#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/redundancy/task_error.hpp"

namespace redpost::test {

// A zigzag raster in the tool plane of the cell's home posture, centred on the home TCP:
// lines `width_mm` long along the home TCP x axis, `stepover_mm` apart along its y axis, points
// `spacing_mm` apart. The tool axis tilts smoothly by up to `max_tilt_deg` about both in-plane
// axes. Stops after `count` poses.
inline std::vector<TcpTarget> raster_in_tool_plane(const Cell& cell, double width_mm,
                                                   double height_mm, double spacing_mm,
                                                   double stepover_mm, double max_tilt_deg,
                                                   size_t count) {
  const Isometry T0 = tcp_pose(cell, cell.home());
  const Eigen::Vector3d p0 = T0.translation();
  const Eigen::Vector3d x0 = T0.linear().col(0), y0 = T0.linear().col(1), z0 = T0.linear().col(2);
  const int per_line = static_cast<int>(std::lround(width_mm / spacing_mm)) + 1;
  const int lines = static_cast<int>(std::lround(height_mm / stepover_mm)) + 1;
  const double tilt = max_tilt_deg * kPi / 180.0;
  std::vector<TcpTarget> out;
  out.reserve(count);
  for (int line = 0; out.size() < count; ++line) {
    const int l = line % (2 * lines);  // back and forth over the square
    const double v = (l < lines ? l : 2 * lines - 1 - l) * stepover_mm - 0.5 * height_mm;
    for (int k = 0; k < per_line && out.size() < count; ++k) {
      const int idx = line % 2 == 0 ? k : per_line - 1 - k;
      const double u = idx * spacing_mm - 0.5 * width_mm;
      const double a = tilt * std::sin(0.5 * kPi * u / (0.5 * width_mm));
      const double b = tilt * std::sin(0.5 * kPi * v / (0.5 * height_mm));
      // Tilt about y0 and x0 by a/sqrt2 and b/sqrt2: the combined tilt is at most the maximum.
      const Eigen::Vector3d z =
          (Eigen::AngleAxisd(a / std::sqrt(2.0), y0) * Eigen::AngleAxisd(b / std::sqrt(2.0), x0)) *
          z0;
      out.push_back(TcpTarget::axis(p0 + u * x0 + v * y0, z));
    }
  }
  return out;
}

// A straight pass from the home TCP along direction `d_B` (unit) over `length_mm`, tool axis
// as at home, points `spacing_mm` apart.
inline std::vector<TcpTarget> straight_pass(const Cell& cell, const Eigen::Vector3d& d_B,
                                            double length_mm, double spacing_mm) {
  const Isometry T0 = tcp_pose(cell, cell.home());
  std::vector<TcpTarget> out;
  const int n = static_cast<int>(std::lround(length_mm / spacing_mm));
  for (int k = 0; k <= n; ++k) {
    out.push_back(TcpTarget::axis(T0.translation() + (k * spacing_mm) * d_B, T0.linear().col(2)));
  }
  return out;
}

}  // namespace redpost::test
