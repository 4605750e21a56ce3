// A workpiece-placement job (Caro 2014 chapter 5, issue 8): the cell, the contour to mill, the
// cutting conditions, the work volume and constraints of problem (5.17), the spin grid of the
// inner problem and the optimiser settings. Format: docs/placement.md.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "redpost/kinematics/cell.hpp"
#include "redpost/machining/cutting_force.hpp"

namespace redpost {

// One straight segment of the contour, in the workpiece frame F_W (mm). The tool path runs
// parallel to it, offset by the tool radius away from the material.
struct ContourSegment {
  std::string name;  // e.g. "AB"
  Eigen::Vector3d from_W_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d to_W_mm = Eigen::Vector3d::Zero();
  double ae_mm = 0.0;  // radial width of cut along this segment
  MillingMode mode = MillingMode::down;
  int points = 0;  // path points on this segment
  int source_line = 0;
};

// Bounds of the placement variables (eqs. 5.13-5.15 and -1 <= Q4 <= 1), O_W in F0, mm.
struct WorkVolume {
  double x_min_mm = 0.0, x_max_mm = 0.0;
  double y_min_mm = 0.0, y_max_mm = 0.0;
  double z_min_mm = 0.0, z_max_mm = 0.0;
  double q4_min = -1.0, q4_max = 1.0;
};

struct PlacementConstraints {
  double c_max_mm = 1.0;       // eq. 5.12
  double inv_kappa_min = 0.2;  // eq. 5.16: 1/kappa_F(J_N) > this
  bool complementary = false;  // include K_C (eq. 4.4) in the deflection
};

// The discretised spin of the inner problem and the continuity of a plan along a segment.
struct SpinSettings {
  double step_rad = deg_to_rad(5.0);             // grid over [-pi, pi)
  double max_step_rad = deg_to_rad(10.0);        // |beta_{i+1} - beta_i| between path points
  double max_joint_step_rad = deg_to_rad(20.0);  // every arm joint between path points
};

struct OptimiserSettings {
  std::string global_algorithm = "GN_CRS2_LM";  // NLopt name without the NLOPT_ prefix
  int global_evaluations = 1500;
  int global_population = 0;                  // 0: NLopt's default
  std::string local_algorithm = "LN_BOBYQA";  // "" or "none": no refinement
  int local_evaluations = 300;
  unsigned seed = 1;
  int history_batch = 50;  // convergence history: best value every this many evaluations
  int threads = 2;         // 1 or 2: the inner evaluation splits the path points
};

struct ProgramSettings {
  std::string name = "PLACEMENT";  // KRL program name
  int name_line = 0;               // the job file's line that gives it (0: the default)
  double retract_mm = 50.0;        // lift along z_W between segments
};

struct PlacementJob {
  std::string source_file;
  std::string cell_file;  // resolved against the job file's folder
  Cell cell;

  MillingConditions milling;  // ae and mode are per segment
  double spindle_rpm = 20000.0;
  double feed_mm_per_min = 4000.0;
  // Which side of the feed the material lies on: +1 left (+y_P), -1 right (-y_P).
  int material_side = -1;

  std::vector<ContourSegment> segments;
  WorkVolume volume;
  PlacementConstraints constraints;
  SpinSettings spin;
  OptimiserSettings optimiser;
  ProgramSettings program;

  int point_count() const;
};

// Loads and checks a job file and the cell it names. Throws Error(bad_input) with file:line for
// anything malformed, unknown or inconsistent (bounds with min > max, ae beyond the tool
// diameter, an unknown NLopt algorithm, a cell without six stiffnesses ...), Error(io) when a
// file cannot be read.
PlacementJob load_placement_job(const std::string& path);
PlacementJob parse_placement_job(const std::string& xml_text, const std::string& source_name);

}  // namespace redpost
