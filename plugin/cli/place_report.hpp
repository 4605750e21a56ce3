// The HTML report of `redpost place --report` (issues 8 and 9): the c_i maps over (path point,
// beta) with the best and worst spin plans (Caro Figures 5.2 and 5.4), the optimiser's
// convergence (Figure 5.1), the four cases of Table 5.1, and a top view of the work volume.
#pragma once

#include <string>

#include "redpost/machining/placement.hpp"

namespace redpost::cli {

struct PlacementReportInput {
  std::string job_path;
  const PlacementProblem* problem = nullptr;
  const PlacementStudy* study = nullptr;
  const CostMap* map_best = nullptr;   // at the best placement
  const CostMap* map_worst = nullptr;  // at the worst placement
  double seconds = 0.0;
};

// Renders the report; the caller writes it with the other outputs (atomically).
std::string placement_report_html(const PlacementReportInput& in);

}  // namespace redpost::cli
