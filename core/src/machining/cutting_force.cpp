#include "redpost/machining/cutting_force.hpp"

#include <cmath>
#include <string>

#include "redpost/io/error.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost {

namespace {

[[noreturn]] void bad(const std::string& what) {
  throw Error(ErrorCode::bad_input, "milling conditions: " + what);
}

void require_positive(double v, const char* name) {
  if (!std::isfinite(v) || !(v > 0.0))
    bad(std::string(name) + " must be a finite value > 0 (got " + std::to_string(v) + ")");
}

// Antiderivatives of the eq. 3.2 integrands per unit Kt ap fz (the terms of eq. 3.3):
//   x: sin(phi) cos(phi) + Kr sin^2(phi)   ->  -cos(2 phi)/4 + Kr (phi/2 - sin(2 phi)/4)
//   y: -sin^2(phi) + Kr sin(phi) cos(phi)  ->  -(phi/2 - sin(2 phi)/4) - Kr cos(2 phi)/4
double primitive_x(double phi, double Kr) {
  return -std::cos(2.0 * phi) / 4.0 + Kr * (phi / 2.0 - std::sin(2.0 * phi) / 4.0);
}
double primitive_y(double phi, double Kr) {
  return std::sin(2.0 * phi) / 4.0 - phi / 2.0 - Kr * std::cos(2.0 * phi) / 4.0;
}

}  // namespace

MillingConditions caro2014_milling_conditions(double ae_mm, MillingMode mode, int material_side) {
  MillingConditions c;
  c.tool_diameter_mm = 20.0;
  c.teeth = 4;
  c.fz_mm = 0.05;
  c.ap_mm = 5.0;
  c.ae_mm = ae_mm;
  c.Kt_N_per_mm2 = kAl7075T6_Kt_N_per_mm2;
  c.Kr = kAl7075T6_Kr;
  c.mode = mode;
  c.material_side = material_side;
  return c;
}

void validate(const MillingConditions& c) {
  require_positive(c.tool_diameter_mm, "tool_diameter_mm");
  if (c.teeth < 1)
    bad("teeth must be >= 1 (got " + std::to_string(c.teeth) + ")");
  require_positive(c.fz_mm, "fz_mm (feed per tooth)");
  require_positive(c.ap_mm, "ap_mm (axial depth of cut)");
  require_positive(c.ae_mm, "ae_mm (radial width of cut)");
  if (c.ae_mm > c.tool_diameter_mm)
    bad("ae_mm = " + std::to_string(c.ae_mm) + " exceeds the tool diameter " +
        std::to_string(c.tool_diameter_mm) + " mm; use ae = diameter for slotting");
  require_positive(c.Kt_N_per_mm2, "Kt_N_per_mm2 (set the material's coefficients)");
  if (!std::isfinite(c.Kr) || c.Kr < 0.0)
    bad("Kr must be a finite ratio >= 0 (got " + std::to_string(c.Kr) + ")");
  if (c.mode != MillingMode::up && c.mode != MillingMode::down)
    bad("mode must be up or down");
  if (c.material_side != 1 && c.material_side != -1)
    bad("material_side must be +1 or -1 (got " + std::to_string(c.material_side) + ")");
}

EngagementAngles engagement_angles(const MillingConditions& c) {
  // The tooth is in the material over an arc of arccos(1 - ae/R) next to the y axis it starts
  // from (up-milling) or ends at (down-milling). The clamp only guards rounding at ae = D.
  const double R = 0.5 * c.tool_diameter_mm;
  const double arc = std::acos(std::fmax(-1.0, std::fmin(1.0, 1.0 - c.ae_mm / R)));
  EngagementAngles e;
  if (c.mode == MillingMode::up) {
    e.phi_in_rad = 0.0;
    e.phi_out_rad = arc;
  } else {
    e.phi_in_rad = kPi - arc;
    e.phi_out_rad = kPi;
  }
  return e;
}

int spindle_sense(const MillingConditions& c) {
  // Clockwise (s = +1): up-milling cuts the +y side (the tooth starts at phi = 0, on +y),
  // down-milling the -y side. The other sense mirrors F_P through its xz plane.
  const int up_side = c.mode == MillingMode::up ? 1 : -1;
  return up_side * c.material_side;
}

Eigen::Vector3d tooth_force_N(const MillingConditions& c, double phi_rad) {
  double phi = std::fmod(phi_rad, 2.0 * kPi);
  if (phi < 0.0)
    phi += 2.0 * kPi;
  const EngagementAngles e = engagement_angles(c);
  if (phi < e.phi_in_rad || phi > e.phi_out_rad)
    return Eigen::Vector3d::Zero();
  // Eq. 3.1: the tangential force opposes the tooth's velocity on the tool, so it drives the
  // workpiece along the tooth's velocity (cos phi, -s sin phi); the radial force pushes the
  // workpiece outwards along (sin phi, s cos phi). These are the integrands of eq. 3.2.
  const double Ft = c.Kt_N_per_mm2 * c.ap_mm * c.fz_mm * std::sin(phi);
  const double Fr = c.Kr * std::abs(Ft);
  const double s = spindle_sense(c);
  return {Ft * std::cos(phi) + Fr * std::sin(phi), s * (-Ft * std::sin(phi) + Fr * std::cos(phi)),
          0.0};
}

Eigen::Vector3d mean_cutting_force_N(const MillingConditions& c) {
  validate(c);
  const EngagementAngles e = engagement_angles(c);
  // Eq. 3.3 integrates phi_in -> phi_out (eq. 3.2 prints the bounds the other way round, which
  // would flip both signs; docs/placement.md). Z teeth, each engaged once per revolution.
  const double scale =
      c.Kt_N_per_mm2 * c.ap_mm * c.fz_mm * static_cast<double>(c.teeth) / (2.0 * kPi);
  const double Fx = primitive_x(e.phi_out_rad, c.Kr) - primitive_x(e.phi_in_rad, c.Kr);
  const double Fy = primitive_y(e.phi_out_rad, c.Kr) - primitive_y(e.phi_in_rad, c.Kr);
  return {scale * Fx, scale * spindle_sense(c) * Fy, 0.0};
}

}  // namespace redpost
