// KUKA A, B, C orientation angles (KRL): R = Rz(A) * Ry(B) * Rx(C), degrees.
//
// A is about Z, B about the new Y, C about the new X (intrinsic Z-Y'-X''). See
// shared/PARAMETERS.md section 3 and docs/conventions.md.
#pragma once

#include <Eigen/Core>

#include "redpost/kinematics/types.hpp"

namespace redpost {

struct KukaAbc {
  double a_deg = 0.0;
  double b_deg = 0.0;
  double c_deg = 0.0;
};

Eigen::Matrix3d rotation_from_abc(const KukaAbc& abc);

// The inverse, with A, C in (-180, 180] and B in [-90, 90]. At B = +-90 deg only A - C (or
// A + C) is defined; C is then set to 0, as the KUKA controller shows it.
KukaAbc abc_from_rotation(const Eigen::Matrix3d& R);

// A frame from KRL-style X, Y, Z (mm) and A, B, C (deg).
Isometry frame_from_xyzabc(double x_mm, double y_mm, double z_mm, const KukaAbc& abc);

}  // namespace redpost
