// The HTML report of a session (rp_options.report_path: `redpost convert --report`, the NX
// handlers' `report` setting; issue 9): what the conversion did to the cell, motion by motion,
// drawn with redpost::report.
//
// The samples are the rp_motion a host's motion observer gets, and are streamed into bounded
// summaries as they arrive: min/max
// decimators for the plots against the motion index and a thinned point list for the toolpath
// views. Memory does not grow with the length of the run (a 1M-pose convert included).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "redpost.h"

namespace redpost::run_report {

// What the report says about the run besides the samples.
struct ConvertReportContext {
  std::string input;     // the CL file
  std::string cell;      // the cell definition file
  std::string program;   // the KRL program name
  double seconds = 0.0;  // conversion time
};

class ConvertReport {
 public:
  // Reads the session's joints (rp_joint_range) and its cell. The session must be open; it
  // gives the report every motion (on_motion, from rp_session's observer). Throws Error when the
  // ABI refuses.
  explicit ConvertReport(rp_session* session);
  ~ConvertReport();
  ConvertReport(const ConvertReport&) = delete;
  ConvertReport& operator=(const ConvertReport&) = delete;

  void on_motion(const rp_motion& m);

  // After a successful rp_prepare: the report's HTML. The caller writes it to `path` (which
  // errors name) before rp_close, so that a report that cannot be written stops the run with
  // the old program still in place.
  std::string html(const std::string& path, const rp_session* session,
                   const ConvertReportContext& context) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

// A duration as the summary and the report print it: "42.0 s", "3 min 5.2 s", "2 h 56 min 5 s".
std::string duration_text(double s);

}  // namespace redpost::run_report
