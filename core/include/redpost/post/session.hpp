// A postprocessing session: CL events in, a KRL program out.
//
// Every front end (the CL file reader, the NX event handlers through the C ABI, other C hosts)
// drives the same session, so the same toolpath gives the same bytes whichever way it came in.
// The session streams: each move is tracked (Andres Algorithm 1, see tracker.hpp) and written at
// once; memory does not grow with the number of poses.
//
// Failures throw Error with the CL source and line ("part.apt:1234: pose 5012 unreachable ...")
// and leave no output that looks finished (the writer's temporary files are removed).
#pragma once

#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "redpost/cl/event.hpp"
#include "redpost/cl/expander.hpp"
#include "redpost/cl/point_reduction.hpp"
#include "redpost/collision/body.hpp"
#include "redpost/collision/setup.hpp"
#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/tool_table.hpp"
#include "redpost/krl/writer.hpp"
#include "redpost/machining/cutting_conditions.hpp"
#include "redpost/redundancy/path_plan.hpp"
#include "redpost/redundancy/tracker.hpp"
#include "redpost/timing/path_timer.hpp"

namespace redpost {

// The tool's deflection under the cutting force at the end of one cutting move
// (docs/deflection.md), at the posture written there. Vectors in the CL (part) frame.
struct MotionDeflection {
  Eigen::Vector3d translation_mm = Eigen::Vector3d::Zero();  // of the TCP
  Eigen::Vector3d rotation_rad = Eigen::Vector3d::Zero();    // small rotation vector
  double normal_mm = 0.0;  // along the machined wall's normal: + the tool cuts too deep
  double force_N = 0.0;    // the mean cutting force's magnitude
  // How far the target was moved against the deflection (0 without compensation), and the error
  // the model leaves at the written posture: the deflected TCP's distance from the CL point and
  // its component along the wall's normal (without compensation: the deflection itself).
  double compensation_mm = 0.0;
  double residual_mm = 0.0;
  double residual_normal_mm = 0.0;
  int iterations = 0;  // of the compensation's fixed point (0 without)
};

// One motion as it is written, for a host that watches the run (the report of `redpost convert`).
// The pointers are valid during the call only; nothing is allocated to make a sample.
// One window's choice between the plan that moves the external axes and the one that holds
// them (PostOptions::on_plan_choice): where the window starts, or in a window with nothing
// committed before it the fastest of a few places its approach may put them. The time model's
// seconds for each over the window's committed path (post/plan_time.hpp; with the approach
// from where the axes stand after a tool change), NaN where that plan has none (it is not
// feasible, or it leaves the room or the conditioning the plan keeps).
struct PlanChoice {
  int first_cl_line = 0, last_cl_line = 0;
  double moving_s = 0.0, still_s = 0.0;
  bool still = false;       // the held plan was taken
  JointVector still_start;  // the held plan's posture at the window's start (empty: none)
};

struct MotionSample {
  long index = 0;  // 1, 2, ... in the order written (the joints CSV's "pose" column)
  KrlMotionKind kind = KrlMotionKind::lin;
  int cl_line = 0;
  const JointVector* q = nullptr;    // DH units (rad, mm), chain order, the virtual joint included
  const AxisValues* axes = nullptr;  // controller values A1..A6, E1..E6 (deg, mm); NaN: unmapped
  double inv_condition = 0.0;        // 1/kappa_F of the arm at q
  int iterations = 0;                // of the solve of the written posture
  // The feed in force for a cutting move (lin); NaN for ptp and rapid motions.
  double feed_mm_per_min = std::numeric_limits<double>::quiet_NaN();
  // The physical TCP (virtual joints at 0: the same point) in the CL (part) frame, mm.
  Eigen::Vector3d p_part_mm = Eigen::Vector3d::Zero();
  // The time model (docs/timing.md): when the motion ends, from the program's start, and how
  // long it takes; the path speed it reaches, what it was asked (feed or rapid speed) and what
  // $VEL.CP was written (lower where an axis limits it); what kept it below the asked speed.
  double time_s = 0.0;
  double duration_s = 0.0;
  double speed_mm_s = 0.0;    // peak path speed (CP motions; 0 for PTP)
  double asked_mm_s = 0.0;    // NaN for PTP
  double command_mm_s = 0.0;  // NaN for PTP
  TimingLimit limit = TimingLimit::none;
  int limit_joint = -1;
  // Per joint (chain order), the largest fraction of its velocity limit it reaches in this
  // motion; 0 for joints without limits.
  const JointVector* speed_fraction = nullptr;
  // The whole-path plan's posture the tracker followed at this motion (docs/redundancy.md);
  // null where none was followed (--plan local, a stretch tracked pose by pose, PTP motions).
  const JointVector* q_plan = nullptr;
  // The deflection at this motion (null where none was predicted: no prediction asked, a rapid,
  // a PTP, a plunge, a drilling cycle, the spindle off, or a step written inside a longer move).
  const MotionDeflection* deflection = nullptr;
  // The tool in force: its length from the spindle's gauge line to the tip (NaN: unknown, the
  // chain's own TCP), and how far its TCP lies beyond the chain's TCP along -z of the TCP frame
  // (cell_for_tool; 0 for the chain's own TCP).
  double tool_length_mm = std::numeric_limits<double>::quiet_NaN();
  double tcp_shift_mm = 0.0;
  // The clearance of the motion (docs/collision.md): the least distance computed between two
  // bodies that may not touch on it (at its end and where the check looked closer; +inf where
  // no pair came within reach of the margin, NaN where nothing is checked), its pair and nearest
  // points in the CL (part) frame; and the proven lower bound of every distance along it.
  double clearance_mm = std::numeric_limits<double>::quiet_NaN();
  double clearance_proven_mm = std::numeric_limits<double>::quiet_NaN();
  const std::string* clearance_pair = nullptr;
  bool clearance_exact = false;
  Eigen::Vector3d clearance_point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d clearance_point_b = Eigen::Vector3d::Zero();
};

// Called for every written motion, after it was written. Empty: no samples are made.
using MotionObserver = std::function<void(const MotionSample&)>;

enum class RedundancyPlan { local, global };

// What the session does with the arm's compliance (docs/deflection.md): nothing, predict the
// tool's deflection at every cutting move, or also move each target against it (a fixed point).
enum class DeflectionMode { off, predict, compensate };

// Collisions (docs/collision.md): the cell's own bodies (its <collision>) are always checked, the
// tool's from the tool table or the CL file, and the set-up's from STL files in the CL frame.
struct CollisionOptions {
  bool check = true;  // false: no body is checked (for tests of what the check changes)
  SetupFiles setup;
  double margin_mm = 5.0;  // the least distance kept between bodies that may not touch
  // The whole-path plan keeps this much more (mm): the tracker follows the plan closely, not
  // exactly, and the plan's keyframes are joined by the joints' straight lines.
  double plan_extra_mm = 10.0;
};

struct PostOptions {
  KrlProgramInfo program;
  TrackerOptions tracker;
  // Where the CL (workpiece) frame sits in the cell's frame {B}. Identity for the reference cell,
  // whose {B} is the workpiece frame on the table.
  Isometry T_B_part = Isometry::Identity();
  // The frame the E6POS coordinates are written in ($BASE), expressed in {B}.
  Isometry T_B_base = Isometry::Identity();
  // Long moves are tracked in steps of at most this length (mm) and this axis turn, so that the
  // redundancy is resolved continuously along them; only the end point is written.
  double max_step_mm = 5.0;
  double max_step_axis_deg = 2.0;
  // Circular moves (circular_move) are split into chords straying at most this far from the arc
  // (mm), like the CL reader's CIRCLE; their ends must lie on one circle within
  // arc_point_tolerance_mm.
  double chordal_tolerance_mm = 0.01;
  double arc_point_tolerance_mm = 0.005;
  // NX's MSYS (cl/expander.hpp): the MCS is the workpiece frame (ignore), or every point after an
  // MSYS is turned into NX's absolute frame (apply).
  MsysMode msys = MsysMode::ignore;
  // Dense CL points merged into fewer straight moves within a tolerance before they are tracked
  // (cl/point_reduction.hpp, docs/timing.md "Point reduction"); tolerance 0: every point kept.
  PointReductionOptions reduction;
  // Feed for cutting moves that come before any FEDRAT (a warning is recorded).
  double default_feed_mm_per_min = 1000.0;
  // Rapids (docs/convert.md, "Rapids"): below a clearance plane a rapid follows the straight
  // line the CL data give (a LIN at rapid_velocity_m_per_s); above it, a joint-interpolated PTP
  // is written where its whole path stays above the plane. The plane is a drilling cycle's
  // clearance for its moves, else z = clearance_z_mm in the CL frame; NaN: none (every rapid
  // outside a cycle is a LIN).
  double clearance_z_mm = std::numeric_limits<double>::quiet_NaN();
  double rapid_velocity_m_per_s = 0.25;
  // A tool table that replaces the cell's entries (docs/tools.md); with no entries anywhere,
  // CL tool n is TOOL_DATA[n] with the CL file's length.
  ToolTable tools;
  // Redundancy resolution along the path (docs/redundancy.md): local is Andres' Algorithm 1 from
  // pose to pose with its secondary goals; global first plans the free joints (table, track,
  // spin) over a horizon of the path ahead (path_plan.hpp) and tracks that plan. Under global
  // the calls are buffered until the horizon is known, so an error may surface a few calls
  // later (its message names its own CL line).
  RedundancyPlan plan = RedundancyPlan::local;
  PathPlanSettings plan_settings;
  double plan_horizon_mm = 800.0;  // path planned ahead before the first half is written
  double plan_follow_gain = 0.5;   // the tracker's pull towards the plan, per pose
  // Threads of the session under the global plan (docs/redundancy.md, "Threads"): 1 the calling
  // thread alone (the default); from 2 on, the calling thread plans the next window while one
  // thread of the session's own tracks and writes the calls the last one released, and from 3
  // on the lattice's nodes are shared among the planning threads; 0 one per core (at most 8).
  // The program is the same for any count.
  int plan_threads = 1;
  // The deflection under the cutting forces (docs/deflection.md): the cell needs six joint
  // stiffnesses; `cutting` gives what the force model needs beyond the CL file, per operation.
  // The tolerance is the one the report draws the normal deflection against (mm).
  DeflectionMode deflection = DeflectionMode::off;
  CuttingTable cutting;
  double deflection_tolerance_mm = 0.05;
  // Name of the CL source, for messages ("part.apt").
  std::string source_name = "<cl>";
  // One row per written motion: pose, CL line, joints in DH units, controller axes. Empty: none.
  std::string joints_csv_path;
  CollisionOptions collision;
  // Sees every written motion (see MotionSample), in order; under plan_threads >= 2 on the
  // session's tracking thread (never two calls at once). Empty: none, at no cost.
  MotionObserver on_motion;
  // Sees each window where the plan moved an external axis and the plan holding them was timed
  // against it (PathPlanSettings::hold_gain, docs/redundancy.md "Held or moved"), on the thread
  // that plans (under plan_threads >= 2 not the caller's). Empty: none.
  std::function<void(const PlanChoice&)> on_plan_choice;
};

struct JointRange {
  double lowest = 0.0, highest = 0.0;             // DH units
  double margin_lower = 0.0, margin_upper = 0.0;  // smallest distance to each limit
};

// A stretch of consecutive motions where one axis keeps the feed below what the CL file asks
// (docs/timing.md): CL lines, the axis, the lowest speed reached and the speed asked.
struct FeedLimit {
  int first_line = 0, last_line = 0;
  long motions = 0;
  int joint = -1;  // chain index; -1 for the motion rate and the look-ahead (no axis)
  TimingLimit limit = TimingLimit::axis_velocity;
  double lowest_mm_per_min = 0.0;
  double asked_mm_per_min = 0.0;
};

// The predicted deflection over one CL operation (docs/deflection.md): the cutting moves with a
// load, the largest and RMS deflection and its normal component, and after compensation the
// model's residual.
struct DeflectionStats {
  std::string operation;  // the CL operation's name ("" before any)
  int first_line = 0, last_line = 0;
  long motions = 0;  // cutting moves with a modelled load
  double max_mm = 0.0, rms_mm = 0.0;
  double max_normal_mm = 0.0, rms_normal_mm = 0.0;  // |normal component|
  int max_normal_line = 0;
  double max_rotation_rad = 0.0;
  double max_force_N = 0.0;
  long over_tolerance = 0;  // motions whose |normal component| passes the tolerance
  // After compensation (equal to the above without it).
  double max_residual_mm = 0.0;
  double max_residual_normal_mm = 0.0;
  long over_tolerance_after = 0;
  double max_compensation_mm = 0.0;
};

struct PostSummary {
  long poses = 0;    // postures tracked (including the intermediate steps of long moves)
  long motions = 0;  // motions written
  double lowest_inv_condition = 1.0;
  int lowest_inv_condition_line = 0;  // CL line where it occurred
  std::vector<JointRange> joints;     // per joint, chain order
  std::vector<std::string> warnings;
  std::vector<std::string> files;  // final .src files written (after finish)

  // The time model (docs/timing.md), complete after finish().
  double cycle_time_s = 0.0;         // every motion and dwell (not the tool changes' own time)
  double cutting_time_s = 0.0;       // the motions at a CL feed, as the controller runs them
  double feed_time_s = 0.0;          // the same motions at exactly the feed the CL file asks
  bool axis_speeds_known = false;    // the cell gives its axes' speeds (else they limit nothing)
  long slowed_motions = 0;           // motions written with a lower $VEL.CP (an axis's limit)
  double peak_speed_fraction = 0.0;  // the largest fraction of a velocity limit any axis reaches
  int peak_speed_joint = -1;
  int peak_speed_line = 0;
  std::vector<FeedLimit> feed_limits;  // where an axis keeps the feed 5 % or more below the ask
  long feed_limits_total = 0;          // how many there were (feed_limits keeps the first 1000)
  int untimed_tool_changes = 0;        // tool changes (HALT or a routine) the model cannot time
  // The controller's clock (docs/timing.md, "The interpolation cycle").
  double interpolation_cycle_s = 0.0;  // the template set's
  long cp_motions = 0;                 // CP motions timed (LIN, CIRC, SLIN)
  long below_cycle_motions = 0;        // of them, lasting less than one cycle at their $VEL.CP
  long rate_limited_motions = 0;       // CP motions kept slow by the motion rate (one per cycle):
                                       // below a cycle, or written at it (rate_slowed_motions)
  long lookahead_limited_motions = 0;  // of them, slowed by the look-ahead ($ADVANCE)
  double shortest_motion_s = 0.0;      // the shortest CP motion at its $VEL.CP (0: none)
  int shortest_motion_line = 0;        // its CL line
  // The point reduction (PostOptions::reduction): the cutting GOTOs it could merge, and the
  // moves tracked for them (both 0 without the reduction).
  long reducible_points = 0;
  long reduced_moves = 0;
  long reduced_arcs = 0;  // of the moves, arcs fitted through the points (a set with CIRC)
  // With the reduction on, the motions that even so would last less than one cycle at the feed,
  // written with the $VEL.CP at which they last one (docs/timing.md, "Point reduction").
  long rate_slowed_motions = 0;

  // The whole-path plan (PostOptions::plan global; docs/redundancy.md).
  long plan_windows = 0;           // windows planned
  long plan_fallback_windows = 0;  // of them, tracked pose by pose (no sequence on the lattice)
  // ... with the external axes held, since that was faster than moving them
  // (PathPlanSettings::hold_gain) or kept the arm's conditioning where moving them did not.
  long plan_still_windows = 0;
  long plan_ik_evaluations = 0;  // lattice nodes solved (closed-form IK of one posture each)

  // Collisions (PostOptions::collision; docs/collision.md): the bodies and the pairs checked, and
  // the least clearance along the program (a lower bound, proven between the poses), its CL
  // line and pair.
  bool collision_checked = false;  // some pair of bodies was checked
  int collision_bodies = 0, collision_pairs = 0;
  double collision_margin_mm = 0.0;
  double least_clearance_mm = std::numeric_limits<double>::infinity();  // computed, closest
  int least_clearance_line = 0;
  std::string least_clearance_pair;
  double proven_clearance_mm = std::numeric_limits<double>::infinity();  // the lower bound
  long clearance_queries = 0;  // distances computed (for the benchmark)

  // The deflection (PostOptions::deflection), per CL operation in order.
  DeflectionMode deflection_mode = DeflectionMode::off;
  double deflection_tolerance_mm = 0.0;
  std::vector<DeflectionStats> deflection;
  long unloaded_moves = 0;           // cutting moves without a modelled load (plunges, spindle off)
  long compensation_iterations = 0;  // fixed-point iterations beyond the first, over the program
  int max_compensation_iterations = 0;  // the most any move needed
};

struct PlanBatch;  // post/session_impl.hpp

// The point reduction a session runs with these options, writer and template set (the share of
// the tolerance the printed decimals and a spline's SPL segments leave it).
PointReductionOptions session_reduction(const PostOptions& o, const KrlWriter& writer,
                                        const KrlTemplateSet& t);

class PostSession {
 public:
  PostSession(const Cell& cell, const KrlTemplateSet& templates, const PostOptions& options);
  ~PostSession();
  PostSession(const PostSession&) = delete;
  PostSession& operator=(const PostSession&) = delete;

  // One event of the toolpath (cl/event.hpp), from any front end: expanded by the session's
  // ClExpander (drilling cycles, NURBS, MSYS, operator text) and tracked. Throws Error with the
  // event's line; under the global plan a motion's tracking (and its error) may come a few
  // events later.
  void handle(const ClEvent& event);

  // handle() in two parts, for a host with a thread to spare (the C ABI's pipeline): front() is
  // the expansion and the point reduction, which depend on nothing the tracking does, and gives
  // its output in order, the expansion's warnings among the events; route_front() takes each
  // item on the session's thread. Together they are handle(): the same program, the same
  // warnings in the same order. front() may run on one thread while route_front() runs on
  // another; no other call may run on the session meanwhile. When front() throws, `out` holds
  // what it gave before the error: the host lets the session's thread take those and every item
  // before them, then calls rethrow_earlier(), which throws a tracking thread's failure (told
  // first, as handle() does), and only then tells front()'s error.
  struct FrontItem {
    ClEvent event;
    std::string warning;
    bool is_warning = false;  // a warning of the expansion, in its place among the events
  };
  void front(const ClEvent& event, std::vector<FrontItem>& out);
  void route_front(const FrontItem& item);
  // Under the global plan with threads: the tracking thread's failure, if one came, thrown.
  void rethrow_earlier() const;

  // Completes the program and the joints log, flushed to the disk but not renamed, and returns
  // the summary (complete but for `files`): every check has run, and a full disk has shown.
  // The host may now write its own files (a report) before the program replaces an old one.
  const PostSummary& prepare();
  // prepare() if not done, then renames the files into place, and returns the summary.
  const PostSummary& finish();

  // Replaces PostOptions::on_motion, for hosts that attach an observer after opening. Under
  // PostOptions::plan_threads >= 2 the observer is called on the session's tracking thread.
  void set_motion_observer(MotionObserver observer);

  // The bodies of the collision check in force (the cell's, the set-up's, the last tool's;
  // docs/collision.md), for a host that draws them; empty where nothing is checked.
  std::vector<Body> collision_bodies() const;

  const PoseResult& last_pose() const;
  const PostSummary& summary() const;
  const Cell& cell() const;

 private:
  // A plain event (the expander's output) to the calls below.
  void route(const ClEvent& event);

  // A tool change at CL line `cl_line` (docs/tools.md): the tool's TOOL_DATA and TCP from the
  // tool table; a retract along the tool axis to the clearance plane first, a PTP approach to
  // the next move after.
  void tool_change(int number, const std::string& name, double diameter_mm, double length_mm,
                   int cl_line = 0);
  void spindle(double rpm, SpindleDirection direction, int cl_line = 0);
  // A feed the controller can take: $VEL.CP within (0, 2] m/s and not 0 at the template set's
  // decimals; else Error(bad_input) at cl_line.
  void feed(double mm_per_min, int cl_line = 0);
  void rapid();  // the next move is a rapid traverse
  void move(const Eigen::Vector3d& p_mm, const Eigen::Vector3d& tool_axis, int cl_line);
  // An arc from the last move's CL point to p_mm about the axis through `centre`, turning by the
  // right-hand rule (a helix if the height along the axis changes), written as the moves of its
  // chords within PostOptions::chordal_tolerance_mm. radius_mm > 0 is checked against the start;
  // 0: taken from the start. The chords keep the previous tool axis, the last one takes
  // `tool_axis`, as the CL reader does for CIRCLE.
  void circular_move(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double radius_mm,
                     const Eigen::Vector3d& p_mm, const Eigen::Vector3d& tool_axis, int cl_line);
  void coolant(bool on, const std::string& mode);
  // A dwell (a drilling cycle's, NX's MOM_delay): 0 to kMaxDwellSeconds.
  void dwell(double seconds, int cl_line = 0);
  // NX's MSYS as the reader saw it (ClEventKind::machine_frame): remembered for the messages.
  void machine_frame(const Eigen::Vector3d& z_mcs_in_absolute, bool applied, int cl_line);
  void operation_start(const std::string& name);
  void operation_end();
  void comment(const std::string& text);
  // KRL code passed through: refused (Error bad_input at cl_line) unless it is one statement of
  // the kinds redpost checks (krl/statement.hpp: assignment, WAIT, HALT, a routine call).
  void literal(const std::string& text, int cl_line = 0);

  // Under PostOptions::plan global: buffers the call (true) and releases what a plan covers.
  bool defer(const ClEvent& event);
  void pump(bool flush);
  void dispatch(PlanBatch& batch);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace redpost
