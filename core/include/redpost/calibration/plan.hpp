// The measurement plan of the calibration (issue 7; Andres et al. 2011 Section 3, eqs. 2-4): a
// grid of commanded TCP frames on each plane for each configuration of the external joints, the
// arm joints solved on the NOMINAL model; the points it gives, which the readings complete.
// docs/calibration.md.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "redpost/calibration/measurement.hpp"
#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost {

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

// The external joints of a cell: the joints mapped to E1..E6, in chain order.
std::vector<int> external_joint_indices(const Cell& cell);

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

}  // namespace redpost
