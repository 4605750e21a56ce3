// The time a controller needs for the written motions, with every axis within its velocity and
// acceleration limits (docs/timing.md).
//
// The profile is trapezoidal along the path. A CP motion (LIN, CIRC, SLIN) of path length S runs
// at most at its cruise speed, the lowest of the $VEL.CP written for it and the path speed at
// which its fastest axis reaches its velocity limit; it speeds up and slows down at the path
// acceleration, the lowest of $ACC.CP and what each axis's acceleration limit allows. Blended
// motions pass their junction at a speed bounded by both cruise speeds and by the corner: over
// the blend, an axis's rate dq/ds changes by |r_next - r| and needs v^2 |r_next - r| / d of
// acceleration (d: the blend length); the TCP's direction change needs v^2 |t_next - t| / d. A
// motion that ends exactly (a PTP, a CP motion without blending, a statement that stops the
// advance) has speed 0 there. A PTP takes the time of KUKA's synchronous PTP: every axis starts
// and stops with the slowest one, each with a trapezoid at the template set's PTP share of its
// limits.
//
// The controller's clock (docs/timing.md, "The interpolation cycle"): a KR C4 interpolates on
// a fixed cycle (12 ms) and prepares each motion block in its advance run, so a CP motion lasts
// at least one cycle: its cruise speed is at most length / cycle. And the planner sees only the
// next $ADVANCE motions: it must be able to stop within them, which bounds every motion's exit
// speed by the speed from which the motions it sees can still stop.
//
// The junction speeds come from the classic two passes (backward from the next stop, forward
// from the last one). They are streamed: a motion is timed once no later motion can change it,
// that is once the motions after it are long enough to stop from its speed; memory stays
// bounded by that look-ahead, not by the program's length.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <vector>

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost {

// What the controller does that the profile depends on (the template set's <timing>,
// docs/krl-templates.md).
struct ControllerTiming {
  double path_acceleration_mm_s2 = 2000.0;                // $ACC.CP
  double orientation_velocity_rad_s = deg_to_rad(200.0);  // $VEL.ORI1
  double ptp_velocity_fraction = 1.0;                     // BAS (#VEL_PTP, n): n / 100
  double ptp_acceleration_fraction = 1.0;                 // BAS (#ACC_PTP, n): n / 100
  double interpolation_cycle_s = 0.012;                   // the IPO cycle; 0: not modelled
  // Motions the path planner sees beyond the current one ($ADVANCE; for SPLINE blocks, planned
  // whole, the block's size). 0: every motion ends at rest; negative: unlimited.
  int lookahead_motions = 3;
};

// The most motions a look-ahead may span (a SPLINE block is at most this long in the model).
inline constexpr int kMaxLookaheadMotions = 4096;

// What kept a motion below the speed the CAM file asked for.
enum class TimingLimit : std::uint8_t {
  none,               // it reaches the asked speed
  axis_velocity,      // an axis's velocity limit: $VEL.CP was written lower
  axis_acceleration,  // an axis's acceleration limit (speeding up or slowing down)
  path_acceleration,  // $ACC.CP: a short motion between stops
  corner,             // a blended corner (an axis's rate or the TCP's direction changes)
  orientation,        // the orientation speed ($VEL.ORI1) on a motion that mostly turns
  stop,               // an exact stop (a PTP, a tool change, a dwell) before or after it
  motion_rate,        // shorter than one interpolation cycle at the asked speed
  lookahead,          // the planner's look-ahead ($ADVANCE motions) is too short to stop in
  curvature,          // a CIRC's radius: the TCP's normal acceleration v^2 / r at most $ACC.CP
};
const char* to_string(TimingLimit limit);

struct TimedMotion {
  enum class Kind : std::uint8_t { cp, ptp };
  Kind kind = Kind::cp;
  long index = 0;  // motion number, 1, 2, ... (the joints CSV's pose)
  int cl_line = 0;
  // CP: the path parameter's length S (mm): the TCP's path, or for a motion that mostly turns,
  // its turn at the orientation speed expressed as mm at the commanded speed.
  double length_mm = 0.0;
  double tcp_length_mm = 0.0;  // the TCP's path alone
  bool at_feed = false;        // a cutting motion at a CL feed (not a rapid)
  double asked_mm_s = 0.0;     // what the CL file asked (its feed, or the rapid speed)
  double command_mm_s = 0.0;   // $VEL.CP as written (<= asked; lower where an axis limits it)
  int command_joint = -1;      // the joint whose velocity limit lowered $VEL.CP, -1: none,
                               // kMotionRate: lowered so that the motion lasts one IPO cycle
  static constexpr int kMotionRate = -2;
  double orientation_cap_mm_s = std::numeric_limits<double>::infinity();
  // A CIRC's 1 / radius (0: straight): it runs at most at sqrt($ACC.CP / curvature), the speed at
  // which its normal acceleration is the path acceleration (as the corner rule bounds a blend).
  double curvature_per_mm = 0.0;
  // The rate of every joint along the path, dq/dS (rad or mm per mm), the largest over the
  // motion in magnitude (for the limits) and the chord's (signed, for the corners).
  JointVector peak_rate, chord_rate;
  // At its two ends (the corners with the motions before and after it): the joints' rates and
  // the TCP's direction (unit, or 0). A LIN's are its chord's; a CIRC's the circle's at its ends.
  // An entry_rate of another size than chord_rate: not given, the chord's (and tangent's).
  JointVector entry_rate, exit_rate;
  Eigen::Vector3d tangent = Eigen::Vector3d::Zero();  // at the start
  Eigen::Vector3d exit_tangent = Eigen::Vector3d::Zero();
  double blend_mm = 0.0;  // blending distance at its end; 0: exact stop
  // It starts at a point a SPLINE block passes smoothly (an SPL knot): the turn there is spread
  // over half of the shorter of its two segments, whatever the blend before it.
  bool entry_smooth = false;
  bool stop_after = false;     // a statement after it stops the advance (HALT, WAIT, a call)
  double dwell_after_s = 0.0;  // WAIT SEC after it
  // PTP: its time, stop to stop; and the joint that sets it.
  double ptp_time_s = 0.0;
  int ptp_joint = -1;
};

struct MotionTiming {
  double start_s = 0.0;     // from the program's start
  double duration_s = 0.0;  // of the motion (a dwell after it is not included)
  double entry_mm_s = 0.0, exit_mm_s = 0.0, peak_mm_s = 0.0;  // path speed (CP)
  TimingLimit limit = TimingLimit::none;
  int joint = -1;  // the joint behind `limit` (axis_velocity, axis_acceleration, corner)
  // The largest fraction of its velocity limit any joint reaches, and which (-1: no limits).
  double axis_fraction = 0.0;
  int axis_fraction_joint = -1;
  // CP: the motion would last less than one interpolation cycle at its asked speed.
  bool below_cycle = false;
  // CP: a SPLINE segment joined smoothly to a neighbour (TimedMotion::entry_smooth, its own or
  // the next one's): part of one path, with no cycle of its own.
  bool spline_joined = false;
};

class PathTimer {
 public:
  using Callback = std::function<void(const TimedMotion&, const MotionTiming&)>;

  // The cell gives the axes' limits (Joint::max_velocity, max_acceleration; without them the
  // axes limit nothing). `done` is called for every motion, in order, once it is timed.
  PathTimer(const Cell& cell, const ControllerTiming& controller, Callback done);

  // A motion as written. Its rates, tangent and blend are read as given.
  void push(const TimedMotion& motion);
  // A statement between motions that stops the advance (HALT, WAIT SEC s, a routine call).
  void stop(double dwell_s = 0.0);
  // Times everything left (the program ends at rest).
  void finish();

  double elapsed_s() const { return clock_s_; }  // of the motions timed so far
  std::size_t buffered() const { return buffer_.size(); }

  // Largest path speed at which every axis stays within its velocity limit, given the rates;
  // `joint` gets the limiting one (-1, and +inf, when none limits).
  static double velocity_cap(const Cell& cell, const JointVector& rate, int* joint);
  // Same for the path acceleration.
  static double acceleration_cap(const Cell& cell, const JointVector& rate, int* joint);
  // Time of a stop-to-stop trapezoid over `distance` at `v_max` and `a_max`.
  static double stop_to_stop_s(double distance, double v_max, double a_max);
  // Time of a trapezoid over `length` from speed v0 to v1 at most v_cap with acceleration a
  // (v0 and v1 must be reachable from each other within the length).
  static double segment_s(double length, double v0, double v1, double v_cap, double a);

 private:
  struct Entry {
    TimedMotion m;
    double cruise = 0.0;       // cruise speed cap
    double accel = 0.0;        // path acceleration
    int accel_joint = -1;      // joint that set accel (below $ACC.CP), -1
    double junction = 0.0;     // cap of the junction at its end
    int corner_joint = -1;     // joint whose corner term set `junction` (-2: the TCP direction)
    double cruise_free = 0.0;  // the cruise cap without the motion rate (an SPL segment's)
    double rate_cap = std::numeric_limits<double>::infinity();       // length / interpolation cycle
    double curvature_cap = std::numeric_limits<double>::infinity();  // sqrt(a_path r)
    bool lookahead_bound = false;  // the look-ahead lowered `junction`
    bool joined = false;           // joined smoothly to a neighbour in a SPLINE block
    double exit = 0.0;             // planned exit speed
  };
  // What the look-ahead needs of the last motions, also of those already timed.
  struct Recent {
    double length_mm = 0.0, accel = 0.0;
    bool ptp = false;
  };
  void bound_by_lookahead();
  void plan(bool final_flush);
  void emit_front(std::size_t count);

  const Cell* cell_;
  ControllerTiming controller_;
  Callback done_;
  std::deque<Entry> buffer_;
  std::vector<Recent> recent_;  // ring of the last lookahead + 1 motions
  long pushed_ = 0;             // motions pushed so far
  long last_stop_ = -1;         // the last motion that is a PTP or ends at rest
  double entry_speed_ = 0.0;    // speed at the start of buffer_.front()
  double clock_s_ = 0.0;
  std::size_t since_plan_ = 0;
};

}  // namespace redpost
