// The laser reading of measurement.hpp as a function of the TCP frame, for any scalar type:
// laser_reading evaluates it in double, observation_matrix in automatic differentiation
// (internal to core; not installed).
#pragma once

#include <cstddef>

#include <Eigen/Core>

#include "redpost/calibration/measurement.hpp"

namespace redpost::detail {

// The reading for the TCP frame (R, t) in {B}; the incidence is checked by check_incidence.
template <class S>
S reading_of(const Eigen::Matrix<S, 3, 3>& R, const Eigen::Matrix<S, 3, 1>& t, PlaneAxis plane,
             const MeasurementModel& model) {
  const int k = static_cast<int>(plane);
  const S u_k = -R(k, 2);  // the beam is -z
  const S gap = S(model.plane_offset_mm[static_cast<size_t>(k)]) - t(k);
  if (model.approximate)
    return u_k < S(0) ? S(-gap) : gap;
  return gap / u_k;
}

// Throws Error(bad_input) when the beam component u_k along the plane's normal is below
// model.min_incidence_cos: the beam is (nearly) parallel to the plane, there is no reading.
void check_incidence(double u_k, PlaneAxis plane, const MeasurementModel& model);

}  // namespace redpost::detail
