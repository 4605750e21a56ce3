// The parameters a calibration identifies (issue 7; Andres et al. 2011 Section 3, Table 1):
// DH values of the chain, read from and written back to a cell. docs/calibration.md.
//
// Parameters are named link<i>.<alpha|a|theta|d> with i the 1-based link index of the chain
// (Andres Table 1). Units: rad for alpha and theta, mm for a and d. For a revolute joint
// link<i>.theta is the constant offset added to q; for a prismatic one link<i>.d is.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "redpost/kinematics/cell.hpp"

namespace redpost {

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

}  // namespace redpost
