// What the time model says of a candidate plan for one window (issue 47, docs/redundancy.md
// "Held or moved"): the motions the session would write if the tracker followed it. The
// lattice's edge costs see each axis's velocity between keyframes 20 mm apart; they do not see
// the corners the axes make at the path's own corners (a raster's line ends), where a slow
// external axis whose rate changes between two blended motions sets the speed at its low
// acceleration, nor the motions the point reduction must keep where the axes do not move
// linearly. The estimate does: the arm solved in closed form at every CL point of the window
// for the free joints the plan interpolates there, the motions joined as the program joins them
// (LINs blended at the program's $APO.CDIS; rapids as synchronous PTPs where the session writes
// them so, above their clearance plane, else as LINs), timed by timing/'s PathTimer with the
// template set's controller.
#pragma once

#include <limits>
#include <vector>

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/redundancy/path_plan.hpp"
#include "redpost/timing/path_timer.hpp"

namespace redpost {

struct PlanTimeEstimate {
  bool feasible = false;   // every point solved in the plan's posture
  int failed_cl_line = 0;  // the first point that was not
  double time_s = 0.0;     // the time model's, from the window's first keyframe to `until_s`
};

// Whether a synchronous PTP from q0 to q1 (every axis on the straight line in joint space) keeps
// the TCP at or above the plane through point_B with normal normal_B ({B}): checked at steps of
// at most half a degree (or half a millimetre) of the axis that moves most, 16 at least and
// max_samples at most. The session writes a rapid as a PTP only where this holds
// (docs/convert.md, "Rapids"), checked at every step; the estimate below, which asks it for
// every candidate plan of a window, at 64 (a PTP that moves the track 3 m would otherwise cost
// it 6000 forward kinematics per candidate).
bool ptp_stays_above(const Cell& cell, const JointVector& q0, const JointVector& q1,
                     const Eigen::Vector3d& point_B, const Eigen::Vector3d& normal_B,
                     KinematicsData& data, int max_samples = std::numeric_limits<int>::max());

// The window's plan (keyframes and their postures, keyframes[0] the committed start) timed over
// its motions' ends (`ends`: one per CL motion, in path order, `rapid` on a rapid written as a
// PTP, `traverse` on any rapid) up to path length until_s. Within a cutting motion the keyframes
// are points of it too (an arc's keyframes lie on the arc). blend_mm: the program's blending
// distance. The controller is taken as given: where the program's point reduction merges dense CL
// points into longer motions, the caller leaves the interpolation cycle and the look-ahead out of
// it, which would otherwise slow every candidate alike on the unmerged points and hide what tells
// them apart.
// approach_from: where the axes stand before a window without a committed start (after a tool
// change): the approach to q[0] is timed too, as a synchronous PTP; null: not known or none.
PlanTimeEstimate estimate_plan_time(const Cell& cell, const PathPlanner& planner,
                                    const ControllerTiming& controller, double blend_mm,
                                    const std::vector<PlanKeyframe>& keyframes,
                                    const std::vector<JointVector>& q,
                                    const std::vector<PlanKeyframe>& ends, double until_s,
                                    const JointVector* approach_from = nullptr);

}  // namespace redpost
