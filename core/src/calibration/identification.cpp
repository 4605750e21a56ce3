// The identification of the calibration (identification.hpp): the robust losses, and
// calibrate() in its steps: the Gauss-Newton iteration of eqs. 8-9 with its Levenberg-Marquardt
// safeguard and the stopping rule of eq. 10, the robust reweighting, the history, and the
// statistics of the result. docs/calibration.md.
#include "redpost/calibration/identification.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <Eigen/SVD>

#include "calibration/column_scaling.hpp"
#include "calibration/fail.hpp"

namespace redpost {

namespace {

using detail::column_norms;
using detail::fail_bad_input;

}  // namespace

const char* to_string(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::none:
      return "none";
    case RobustLoss::huber:
      return "huber";
    case RobustLoss::cauchy:
      return "cauchy";
  }
  return "none";
}

RobustLoss parse_robust_loss(const std::string& name) {
  if (name == "none")
    return RobustLoss::none;
  if (name == "huber")
    return RobustLoss::huber;
  if (name == "cauchy")
    return RobustLoss::cauchy;
  fail_bad_input("unknown loss '" + name + "' (use none, huber or cauchy)");
}

namespace {

// The tuning constants that give 95 % efficiency on Gaussian noise.
constexpr double kHuberK = 1.345;
constexpr double kCauchyC = 2.385;

// rho(r / s), scaled so that it equals (r/s)^2 for small residuals (the least-squares cost).
double robust_rho(RobustLoss loss, double u) {
  const double a = std::abs(u);
  switch (loss) {
    case RobustLoss::huber:
      return a <= kHuberK ? u * u : 2.0 * kHuberK * a - kHuberK * kHuberK;
    case RobustLoss::cauchy:
      return kCauchyC * kCauchyC * std::log1p(u * u / (kCauchyC * kCauchyC));
    case RobustLoss::none:
      break;
  }
  return u * u;
}

// The IRLS weight rho'(u) / (2u): the step of a weighted least-squares problem with these
// weights is the Gauss-Newton step of the robust cost.
double robust_weight(RobustLoss loss, double u) {
  const double a = std::abs(u);
  switch (loss) {
    case RobustLoss::huber:
      return a <= kHuberK ? 1.0 : kHuberK / a;
    case RobustLoss::cauchy:
      return 1.0 / (1.0 + u * u / (kCauchyC * kCauchyC));
    case RobustLoss::none:
      break;
  }
  return 1.0;
}

double median_of(std::vector<double> v) {
  if (v.empty())
    return 0.0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  double m = v[mid];
  if (v.size() % 2 == 0)
    m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
  return m;
}

// The residual scale: given, or 1.4826 MAD (a consistent estimate of sigma for Gaussian noise
// that a minority of outliers does not move).
double residual_scale(const CalibrationOptions& o, const Eigen::VectorXd& r) {
  if (o.loss_scale_mm > 0.0)
    return o.loss_scale_mm;
  std::vector<double> v(r.data(), r.data() + r.size());
  const double med = median_of(v);
  for (double& x : v)
    x = std::abs(x - med);
  return std::max(1.4826 * median_of(v), 1e-4);
}

double robust_cost(const CalibrationOptions& o, const Eigen::VectorXd& r, double scale) {
  if (o.loss == RobustLoss::none)
    return r.squaredNorm();
  double c = 0.0;
  for (Eigen::Index i = 0; i < r.size(); ++i)
    c += robust_rho(o.loss, r[i] / scale);
  return c * scale * scale;
}

Eigen::VectorXd robust_weights(const CalibrationOptions& o, const Eigen::VectorXd& r,
                               double scale) {
  Eigen::VectorXd w = Eigen::VectorXd::Ones(r.size());
  if (o.loss != RobustLoss::none)
    for (Eigen::Index i = 0; i < r.size(); ++i)
      w[i] = robust_weight(o.loss, r[i] / scale);
  return w;
}

// ---- The steps of calibrate() ---------------------------------------------------------------

// What one identification works on, fixed over its iterations.
struct IdentificationProblem {
  const Cell& nominal;
  const std::vector<CalibrationParameter>& params;
  const std::vector<CalibrationPoint>& points;
  const CalibrationOptions& options;
  Eigen::VectorXd readings;  // the points' laser readings (mm)
};

// Parameter values beta and what the identification evaluates there.
struct Iterate {
  Eigen::VectorXd beta;
  Eigen::MatrixXd W;  // eq. 8 at beta (unweighted)
  Eigen::VectorXd r;  // Delta p of eq. 8: readings - model at beta
  // The robust loss's scale, weights and cost at r (reweight).
  double scale = 0.0;
  Eigen::VectorXd w;
  double cost = 0.0;
};

void check_problem_size(const std::vector<CalibrationParameter>& params,
                        const std::vector<CalibrationPoint>& points) {
  if (params.empty())
    fail_bad_input("calibration: no parameters to identify");
  const auto mp = static_cast<Eigen::Index>(params.size());
  const auto np = static_cast<Eigen::Index>(points.size());
  if (np < mp)
    fail_bad_input("calibration: " + std::to_string(np) + " readings cannot identify " +
                   std::to_string(mp) + " parameters");
}

Eigen::VectorXd readings_of(const std::vector<CalibrationPoint>& points) {
  const auto np = static_cast<Eigen::Index>(points.size());
  Eigen::VectorXd readings(np);
  for (Eigen::Index i = 0; i < np; ++i)
    readings[i] = points[static_cast<size_t>(i)].reading_mm;
  return readings;
}

// W and the residuals at beta; the weighting is left to reweight().
Iterate evaluate(const IdentificationProblem& pb, const Eigen::VectorXd& beta) {
  Iterate x;
  x.beta = beta;
  Eigen::VectorXd pred;
  x.W = observation_matrix(pb.nominal, pb.params, x.beta, pb.points, pb.options.model, &pred);
  x.r = pb.readings - pred;
  return x;
}

// Least squares: weights 1 and the plain sum of squares. A robust loss reweights the rows at
// every iteration (IRLS) with the scale of that iteration.
void reweight(const CalibrationOptions& options, Iterate& x) {
  x.scale = residual_scale(options, x.r);
  x.w = robust_weights(options, x.r, x.scale);
  x.cost = robust_cost(options, x.r, x.scale);
}

double rms_of(const Eigen::VectorXd& r) {
  return std::sqrt(r.squaredNorm() / static_cast<double>(r.size()));
}

// The history for reports: beta and the RMS of the residuals.
void record_history(const Iterate& x, CalibrationResult& res) {
  res.value_history.push_back(x.beta);
  res.rms_history_mm.push_back(rms_of(x.r));
}

void refuse_rank_deficiency(const Eigen::MatrixXd& W,
                            const std::vector<CalibrationParameter>& params,
                            const CalibrationOptions& options) {
  const auto mp = static_cast<Eigen::Index>(params.size());
  ObservabilityReport obs = analyse_observability(W, params, options.rank_tolerance);
  if (obs.rank_deficient() && !options.allow_partial) {
    fail_bad_input("calibration: the readings cannot identify every parameter (rank " +
                   std::to_string(obs.rank) + " of " + std::to_string(mp) + "): " + obs.summary());
  }
}

// Eq. 9 (lambda = 0): dbeta = W^+ dp, through the SVD of the scaled W; with lambda > 0
// the Levenberg-Marquardt step (Ws^T Ws + lambda I)^-1 Ws^T dp.
Eigen::VectorXd damped_step(const Eigen::JacobiSVD<Eigen::MatrixXd>& svd,
                            const Eigen::VectorXd& Utr, const Eigen::VectorXd& D, double lambda,
                            double rank_tolerance) {
  const Eigen::VectorXd& s = svd.singularValues();
  const double smax = s.size() > 0 ? s[0] : 0.0;
  Eigen::VectorXd g(s.size());
  for (Eigen::Index k = 0; k < s.size(); ++k)
    g[k] = s[k] > rank_tolerance * smax ? s[k] / (s[k] * s[k] + lambda) * Utr[k] : 0.0;
  return D.cwiseInverse().cwiseProduct(svd.matrixV() * g);
}

// Eq. 10 and the absolute step tolerance.
bool step_is_small(const Eigen::VectorXd& step, const Eigen::VectorXd& beta,
                   const Eigen::VectorXd& initial, const CalibrationOptions& options) {
  bool small = true;
  for (Eigen::Index j = 0; j < step.size(); ++j)
    if (!(std::abs(step[j]) <
          std::max(options.relative_step * std::abs(beta[j] - initial[j]), options.absolute_step)))
      small = false;
  return small;
}

enum class IterationOutcome { accepted, converged, stalled };

// One Gauss-Newton iteration: steps ever more damped (lambda, in column-scaled coordinates)
// until one lowers the cost; an accepted step moves x and is recorded in res. converged: the
// stopping rule is met; stalled: no step lowered the cost.
IterationOutcome gauss_newton_iteration(const IdentificationProblem& pb, Iterate& x, double& lambda,
                                        CalibrationResult& res) {
  const CalibrationOptions& options = pb.options;
  const Eigen::VectorXd sqrt_w = x.w.cwiseSqrt();
  const Eigen::MatrixXd Wr = sqrt_w.asDiagonal() * x.W;
  const Eigen::VectorXd D = column_norms(Wr);
  const Eigen::MatrixXd Ws = Wr * D.cwiseInverse().asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Ws, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  const double smax = s.size() > 0 ? s[0] : 0.0;
  const Eigen::VectorXd Utr = svd.matrixU().transpose() * sqrt_w.cwiseProduct(x.r);
  for (int attempt = 0; attempt < 40; ++attempt) {
    const Eigen::VectorXd step = damped_step(svd, Utr, D, lambda, options.rank_tolerance);
    Iterate trial = evaluate(pb, x.beta + step);
    const double cost_new = robust_cost(options, trial.r, x.scale);
    const bool small = step_is_small(step, x.beta, res.initial, options);
    if (cost_new <= x.cost) {
      reweight(options, trial);
      x = std::move(trial);
      ++res.iterations;
      record_history(x, res);
      lambda = lambda * 0.1 < 1e-12 * smax * smax ? 0.0 : lambda * 0.1;
      return small ? IterationOutcome::converged : IterationOutcome::accepted;
    }
    if (small)  // A step below the tolerance that no longer lowers the cost: rounding level.
      return IterationOutcome::converged;
    lambda = lambda == 0.0 ? 1e-4 * smax * smax : 10.0 * lambda;
  }
  return IterationOutcome::stalled;
}

std::vector<int> outliers_of(const Eigen::VectorXd& w) {
  std::vector<int> out;
  for (Eigen::Index i = 0; i < w.size(); ++i)
    if (w[i] < 0.5)
      out.push_back(static_cast<int>(i));
  return out;
}

// Least squares: sigma_hat^2 = RSS / (np - rank). A robust fit reports the robust scale
// (1.4826 MAD of the residuals, corrected for the degrees of freedom): a weighted RSS would
// still carry the down-weighted outliers' share.
double residual_sigma(const CalibrationOptions& options, const Eigen::VectorXd& r,
                      double weighted_ss, int rank) {
  const auto np = r.size();
  const double dof = static_cast<double>(np - rank);
  if (options.loss == RobustLoss::none)
    return dof > 0 ? std::sqrt(weighted_ss / dof) : 0.0;
  CalibrationOptions mad = options;
  mad.loss_scale_mm = 0.0;
  return dof > 0 ? residual_scale(mad, r) * std::sqrt(static_cast<double>(np) / dof) : 0.0;
}

// Standard errors: sigma_hat^2 (W^T W)^-1, through the SVD of the scaled W. A parameter with
// a component in the null space (partial calibration) has none.
Eigen::VectorXd standard_errors(const Eigen::MatrixXd& W, int rank, double sigma_hat_mm) {
  const Eigen::Index mp = W.cols();
  const Eigen::VectorXd D = column_norms(W);
  const Eigen::MatrixXd Ws = W * D.cwiseInverse().asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Ws, Eigen::ComputeFullV);
  const Eigen::VectorXd& s = svd.singularValues();
  Eigen::VectorXd se(mp);
  for (Eigen::Index j = 0; j < mp; ++j) {
    double var = 0.0;
    bool in_null = false;
    for (Eigen::Index k = 0; k < mp; ++k) {
      const double vjk = svd.matrixV()(j, k);
      if (k < rank)
        var += vjk * vjk / (s[k] * s[k]);
      else if (std::abs(vjk) > 1e-6)
        in_null = true;
    }
    se[j] =
        in_null ? std::numeric_limits<double>::quiet_NaN() : sigma_hat_mm * std::sqrt(var) / D[j];
  }
  return se;
}

// The result at the identified values x: residuals, weights and outliers, the statistics, the
// observability and the calibrated cell.
void finish_result(const IdentificationProblem& pb, const Iterate& x, CalibrationResult& res) {
  res.values = x.beta;
  res.residuals_mm = x.r;
  res.rms_after_mm = rms_of(x.r);
  res.weights = x.w;
  res.outliers = outliers_of(x.w);
  // The statistics of a robust fit use the weighted rows: an outlier's small weight keeps it
  // from inflating sigma_hat (a down-weighted reading counts as a fraction of one).
  const Eigen::VectorXd sqrt_w_final = x.w.cwiseSqrt();
  const Eigen::MatrixXd W = sqrt_w_final.asDiagonal() * x.W;
  const double weighted_ss = sqrt_w_final.cwiseProduct(x.r).squaredNorm();
  res.observability = analyse_observability(W, pb.params, pb.options.rank_tolerance);
  const int rank = res.observability.rank;
  res.sigma_hat_mm = residual_sigma(pb.options, x.r, weighted_ss, rank);
  res.standard_errors = standard_errors(W, rank, res.sigma_hat_mm);
  res.calibrated = apply_parameters(pb.nominal, pb.params, x.beta);
}

}  // namespace

CalibrationResult calibrate(const Cell& nominal, const std::vector<CalibrationParameter>& params,
                            const std::vector<CalibrationPoint>& points,
                            const CalibrationOptions& options) {
  check_problem_size(params, points);
  CalibrationResult res;
  res.parameters = params;
  res.initial = parameter_values(nominal, params);
  const IdentificationProblem pb{nominal, params, points, options, readings_of(points)};

  Iterate x = evaluate(pb, res.initial);
  res.rms_before_mm = rms_of(x.r);
  record_history(x, res);
  reweight(options, x);
  refuse_rank_deficiency(x.W, params, options);

  double lambda = 0.0;  // Levenberg-Marquardt damping, in column-scaled coordinates
  for (int it = 0; it < options.max_iterations; ++it) {
    const IterationOutcome outcome = gauss_newton_iteration(pb, x, lambda, res);
    if (outcome == IterationOutcome::converged)
      res.converged = true;
    if (outcome != IterationOutcome::accepted)
      break;
  }
  finish_result(pb, x, res);
  return res;
}

}  // namespace redpost
