// The KRL program that runs a calibration plan on the robot (issue 7): every point of the plan,
// in the plan's order, numbered in a comment as in the readings template, so that the operator
// writes each laser reading into the row of the same number.
//
// Every motion is a PTP to the full E6AXIS the plan computed on the nominal model: the
// controller then reaches exactly the joints the identification assumes, whatever $BASE or the
// coupling of the external axes. Before each group of points (a plane in one configuration of
// the external axes) the sensor approaches from a retract pose backed off along its beam, and
// leaves to one after the group: the approach and retract are solved with the external axes of
// the group held, and like every point are checked against the joint limits.
#pragma once

#include <string>
#include <vector>

#include "redpost/calibration/plan.hpp"
#include "redpost/kinematics/cell.hpp"
#include "redpost/krl/template.hpp"

namespace redpost {

struct CalibrationProgramOptions {
  std::string name = "calib_plan";  // KRL identifier (<= 24 characters)
  std::string output_dir;
  std::string base = "BASE_DATA[1]";  // $BASE; the motions are joint moves, it is only restated
  std::string tool = "TOOL_DATA[2]";  // $TOOL: the laser sensor, beam along -z
  // At each point: WAIT SEC dwell_s for the reading to settle (0: HALT, the operator restarts
  // after noting the reading).
  double dwell_s = 2.0;
  double retract_mm = 100.0;         // approach/retract distance along the beam
  std::vector<int> external_joints;  // chain indices; empty: external_joint_indices(cell)
  int perturbed_starts = 24;
  std::uint64_t seed = 1;
  std::string header_comment;
};

// Writes NAME.src/.dat through the template set; returns the .src paths. The files appear under
// their final names only when complete (KrlWriter). Throws Error(unreachable) when an approach
// pose cannot be reached, Error(internal) if a point lies outside the joint limits.
std::vector<std::string> write_calibration_program(const Cell& nominal,
                                                   const std::vector<CalibrationPoint>& points,
                                                   const KrlTemplateSet& templates,
                                                   const CalibrationProgramOptions& options);

}  // namespace redpost
