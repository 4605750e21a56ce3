// The state of a post session (PostSession::Impl) and its steps, shared by the session's
// sources: session.cpp (the public calls, the joints log, finish), motion.cpp (tracking moves,
// rapids against the clearance plane, what is written), tools.cpp (the tool table and tool
// changes).
//
// Internal to redpost::core; not installed.
#pragma once

#include <deque>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cl/arc_chords.hpp"
#include "post/dispatch_stage.hpp"
#include "post/pending_file.hpp"
#include "redpost/collision/cell_bodies.hpp"
#include "redpost/collision/clearance.hpp"
#include "redpost/collision/tool_bodies.hpp"
#include "redpost/kinematics/arm_ik.hpp"
#include "redpost/kinematics/circle.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "redpost/machining/deflection.hpp"
#include "redpost/post/session.hpp"
#include "redpost/redundancy/clearance_goal.hpp"
#include "redpost/timing/path_timer.hpp"

namespace redpost {

// The largest coordinate a move may have (mm): the CL reader's bound, here for the hosts that
// send moves through the ABI. Beyond it a move's length overflows what the steps can count.
inline constexpr double kMaxCoordinateMm = 1e7;

// A plane the tool may be below only on a straight line: points p with n . (p - point) >= 0
// are above it. In CL (part) coordinates.
struct ClearancePlane {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double height(const Eigen::Vector3d& p) const { return normal.dot(p - point); }
};

namespace detail {

// One sample of a replayed controller motion (lin_replay, circ_replay_ok; `what` is "line" or
// "arc"): the arm solved in closed form for the start's Status at T with the other joints from
// q_other, within its limits and without an arm joint jumping more than 10 deg from q_prev; the
// peak |dq/ds| of the arm joints updated. False with why; q_prev becomes the sample's posture.
bool replay_sample(const ArmIk& ik, const Isometry& T, const JointVector& q_other, int status,
                   double s, double ds, const char* what, JointVector& q_prev,
                   JointVector& peak_rate, std::string& why);
// The replay ended at q_end: false (with why) if an arm joint is more than 0.01 deg from q1.
bool replay_ends_at(const ArmIk& ik, const JointVector& q_end, const JointVector& q1,
                    const char* what, std::string& why);

}  // namespace detail

// What planning a window needs to know of the calls released before it (plan.cpp), kept on the
// planning side and advanced over every call a window releases (advance_cursor). It is what the
// tracking of those calls leaves, known without tracking them, so that the next window can be
// planned while they are still being tracked and written (DispatchStage).
struct PlanCursor {
  bool started = false;           // a motion was released
  bool approach_pending = false;  // a tool change was released since the last motion
  bool next_rapid = false;        // a RAPID waits for its motion
  double feed_mm_per_min = std::numeric_limits<double>::quiet_NaN();  // the last FEDRAT
  // The last released motion's end as the plan's walk has it (CL frame, unit axis).
  Eigen::Vector3d cl_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d cl_axis = Eigen::Vector3d::UnitZ();
  bool plan_empty = true;  // no committed plan to go on from (start, tool change, fallback)
  PlanKeyframe tail_kf;    // the last committed keyframe and its posture
  JointVector tail_q;
  JointHeading tail_heading{};  // how each joint last moved in the committed plan
  double plan_s = 0.0;          // path length at the end of the last released motion
  // The next window needs what only tracking gives (the tracker's posture after a stretch
  // tracked without the plan, the new tool's cell): the tracking must have caught up.
  bool sync = false;
};

// The calls one window releases, and what the plan does to the tracking side before them.
struct PlanBatch {
  std::vector<ClEvent> calls;
  std::vector<double> end_s;  // per call: path length at the end of its motion (NaN: none)
  std::vector<Eigen::Vector3d> end_p, end_z;  // ... and the walk's CL point and unit tool axis
  bool reset = false;                         // the plan ends (tool change, fallback) ...
  double reset_plan_s = 0.0;                  // ... and the path length starts here
  std::vector<PlanKeyframe> kf;               // keyframes committed, with their postures
  std::vector<JointVector> q;
  std::vector<std::string> front_warnings;  // the reading's since the batch before, first
  std::vector<std::string> warnings;        // the plan's
  long windows = 0, ik_evaluations = 0, fallback_windows = 0;  // for the summary
  long still_windows = 0;  // of them, with the external axes held (choose_still)
};

// The cell's external axes that move metal (E1..E6 but the tool's virtual spin).
std::bitset<kMaxJoints> external_axes(const Cell& cell);

struct PostSession::Impl {
  const Cell& cell;  // as given, with the chain's TCP
  PostOptions o;
  // The cell of the active tool (its TCP) and the tracker on it; tools keep their cells here so
  // that a tool used twice is made once.
  std::deque<std::pair<int, Cell>> tool_cells;
  const Cell* active_cell;
  Tracker tracker;
  KrlWriter writer;
  ArmStatusModel arm;
  std::unique_ptr<PendingFile> csv;
  fmt::memory_buffer line;

  bool started = false;
  bool prepared = false;          // prepare() ran: the files are complete, no event may follow
  bool approach_pending = false;  // after a tool change: the next move is a PTP approach
  // A move no plan covers (the retract before a tool change): follow_plan holds the external
  // axes where they are instead of Algorithm 1's centring.
  bool hold_unplanned = false;
  bool next_rapid = false;
  double feed_mm_per_min = std::numeric_limits<double>::quiet_NaN();
  bool feed_warned = false;
  TcpTarget last_target;
  // The last move's point and tool axis in CL coordinates: the start of a circular move.
  Eigen::Vector3d last_cl_point = Eigen::Vector3d::Zero();
  Eigen::Vector3d last_cl_axis = Eigen::Vector3d::UnitZ();
  PoseResult last;
  KinematicsData data;
  JointVector q_physical;
  int spin_last = -1;  // chain index of a final pure-spin virtual joint (see physical_tcp)
  PostSummary summary;

  // Tools (tools.cpp).
  int tool_number = -1;  // the active CL tool, -1 before any tool change
  double active_length_mm = std::numeric_limits<double>::quiet_NaN();  // NaN: the cell's TCP
  double first_length_mm = std::numeric_limits<double>::quiet_NaN();   // without a reference
  int first_length_line = 0;

  // CIRC (circ.cpp): the arm's closed-form IK on the active cell, for the replay of a CIRC.
  int templates_position_decimals = 3;
  long program_memory_bytes = 0;  // the set's <limits program-memory> (0: not given)
  std::unique_ptr<ArmIk> arm_ik;
  const Cell* arm_ik_cell = nullptr;
  std::string arm_ik_problem;
  int circ_fallbacks = 0;

  // The time model (timing.cpp): every written motion is timed by `timer`; its joints-log row
  // and its observer sample wait in `pending` until the timer has timed it.
  struct PendingMotion {
    long index = 0;
    int cl_line = 0;
    int first_line = 0;  // the first CL line the motion covers
    KrlMotionKind kind = KrlMotionKind::lin;
    JointVector q;
    AxisValues axes;
    double inv_condition = 0.0;
    int iterations = 0;
    double feed_mm_per_min = std::numeric_limits<double>::quiet_NaN();
    Eigen::Vector3d p_part_mm = Eigen::Vector3d::Zero();
    bool planned = false;  // the tracker followed the whole-path plan at this motion
    JointVector q_plan;    // ... and the plan's posture there
    bool has_deflection = false;
    MotionDeflection deflection;
    double tool_length_mm = std::numeric_limits<double>::quiet_NaN();
    double tcp_shift_mm = 0.0;
    double clearance_mm = std::numeric_limits<double>::quiet_NaN();
    double clearance_proven_mm = std::numeric_limits<double>::quiet_NaN();
    int clearance_pair = -1;
    bool clearance_exact = false;
    Eigen::Vector3d clearance_a = Eigen::Vector3d::Zero(), clearance_b = Eigen::Vector3d::Zero();
  };
  std::unique_ptr<PathTimer> timer;
  std::deque<PendingMotion> pending;
  double asked_m_per_s = std::numeric_limits<double>::quiet_NaN();  // the next CP motion's speed
  bool asked_is_feed = false;  // ... is the CL feed (not the rapid speed)
  bool have_written = false;   // q_written and T_written hold the last written motion
  JointVector q_written;
  Isometry T_written = Isometry::Identity();  // its physical TCP in {B}
  double apo_mm = 0.0;
  int velocity_decimals = 6;
  bool rate_vel = false;  // $VEL.CP lowered to the motion rate (timing.cpp, timed_cp)
  double orientation_velocity_rad_s = 0.0;
  double ptp_velocity_fraction = 1.0, ptp_acceleration_fraction = 1.0;
  // The template set's controller (start_timing): the plan times its candidates with it too.
  ControllerTiming controller_timing;
  // The postures tracked along the last track_line(), when it took several steps: written one
  // by one where the controller's straight line between its ends cannot be proven.
  std::vector<JointVector> line_steps;
  int unproven_lines = 0;
  // The stretch of motions an axis is slowing now (summary.feed_limits, warnings).
  std::optional<FeedLimit> open_limit;
  std::optional<FeedLimit> open_slowdown;
  int slowdown_warnings = 0;
  long slowdown_groups = 0;
  JointVector fraction;

  // The deflection under the cutting forces (deflection.cpp): what the CL file said of the
  // tool, the spindle and the operation; the deflection of the move being written, for the
  // motion at its end.
  double tool_diameter_mm = std::numeric_limits<double>::quiet_NaN();
  enum class Spindle { unknown, on, off } spindle_state = Spindle::unknown;
  double spindle_rpm = std::numeric_limits<double>::quiet_NaN();
  bool spindle_cw = true;
  std::string operation_name;
  long operation_serial = 0;  // operation_start calls so far
  long stats_serial = -1;     // the operation summary.deflection.back() belongs to
  bool compensating = false;  // track_line's messages name the compensation
  std::optional<MotionDeflection> move_deflection;
  KinematicsData deflection_data;

  // NX's MSYS, for the messages of an unreachable first pose.
  int msys_line = 0;
  bool msys_applied = false;
  Eigen::Vector3d msys_z = Eigen::Vector3d::UnitZ();

  // Whole-path planning (plan.cpp): the buffered calls, the committed plan the tracker follows
  // (keyframes and postures, s along the path in {B}), and the path length at last_target.
  std::deque<ClEvent> deferred;
  // An estimate of the buffered path's length (straight between the calls' points) and whether
  // a tool change waits in the buffer: plan_window is tried only when a window may be complete.
  double deferred_length_mm = 0.0;
  Eigen::Vector3d deferred_tail =
      Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  bool deferred_barrier = false;
  PlanCursor cursor;
  // The expander's warnings while the pipeline runs (its tracking thread owns `summary`): they
  // go with the next batch, or into the summary once the tracking has caught up.
  std::vector<std::string> front_warnings;
  // Where the expansion's warnings go while PostSession::front runs (its caller's thread).
  std::vector<PostSession::FrontItem>* front_sink = nullptr;
  // The writer's parts, said where they matter: boundaries in a cut, a program larger than the
  // controller's memory (session.cpp).
  void warn_about_parts();
  void take_front_warnings() {
    for (std::string& w : front_warnings)
      summary.warnings.push_back(std::move(w));
    front_warnings.clear();
  }
  std::unique_ptr<WorkerPool> plan_pool;  // before the planners that use it (destroyed after)
  std::unique_ptr<PathPlanner> planner;
  // The same plan with the cell's rotary external axes (the table) held at home: the first
  // window after an approach is planned both ways and the cheaper kept (plan.cpp).
  std::unique_ptr<PathPlanner> planner_held;
  // Every free external axis held where a window starts (choose_still); null when the cell has
  // none free or the preset never holds them.
  std::unique_ptr<PathPlanner> planner_still;
  const Cell* planner_cell = nullptr;
  std::vector<PlanKeyframe> plan_kf;
  std::vector<JointVector> plan_q;
  double plan_s = 0.0;

  // The front door (cl/expander.hpp): every event of handle() goes through it first, then the
  // point reduction (cl/point_reduction.hpp); the first CL line the move being tracked covers
  // (0: its own), for the joints log.
  ClExpander front;
  PointReducer reducer;
  int move_first_line = 0;

  Impl(const Cell& c, const KrlTemplateSet& templates, const PostOptions& options);

  // --- motion.cpp ----------------------------------------------------------------------------
  [[noreturn]] void fail(const PoseResult& r, int cl_line, const char* what);
  std::string first_pose_advice() const;
  // A posture tracked: counted (unless it corrects the last one, as the deflection compensation
  // does) and taken into the joint ranges and the conditioning.
  void record(const PoseResult& r, int cl_line, bool new_pose = true);
  void emit(KrlMotionKind kind, const JointVector& q, int cl_line);
  KrlMotion motion_at(KrlMotionKind kind, const JointVector& q, int cl_line);
  void after_write(const KrlMotion& m, const JointVector& q, const TimedMotion& t);
  void observe(const PendingMotion& p, const TimedMotion& t, const MotionTiming& mt);
  Isometry physical_tcp(const JointVector& q);
  static int last_pure_spin(const Cell& c);
  TcpTarget target_in_B(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis, int cl_line);
  // A move to p_mm; `cycle` is the clearance of a drilling cycle's move, if it is one.
  void move(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis, int cl_line,
            const ClearancePlane* cycle);
  void first_or_approach(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis, int cl_line,
                         const std::optional<ClearancePlane>& plane);
  // Tracks the straight line from the last target to `target` in steps; false if a rapid's line
  // could not be tracked and its end was solved directly (it must then be a PTP).
  bool track_line(const TcpTarget& target, int cl_line, bool rapid);
  void rapid_move(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis, int cl_line,
                  const std::optional<ClearancePlane>& plane);
  void rapid_piece(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis, int cl_line,
                   const std::optional<ClearancePlane>& plane, bool below);
  bool ptp_stays_above(const JointVector& q0, const JointVector& q1, const ClearancePlane& plane);
  std::optional<ClearancePlane> plane_for(const ClearancePlane* cycle) const;
  void remember_cl(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis);
  // chordal_tolerance_mm: the arc's chords, and the controller's circle, keep within it.
  // How far a CL arc's chords or CIRC may leave it: the chordal tolerance, less the printed
  // decimals' share where the point reduction is on (--fit-tol 0 keeps 0.7's chords).
  double cl_arc_tolerance_mm() const;
  void circular_move(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double radius_mm,
                     const Eigen::Vector3d& p_mm, const Eigen::Vector3d& tool_axis, int cl_line,
                     double chordal_tolerance_mm);

  // --- collision.cpp -------------------------------------------------------------------------
  // The cell's bodies, the set-up's, the active tool's; the scene of them all on the active
  // tool's cell and the monitor that follows the written motions; the clearance of the motion
  // being written (for its joints-log row and observer sample).
  CellBodies cell_bodies;
  std::vector<Body> setup;
  std::vector<Body> tool_bodies_in_use;
  std::unique_ptr<CollisionScene> scene;
  std::unique_ptr<ClearanceMonitor> clearance;
  // The clearance as the tracker's extra goal (redundancy/clearance_goal.hpp): the tracker holds
  // the proxy, which forwards to the goal of the scene in force.
  struct GoalProxy : ExtraGoal {
    const ClearanceGoal* goal = nullptr;
    void add(const JointVector& q, JointVector& h) const override {
      if (goal)
        goal->add(q, h);
    }
  };
  GoalProxy goal_proxy;
  std::unique_ptr<ClearanceGoal> clearance_goal;
  std::optional<MotionClearance> motion_clearance;
  std::vector<std::string> pair_names;  // the scene's, for the observer (by pair index)
  int tool_notes = 0;
  double spline_allowance_mm = 0.0;
  // The last CP motion's TCP direction and length (0: none, or an exact stop since), for the
  // blend at the next one's start.
  Eigen::Vector3d last_cp_direction = Eigen::Vector3d::UnitX();
  double last_cp_length = 0.0;
  void start_collision();
  void rebuild_scene();
  void collision_tool(const ToolEntry* entry, double length_mm, int number, int cl_line);
  void check_clearance(KrlMotionKind kind, const JointVector& q1, int cl_line,
                       const Circle* arc_B = nullptr);
  [[noreturn]] void collision_fail(const MotionClearance& c, KrlMotionKind kind, int cl_line);
  // The planning side's (plan.cpp): the plan's keyframes checked, joined joint-linearly, with the
  // margin and plan_extra_mm; a window whose plan comes too close is planned again without the
  // postures of the keyframes around (PlanNodeFilter).
  std::unique_ptr<ClearanceMonitor> plan_monitor;
  const CollisionScene* plan_monitor_scene = nullptr;
  std::vector<int> unclear_keyframes(const std::vector<JointVector>& q, double need);
  void avoid_in_plan(const std::vector<PlanKeyframe>& kf, PlanWindowResult& r,
                     const PathPlanner& pl, const JointVector* start, const PlanHistory* history,
                     PlanBatch& batch);
  // A rapid's motion from the last written posture to q1 (a PTP, else a LIN) clear of every body,
  // probed without writing; true where nothing is checked.
  bool rapid_clear(const JointVector& q1, bool ptp);
  // The motion from qa to qb as the controller runs it (a PTP, else a LIN through the arm's
  // closed form where it has one) probed by the monitor without writing: clear of every body.
  bool probe_clear(const JointVector& qa, const JointVector& qb, bool ptp);
  // The rapid from the last CL point to p_mm as three LINs: up along the tool axis, over, down
  // along the target's tool axis, 100, 200 or 400 mm up (the first whose legs are all clear);
  // refused (Error) where none is.
  void route_rapid_up(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& axis, int cl_line);
  bool routing_rapid = false;
  // What tracking a move changes before anything is written, to try a move and take it back.
  struct TrackedState {
    long poses = 0;
    std::vector<JointRange> joints;
    double lowest = 0.0;
    int lowest_line = 0;
    double plan_s = 0.0;
    TcpTarget last_target;
    Eigen::Vector3d cl_point, cl_axis;
  };
  TrackedState tracked_state() const;
  void restore_tracked(const TrackedState& s, const JointVector& q);
  // The first pose (or an approach's) clear of every body: the tracker's solution, else the
  // nearest to home of the arm's closed-form postures at its external axes and spins.
  PoseResult clear_first_pose(const TcpTarget& target, const PoseResult& solved);

  // --- deflection.cpp ------------------------------------------------------------------------
  bool deflection_on() const { return o.deflection != DeflectionMode::off; }
  void check_deflection_inputs() const;
  // Tracks a cutting move to the CL target `cam` (p_mm in CL coordinates), predicting its
  // deflection and, under compensate, moving the target against it; returns the target tracked.
  TcpTarget track_cut(const TcpTarget& cam, const Eigen::Vector3d& p_mm, int cl_line);
  bool load_for_move(const TcpTarget& cam, const Eigen::Vector3d& p_mm, int cl_line,
                     CuttingLoad& load);
  ToolDeflection deflection_at(const JointVector& q, const CuttingLoad& load);
  void note_deflection(const MotionDeflection& d, int cl_line);

  // --- timing.cpp ----------------------------------------------------------------------------
  void start_timing(const KrlTemplateSet& templates);
  void set_speed(double m_per_s, bool is_feed);
  // Writes the LIN to the tracker's posture: as one LIN where the controller's straight line
  // between the last written posture and it is proven (lin_replay), else as the steps tracked.
  void emit_line(int cl_line);
  void write_lin(const JointVector& q, int cl_line, const JointVector* replay_peak);
  TimedMotion timed_cp(const JointVector& q0, const Isometry& T0, const JointVector& q1,
                       const Isometry& T1, double length_mm, int cl_line,
                       const JointVector* replay_peak);
  TimedMotion timed_ptp(const JointVector& q1, int cl_line);
  bool lin_replay(const JointVector& q0, const Isometry& T0, const JointVector& q1,
                  const Isometry& T1, JointVector& peak_rate, double length_mm, std::string& why);
  void remember_written(const JointVector& q, const Isometry& T_B);
  void on_timed(const TimedMotion& t, const MotionTiming& mt);
  void record_timed(const TimedMotion& t, const MotionTiming& mt);
  void write_joints_row(const PendingMotion& p, double end_s);
  void close_slowdown();
  void close_limit();
  void finish_timing();
  void timing_stop(double dwell_s);

  // --- circ.cpp ------------------------------------------------------------------------------
  bool try_circ(const detail::ArcChords& arc, const Eigen::Vector3d& tool_axis, int cl_line);
  void arc_chord_moves(const detail::ArcChords& arc, const Eigen::Vector3d& chord_axis,
                       const Eigen::Vector3d& end_axis, bool rapid, int cl_line);
  // The rates of the joints and the TCP's direction at the two ends of a replayed motion, for
  // the time model's corners (a CIRC's are the circle's, not its chord's).
  struct MotionEnds {
    JointVector entry_rate, exit_rate;  // dq/dS, per mm of path
    Eigen::Vector3d entry_tangent = Eigen::Vector3d::Zero(), exit_tangent = Eigen::Vector3d::Zero();
  };
  bool circ_replay_ok(const JointVector& q0, const JointVector& q1, const detail::ArcChords& arc,
                      JointVector& peak_rate, std::string& why, MotionEnds* ends = nullptr);
  const ArmIk* arm_ik_for_active(std::string& why);
  Isometry physical_tcp_fk(const JointVector& q);

  // --- tools.cpp -----------------------------------------------------------------------------
  void tool_change(int number, const std::string& name, double length_mm, int cl_line);
  void use_tool_cell(int number, double length_mm, int cl_line);
  void retract_for_tool_change(int cl_line, double longer_mm);

  // plan.cpp
  bool planning() const { return o.plan == RedundancyPlan::global; }
  // The path a window must see before it is planned: three horizons for the first window after
  // an approach (plan.cpp), one after that.
  double window_mm() const;
  // Plans the next window when the buffer covers it (always with `flush`): moves the calls it
  // releases into `batch` with what the plan does before them; false: wait for more calls.
  bool plan_window(bool flush, PlanBatch& batch);
  void follow_plan(double s_mm);
  void reset_plan();
  std::size_t commit_window(const std::vector<PlanKeyframe>& kf, const std::vector<JointVector>& q,
                            const std::vector<double>& end_s, std::size_t end, double commit_s,
                            bool fresh, PlanBatch& batch) const;
  // The cursor over the calls of a batch (on the planning side).
  void advance_cursor(const PlanBatch& batch);
  // What the plan does before the batch's calls are tracked (on the tracking side).
  void apply_plan(const PlanBatch& batch);
  const PathPlanner& planner_for_active(int cl_line);
  bool choose_still(const std::vector<PlanKeyframe>& kf, const std::vector<PlanKeyframe>& ends,
                    double until_s, const JointVector* start, const PlanHistory& history,
                    PlanWindowResult& r, PlanBatch& batch);

  // The tracking side's thread under PostOptions::plan_threads >= 2 (session.cpp, pump); the
  // last member, so that its thread stops before anything it uses goes.
  std::unique_ptr<DispatchStage<PlanBatch>> stage;
};

}  // namespace redpost
