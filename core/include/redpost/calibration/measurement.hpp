// The measurement model of the calibration (issue 7; Andres et al. 2011 Section 3, eq. 1): the
// laser beam is the TCP's -z axis from the TCP origin; the reading is the signed distance along
// the beam to the plane x, y or z = offset of {B}. docs/calibration.md.
#pragma once

#include <array>

#include "redpost/kinematics/types.hpp"

namespace redpost {

enum class PlaneAxis { x = 0, y = 1, z = 2 };

const char* to_string(PlaneAxis plane);

struct MeasurementModel {
  // Plane k is {p in {B} : p_k = plane_offset_mm[k]}.
  std::array<double, 3> plane_offset_mm{0.0, 0.0, 0.0};
  // A beam whose angle to the plane's normal has a cosine below this is refused as (nearly)
  // parallel to the plane: the reading would be meaningless. 0.1 is 84.3 deg from the normal.
  double min_incidence_cos = 0.1;
  // false: the exact ray-plane intersection (the default). true: the paper's approximation,
  // the reading equals the TCP's distance from the plane, signed positive on the side the beam
  // points away from (exact when the beam is perpendicular to the plane).
  bool approximate = false;
};

// The reading for a TCP pose in {B}: the signed distance d from the TCP origin p along the beam
// u = -z_tcp to the plane, positive when the plane lies beyond the TCP: p + d u on the plane,
// d = (offset - p_k) / u_k. Throws Error(bad_input) when |u_k| < min_incidence_cos.
double laser_reading(const Isometry& T_B_tcp, PlaneAxis plane, const MeasurementModel& model = {});

}  // namespace redpost
