// Mean milling forces of Tlusty and MacNeil (1975) as Caro 2014 section 3.2, eqs. 3.1-3.4
// (issue 8). docs/placement.md gives the derivation, the engagement angles and the coefficients.
//
// Frame of the result, F_P (Caro Figure 3.1): x along the feed, z along the tool axis pointing
// towards the robot (away from the workpiece), y = z x x. Forces in N.
#pragma once

#include <Eigen/Core>

namespace redpost {

enum class MillingMode { up, down };

struct MillingConditions {
  double tool_diameter_mm = 20.0;
  int teeth = 4;
  double fz_mm = 0.05;  // feed per tooth
  double ap_mm = 5.0;   // axial depth of cut
  double ae_mm = 10.0;  // radial width of cut, 0 < ae <= diameter
  double Kt_N_per_mm2 = 0.0;  // specific tangential cutting pressure
  double Kr = 0.0;            // radial / tangential force ratio (dimensionless)
  MillingMode mode = MillingMode::down;
  // Which side of the feed the material lies on (Caro Figure 3.3): +1 the material is on the
  // +y side of F_P, -1 on the -y side. With mode, it fixes the engagement angles' sign.
  int material_side = 1;
};

struct EngagementAngles {
  double phi_in_rad = 0.0;   // tooth enters the material
  double phi_out_rad = 0.0;  // tooth leaves it
};

// Throws Error(bad_input) on non-finite, non-positive or inconsistent values (ae > diameter).
void validate(const MillingConditions& c);

EngagementAngles engagement_angles(const MillingConditions& c);

// The force one tooth at rotation angle phi exerts on the WORKPIECE, in F_P (zero outside the
// engagement): eq. 3.1 with chip thickness fz sin(phi).
Eigen::Vector3d tooth_force_N(const MillingConditions& c, double phi_rad);

// The mean force of the whole tool on the WORKPIECE over one revolution, in F_P: eqs. 3.2-3.3
// (closed form) summed over the teeth. The robot's spindle receives the opposite.
Eigen::Vector3d mean_cutting_force_N(const MillingConditions& c);

}  // namespace redpost
