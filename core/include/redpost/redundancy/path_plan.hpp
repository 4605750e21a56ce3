// Whole-path planning of the redundancy (issue 17, docs/redundancy.md "Whole-path planning"):
// the free joints (the joints outside the 6R arm: table, track, the tool's spin) are sampled on a
// lattice at keyframes along the path, the arm is solved in closed form for one posture, and the
// cheapest sequence is found by dynamic programming over the layers (lattice_dp.hpp). Node cost:
// the arm's centring, the margin to every joint limit and the arm's conditioning 1/kappa_F (and
// Caro's compliance under the stiff preset). Edge cost: the axis travel in seconds at each axis's
// speed limit (more for an external axis in the cut after a rapid, where it could have moved in
// the air), the time the axes would need beyond the time the feed gives (on a rapid written as a
// PTP, the whole PTP time), and a price for each turn back of an external axis (issue 47). The
// tracker then follows the planned joints, the external axes exactly (Tracker::follow).
#pragma once

#include <array>
#include <bitset>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "redpost/kinematics/arm_ik.hpp"
#include "redpost/kinematics/cell.hpp"
#include "redpost/redundancy/lattice_dp.hpp"
#include "redpost/redundancy/task_error.hpp"

namespace redpost {

// One keyframe: the TCP target (position and tool axis in {B}), its path length from the
// window's start, the speed asked on the way to it (feed or rapid), and its CL line.
struct PlanKeyframe {
  TcpTarget target;
  double s_mm = 0.0;
  double speed_mm_s = 0.0;
  bool rapid = false;  // on a rapid written as a PTP (above a clearance plane)
  // The plane a rapid's PTP must stay above ({B}): where its joint-space path dips below, the
  // session writes a LIN instead (post/plan_time.hpp, ptp_stays_above).
  Eigen::Vector3d clearance_point_B = Eigen::Vector3d::Zero();
  Eigen::Vector3d clearance_normal_B = Eigen::Vector3d::UnitZ();
  // On a rapid traverse, written as a PTP or as a LIN at the rapid speed.
  bool traverse = false;
  // The path from the previous keyframe to this one is out of the material: all rapid
  // traverse, or a retract at feed along the tool axis. An external axis moved here does not
  // move in the cut (PathPlanSettings::w_travel_cut).
  bool in_air = false;
  int cl_line = 0;
};

enum class PlanPreset { smooth, stiff, fast };

struct PathPlanSettings {
  double keyframe_spacing_mm = 20.0;
  // Lattice steps of the free joints. A prismatic joint's is a multiple of the keyframe
  // spacing: with a reach of one step it may then move twice as fast as the tool along the
  // path; at one spacing it could only keep pace, and a track once behind never caught up.
  double prismatic_step_spacings = 2.0;
  double rotary_step_deg = 3.0;
  double spin_step_deg = 10.0;
  int reach = 1;  // lattice steps a free joint may change between keyframes
  // Free joints that may change at once between keyframes: 2 of 3 keeps 19 of the 27
  // neighbours, 13 % fewer IK solutions with plans as good (docs/redundancy.md).
  int max_moving = 2;
  int beam = 24;  // nodes kept per keyframe
  // Threads that evaluate a keyframe's lattice nodes together (nullptr: the calling thread
  // alone); the plan is the same either way. Not owned.
  WorkerPool* pool = nullptr;
  // The first keyframe of a program (no committed posture): every free joint sampled over its
  // range in this many lattice steps at a time (a coarse first layer).
  int first_layer_stride = 4;
  int first_layer_max_nodes = 20000;
  // Axis speeds are planned within this fraction of each limit, leaving the rest for the
  // tracker's deviation from the plan and the controller's corners.
  double speed_margin = 0.8;
  // Cost weights (the preset sets them).
  double w_limit = 1.0;  // per joint, (zone - margin)^2 / zone^2 inside the zone
  // Joint centring of the arm (Andres eq. 13's first goal, as a cost): per arm joint,
  // ((q - home) / half-range)^2. It makes the external axes carry the path.
  double w_centre = 30.0;
  double limit_zone = 0.1;   // fraction of the range
  double w_condition = 1.0;  // (threshold - 1/kappa_F)^2 / threshold^2 below the threshold
  double condition_threshold = 0.3;
  double w_travel = 1.0;  // per second of external axis motion at its speed limit
  // ... of arm axis motion: the arm's big axes swinging under a straight cut cost stiffness and
  // accuracy (Caro 2014), so the track and the table should carry the path.
  double w_travel_arm = 3.0;
  // ... of external axis motion on the way to a keyframe not in the air (in the cut, or a feed
  // move), after the window's first rapid: the heavy axes' dynamics and positioning errors go
  // into the part, so where a rapid comes, the track and the table change position there rather
  // than under the cutter (issue 47; docs/redundancy.md). It adds to w_travel. 5: on
  // swcam_gasket_circles all the track's travel went into the rapids (10 kept
  // nx_kontur_nar_40_circle's arm at 1/kappa_F 0.275).
  double w_travel_cut = 5.0;
  double w_time = 20.0;  // per second the axes need beyond the time the feed gives
  // Rapids above a clearance plane are PTPs at this share of each axis's velocity limit
  // (BAS (#VEL_PTP, n)): their time is the slowest axis's, all of it weighed by w_time (the time
  // model's synchronous PTP, docs/timing.md), since it is the posture, not the CL file, that sets
  // it. Other rapids are LINs at their speed, weighed as feed moves.
  double rapid_velocity_fraction = 1.0;
  // Per turn back of an external axis (the track, the table; not the tool's spin).
  double w_reversal = 2.0;
  // A window's plan holds the external axes where the window starts when the time model finds
  // that this much faster (a fraction) than the plan that moves them (the session's choice,
  // post/plan_time.hpp; issue 47). Negative: no such choice. Where the two are as fast, the
  // moving plan is kept: held, the arm alone carries the path, and its orientation changes
  // along the lines split the motions the point reduction would merge (the 1M raster: 2.5 times
  // the motions, for the same cycle time).
  double hold_gain = 0.01;
  // Per second the external axes need to reach a fresh window's first keyframe from where they
  // stand (PlanHistory::standing): the approach after a tool change.
  double w_reposition = 5.0;
  // Compliance (Caro 2014 eq. 5.1, with stiffness data in the cell): per keyframe,
  // w_compliance * c / compliance_ref_mm, c the tool's deflection normal to the feed and the
  // tool axis under a nominal cutting load, given by normal_deflection_mm (set by the session
  // from the elastostatic model; empty: no such term). Arguments: the posture, the feed
  // direction and the tool axis (unit, in {B}). 0 but in the stiff preset: a cell's stiffness
  // data must not move the axes of a plan that did not ask for it.
  double w_compliance = 0.0;
  double compliance_ref_mm = 0.1;
  std::function<double(const JointVector&, const Eigen::Vector3d&, const Eigen::Vector3d&)>
      normal_deflection_mm;
  double max_arm_step_deg = 30.0;
  // Keyframes each side of the moving average that smooths the lattice's steps (0: none).
  int smoothing = 3;
  // Joints held (not sampled): their value from the start posture or lock_value.
  std::bitset<kMaxJoints> locked;
  JointVector lock_value;  // DH units; NaN: hold at the start posture's value
};

PathPlanSettings plan_preset(PlanPreset preset);

// Per joint of the chain, the sign of its last change before a window (0: none known): a window
// that turns an axis back pays the reversal.
using JointHeading = std::array<std::int8_t, kMaxJoints>;

// What a window knows of the motion before it (the session keeps it).
struct PlanHistory {
  JointHeading heading{};  // how each joint last moved
  // Where the axes stand before a window without a start posture (after a tool change): its
  // first keyframe pays for moving the external axes from there. Empty: not known (the start of
  // a program).
  JointVector standing;
};

// Updates `heading` over a sequence of postures (each joint's last change, ignoring changes
// below `tol` in DH units).
void update_heading(const std::vector<JointVector>& q, JointHeading& heading, double tol = 1e-9);

// Postures the plan may not use (docs/collision.md, "The plan"): on the keyframes marked, each
// lattice node's posture must pass `clear`, which is called from the pool's threads at once and
// must only read shared state. The session marks the keyframes where a plan came too close to
// a body and plans again.
struct PlanNodeFilter {
  std::vector<char> layers;  // per keyframe: 1 where nodes are checked
  std::function<bool(const JointVector& q)> clear;
};

struct PlanWindowResult {
  bool feasible = false;
  double cost = 0.0;           // of the sequence found (before smoothing)
  int dead_keyframe = -1;      // the first keyframe no sequence reaches
  int limiting_joint = -1;     // the joint most often out of its limits there (-1: unknown)
  std::vector<JointVector> q;  // planned posture per keyframe
  long ik_evaluations = 0;
};

class PathPlanner {
 public:
  // The solver keeps pointers: cell and ik must outlive it. Throws Error(bad_input) when the
  // cell has more than kMaxFreeJoints free joints not locked, or a free joint the plan needs
  // has no <speed>.
  PathPlanner(const Cell& cell, const ArmIk& ik, const PathPlanSettings& settings);

  // Plans the keyframes. start: the committed posture at keyframes[0] (its free joints are the
  // lattice's origin, its posture kept); nullptr: the first keyframe is sampled over the free
  // joints' ranges and every posture.
  // beam > 0 overrides settings().beam (a wider search where the first found no sequence).
  // history: how the joints moved before the window (nullptr: not known).
  PlanWindowResult plan(const std::vector<PlanKeyframe>& keyframes, const JointVector* start,
                        int beam = 0, const PlanNodeFilter* filter = nullptr,
                        const PlanHistory* history = nullptr) const;

  // The posture at `target` for the free joints `q_plan` gives (the plan interpolated there, as
  // the tracker follows it): the arm in closed form, in q_plan's posture, nearest to it. False
  // where that posture has no solution within the limits.
  bool solve_at(const TcpTarget& target, const JointVector& q_plan, JointVector& q) const;

  const std::vector<int>& free_joints() const { return free_; }
  const ArmIk& ik() const { return *ik_; }
  const PathPlanSettings& settings() const { return settings_; }

 private:
  bool evaluate(const Isometry& T_B_tcp, const LatticeKey& key, const JointVector& origin,
                const JointVector& q_near, JointVector& q, double& cost, int* limit_joint) const;
  double condition_cost(const JointVector& q) const;
  double compliance_cost(const JointVector& q, const Eigen::Vector3d& feed_B,
                         const Eigen::Vector3d& z_B) const;
  double edge_cost(const PlanKeyframe& from, const PlanKeyframe& to, const JointVector& q0,
                   const JointVector& q1, bool price_cut) const;
  double reversal_cost(const LatticeNode& a, const LatticeNode& b) const;
  double reposition_cost(const JointVector& standing, const JointVector& q) const;
  LatticeDpSettings dp_settings(int beam, const PlanHistory* history) const;
  // The first keyframe's lattice (every free joint over its range, `stride` steps apart).
  std::vector<LatticeKey> first_layer(const PlanKeyframe& kf, JointVector& origin,
                                      int& stride) const;
  void smooth(const std::vector<PlanKeyframe>& keyframes, const LatticeDpResult& r,
              std::vector<JointVector>& q, const PlanNodeFilter* filter) const;

  const Cell* cell_;
  const ArmIk* ik_;
  PathPlanSettings settings_;
  std::vector<int> free_;
  // Per joint: travel weight over the velocity limit (0: no limit known), 1 / (margin * limit),
  // and whether it is an arm joint (its step between keyframes is bounded).
  std::array<double, kMaxJoints> travel_per_unit_{}, need_per_unit_{};
  std::array<double, kMaxJoints> cut_per_unit_{};  // w_travel_cut over the limit (external axes)
  std::bitset<kMaxJoints> arm_;                    // chain indices of the sampled joints
  std::vector<int> timed_;                         // the arm's joints and those with a speed
  double max_arm_step_rad_ = 0.0;
  std::array<double, kMaxFreeJoints> step_{};    // lattice step per free joint (DH units)
  std::array<bool, kMaxFreeJoints> external_{};  // a real axis (not the tool's spin)
};

// The posture planned at path length s_mm, interpolated linearly between keyframes.
JointVector interpolate_plan(const std::vector<PlanKeyframe>& keyframes,
                             const std::vector<JointVector>& q, double s_mm);

}  // namespace redpost
