// `redpost diff` as a stream (docs/krl-diff.md): the motions of two programs are aligned and
// compared as they are read, holding a window of each, never a whole program.
//
// Alignment: by CL line when both programs carry "; CL line N" comments in their first window
// (a merge walk over runs of equal CL line, each pair of runs aligned by Myers on the motions'
// keys), else by Myers on the keys over a window of `KrlDiffOptions::window` motions of each
// program, committing up to the last match in the window's first half. Each Cartesian point is
// measured against the other program's path from a quarter window behind its aligned place to what
// has been read ahead of it.
//
// Internal to redpost::core; not installed.
#pragma once

#include "krl/diff_source.hpp"
#include "redpost/krl/diff.hpp"

namespace redpost::krl {

KrlDiffResult diff_pose_streams(PoseSource& a, PoseSource& b, const KrlDiffOptions& options);

}  // namespace redpost::krl
