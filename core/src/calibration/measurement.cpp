// The laser reading of the calibration's measurement model (measurement.hpp).
// docs/calibration.md.
#include "redpost/calibration/measurement.hpp"

#include <cmath>
#include <sstream>

#include "calibration/fail.hpp"
#include "calibration/reading_model.hpp"

namespace redpost {

namespace detail {

void check_incidence(double u_k, PlaneAxis plane, const MeasurementModel& model) {
  if (!(std::abs(u_k) >= model.min_incidence_cos)) {
    std::ostringstream m;
    m << "the laser beam is nearly parallel to the plane " << to_string(plane) << " = "
      << model.plane_offset_mm[static_cast<size_t>(plane)] << " (cosine to its normal "
      << std::abs(u_k) << " < " << model.min_incidence_cos << "): no reading";
    fail_bad_input(m.str());
  }
}

}  // namespace detail

const char* to_string(PlaneAxis plane) {
  switch (plane) {
    case PlaneAxis::x:
      return "x";
    case PlaneAxis::y:
      return "y";
    case PlaneAxis::z:
      return "z";
  }
  return "?";
}

double laser_reading(const Isometry& T_B_tcp, PlaneAxis plane, const MeasurementModel& model) {
  const Eigen::Matrix3d R = T_B_tcp.linear();
  const Eigen::Vector3d t = T_B_tcp.translation();
  detail::check_incidence(-R(static_cast<int>(plane), 2), plane, model);
  return detail::reading_of<double>(R, t, plane, model);
}

}  // namespace redpost
