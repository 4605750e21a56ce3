// The HTML report of `redpost convert --report` (see convert_report.hpp): the observer that
// streams the motions into bounded summaries, and one step per report section.
#include "convert_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "convert_report_clearance.hpp"
#include "convert_report_deflection.hpp"
#include "convert_report_scene.hpp"
#include "redpost/io/durable_write.hpp"
#include "redpost/io/error.hpp"
#include "redpost/report/html_report.hpp"
#include "redpost/report/plot_scale.hpp"

namespace redpost::run_report {

namespace {

namespace rep = redpost::report;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRadToDeg = 57.295779513082320876798;
// Fraction of a joint's range next to each limit where the tracker pushes the joint back
// (NullSpaceGains::limit_zone): the band drawn on the joints plot.
constexpr double kLimitZone = 0.1;
// Buckets of the plots against the motion index: about one per pixel of a wide plot, which
// keeps the twelve or so decimators at ~100 KB each.
constexpr int kBuckets = 1000;
// The toolpath views keep at most this many points (see Toolpath).
constexpr std::size_t kMaxPathPoints = 100000;

struct JointInfo {
  std::string name;
  std::string axis;  // "A1".."E6" or "none"
  bool prismatic = false;
  int axis_index = -1;  // into rp_motion::axes, -1: the joint has no controller axis
  bool external() const { return !axis.empty() && axis[0] == 'E'; }
  std::string label() const { return axis == "none" ? name : name + " (" + axis + ")"; }
};

// The toolpath in the CL frame, thinned as it streams: a point closer than tol_mm to the last
// kept one is dropped, but its 1/kappa_F is folded into that point (the minimum), so a badly
// conditioned spot stays visible. When the list outgrows kMaxPathPoints, the tolerance doubles
// and the list is thinned again, so memory stays bounded whatever the run length.
class Toolpath {
 public:
  // Single precision: 0.1 um at 1 m, far below a pixel, and half the memory.
  struct Point {
    float p[3];
    float value;
  };

  void add(const double p[3], double value) {
    last_ = Point{{static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])},
                  static_cast<float>(value)};
    has_last_ = true;
    if (!points_.empty() && distance(points_.back(), last_) < tol_mm_) {
      points_.back().value = std::min(points_.back().value, last_.value);
      last_dropped_ = true;
      return;
    }
    points_.push_back(last_);
    last_dropped_ = false;
    while (points_.size() > kMaxPathPoints) {
      tol_mm_ *= 2.0;
      rethin();
    }
  }

  // f(point) for every kept point and the path's end point, in path order.
  template <class F>
  void for_each(F&& f) const {
    for (const Point& p : points_)
      f(p);
    if (has_last_ && last_dropped_)
      f(last_);
  }
  std::size_t size() const { return points_.size() + (has_last_ && last_dropped_ ? 1 : 0); }
  double tolerance_mm() const { return tol_mm_; }

 private:
  static double distance(const Point& a, const Point& b) {
    const double dx = a.p[0] - b.p[0], dy = a.p[1] - b.p[1], dz = a.p[2] - b.p[2];
    return std::sqrt(dx * dx + dy * dy + dz * dz);
  }
  void rethin() {
    std::size_t kept = 1;
    for (std::size_t i = 1; i < points_.size(); ++i) {
      if (distance(points_[kept - 1], points_[i]) < tol_mm_) {
        points_[kept - 1].value = std::min(points_[kept - 1].value, points_[i].value);
      } else {
        points_[kept++] = points_[i];
      }
    }
    points_.resize(kept);
  }

  std::vector<Point> points_;
  Point last_{};
  bool has_last_ = false;
  bool last_dropped_ = false;
  double tol_mm_ = 0.001;
};

rep::HLine hline(double y, std::string name, bool right_axis = false) {
  rep::HLine h;
  h.y = y;
  h.name = std::move(name);
  h.right_axis = right_axis;
  return h;
}

rep::HBand hband(double lo, double hi, std::string name) {
  rep::HBand b;
  b.y_lo = lo;
  b.y_hi = hi;
  b.name = std::move(name);
  return b;
}

// The motion-number axis ends at the last motion (a free end would grow to the next tick).
rep::Axis motion_axis(long motions) {
  rep::Axis a = rep::make_axis("motion", "");
  if (motions > 1) {
    a.min = 0.0;
    a.max = static_cast<double>(motions);
  }
  return a;
}

rep::Series series_of(std::string name, rep::XYSeries data) {
  rep::Series s;
  s.name = std::move(name);
  s.x = std::move(data.x);
  s.y = std::move(data.y);
  return s;
}

std::string unit_of(const JointInfo& j) {
  return j.prismatic ? "mm" : "deg";
}

}  // namespace

struct ConvertReport::Impl {
  std::vector<JointInfo> joints;
  // Against the motion index: one per joint (in controller units, deg or mm), then the rest.
  std::vector<rep::MinMaxDecimator> joint_values;
  rep::MinMaxDecimator inv_condition{kBuckets}, iterations{kBuckets}, feed{kBuckets};
  // The time model: per joint the fraction of its velocity limit; path speeds in mm/min.
  std::vector<rep::MinMaxDecimator> speed_fraction;
  rep::MinMaxDecimator speed_reached{kBuckets}, speed_asked{kBuckets}, speed_written{kBuckets};
  // The controller's clock: each CP motion's duration at its $VEL.CP and as the model runs it
  // (ms), against the interpolation cycle.
  rep::MinMaxDecimator duration_at_command{kBuckets}, duration_run{kBuckets};
  double last_tcp[3] = {kNaN, kNaN, kNaN};
  // The whole-path plan: per joint, the planned and the written value in DH units (deg, mm).
  std::vector<rep::MinMaxDecimator> planned_dh, written_dh;
  std::vector<double> plan_deviation;  // per joint, the largest |written - planned|
  long planned_motions = 0;
  double last_time_s = 0.0;
  Toolpath path;
  double threshold = kNaN;
  long motions = 0;
  // The deflection under the cutting force (docs/deflection.md): its own section.
  DeflectionTrace deflection{kBuckets};
  // The clearance between bodies (docs/collision.md): its own section.
  ClearanceTrace clearance{kBuckets};
  // The 3D view (convert_report_scene.hpp); made once the session's cell is known.
  std::optional<SceneTrace> scene;

  // The value of joint i as the robot programmer reads it, in the units rp_joint_range uses.
  double value_of(const rp_motion& m, std::size_t i) const {
    const JointInfo& j = joints[i];
    if (j.axis_index >= 0)
      return m.axes[j.axis_index];
    const double q = i < static_cast<std::size_t>(m.joint_count) ? m.joints[i] : kNaN;
    return j.prismatic ? q : q * kRadToDeg;
  }

  void on_motion(const rp_motion& m) {
    ++motions;
    const double x = static_cast<double>(m.index);
    for (std::size_t i = 0; i < joints.size(); ++i)
      joint_values[i].push(x, value_of(m, i));
    inv_condition.push(x, m.inv_condition);
    iterations.push(x, m.iterations);
    feed.push(x, m.feed_mm_per_min);
    threshold = m.conditioning_threshold;
    path.add(m.tcp, m.inv_condition);
    for (std::size_t i = 0; i < joints.size(); ++i)
      speed_fraction[i].push(x, i < 16 ? m.speed_fraction[i] : kNaN);
    const bool cp = m.kind != RP_MOTION_PTP && m.kind != RP_MOTION_RAPID;
    speed_reached.push(x, cp ? 60.0 * m.speed_mm_s : kNaN);
    speed_asked.push(x, cp ? 60.0 * m.asked_mm_s : kNaN);
    speed_written.push(x, cp ? 60.0 * m.command_mm_s : kNaN);
    const double moved = std::sqrt((m.tcp[0] - last_tcp[0]) * (m.tcp[0] - last_tcp[0]) +
                                   (m.tcp[1] - last_tcp[1]) * (m.tcp[1] - last_tcp[1]) +
                                   (m.tcp[2] - last_tcp[2]) * (m.tcp[2] - last_tcp[2]));
    const bool timed_cp = cp && moved > 1e-6 && m.command_mm_s > 0.0;  // NaN compares false
    duration_at_command.push(x, timed_cp ? 1000.0 * moved / m.command_mm_s : kNaN);
    duration_run.push(x, timed_cp ? 1000.0 * m.duration_s : kNaN);
    std::copy(m.tcp, m.tcp + 3, last_tcp);
    last_time_s = m.time_s;
    planned_motions += m.planned ? 1 : 0;
    for (std::size_t i = 0; i < joints.size() && i < 16; ++i) {
      const double scale = joints[i].prismatic ? 1.0 : kRadToDeg;
      planned_dh[i].push(x, m.planned ? scale * m.planned_joints[i] : kNaN);
      written_dh[i].push(x, scale * m.joints[i]);
      if (m.planned)
        plan_deviation[i] =
            std::max(plan_deviation[i], scale * std::fabs(m.joints[i] - m.planned_joints[i]));
    }
    deflection.on_motion(m);
    clearance.on_motion(m);
    scene->on_motion(m);
  }
};

ConvertReport::ConvertReport(rp_session* session) : impl_(std::make_unique<Impl>()) {
  static const char* const kAxes[] = {"A1", "A2", "A3", "A4", "A5", "A6",
                                      "E1", "E2", "E3", "E4", "E5", "E6"};
  rp_joint_range_info r{};
  for (int i = 0; rp_joint_range(session, i, &r) == RP_OK; ++i) {
    JointInfo j;
    j.name = r.name;
    j.axis = r.axis_name;
    j.prismatic = r.prismatic != 0;
    for (int k = 0; k < 12; ++k) {
      if (j.axis == kAxes[k])
        j.axis_index = k;
    }
    impl_->joints.push_back(std::move(j));
    impl_->joint_values.emplace_back(kBuckets);
    impl_->speed_fraction.emplace_back(kBuckets);
    impl_->planned_dh.emplace_back(kBuckets);
    impl_->written_dh.emplace_back(kBuckets);
    impl_->plan_deviation.push_back(0.0);
  }
  impl_->scene.emplace(session);
}

void ConvertReport::on_motion(const rp_motion& m) {
  impl_->on_motion(m);
}

ConvertReport::~ConvertReport() = default;

namespace {

// A joint's limits, in the units of its values (controller units, else DH degrees or mm).
struct Limits {
  double lo = kNaN, hi = kNaN;
};

// The rows under the title: inputs, counts, time, the lowest 1/kappa_F and the warnings.
void add_summary(rep::HtmlReport& r, const rp_summary& summary,
                 const ConvertReportContext& context) {
  r.add_summary("input", context.input);
  r.add_summary("cell", context.cell);
  r.add_summary("program", context.program);
  r.add_summary("poses tracked", fmt::format("{}", summary.poses));
  r.add_summary("motions written", fmt::format("{}", summary.motions));
  r.add_summary("conversion time", fmt::format("{:.2f} s", context.seconds));
  r.add_summary("lowest 1/kappa_F", fmt::format("{:.3f} (CL line {})", summary.lowest_inv_condition,
                                                summary.lowest_inv_condition_line));
  r.add_summary("warnings", "");  // counted once every section is made (count_warnings)
}

// The warnings row: those of the run (all of them, also those past the page's screenful) and
// those the report's own checks add (joints near their limits, speeds not checked, ...), so
// that the count in the header is the count on the page.
void count_warnings(rep::HtmlReport& r, std::size_t run_total, std::size_t run_shown) {
  const std::size_t checks = static_cast<std::size_t>(r.warning_count()) - run_shown;
  r.set_summary("warnings", checks == 0 ? fmt::format("{}", run_total)
                                        : fmt::format("{}: {} of the run, {} of the checks below",
                                                      run_total + checks, run_total, checks));
}

// The range of every joint and its margins to the limits, with a warning for each joint that
// came into the limit zone. Returns the limits of the joints (NaN where the ABI has none).
std::vector<Limits> add_joint_ranges_section(rep::HtmlReport& r, const ConvertReport::Impl& d,
                                             const rp_session* session) {
  r.add_section("Joint ranges and margins to the limits");
  std::vector<Limits> limits(d.joints.size());
  rep::Table t;
  t.caption =
      "Values in controller units where the joint has an axis (A1..E6), else DH degrees or mm. "
      "Margins are the smallest distances to each limit over all poses tracked.";
  t.header = {"joint",       "axis",        "unit",       "lowest",      "highest",
              "lower limit", "upper limit", "margin low", "margin high", "margin [% of range]"};
  std::vector<std::string> near_limit;
  for (std::size_t i = 0; i < d.joints.size(); ++i) {
    rp_joint_range_info jr{};
    if (rp_joint_range(session, static_cast<int>(i), &jr) != RP_OK)
      continue;
    const JointInfo& j = d.joints[i];
    // The limits follow from the range and its margins (rp_joint_range).
    Limits& l = limits[i];
    l.lo = jr.lowest - jr.margin_lower;
    l.hi = jr.highest + jr.margin_upper;
    const double range = l.hi - l.lo;
    const double margin_pct =
        range > 0 ? 100.0 * std::min(jr.margin_lower, jr.margin_upper) / range : kNaN;
    const int decimals = j.prismatic ? 1 : 2;
    t.rows.push_back({rep::text(j.name), rep::text(j.axis), rep::text(unit_of(j)),
                      rep::num(jr.lowest, decimals), rep::num(jr.highest, decimals),
                      rep::num(l.lo, decimals), rep::num(l.hi, decimals),
                      rep::num(jr.margin_lower, decimals), rep::num(jr.margin_upper, decimals),
                      rep::num(margin_pct, 1)});
    if (margin_pct < 100.0 * kLimitZone) {
      near_limit.push_back(
          fmt::format("{} came within {:.1f} % of its range of a limit", j.label(), margin_pct));
    }
  }
  r.add_table(t);
  for (const std::string& w : near_limit)
    r.add_warning(w);
  return limits;
}

// The run's warnings (the host's, then the session's); returns how many there are and how many are
// shown.
std::pair<std::size_t, std::size_t> add_run_warnings(rep::HtmlReport& r,
                                                     const rp_session* session) {
  // Every warning up to a screenful; the rest are counted (the terminal printed them all).
  constexpr std::size_t kMaxWarnings = 50;
  std::size_t shown = 0;
  auto warn = [&](const std::string& w) {
    if (shown++ < kMaxWarnings)
      r.add_warning(w);
  };
  for (int i = 0; const char* w = rp_warning(session, i); ++i)
    warn(w);
  if (shown > kMaxWarnings)
    r.add_paragraph(fmt::format("... and {} more warnings.", shown - kMaxWarnings));
  return {shown, std::min(shown, kMaxWarnings)};
}

// How the plots against the motion index are reduced, when they are.
void add_decimation_note(rep::HtmlReport& r, const ConvertReport::Impl& d) {
  const std::size_t width = d.inv_condition.bucket_width();
  if (width > 1) {
    r.add_paragraph(fmt::format(
        "The plots below show {} motions, each point pair the lowest and highest value of {} "
        "consecutive motions: no peak is lost, however short.",
        d.motions, width));
  }
}

// Every joint with limits, normalised to them, with the limit zones shaded.
void add_joints_section(rep::HtmlReport& r, const ConvertReport::Impl& d,
                        const std::vector<Limits>& limits) {
  r.add_section("Joints");
  rep::LinePlot jp;
  jp.title = "Joint positions, normalised to their limits (0 = lower, 1 = upper limit)";
  jp.x = motion_axis(d.motions);
  jp.y = rep::make_axis("position in range", "1");
  jp.y.min = 0.0;
  jp.y.max = 1.0;
  jp.bands.push_back(hband(0.0, kLimitZone, "limit zone (tracker pushes back)"));
  jp.bands.push_back(hband(1.0 - kLimitZone, 1.0, ""));
  for (std::size_t i = 0; i < d.joints.size(); ++i) {
    const Limits& l = limits[i];
    if (!(l.hi > l.lo))
      continue;
    rep::XYSeries s = d.joint_values[i].result();
    for (double& y : s.y)
      y = (y - l.lo) / (l.hi - l.lo);
    jp.series.push_back(series_of(d.joints[i].label(), std::move(s)));
  }
  r.add_plot(std::move(jp));
}

// 1/kappa_F per motion, with the threshold where the tracker switches.
void add_conditioning_plot(rep::HtmlReport& r, const ConvertReport::Impl& d) {
  rep::LinePlot kp;
  kp.title = "Inverse condition number 1/kappa_F of the arm";
  kp.x = motion_axis(d.motions);
  kp.y = rep::make_axis("1/kappa_F", "1");
  kp.y.min = 0.0;
  kp.series.push_back(series_of("1/kappa_F", d.inv_condition.result()));
  if (std::isfinite(d.threshold)) {
    kp.hlines.push_back(hline(d.threshold, fmt::format("switch threshold {:g}", d.threshold)));
  }
  r.add_plot(std::move(kp));
}

// The external axes in their own units (none: no plot).
void add_external_axes_plot(rep::HtmlReport& r, const ConvertReport::Impl& d) {
  bool has_mm = false, has_deg = false;
  for (const JointInfo& j : d.joints) {
    if (j.external())
      (j.prismatic ? has_mm : has_deg) = true;
  }
  if (!has_mm && !has_deg)
    return;
  rep::LinePlot ep;
  ep.title = "External axes";
  ep.x = motion_axis(d.motions);
  // Tracks in mm on the left; turn tables in degrees on the right (or left when alone).
  ep.y = has_mm ? rep::make_axis("track", "mm") : rep::make_axis("table", "deg");
  ep.has_y2 = has_mm && has_deg;
  if (ep.has_y2)
    ep.y2 = rep::make_axis("table", "deg");
  for (std::size_t i = 0; i < d.joints.size(); ++i) {
    const JointInfo& j = d.joints[i];
    if (!j.external())
      continue;
    rep::Series s = series_of(j.label() + " [" + unit_of(j) + "]", d.joint_values[i].result());
    s.right_axis = ep.has_y2 && !j.prismatic;
    s.dashed = s.right_axis;
    ep.series.push_back(std::move(s));
  }
  r.add_plot(std::move(ep));
}

// The whole-path plan (docs/redundancy.md): per joint outside the arm, the posture planned at
// the keyframes (interpolated at each motion) against the one written, which the tracker keeps
// near the plan while it tracks every pose exactly.
void add_plan_section(rep::HtmlReport& r, const ConvertReport::Impl& d) {
  if (d.planned_motions == 0)
    return;
  r.add_section("Whole-path plan: planned against tracked");
  r.add_paragraph(fmt::format(
      "{} of {} motions were tracked towards the whole-path plan (the others, if any: "
      "PTP motions, stretches tracked pose by pose). The plan samples the joints outside the arm "
      "on a lattice at keyframes and chooses the cheapest sequence by dynamic programming; the "
      "tracker then pulls its null-space motion towards it. DH units: degrees and millimetres.",
      d.planned_motions, d.motions));
  for (std::size_t i = 0; i < d.joints.size() && i < 16; ++i) {
    const JointInfo& j = d.joints[i];
    if (!j.axis.empty() && j.axis[0] == 'A')
      continue;  // the arm follows from the IK
    rep::LinePlot pp;
    pp.title = fmt::format("{}: planned and written (at most {:.3g} {} apart)", j.label(),
                           d.plan_deviation[i], unit_of(j));
    pp.x = motion_axis(d.motions);
    pp.y = rep::make_axis(j.name, unit_of(j));
    pp.series.push_back(series_of("written", d.written_dh[i].result()));
    pp.series.push_back(series_of("planned", d.planned_dh[i].result()));
    pp.series.back().dashed = true;
    pp.width = 620;
    pp.height = 300;
    r.add_plot(std::move(pp));
  }
}

// Iterations per written pose and the feed of the cutting moves.
void add_solver_and_feed_section(rep::HtmlReport& r, const ConvertReport::Impl& d) {
  r.add_section("Solver and feed");
  rep::LinePlot ip;
  ip.title = "Iterations per written pose";
  ip.x = motion_axis(d.motions);
  ip.y = rep::make_axis("iterations", "");
  ip.y.min = 0.0;
  ip.series.push_back(series_of("iterations", d.iterations.result()));
  ip.width = 620;
  ip.height = 300;
  r.add_plot(std::move(ip));

  rep::LinePlot fp;
  fp.title = "Feed of the cutting moves (gaps: rapids)";
  fp.x = motion_axis(d.motions);
  fp.y = rep::make_axis("feed", "mm/min");
  fp.y.min = 0.0;
  fp.series.push_back(series_of("feed", d.feed.result()));
  // Headroom above the highest feed: a constant feed would otherwise run along the frame.
  double feed_max = 0.0;
  for (double f : fp.series.back().y) {
    if (std::isfinite(f))
      feed_max = std::max(feed_max, f);
  }
  if (feed_max > 0.0)
    fp.y.max = 1.15 * feed_max;
  fp.width = 620;
  fp.height = 300;
  r.add_plot(std::move(fp));
}

// The time model (docs/timing.md): cycle time, every axis's speed against its limit along the
// path, the path speed against the feed, and where an axis keeps the feed low.
// The controller's clock (docs/timing.md, "The interpolation cycle"): how long each CP motion
// lasts at its $VEL.CP, and as the controller runs it, against one interpolation cycle.
void add_cycle_plot(rep::HtmlReport& r, const ConvertReport::Impl& d, const rp_timing& t) {
  if (!(t.interpolation_cycle_s > 0.0) || t.cp_motions == 0)
    return;
  const double cycle_ms = 1000.0 * t.interpolation_cycle_s;
  std::string text = fmt::format(
      "The controller interpolates every {:g} ms and prepares one motion per cycle at most: {} of "
      "the {} CP motions ({:.0f} %) last less than a cycle at their $VEL.CP (the shortest {:.1f} "
      "ms, CL line {}). The time model runs them at one per cycle: {} were slowed by that motion "
      "rate, {} by the look-ahead ($ADVANCE: the planner must be able to stop within the motions "
      "it sees).{}",
      cycle_ms, t.below_cycle_motions, t.cp_motions,
      100.0 * static_cast<double>(t.below_cycle_motions) / static_cast<double>(t.cp_motions),
      1000.0 * t.shortest_motion_s, t.shortest_motion_line, t.rate_limited_motions,
      t.lookahead_limited_motions,
      t.rate_slowed_motions > 0
          ? fmt::format(" {} motions, too short for a cycle at the feed even after the point "
                        "reduction, are written with the $VEL.CP at which they last one.",
                        t.rate_slowed_motions)
          : std::string());
  if (t.below_cycle_motions > 0)
    r.add_warning(text);
  else
    r.add_paragraph(text);
  rep::LinePlot cp;
  cp.title = "Duration of the CP motions against the interpolation cycle";
  cp.x = motion_axis(d.motions);
  cp.y = rep::make_axis("duration", "ms", true);
  cp.hlines.push_back(hline(cycle_ms, fmt::format("interpolation cycle ({:g} ms)", cycle_ms)));
  cp.series.push_back(series_of("at its $VEL.CP", d.duration_at_command.result()));
  cp.series.push_back(series_of("as the controller runs it (time model)", d.duration_run.result()));
  cp.series.back().dashed = true;
  r.add_plot(std::move(cp));
}

void add_speed_section(rep::HtmlReport& r, const ConvertReport::Impl& d,
                       const rp_session* session) {
  r.add_section("Axis speeds and cycle time");
  rp_timing t{};
  t.struct_size = sizeof t;
  if (rp_timing_get(session, &t) != RP_OK)
    return;
  std::string text = "Cycle time " + duration_text(t.cycle_time_s);
  if (t.feed_time_s > 0.0) {
    text += fmt::format(
        "; the cutting moves take {} where the CL feeds alone would take {} "
        "({:+.1f} %)",
        duration_text(t.cutting_time_s), duration_text(t.feed_time_s),
        100.0 * (t.cutting_time_s / t.feed_time_s - 1.0));
  }
  text +=
      ". Trapezoidal profile along the path within every axis's velocity and acceleration "
      "limits, one motion per interpolation cycle at most and the look-ahead of $ADVANCE "
      "motions, as docs/timing.md describes.";
  if (t.untimed_tool_changes > 0)
    text += fmt::format(" The {} tool change(s) are not timed.", t.untimed_tool_changes);
  r.add_paragraph(text);
  add_cycle_plot(r, d, t);
  if (!t.axis_speeds_known) {
    r.add_warning("The cell gives no axis speeds: they were not checked.");
    return;
  }
  if (t.slowed_motions > 0) {
    r.add_warning(fmt::format(
        "{} motion(s) written with a $VEL.CP below the asked speed, so that no axis passes its "
        "velocity limit.",
        t.slowed_motions));
  }
  rep::LinePlot sp;
  sp.title = "Axis speeds as a fraction of their velocity limits (highest in each motion)";
  sp.x = motion_axis(d.motions);
  sp.y = rep::make_axis("speed / limit", "1");
  sp.y.min = 0.0;
  sp.y.max = 1.1;
  sp.hlines.push_back(hline(1.0, "velocity limit"));
  for (std::size_t i = 0; i < d.joints.size(); ++i) {
    if (d.joints[i].axis == "none")
      continue;
    sp.series.push_back(series_of(d.joints[i].label(), d.speed_fraction[i].result()));
  }
  r.add_plot(std::move(sp));

  rep::LinePlot vp;
  vp.title = "Path speed of the CP motions: asked, written ($VEL.CP) and reached";
  vp.x = motion_axis(d.motions);
  vp.y = rep::make_axis("speed", "mm/min");
  vp.y.min = 0.0;
  vp.series.push_back(series_of("asked (feed or rapid)", d.speed_asked.result()));
  vp.series.push_back(series_of("$VEL.CP written", d.speed_written.result()));
  vp.series.back().dashed = true;
  vp.series.push_back(series_of("reached", d.speed_reached.result()));
  r.add_plot(std::move(vp));

  if (t.feed_limits == 0)
    return;
  rep::Table tab;
  tab.caption = fmt::format(
      "Where an axis or the controller's clock keeps the feed 5 % or more below the "
      "CL file's: {} stretch(es){}.",
      t.feed_limits,
      t.feed_limits > t.feed_limits_listed
          ? fmt::format(", the first {} listed", t.feed_limits_listed)
          : std::string());
  tab.header = {"CL lines",        "axis",           "joint",  "limited by",
                "lowest [mm/min]", "asked [mm/min]", "motions"};
  for (int i = 0; i < t.feed_limits_listed; ++i) {
    rp_feed_limit_info f{};
    f.struct_size = sizeof f;
    if (rp_feed_limit(session, i, &f) != RP_OK)
      break;
    tab.rows.push_back(
        {rep::text(f.first_line == f.last_line ? fmt::format("{}", f.first_line)
                                               : fmt::format("{}-{}", f.first_line, f.last_line)),
         rep::text(f.axis_name), rep::text(f.joint_name), rep::text(f.limit),
         rep::num(f.lowest_mm_per_min, 0), rep::num(f.asked_mm_per_min, 0),
         rep::num(static_cast<double>(f.motions), 0)});
  }
  r.add_table(tab);
}

// The toolpath in the CL frame, projected on XY, XZ and YZ, coloured by 1/kappa_F.
void add_toolpath_section(rep::HtmlReport& r, const ConvertReport::Impl& d) {
  r.add_section("Toolpath in the CL frame, coloured by 1/kappa_F");
  if (d.path.tolerance_mm() > 0.001) {
    r.add_paragraph(fmt::format(
        "Points closer than {:g} mm to the last one drawn are left out (each drawn point "
        "shows the lowest 1/kappa_F of those it stands for).",
        d.path.tolerance_mm()));
  }
  const char* views[3][3] = {{"XY", "x", "y"}, {"XZ", "x", "z"}, {"YZ", "y", "z"}};
  for (const auto& v : views) {
    rep::XYView view;
    view.title = std::string("Toolpath, ") + v[0] + " projection";
    view.x = rep::make_axis(v[1], "mm");
    view.y = rep::make_axis(v[2], "mm");
    view.colour = rep::make_axis("1/kappa_F", "1");
    rep::PointSet s;
    s.name = "TCP";
    s.connect = true;
    s.markers = false;
    const int a = v[1][0] - 'x', b = v[2][0] - 'x';
    s.x.reserve(d.path.size());
    s.y.reserve(d.path.size());
    s.value.reserve(d.path.size());
    d.path.for_each([&](const Toolpath::Point& p) {
      s.x.push_back(p.p[a]);
      s.y.push_back(p.p[b]);
      s.value.push_back(p.value);
    });
    view.sets.push_back(std::move(s));
    view.width = 420;
    view.height = 400;
    r.add_plot(std::move(view));
  }
}

}  // namespace

std::string ConvertReport::html(const std::string& path, const rp_session* session,
                                const ConvertReportContext& context) const {
  const Impl& d = *impl_;
  rp_summary summary{};
  rp_summary_get(session, &summary);

  try {
    rep::HtmlReport r("redpost convert: " + context.program);
    add_summary(r, summary, context);
    const std::vector<Limits> limits = add_joint_ranges_section(r, d, session);
    const auto [run_total, run_shown] = add_run_warnings(r, session);
    add_decimation_note(r, d);
    add_joints_section(r, d, limits);
    add_speed_section(r, d, session);
    add_conditioning_plot(r, d);
    add_external_axes_plot(r, d);
    add_plan_section(r, d);
    add_solver_and_feed_section(r, d);
    d.deflection.add_section(r, session, motion_axis(d.motions));
    d.clearance.add_section(r, session, motion_axis(d.motions));
    add_toolpath_section(r, d);
    d.scene->add_section(r, session, d.clearance.closest());
    count_warnings(r, run_total, run_shown);
    return r.html();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    // The ABI's errors are Errors already; the location names the report for the rest.
    throw Error(ErrorCode::io, std::string("report: ") + e.what(), SourceLocation{path, 0, 0});
  }
}

std::string duration_text(double s) {
  if (s < 60.0)
    return fmt::format("{:.1f} s", s);
  const long minutes = static_cast<long>(s / 60.0);
  if (minutes < 60)
    return fmt::format("{} min {:.1f} s", minutes, s - 60.0 * minutes);
  return fmt::format("{} h {} min {:.0f} s", minutes / 60, minutes % 60, s - 60.0 * minutes);
}

}  // namespace redpost::run_report
