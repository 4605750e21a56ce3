#include "redpost/machining/deflection.hpp"

#include <cmath>

#include <Eigen/Geometry>

namespace redpost {

bool cutting_load(const MillingConditions& c, const Eigen::Vector3d& z_tool_B,
                  const Eigen::Vector3d& feed_B, CuttingLoad& load) {
  load = CuttingLoad{};
  const double feed_len = feed_B.norm();
  const Eigen::Vector3d z = z_tool_B.normalized();
  if (!(feed_len > 1e-12) || !z.allFinite())
    return false;
  // F_P of Caro Figure 3.1: x the feed across the tool axis, z the tool axis towards the robot
  // (the spindle), y = z x x.
  const Eigen::Vector3d across = feed_B - feed_B.dot(z) * z;
  if (!(across.norm() > kPlungeSine * feed_len))
    return false;
  const Eigen::Vector3d x = across.normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R_B_P;
  R_B_P << x, y, z;
  // The mean force of eq. 3.3 is the tool's on the workpiece; the tool receives the opposite.
  const Eigen::Vector3d f_B = -(R_B_P * mean_cutting_force_N(c));
  // The edges cut over the depth ap from the tip: the resultant acts at its middle.
  const Eigen::Vector3d r_B = (0.5 * c.ap_mm) * z;
  load.w_on_tcp.head<3>() = r_B.cross(f_B);
  load.w_on_tcp.tail<3>() = f_B;
  load.n_material_B = static_cast<double>(c.material_side) * y;
  load.force_N = f_B.norm();
  return true;
}

ToolDeflection tool_deflection(const Cell& cell, const KinematicsData& data,
                               const CuttingLoad& load, const ElastostaticOptions& options) {
  const Vector6d dX = tcp_displacement(cell, data, load.w_on_tcp, options);
  ToolDeflection d;
  d.rotation_rad = dX.head<3>();
  d.translation_mm = dX.tail<3>();
  d.normal_mm = d.translation_mm.dot(load.n_material_B);
  return d;
}

}  // namespace redpost
