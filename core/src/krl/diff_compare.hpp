// The comparison of `redpost diff` (docs/krl-diff.md) once the motions are aligned: an aligned
// pair measured on every quantity, a motion of one side only counted as an insertion or a
// removal, each Cartesian point measured against the other program's path, and the results
// gathered into a KrlDiffResult (the first differences listed, the rest counted).
//
// Internal to redpost::core; not installed.
#pragma once

#include <string>
#include <vector>

#include "krl/diff_path.hpp"
#include "krl/diff_pose.hpp"
#include "redpost/krl/diff.hpp"

namespace redpost::krl {

class Comparer {
 public:
  // paths[0], paths[1]: the windows of A's and B's paths the points are measured against.
  Comparer(const KrlDiffOptions& o, KrlDiffResult& r, const PathWindow* const paths[2])
      : opt_(o), r_(r), paths_{paths[0], paths[1]} {}

  // Each motion goes through exactly one of these, in program order.
  void pair(const DiffPose& a, const DiffPose& b);
  void only(const DiffPose& p, bool in_b);

 private:
  // The point against the other program's path: the path statistics; true when it lies on it.
  bool measure_path(const DiffPose& p, bool in_b);
  void summarise(const KrlDeviation& d, const DiffPose* a, const DiffPose* b);
  template <class Measure>
  void measure_settings(const DiffPose& a, const DiffPose& b, Measure& measure);
  bool add(KrlDifference d);

  const KrlDiffOptions& opt_;
  KrlDiffResult& r_;
  const PathWindow* paths_[2];
  KrlDifference::Kind last_ = KrlDifference::Kind::changed;
  bool run_open_ = false, run_shown_ = false;
};

// A run of unmatched motions (dels from A, ins into B) between two matches: motions are paired
// again (by CL line when aligning by CL lines, else in order, at the offset that keeps the
// paired positions closest); the rest are removals or insertions.
void flush_hunk(const std::vector<const DiffPose*>& dels, const std::vector<const DiffPose*>& ins,
                bool by_cl, Comparer& cmp);

}  // namespace redpost::krl
