// The checks of `redpost check` on a program's motions, a motion at a time (check.cpp reads
// the program with a KrlMotionSink, so that memory does not grow with it): the first motion a
// PTP to a full E6AXIS, S/T on the first Cartesian PTP, the axes against the cell's limits, the
// motion rate (docs/krl-diff.md).
#pragma once

#include <memory>
#include <set>
#include <string>
#include <vector>

#include "redpost/krl/check.hpp"
#include "redpost/krl/motion_rate.hpp"

namespace redpost::krl {

class MotionChecks {
 public:
  MotionChecks(const KrlCheckOptions& options, std::string main_file);
  void add(const KrlMotionRecord& m);  // in execution order
  std::vector<KrlFinding> finish();

 private:
  void first_motion(const KrlMotionRecord& m);
  void first_cartesian_ptp(const KrlMotionRecord& m);
  void motion_rate(KrlMotionRate rate);
  void limits(const KrlMotionRecord& m);

  const KrlCheckOptions& options_;
  std::string main_file_;
  std::unique_ptr<KrlClearanceCheck> clearance_;
  KrlMotionRateCounter rate_;
  bool motion_seen_ = false;
  bool ptp_seen_ = false;
  std::set<std::string> unmapped_reported_;
  std::vector<KrlFinding> out_;
};

}  // namespace redpost::krl
