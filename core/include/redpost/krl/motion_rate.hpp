// The motion rate of a written program (`redpost check`, docs/timing.md "The interpolation
// cycle"): which CP motions last less than one interpolation cycle at the $VEL.CP in force.
//
// A KR C4 interpolates on a fixed cycle (12 ms) and prepares at most one motion block per cycle:
// a LIN, CIRC or SLIN that its $VEL.CP would run in less than a cycle cannot run at that speed.
// Recomputed from the program's own text: the TCP path between the printed positions (a CIRC's
// arc through its auxiliary point), the turn at $VEL.ORI1, at the $VEL.CP in force (or the
// motion's own, WITH $VEL.CP). Segments of a SPLINE block joined smoothly (an SPL and its
// neighbour in the block) are one path to the controller and are not counted.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "redpost/krl/reader.hpp"

namespace redpost {

// "Less than a cycle": below 1 - 1e-4 of it, so that a motion of exactly one cycle (2 mm at
// 10 m/min) is not decided by the printed $VEL.CP's last decimal.
inline constexpr double kKrlBelowCycle = 1.0 - 1e-4;

// The $VEL.CP (m/s) at which a CP motion of `length_mm` lasts one interpolation cycle, as a
// check of the printed program measures it: the length taken short by what the printed
// decimals of both ends may take off it (sqrt(3) units of the last position decimal), the speed
// rounded down to the printed decimals (at least one unit). NaN where the motion lasts a cycle
// at `vel_m_per_s` already, or that length is not above 0. The motion-rate speeds the program
// states (the session's LINs, a spline set's lone SLINs) come from here.
double krl_cycle_velocity(double length_mm, double vel_m_per_s, double cycle_s,
                          int position_decimals, int velocity_decimals);

struct KrlMotionRateOptions {
  double interpolation_cycle_s = 0.012;       // KR C2 and KR C4
  double orientation_velocity_deg_s = 200.0;  // $VEL.ORI1 (BAS (#INITMOV,0)'s, docs/timing.md)
};

// Consecutive CP motions of one file that each last less than a cycle.
struct KrlShortStretch {
  std::string file;
  int first_line = 0, last_line = 0;
  long motions = 0;
  double shortest_s = 0.0;
};

struct KrlMotionRate {
  long cp_motions = 0;      // CP motions measured (a Cartesian position before and after)
  long unmeasured = 0;      // CP motions after an axis-only target (their start not known)
  long below_cycle = 0;     // of the measured, lasting less than one cycle
  long spline_joined = 0;   // of the measured, SPLINE segments joined smoothly to a neighbour
                            // (one path the controller plans whole: not timed one by one)
  double shortest_s = 0.0;  // the shortest measured (0: none)
  std::string shortest_file;
  int shortest_line = 0;
  long stretch_count = 0;                  // stretches of short motions, all of them
  std::vector<KrlShortStretch> stretches;  // the first kKrlMaxShortStretches, in program order
};

// Stretches a KrlMotionRate keeps (the rest are counted): memory stays flat whatever the
// program's length.
inline constexpr std::size_t kKrlMaxShortStretches = 1000;

KrlMotionRate krl_motion_rate(const KrlProgram& program, const KrlMotionRateOptions& options);

namespace detail {
struct KrlTcpPose {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  bool has_orientation = false;
};
struct KrlSplineJoint {
  int spline_block = 0;  // the SPLINE block of a motion (0: none)
  bool spl = false;      // an SPL segment
};
// What the counter keeps of a motion it holds back: what it measured, not the motion.
struct KrlMeasuredMotion {
  enum class Kind { axis_target, untimed, still, timed };
  Kind kind = Kind::untimed;
  KrlSplineJoint joint;
  bool unmeasured = false;      // a CP motion whose start is not known
  bool closes_stretch = false;  // not a CP motion: a stretch of short ones ends here
  double seconds = 0.0;         // timed: at its $VEL.CP and the orientation velocity
  std::string file;             // its buffer is reused from motion to motion
  int line = 0;
};
}  // namespace detail

// The same count, a motion at a time (a program read with a KrlMotionSink): it holds back what
// it measured of one motion, until the next one says whether the two are joined smoothly.
class KrlMotionRateCounter {
 public:
  explicit KrlMotionRateCounter(const KrlMotionRateOptions& options);
  void add(const KrlMotionRecord& m);  // in execution order
  KrlMotionRate finish();

 private:
  void measure(const KrlMotionRecord& m, detail::KrlMeasuredMotion& out);
  void count(const detail::KrlMeasuredMotion& m, const detail::KrlSplineJoint* next);
  void close_stretch();

  KrlMotionRateOptions options_;
  KrlMotionRate out_;
  detail::KrlMeasuredMotion held_[2];  // the one held back is held_[current_]
  int current_ = 0;
  bool holding_ = false;
  detail::KrlSplineJoint before_;  // of the motion before the held one
  bool have_before_ = false;
  detail::KrlTcpPose last_;  // the TCP where the last measured motion ended
  bool have_last_ = false;
  KrlShortStretch open_;
};

}  // namespace redpost
