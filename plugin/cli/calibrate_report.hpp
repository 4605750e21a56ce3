// The HTML report of `redpost calibrate --report` (issues 7 and 9): the parameters per
// iteration (Andres Figure 8), the residual RMS per iteration, the validation histograms
// (Figure 9), the singular values, and the before / after / standard-error table.
#pragma once

#include <string>
#include <vector>

#include "redpost/calibration/identification.hpp"
#include "redpost/calibration/validation.hpp"

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

}  // namespace redpost::cli
