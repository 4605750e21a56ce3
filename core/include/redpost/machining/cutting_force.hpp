// Mean milling forces of Tlusty and MacNeil (1975) as Caro 2014 section 3.2, eqs. 3.1-3.4
// (issue 8). docs/placement.md gives the derivation, the engagement angles and the coefficients.
//
// Frame of the result, F_P (Caro Figure 3.1): x along the feed, z along the tool axis pointing
// towards the robot (away from the workpiece), y = z x x. Forces in N.
//
// Angle convention (Altintas's, PARAMETERS.md section 4, extended to both spindle senses): phi
// is the tooth's angle measured in the tool's sense of rotation from the axis s*y of F_P, where
// s = spindle_sense(c) is +1 when the tool turns clockwise seen from the robot (about -z, M3)
// and -1 when it turns the other way (M4). The tooth then sits at (sin phi, s cos phi, 0) * R,
// the chip is fz sin(phi) thick, and the engagement angles lie in [0, pi] whatever s is:
//   up-milling   phi_in = 0,                      phi_out = arccos(1 - ae/R)
//   down-milling phi_in = pi - arccos(1 - ae/R),  phi_out = pi
// Slotting (ae = D) is 0 -> pi in both modes.
//
// The model has no axial force: the z component of every force here is zero.
#pragma once

#include <Eigen/Core>

namespace redpost {

enum class MillingMode { up, down };

struct MillingConditions {
  double tool_diameter_mm = 20.0;
  int teeth = 4;
  double fz_mm = 0.05;        // feed per tooth
  double ap_mm = 5.0;         // axial depth of cut
  double ae_mm = 10.0;        // radial width of cut, 0 < ae <= diameter
  double Kt_N_per_mm2 = 0.0;  // specific tangential cutting pressure
  double Kr = 0.0;            // radial / tangential force ratio (dimensionless), eq. 3.1
  MillingMode mode = MillingMode::down;
  // Which side of the feed the material lies on (Caro Figure 3.3): +1 the material is on the
  // +y side of F_P, -1 on the -y side. With mode, it fixes the spindle's sense of rotation
  // (spindle_sense) and therefore the sign of the y force; the engagement angles depend on mode
  // and ae only.
  int material_side = 1;
};

// Coefficients for Al7075-T6 (PARAMETERS.md section 4, CJME 2021 Table 5, first Al7075-T6 row):
// Ktc = 767.01 N/mm^2, Krc = 168.8 N/mm^2, so Kr = Krc / Ktc. The edge coefficients (Kte, Kre)
// have no place in the Tlusty-MacNeil model of eq. 3.1 and are dropped. Caro does not print the
// coefficients of their aluminium alloy.
inline constexpr double kAl7075T6_Kt_N_per_mm2 = 767.01;
inline constexpr double kAl7075T6_Kr = 168.8 / 767.01;

// The cutting conditions of Caro 2014 Table 3.1: 4 teeth, fz = 0.05 mm, ap = 5 mm (20000 rpm,
// so the feed is 20000 * 4 * 0.05 = 4000 mm/min, the 4 m/min of the table), with the Al7075-T6
// coefficients above and the width of cut ae that the table leaves to vary. The paper gives no
// tool diameter: 20 mm is our choice (docs/placement.md).
MillingConditions caro2014_milling_conditions(double ae_mm, MillingMode mode = MillingMode::down,
                                              int material_side = 1);

// Throws Error(bad_input) on non-finite, non-positive or inconsistent values (ae > diameter,
// material_side not +-1).
void validate(const MillingConditions& c);

struct EngagementAngles {
  double phi_in_rad = 0.0;   // tooth enters the material
  double phi_out_rad = 0.0;  // tooth leaves it
};

EngagementAngles engagement_angles(const MillingConditions& c);

// +1 when the tool turns clockwise seen from the robot (about -z of F_P, M3), -1 otherwise:
// up-milling with the material on +y and down-milling with it on -y need the clockwise sense.
int spindle_sense(const MillingConditions& c);

// The force one tooth at rotation angle phi exerts on the WORKPIECE, in F_P (zero outside the
// engagement): eq. 3.1 with chip thickness fz sin(phi), projected as the integrand of eq. 3.2.
// phi is taken modulo 2 pi.
Eigen::Vector3d tooth_force_N(const MillingConditions& c, double phi_rad);

// The mean force of the whole tool on the WORKPIECE over one revolution, in F_P: the closed-form
// integral of eq. 3.3 over [phi_in, phi_out], times teeth / (2 pi). The robot's spindle receives
// the opposite. Calls validate().
Eigen::Vector3d mean_cutting_force_N(const MillingConditions& c);

}  // namespace redpost
