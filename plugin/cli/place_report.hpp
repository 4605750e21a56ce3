// The HTML report of `redpost place --report` (issues 8 and 9): the c_i maps over (path point,
// beta) with the best and worst spin plans (Caro Figures 5.2 and 5.4), the optimiser's
// convergence (Figure 5.1), the four cases of Table 5.1, a top view of the work volume and the
// cell in 3D running the best placement's best plan (issue 21).
#pragma once

#include <string>
#include <vector>

#include "redpost/machining/placement.hpp"

namespace redpost::cli {

struct PlacementReportInput {
  std::string job_path;
  const PlacementProblem* problem = nullptr;
  const PlacementStudy* study = nullptr;
  const CostMap* map_best = nullptr;   // at the best placement
  const CostMap* map_worst = nullptr;  // at the worst placement
  // The joints of the best placement's best plan, one per path point (the program written).
  const std::vector<JointVector>* q_path = nullptr;
  double seconds = 0.0;
};

// Renders the report; the caller writes it with the other outputs (atomically).
std::string placement_report_html(const PlacementReportInput& in);

}  // namespace redpost::cli
