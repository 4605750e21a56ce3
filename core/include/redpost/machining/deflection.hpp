// The tool's deflection along a program (issue 20): the mean cutting force of a move
// (cutting_force.hpp) as a wrench on the tool, and the elastostatic displacement it causes at the
// posture the program uses (elastostatic.hpp, Caro 2014 eq. 4.1). docs/deflection.md.
#pragma once

#include <Eigen/Core>

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/machining/cutting_force.hpp"
#include "redpost/machining/elastostatic.hpp"

namespace redpost {

// A cutting move's load, in {B}.
struct CuttingLoad {
  Vector6d w_on_tcp = Vector6d::Zero();  // [m; f] on the tool at the TCP (N mm, N)
  // The machined wall's normal, pointing into the material: the direction of Caro's c_i (eq. 5.1,
  // z7 x x_P up to its sign). A deflection along it cuts too deep.
  Eigen::Vector3d n_material_B = Eigen::Vector3d::Zero();
  double force_N = 0.0;  // |f|
};

// A feed that runs within this angle's sine of the tool axis is a plunge (or a retract): the
// side-milling force model of eq. 3.1 does not describe it, and no F_P frame exists.
inline constexpr double kPlungeSine = 0.1;  // 5.7 deg

// The load of a move fed along `feed_B` with the tool axis `z_tool_B` (from the tip towards the
// spindle; both in {B}, any length): F_P has x along the feed's part across the tool axis and z
// along the tool axis (Caro Figure 3.1); the tool receives the opposite of the mean force on the
// workpiece, acting on the cutting edge's middle, ap/2 up the tool from the tip. False (and no
// load) for a plunge or a move of no length.
bool cutting_load(const MillingConditions& c, const Eigen::Vector3d& z_tool_B,
                  const Eigen::Vector3d& feed_B, CuttingLoad& load);

struct ToolDeflection {
  Eigen::Vector3d translation_mm = Eigen::Vector3d::Zero();  // of the TCP, in {B}
  Eigen::Vector3d rotation_rad = Eigen::Vector3d::Zero();    // small rotation vector, in {B}
  double normal_mm = 0.0;  // translation . n_material_B: + the tool cuts too deep
};

// The deflection under `load` at the posture of `data` (forward_kinematics of the cell at q):
// eq. 4.1 with the compliant joints of the cell. No allocation.
ToolDeflection tool_deflection(const Cell& cell, const KinematicsData& data,
                               const CuttingLoad& load, const ElastostaticOptions& options = {});

}  // namespace redpost
