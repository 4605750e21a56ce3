// In-situ calibration of a cell's DH parameters from laser readings on three planes: Andres et
// al. (2011) Section 3, eqs. 1-10 (issue 7). docs/calibration.md gives the mathematics.
//
//   measurement model : the laser beam is the TCP's -z axis from the TCP origin; the reading is
//                       the signed distance along the beam to the plane x, y or z = offset of {B}
//   plan (eqs. 2-4)   : a grid of commanded TCP frames on each plane for each configuration of
//                       the external joints, the arm joints solved on the NOMINAL model
//   identification    : Gauss-Newton on eqs. 8-9 with a Levenberg-Marquardt safeguard, the
//                       Jacobian by automatic differentiation, the stopping rule of eq. 10
//
// Parameters are named link<i>.<alpha|a|theta|d> with i the 1-based link index of the chain
// (Andres Table 1). Units: rad for alpha and theta, mm for a and d. For a revolute joint
// link<i>.theta is the constant offset added to q; for a prismatic one link<i>.d is.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost {

// ---- Parameters -----------------------------------------------------------------------------

enum class DhField { alpha, a, theta, d };

struct CalibrationParameter {
  int link = 0;  // 1-based link (joint) index of the chain
  DhField field = DhField::alpha;

  std::string name() const;  // "link1.alpha"
  bool is_angle() const { return field == DhField::alpha || field == DhField::theta; }
};

// Parses "link<i>.<alpha|a|theta|d>"; throws Error(bad_input) on anything else or on a link
// index outside 1..cell.size().
CalibrationParameter parse_calibration_parameter(const std::string& name, const Cell& cell);

// Parses a comma-separated list; rejects duplicates. Empty text: the paper's beta.
std::vector<CalibrationParameter> parse_calibration_parameters(const std::string& list,
                                                               const Cell& cell);

// The paper's beta = [alpha_1 a_1 theta_M d_1 theta_2 d_L]: link1.alpha, link1.a, link1.theta,
// link1.d, link2.theta, link2.d.
std::vector<CalibrationParameter> default_calibration_parameters();

// The current values of the parameters in the cell (rad, mm).
Eigen::VectorXd parameter_values(const Cell& cell, const std::vector<CalibrationParameter>& params);

// A copy of `cell` with the parameters set to `values`, finalized (finalize_cell).
Cell apply_parameters(const Cell& cell, const std::vector<CalibrationParameter>& params,
                      const Eigen::VectorXd& values);

// ---- Measurement model ----------------------------------------------------------------------

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

// ---- Plan (eqs. 2-4) ------------------------------------------------------------------------

struct CalibrationPlanOptions {
  // Chain indices of the external joints held fixed per configuration (Andres: theta_M, d_L).
  std::vector<int> external_joints{0, 1};
  // One entry per configuration, values in DH units in the order of external_joints. The paper:
  // {theta_M, d_L} = {0, 700} and {pi/4, 300}.
  std::vector<std::vector<double>> configurations{{0.0, 700.0}, {kPi / 4.0, 300.0}};
  std::array<bool, 3> planes{true, true, true};  // x, y, z
  int grid = 6;                                  // a grid x grid mesh per plane
  // The paper measures 108 points: one 6 x 6 mesh per plane, over two configurations. true
  // (the default): each mesh point is measured in one configuration, configuration
  // (i + j) mod count for grid point (i, j), a checkerboard for two; false: every mesh point in
  // every configuration (count x 3 x grid^2 points).
  bool alternate_configurations = true;
  // Extents of the grids in {B} (mm): the in-plane horizontal coordinates (y on Pi_x, x on
  // Pi_y, x and y on Pi_z) span [-half_width, +half_width]; the height z on Pi_x and Pi_y spans
  // [z_min, z_max]. The defaults are reached by the Andres cell in both paper configurations.
  double half_width_mm = 200.0;
  double z_min_mm = 150.0;
  double z_max_mm = 450.0;
  // Distance of the commanded TCP from its plane, on the side the beam comes from; 0 puts the
  // commanded point on the plane, as the paper does (the nominal reading is then 0).
  double stand_off_mm = 0.0;
  MeasurementModel model;  // plane offsets: the grid lies on the offset planes
  int perturbed_starts = 24;
  std::uint64_t seed = 1;
};

struct CalibrationPoint {
  PlaneAxis plane = PlaneAxis::z;
  int configuration = 0;                          // index into the plan's configurations
  Isometry T_B_commanded = Isometry::Identity();  // the commanded TCP frame, eqs. 2-4
  JointVector q;            // all joints (DH units), arm from the nominal model
  double reading_mm = 0.0;  // the laser reading (filled by simulate or from a readings file)
};

// The commanded TCP frame of eqs. 2-4 for a point p on the plane (p_k = plane offset):
// Pi_x: ABC = (0, -90, 0) deg, Pi_y: (0, 0, -90), Pi_z: (0, 0, 0), then moved back along the
// beam by stand_off.
Isometry commanded_frame(PlaneAxis plane, const Eigen::Vector3d& p_on_plane, double stand_off_mm);

// The joints with which the controller reaches a commanded TCP frame: the external joints
// (chain indices external_joints) at external_values, the others solved on the NOMINAL cell
// (Tracker::solve_first_pose with the external joints locked). Throws Error(unreachable) when
// the frame cannot be reached within the limits, Error(bad_input) on bad external values.
JointVector joints_for_commanded_frame(const Cell& nominal, const std::vector<int>& external_joints,
                                       const std::vector<double>& external_values,
                                       const Isometry& T_B_commanded, int perturbed_starts = 24,
                                       std::uint64_t seed = 1);

// Plans the measurement: for each configuration, each enabled plane, a grid of commanded
// frames, and the joints that reach each frame on the nominal cell with the external joints
// locked at the configuration's values (Tracker::solve_first_pose). Throws Error(unreachable)
// naming the point when one cannot be reached.
std::vector<CalibrationPoint> plan_calibration(const Cell& nominal,
                                               const CalibrationPlanOptions& options = {});

// Fills reading_mm of every point from `true_cell` at the point's joints, plus Gaussian noise
// of sigma_mm (seeded).
void simulate_readings(const Cell& true_cell, std::vector<CalibrationPoint>& points,
                       double sigma_mm, std::uint64_t seed, const MeasurementModel& model = {});

// ---- Identification (eqs. 5-10) -------------------------------------------------------------

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

// ---- Validation (paper section 3.3) --------------------------------------------------------

// The external joints of a cell: the joints mapped to E1..E6, in chain order.
std::vector<int> external_joint_indices(const Cell& cell);

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
