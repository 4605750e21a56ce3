// The validation of a calibration (issue 7; Andres et al. 2011 Section 3.3): random commanded
// points on one plane with random external joints, and the statistics of the distances the
// nominal and the calibrated models leave. docs/calibration.md.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "redpost/calibration/measurement.hpp"
#include "redpost/calibration/plan.hpp"
#include "redpost/kinematics/cell.hpp"

namespace redpost {

struct ValidationPlanOptions {
  int points = 96;
  PlaneAxis plane = PlaneAxis::z;
  // Chain indices of the external joints; empty: external_joint_indices(cell).
  std::vector<int> external_joints;
  // Per external joint, the range its random value is drawn from (DH units), clipped to the
  // joint's limits. Empty: the paper's theta_M in [0, pi], d_L in [0, 1000] mm for a revolute
  // and a prismatic joint, else the joint's limits.
  std::vector<std::pair<double, double>> ranges;
  double half_width_mm = 200.0;  // in-plane coordinates uniform in [-w, w]
  double z_min_mm = 150.0;       // height range on the x and y planes
  double z_max_mm = 450.0;
  double stand_off_mm = 0.0;
  MeasurementModel model;
  int perturbed_starts = 24;
  std::uint64_t seed = 7;
};

// Random commanded points on one plane with random external joints (seeded), the arm solved on
// the nominal model, as the paper's 96 validation points. Each point is its own configuration.
std::vector<CalibrationPoint> plan_validation(const Cell& nominal,
                                              const ValidationPlanOptions& options = {});

// Mean, RMS and standard deviation of a set of distances (mm), as the paper's section 3.3.
struct DistanceStatistics {
  int count = 0;
  double mean_mm = 0.0;
  double rms_mm = 0.0;
  double std_mm = 0.0;  // sample standard deviation (n - 1)
  double max_abs_mm = 0.0;
};

DistanceStatistics distance_statistics(const Eigen::VectorXd& distances_mm);

// The validation of a calibration on readings taken with the NOMINAL model (the commanded
// points on their planes): "before" is what the laser saw against what the nominal model
// predicts; "after" is what it saw against what the calibrated model predicts at the same
// joints, that is the error a controller using the calibrated model would leave, to first order.
struct ValidationResult {
  Eigen::VectorXd before_mm;  // reading - nominal model's reading
  Eigen::VectorXd after_mm;   // reading - calibrated model's reading
  DistanceStatistics before;
  DistanceStatistics after;
};

ValidationResult validate_calibration(const Cell& nominal, const Cell& calibrated,
                                      const std::vector<CalibrationPoint>& points,
                                      const MeasurementModel& model = {});

}  // namespace redpost
