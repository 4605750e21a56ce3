// The HTML report of `redpost calibrate --report` (issues 7 and 9): the parameters per
// iteration (Andres Figure 8), the residual RMS per iteration, the validation histograms
// (Figure 9), the singular values, and the before / after / standard-error table.
#pragma once

#include <string>
#include <vector>

#include "redpost/calibration/identification.hpp"
#include "redpost/calibration/plan.hpp"
#include "redpost/calibration/validation.hpp"
#include "redpost/kinematics/cell.hpp"

namespace redpost::cli {

struct CalibrationReportInput {
  std::string cell_path;
  std::string readings_path;
  std::string validation_path;  // empty: no validation
  int readings = 0;
  const CalibrationResult* result = nullptr;
  const CalibrationOptions* options = nullptr;
  const ValidationResult* validation = nullptr;  // null: no validation
};

// Writes the report (atomically). Throws Error(io) when it cannot be written.
void write_calibration_report(const std::string& path, const CalibrationReportInput& in);

// The report of `redpost calibrate plan --report` (issue 21): the points per plane and
// configuration, those near a joint limit, and the cell in 3D visiting every point over the
// three measurement planes.
struct CalibrationPlanReportInput {
  std::string cell_path;
  const Cell* cell = nullptr;
  const std::vector<CalibrationPoint>* points = nullptr;
  std::size_t configurations = 0;  // 0: validation points (random external joints)
};
std::string calibration_plan_report_html(const CalibrationPlanReportInput& in);

}  // namespace redpost::cli
