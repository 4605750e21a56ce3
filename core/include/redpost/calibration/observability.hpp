// What the calibration's readings can see (issue 7; Andres et al. 2011 Section 3, eq. 8): the
// observation matrix W of the readings with respect to the parameters, by automatic
// differentiation, and the parameter combinations it leaves unobservable. docs/calibration.md.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "redpost/calibration/measurement.hpp"
#include "redpost/calibration/parameters.hpp"
#include "redpost/calibration/plan.hpp"
#include "redpost/kinematics/cell.hpp"

namespace redpost {

// A direction of the parameter space the data cannot see.
struct UnobservableCombination {
  std::vector<std::string> parameters;  // the parameters involved
  Eigen::VectorXd direction;            // unit direction in column-scaled coordinates
  std::string description;  // "link1.theta is not observable" / "link1.d and link2.d cannot
                            // be separated"
};

struct ObservabilityReport {
  Eigen::VectorXd singular_values;  // of the column-scaled W, descending
  double condition_number = 0.0;    // sigma_max / sigma_min (inf when rank-deficient)
  int rank = 0;
  bool rank_deficient() const { return rank < singular_values.size(); }
  std::vector<UnobservableCombination> unobservable;
  std::string summary() const;  // the descriptions joined by "; "
};

// W (eq. 8, np x mp) at the given parameter values: d reading_i / d beta_j, by automatic
// differentiation. `predicted` (optional) receives the model's readings.
Eigen::MatrixXd observation_matrix(const Cell& cell,
                                   const std::vector<CalibrationParameter>& params,
                                   const Eigen::VectorXd& values,
                                   const std::vector<CalibrationPoint>& points,
                                   const MeasurementModel& model = {},
                                   Eigen::VectorXd* predicted = nullptr);

// Singular values, rank and the unobservable combinations of W, columns scaled to unit norm.
ObservabilityReport analyse_observability(const Eigen::MatrixXd& W,
                                          const std::vector<CalibrationParameter>& params,
                                          double rank_tolerance = 1e-6);

}  // namespace redpost
