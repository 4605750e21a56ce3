// Stiffness-aware workpiece placement and tool-spin planning (Caro 2014 chapter 5, issue 8).
// docs/placement.md gives the frames, the path, the algorithms and the choices made.
//
// Outer problem: the placement (x_OW, y_OW, z_OW, Q4) of eq. 5.17, searched with NLopt (a
// global method, then a local refinement). Inner problem, for one placement: the machining
// quality c_i (eq. 5.1) on a grid of spin angles beta for every path point and posture mu, then
// the spin plan beta_1..beta_n and one posture per segment by dynamic programming, the global
// optimum of f_MQC (eq. 5.3) on the grid under the continuity bounds.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "redpost/kinematics/arm_ik.hpp"
#include "redpost/kinematics/types.hpp"
#include "redpost/machining/placement_job.hpp"

namespace redpost {

// The decision variables of the outer problem: O_W in F0 (mm) and Q4.
struct Placement {
  double x_mm = 0.0, y_mm = 0.0, z_mm = 0.0;
  double q4 = 0.0;
};

// Eq. 2.8: 0T_W, a rotation about z_0 by theta = 2 atan2(Q4, Q1), Q1 = sqrt(1 - Q4^2) (the
// printed (2,1) entry misses the factor 2; the matrix is a rotation only with it).
Isometry workpiece_frame(const Placement& p);

// One point of the tool path: its frame F_Pi in F_W (x along the feed, z along the tool axis
// towards the robot), its segment and the mean cutting force ON THE WORKPIECE in F_Pi (N).
struct PathPoint {
  Isometry T_W_P = Isometry::Identity();
  int segment = 0;
  Eigen::Vector3d force_on_workpiece_P_N = Eigen::Vector3d::Zero();
};

// The tool path of the job's contour: each segment offset by the tool radius away from the
// material, `points` points at the middles of equal parts.
std::vector<PathPoint> tool_path(const PlacementJob& job);

// Eq. 2.7 solved for the chain's TCP: with 7T_Pi(beta) = Rz(beta) Rx(pi) (eq. 2.10) and the TCP
// being F7 turned by the virtual joint beta, T_B_tcp = T_B_0 0T_W WT_Pi Rx(pi) whatever beta,
// and beta is the virtual joint's value.
Isometry tcp_target(const Cell& cell, const Isometry& T_0_W, const Isometry& T_W_P);

// The spin grid: beta_b = -pi + b * step, b = 0 .. count - 1. Cyclic: b = count - 1 and b = 0
// are neighbours (beta is the tool's free spin, not a joint with ends).
struct SpinGrid {
  int count = 72;
  double step_rad = deg_to_rad(5.0);
  double beta_rad(int b) const { return -kPi + b * step_rad; }
};

inline constexpr int kPostures = 8;

// c_i over (path point i, grid beta b, posture mu) and the arm joints there. NaN marks an
// infeasible cell: no valid IK, beyond a joint limit, 1/kappa_F <= the minimum, c_i > c_max.
struct CostMap {
  int points = 0;
  int betas = 0;
  std::vector<double> c_mm;   // [(i * betas + b) * 8 + mu - 1]
  std::vector<double> q_arm;  // [((i * betas + b) * 8 + mu - 1) * 6 + k], A1..A6 chain values
  // Points whose rows were computed (an early stop leaves the rest unfilled).
  std::vector<unsigned char> computed;

  void resize(int n_points, int n_betas);
  size_t index(int i, int b, int mu) const {
    return (static_cast<size_t>(i) * static_cast<size_t>(betas) + static_cast<size_t>(b)) * 8 +
           static_cast<size_t>(mu - 1);
  }
  double c(int i, int b, int mu) const { return c_mm[index(i, b, mu)]; }
  bool feasible(int i, int b, int mu) const {
    return c_mm[index(i, b, mu)] == c_mm[index(i, b, mu)];
  }
  const double* q(int i, int b, int mu) const { return &q_arm[index(i, b, mu) * 6]; }
};

// A run of consecutive path points that keeps one posture.
struct SegmentRange {
  int first = 0;
  int count = 0;
};

// What a plan may do between consecutive points of a segment.
struct ContinuityLimits {
  int max_beta_steps = 2;            // |beta_{i+1} - beta_i| <= this many grid steps
  double max_joint_step_rad = 0.35;  // every arm joint, modulo 2 pi where it wraps
  std::array<bool, 6> wraps{};       // the joint's range spans 2 pi or more
};

enum class PlanGoal { best, worst };

struct SpinPlan {
  bool feasible = false;
  int infeasible_segment = -1;  // the first segment without a plan
  std::vector<int> beta_index;  // per path point
  std::vector<int> mu;          // per segment, 1..8
  double f_mqc_mm = 0.0;        // eq. 5.3
  double max_c_mm = 0.0;        // max c_i along the plan (eq. 5.12)
};

// Reusable buffers of plan_spin (no allocation once grown).
struct DpWorkspace {
  std::vector<double> value;
  std::vector<int> parent;
};

// The globally optimal plan on the grid: per segment and posture, a Viterbi pass over the beta
// grid; per segment the posture with the best total; segments are independent (the posture and
// the spin may change at a corner). Goal best minimises sum c_i, worst maximises it. Ties go to
// the lowest posture, then the lowest beta index.
SpinPlan plan_spin(const CostMap& map, const std::vector<SegmentRange>& segments,
                   const ContinuityLimits& limits, PlanGoal goal, DpWorkspace& ws);

// The result of the inner problem for one placement.
struct InnerResult {
  bool feasible = false;
  // Share of the path points found to have at least one feasible cell before the evaluation
  // stopped (1 when feasible): a graded infeasibility for the outer penalty.
  double reached_fraction = 0.0;
  SpinPlan best, worst;
};

struct InnerWorkspace {
  CostMap map;
  DpWorkspace dp;
};

class PlacementProblem {
 public:
  // Throws Error(bad_input) for a cell that the IK or the stiffness model cannot handle.
  explicit PlacementProblem(const PlacementJob& job);
  ~PlacementProblem();
  PlacementProblem(const PlacementProblem&) = delete;
  PlacementProblem& operator=(const PlacementProblem&) = delete;

  const PlacementJob& job() const { return job_; }
  const Cell& cell() const { return job_.cell; }
  const std::vector<PathPoint>& path() const { return path_; }
  const std::vector<SegmentRange>& segments() const { return segments_; }
  const SpinGrid& grid() const { return grid_; }
  const ContinuityLimits& continuity() const { return continuity_; }
  const ArmIk& ik() const { return *ik_; }
  int spin_joint() const { return spin_joint_; }

  // c_i of eq. 5.1 at the full joint vector q for path point i of the placement whose wrench
  // in {B} (applied TO the TCP) is w_B and whose y_Pi axis (= x_Pi x z_Pi) in {B} is y_B.
  // NaN when 1/kappa_F is at or below the minimum. No allocation.
  double deflection_mm(const JointVector& q, const Vector6d& w_B, const Eigen::Vector3d& y_B,
                       double* inv_kappa = nullptr) const;

  // Fills the cost map of a placement. With early_stop, each worker stops at its first point
  // without a feasible cell (deterministic: the points are dealt to the workers by parity).
  // Returns the number of points found to have a feasible cell.
  int fill_cost_map(const Placement& p, CostMap& map, bool early_stop) const;

  // The inner problem: cost map, then the best (and with_worst, the worst) plan.
  InnerResult solve(const Placement& p, InnerWorkspace& ws, bool with_worst) const;

  // The wrench applied TO the TCP in {B} for point i (the opposite of the force on the
  // workpiece, acting at the middle of the axial depth of cut) and y_Pi in {B}.
  void point_load(const Isometry& T_B_W, int i, Vector6d& w_B, Eigen::Vector3d& y_B) const;

  // The full joint vectors of a plan at a placement, the 2 pi representatives of the wrapping
  // joints chosen continuously along each segment. Throws Error(bad_input) when the plan is not
  // feasible or a joint would jump (wrap beyond its limits).
  std::vector<JointVector> joint_path(const Placement& p, const SpinPlan& plan) const;

 private:
  PlacementJob job_;
  std::vector<PathPoint> path_;
  std::vector<SegmentRange> segments_;
  SpinGrid grid_;
  ContinuityLimits continuity_;
  std::unique_ptr<ArmIk> ik_;
  std::array<int, 6> compliant_{};
  std::array<double, 6> compliance_{};  // 1 / k_theta, rad / (N mm)
  int spin_joint_ = -1;
  void fill_points(const Placement& p, CostMap& map, bool early_stop, int first, int stride,
                   int& reached, int& first_failure) const;
};

// One point of the optimiser's convergence history.
struct ConvergencePoint {
  int evaluations = 0;
  double best_f_mqc_mm = 0.0;  // of the feasible placements so far (NaN: none yet)
};

struct PlacementSearch {
  Placement placement;
  InnerResult inner;  // at the placement, with both plans
  std::vector<ConvergencePoint> history;
  int evaluations = 0;
  int feasible_evaluations = 0;
};

// Goal best: minimise f_MQC of the best plan over the work volume; worst: maximise it. Global
// algorithm then local refinement (job.optimiser), penalty for infeasible placements, seeded
// (nlopt_srand) and deterministic. Throws Error(unreachable) when no feasible placement is found.
PlacementSearch search_placement(const PlacementProblem& problem, PlanGoal goal,
                                 const OptimiserSettings& settings);

// The four cases of Caro Table 5.1.
struct PlacementStudy {
  PlacementSearch best, worst;
  // best_placement_best_spin, best_placement_worst_spin, worst_placement_best_spin,
  // worst_placement_worst_spin
  std::array<SpinPlan, 4> cases;
  static constexpr std::array<const char*, 4> kCaseNames = {
      "best_placement_best_spin", "best_placement_worst_spin", "worst_placement_best_spin",
      "worst_placement_worst_spin"};
};

PlacementStudy run_placement_study(const PlacementProblem& problem,
                                   const OptimiserSettings& settings);

// Uniformly random placements in the work volume (seeded), for comparisons with the optimiser.
Placement random_placement(const WorkVolume& v, unsigned long long& state);

}  // namespace redpost
