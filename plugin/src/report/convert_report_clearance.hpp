// The "Clearance between bodies" section of the `redpost convert --report` page
// (docs/collision.md): the closest approach of each pair of bodies along the program, against the
// margin, and where the closest of all was.
//
// Fed with the observer's samples like the rest of the report, streamed into one min/max
// decimator per pair (the pairs that come within reach of the margin, the first kMaxPairs of
// them by first approach, the rest together), so memory does not grow with the run.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "redpost.h"
#include "redpost/report/html_report.hpp"
#include "redpost/report/plot_scale.hpp"

namespace redpost::run_report {

class ClearanceTrace {
 public:
  static constexpr std::size_t kMaxPairs = 8;
  explicit ClearanceTrace(int buckets);

  void on_motion(const rp_motion& m);

  // The section, after rp_prepare; nothing when no pair was checked (--no-collision-check, no
  // bodies at all), so that such a report does not change.
  void add_section(report::HtmlReport& r, const rp_session* session,
                   const report::Axis& motions) const;

  // The closest approach computed: its pair, motion, CL line, distance and nearest points (CL
  // frame; valid where `exact`). For the 3D view's marker.
  struct Closest {
    std::string pair;
    long motion = 0;
    int line = 0;
    double mm = 0.0;
    bool exact = false;
    std::array<double, 3> a{}, b{};
  };
  const Closest* closest() const { return has_closest_ ? &closest_ : nullptr; }

 private:
  int buckets_;
  std::vector<std::string> names_;
  std::vector<report::MinMaxDecimator> per_pair_;
  report::MinMaxDecimator others_;
  bool others_used_ = false;
  Closest closest_;
  bool has_closest_ = false;
  long checked_motions_ = 0;
};

}  // namespace redpost::run_report
