// The "The cell in 3D" section of the `redpost convert --report` page (docs/reports.md, "The 3D
// view"): the session's cell drawn from its DH chain through the program's motions, the toolpath
// coloured by 1/kappa_F, the axes' speed, the joints' limit margin or the deflection.
//
// Fed with the same observer samples as the rest of the report (convert_report.cpp) and kept
// within Scene3dLimits, so memory and page size do not grow with the run.
#pragma once

#include "convert_report_clearance.hpp"
#include "redpost.h"
#include "redpost/report/html_report.hpp"
#include "redpost/report/scene3d.hpp"

namespace redpost::run_report {

class SceneTrace {
 public:
  // Reads the session's cell model (rp_cell_info_get, rp_link_get). Throws Error when the ABI
  // refuses.
  explicit SceneTrace(const rp_session* session);

  void on_motion(const rp_motion& m);

  // The section, after rp_prepare (the deflection tolerance is read from the session then).
  // With the closest approach of the clearance section, marked in the view (null: none).
  void add_section(report::HtmlReport& r, const rp_session* session,
                   const ClearanceTrace::Closest* closest) const;

 private:
  report::SceneCell cell_;
  report::Scene3dRecorder recorder_;
  double conditioning_threshold_ = 0.0;
};

}  // namespace redpost::run_report
