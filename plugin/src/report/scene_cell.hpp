// The cell as the reports' 3D view draws it (redpost/report/scene3d.hpp), from either side of the
// product boundary: the C ABI's model of a session (convert, like any host) or a Cell loaded by
// the command itself (place).
#pragma once

#include "redpost.h"
#include "redpost/kinematics/cell.hpp"
#include "redpost/report/scene3d.hpp"

namespace redpost::run_report {

// A rigid transform as the page's 3 x 4 rows.
report::Transform34 from_isometry(const Isometry& T);

// Through rp_cell_info_get and rp_link_get. Throws Error when the ABI refuses.
report::SceneCell scene_cell_of(const rp_session* session);

// The loaded cell with the workpiece frame at T_B_part in {B}.
report::SceneCell scene_cell_of(const Cell& cell, const Isometry& T_B_part);

// The joint closest to one of its limits at q, as a share of its range (%), virtual joints left
// out: the 3D view's "closest joint limit". NaN and -1 for a chain without limits.
struct LimitMargin {
  double percent;
  int joint;
};
LimitMargin closest_limit(const Cell& cell, const JointVector& q);

// The first joints that carry the workpiece: those up to the turntable that carries the base
// (<controller><kinematic type="base">), none without one.
int positioner_joints(int coupled_base_joint);

}  // namespace redpost::run_report
