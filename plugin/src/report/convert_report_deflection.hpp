// The "Deflection" section of the `redpost convert --report` page (docs/deflection.md): the
// arm's deflection under the cutting force, predicted or compensated, per CL operation and
// along the motions, against the tolerance.
//
// Fed with the same observer samples as the rest of the report (convert_report.cpp), streamed
// into min/max decimators, so memory does not grow with the run.
#pragma once

#include "redpost.h"
#include "redpost/report/html_report.hpp"
#include "redpost/report/plot_scale.hpp"

namespace redpost::run_report {

class DeflectionTrace {
 public:
  // buckets: of each decimator, as the report's other plots against the motion index.
  explicit DeflectionTrace(int buckets);

  // Every motion, in order. Cutting moves without a deflection (steps inside a longer move,
  // plunges) are skipped; a rapid or PTP motion after a deflection breaks the lines.
  void on_motion(const rp_motion& m);

  // The section, after rp_prepare; nothing when the session ran without the model
  // (RP_DEFLECTION_OFF), so that such a report does not change. motions: the x axis of the
  // plots (the report's motion axis).
  void add_section(report::HtmlReport& r, const rp_session* session,
                   const report::Axis& motions) const;

 private:
  report::MinMaxDecimator normal_, residual_normal_, force_;
  bool gap_pending_ = false;  // a finite sample was pushed since the last break
};

}  // namespace redpost::run_report
