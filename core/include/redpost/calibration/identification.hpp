// The identification of the calibration (issue 7; Andres et al. 2011 Section 3, eqs. 5-10):
// Gauss-Newton on eqs. 8-9 with a Levenberg-Marquardt safeguard, the Jacobian by automatic
// differentiation (observability.hpp), the stopping rule of eq. 10, optionally a robust loss.
// docs/calibration.md.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "redpost/calibration/measurement.hpp"
#include "redpost/calibration/observability.hpp"
#include "redpost/calibration/parameters.hpp"
#include "redpost/calibration/plan.hpp"
#include "redpost/kinematics/cell.hpp"

namespace redpost {

// Robust losses for readings with outliers (a spot of dirt on a plane, a reflection): the
// identification then minimises sum rho(r_i / s) by iteratively reweighted least squares.
// Huber: rho(u) = u^2/2 for |u| <= k, k|u| - k^2/2 beyond (k = 1.345); Cauchy: rho(u) =
// c^2/2 log(1 + (u/c)^2) (c = 2.385). Both are 95 % efficient on Gaussian noise.
enum class RobustLoss { none, huber, cauchy };

const char* to_string(RobustLoss loss);
RobustLoss parse_robust_loss(const std::string& name);  // none|huber|cauchy; throws bad_input

struct CalibrationOptions {
  // Eq. 10: stop when |dbeta_j| < relative_step * |beta_j - beta_j(0)| for every j, or ...
  double relative_step = 1e-3;
  // ... |dbeta_j| < absolute_step (rad or mm) where the relative test cannot apply.
  double absolute_step = 1e-10;
  int max_iterations = 50;
  // Singular values of the column-scaled W below rank_tolerance * sigma_max are taken as zero.
  double rank_tolerance = 1e-6;
  // On rank deficiency: false refuses (Error bad_input naming the combinations); true
  // identifies the observable subspace only (minimum-norm steps in scaled coordinates).
  bool allow_partial = false;
  MeasurementModel model;
  RobustLoss loss = RobustLoss::none;
  // The residual scale s of the robust loss (mm). 0: estimated at every iteration as
  // 1.4826 * the median absolute deviation of the residuals (floored at 1e-4 mm).
  double loss_scale_mm = 0.0;
};

struct CalibrationResult {
  std::vector<CalibrationParameter> parameters;
  Eigen::VectorXd initial;          // beta(0), from the nominal cell
  Eigen::VectorXd values;           // the identified beta
  Eigen::VectorXd standard_errors;  // sqrt(diag(sigma_hat^2 (W^T W)^-1)); NaN if unidentifiable
  double sigma_hat_mm = 0.0;        // residual standard deviation, RSS / (np - rank)
  double rms_before_mm = 0.0;       // RMS of the residuals at beta(0)
  double rms_after_mm = 0.0;
  int iterations = 0;                 // accepted Gauss-Newton / LM steps
  bool converged = false;             // the stopping rule was met within max_iterations
  ObservabilityReport observability;  // at the identified values (initial ones if refused)
  Cell calibrated;                    // the nominal cell with the identified values
  // History for reports (the paper's Figure 8): beta and the RMS of the residuals before the
  // first step and after every accepted one (iterations + 1 entries).
  std::vector<Eigen::VectorXd> value_history;
  std::vector<double> rms_history_mm;
  Eigen::VectorXd residuals_mm;  // r_i = reading - model at the identified values
  // Robust loss only: the final weight of every reading (1 for least squares) and the indices
  // (0-based) of the readings weighted below 0.5, the likely outliers.
  Eigen::VectorXd weights;
  std::vector<int> outliers;
};

// Identifies the parameters from the points (joints and readings). Throws Error(bad_input) on
// rank deficiency unless options.allow_partial, on fewer points than parameters, or on an
// empty parameter list.
CalibrationResult calibrate(const Cell& nominal, const std::vector<CalibrationParameter>& params,
                            const std::vector<CalibrationPoint>& points,
                            const CalibrationOptions& options = {});

}  // namespace redpost
