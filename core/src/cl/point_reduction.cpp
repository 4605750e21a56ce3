// Tolerance-bounded point reduction (redpost/cl/point_reduction.hpp, docs/timing.md).
#include "redpost/cl/point_reduction.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "kinematics/sincos.hpp"
#include "redpost/kinematics/circle.hpp"
#include "redpost/kinematics/tool_axis.hpp"

namespace redpost {

namespace {

// A merged move shorter than this (mm) is a turn of the tool on the spot: its tool axis is not
// tied to the position, so nothing is merged into it.
constexpr double kShortestMergeMm = 1e-6;

// A GOTO, or a chord of a NURBS: a host that reads plain moves (C ABI 0.5) sends a NURBS's
// chords as plain moves, and must get the same program.
bool mergeable_origin(MoveOrigin o) {
  return o == MoveOrigin::goto_point || o == MoveOrigin::nurbs;
}

// The straight move a -> b made once for the many points a run tests against it: its direction,
// and the great circle of its tool axis (normal n, the axis a_axis turned by 90 deg along it as
// m), so that a point costs one sincos and no inverse trigonometry. The same circle as
// slerp_axis (kinematics/tool_axis.hpp), which the tracker steps along.
class MergedLin {
 public:
  MergedLin(const Eigen::Vector3d& a, const Eigen::Vector3d& a_axis, const Eigen::Vector3d& b,
            const Eigen::Vector3d& b_axis)
      : a_(a), d_(b - a), a_axis_(a_axis) {
    const double length2 = d_.squaredNorm();
    inv_length2_ = length2 > 0.0 ? 1.0 / length2 : 0.0;
    const Eigen::Vector3d c = a_axis.cross(b_axis);
    const double s = c.norm();
    angle_rad_ = std::atan2(s, a_axis.dot(b_axis));
    // Parallel (or opposite) axes: no circle to follow; the axis stays a's (opposite axes are
    // refused by the caller, which compares the end's axis too).
    m_ = s > 1e-300 ? Eigen::Vector3d((c / s).cross(a_axis)) : Eigen::Vector3d::Zero();
  }
  // The fraction of the line nearest p (clamped to the segment).
  double fraction(const Eigen::Vector3d& p) const {
    return std::clamp((p - a_).dot(d_) * inv_length2_, 0.0, 1.0);
  }
  double distance2(const Eigen::Vector3d& p, double t) const {
    return (p - (a_ + t * d_)).squaredNorm();
  }
  Eigen::Vector3d axis_at(double t) const {
    double s = 0.0, c = 1.0;
    detail::sincos_one(turn_at(t), s, c);
    return axis_at(s, c);
  }
  // The same from the sine and cosine of turn_at(t), for a run taken together.
  double turn_at(double t) const { return t * angle_rad_; }
  Eigen::Vector3d axis_at(double sin_phi, double cos_phi) const {
    return a_axis_ * cos_phi + m_ * sin_phi;
  }

 private:
  Eigen::Vector3d a_, d_, a_axis_, m_;
  double inv_length2_ = 0.0;
  double angle_rad_ = 0.0;
};

}  // namespace

std::string point_reduction_problem(const PointReductionOptions& o) {
  if (!std::isfinite(o.tolerance_mm) ||
      (o.tolerance_mm != 0.0 &&
       (o.tolerance_mm < kMinFitToleranceMm || o.tolerance_mm > kMaxFitToleranceMm))) {
    return fmt::format("--fit-tol is {} mm: it must be 0 (no point reduction) or {:g} to {:g} mm",
                       o.tolerance_mm, kMinFitToleranceMm, kMaxFitToleranceMm);
  }
  if (!std::isfinite(o.axis_tolerance_deg) || o.axis_tolerance_deg < kMinFitAngleToleranceDeg ||
      o.axis_tolerance_deg > kMaxFitAngleToleranceDeg) {
    return fmt::format("--fit-ang-tol is {} deg: it must be {:g} to {:g} deg", o.axis_tolerance_deg,
                       kMinFitAngleToleranceDeg, kMaxFitAngleToleranceDeg);
  }
  if (o.max_points < 2)
    return fmt::format("a merged move must be allowed at least 2 points, got {}", o.max_points);
  return "";
}

LinDeviation lin_deviation(const Eigen::Vector3d& a, const Eigen::Vector3d& a_axis,
                           const Eigen::Vector3d& b, const Eigen::Vector3d& b_axis,
                           const Eigen::Vector3d& p, const Eigen::Vector3d& p_axis) {
  const MergedLin line(a, a_axis, b, b_axis);
  const double t = line.fraction(p);
  LinDeviation r;
  r.distance_mm = std::sqrt(line.distance2(p, t));
  r.axis_rad = angle_between(line.axis_at(t), p_axis);
  return r;
}

PointReducer::PointReducer(const PointReductionOptions& options)
    : o_(options),
      axis_tolerance_rad_(0.5 * options.axis_tolerance_deg * kPi / 180.0),
      sin_axis_tolerance_(std::sin(axis_tolerance_rad_)) {
  run_.reserve(static_cast<std::size_t>(std::max(o_.max_points, 2)));
  run_points_.reserve(run_.capacity());
  turns_.reserve(run_.capacity());
  sin_phi_.reserve(run_.capacity());
  cos_phi_.reserve(run_.capacity());
  replay_.reserve(run_.capacity());  // the two swap in replay_as_lines
}

void PointReducer::push(const ClEvent& e) {
  if (!enabled()) {
    out_.push_back(e);
    return;
  }
  switch (e.kind) {
    case ClEventKind::move:
      // Only a cutting GOTO from a known position may be dropped or merged into. The first one
      // after a move kept as it is (a rapid, which may become a PTP, an approach, a cycle's
      // move) is kept too: the merged line would start where the program prints no position.
      if (anchored_ && !keep_next_ && !next_rapid_ && !e.rapid && !e.has_clearance &&
          mergeable_origin(e.origin) && e.p_mm.allFinite() && e.tool_axis.allFinite()) {
        add_point(e);
        return;
      }
      pass(e);
      keep_next_ = !(anchored_ && !next_rapid_ && !e.rapid && !e.has_clearance &&
                     mergeable_origin(e.origin));
      next_rapid_ = false;
      anchored_ = e.p_mm.allFinite() && e.tool_axis.allFinite();
      anchor_p_ = e.p_mm;
      anchor_axis_ = e.tool_axis.normalized();
      return;
    case ClEventKind::arc:
      pass(e);
      next_rapid_ = false;
      anchored_ = true;
      anchor_p_ = e.p_mm;
      anchor_axis_ = e.tool_axis.normalized();
      return;
    case ClEventKind::feed:
      // The same feed again changes nothing (CAM systems repeat it): the run goes on.
      if (e.value == feed_) {
        out_.push_back(e);
        return;
      }
      feed_ = e.value;
      pass(e);
      return;
    case ClEventKind::rapid:
      pass(e);
      next_rapid_ = true;
      return;
    case ClEventKind::tool_change:
    case ClEventKind::machine_frame:
      pass(e);
      anchored_ = false;
      return;
    case ClEventKind::unknown_word:
      out_.push_back(e);  // nothing for the session: no reason to end a run
      return;
    default:
      pass(e);
      return;
  }
}

bool PointReducer::next(ClEvent& e) {
  if (out_.empty())
    return false;
  e = std::move(out_.front());
  out_.pop_front();
  return true;
}

void PointReducer::finish() {
  flush();
}

void PointReducer::pass(const ClEvent& e) {
  flush();
  out_.push_back(e);
}

bool PointReducer::covers(const ClEvent& end) const {
  if ((end.p_mm - anchor_p_).norm() < kShortestMergeMm)
    return false;
  const Eigen::Vector3d end_axis = end.tool_axis.normalized();
  // A half turn of the tool within one move has no one great circle: never merged.
  if (anchor_axis_.dot(end_axis) < 0.0)
    return false;
  const MergedLin line(anchor_p_, anchor_axis_, end.p_mm, end_axis);
  const double tolerance2 = o_.tolerance_mm * o_.tolerance_mm;
  const double sin_axis = sin_axis_tolerance_;
  // Most refusals come from the point added last: test it first, and the distances (cheap)
  // before the axes.
  const std::size_t n = run_points_.size();
  turns_.resize(n);
  for (std::size_t k = n; k-- > 0;) {
    const double t = line.fraction(run_points_[k].p_mm);
    if (!(line.distance2(run_points_[k].p_mm, t) <= tolerance2))
      return false;
    turns_[k] = line.turn_at(t);
  }
  // Every point passed: the axes' turns all needed, two at a time (sincos.hpp; a libm call per
  // point was 7 % of a conversion on one thread).
  sin_phi_.resize(n);
  cos_phi_.resize(n);
  detail::sincos_batch(turns_.data(), sin_phi_.data(), cos_phi_.data(), static_cast<int>(n));
  for (std::size_t k = n; k-- > 0;) {
    // The angle between two unit vectors within the tolerance (below 90 deg): the sine by the
    // cross product, accurate where the cosine is not.
    const Eigen::Vector3d g = line.axis_at(sin_phi_[k], cos_phi_[k]);
    const Eigen::Vector3d& p_axis = run_points_[k].axis;
    if (!(g.cross(p_axis).norm() <= sin_axis) || g.dot(p_axis) <= 0.0)
      return false;
  }
  return true;
}

void PointReducer::run_push(const ClEvent& e) {
  run_.push_back(e);
  run_points_.push_back(RunPoint{e.p_mm, e.tool_axis.normalized()});
}

void PointReducer::run_clear() {
  run_.clear();
  run_points_.clear();
}

bool PointReducer::fits_arc(const ClEvent& end, Eigen::Vector3d& centre,
                            Eigen::Vector3d& normal) const {
  // The circle through the anchor, the middle point of the run (end included) and the end.
  const std::size_t n = run_.size() + 1;
  const std::size_t m = n / 2;  // 1-based among the n points; n >= 2, so m is a run point
  Circle c;
  if (!circle_through(anchor_p_, run_[m - 1].p_mm, end.p_mm, c))
    return false;
  if (!(c.radius >= kMinArcRadiusMm && c.radius <= kMaxArcRadiusMm) || c.sweep > kMaxArcSweepRad)
    return false;
  const double tol = arc_tolerance_mm();
  const double sin_axis = sin_axis_tolerance_;
  double last_phi = 0.0;
  // In order along the circle, on it, each chord of the CL polyline close to it, the tool axis
  // the anchor's.
  const auto on_arc = [&](const ClEvent& p) {
    const Eigen::Vector3d rel = p.p_mm - c.centre;
    const double h = rel.dot(c.normal);
    const Eigen::Vector3d in_plane = rel - h * c.normal;
    if (!(std::hypot(h, in_plane.norm() - c.radius) <= tol))
      return false;
    double phi = std::atan2(in_plane.dot(c.v), in_plane.dot(c.u));
    if (phi <= 0.0)
      phi += 2.0 * kPi;
    if (!(phi > last_phi && phi <= c.sweep + 1e-9))
      return false;
    // The sagitta of the chord from the point before: the circle within tol of the polyline.
    if (!(c.radius * (1.0 - std::cos(0.5 * (phi - last_phi))) <= tol))
      return false;
    last_phi = phi;
    const Eigen::Vector3d axis = p.tool_axis.normalized();
    return anchor_axis_.cross(axis).norm() <= sin_axis && anchor_axis_.dot(axis) > 0.0;
  };
  for (const ClEvent& p : run_) {
    if (!on_arc(p))
      return false;
  }
  if (!on_arc(end))
    return false;
  centre = c.centre;
  normal = c.normal;
  return true;
}

void PointReducer::add_point(const ClEvent& e) {
  ++moves_in_;
  extend(e);
}

// One more point for the run: the run goes on as a line or an arc, or ends before the point.
void PointReducer::extend(const ClEvent& e) {
  if (run_.empty()) {
    run_push(e);
    return;
  }
  const bool full = static_cast<int>(run_.size()) >= o_.max_points;
  Eigen::Vector3d centre, normal;
  if (arc_) {
    if (!full && fits_arc(e, centre, normal)) {
      arc_centre_ = centre;
      arc_normal_ = normal;
      run_push(e);
      return;
    }
    if (static_cast<int>(run_.size()) >= kMinArcPoints) {
      flush_arc();
    } else {
      replay_as_lines();  // too few points to prove the circle: lines after all
      extend(e);
      return;
    }
  } else if (!full && covers(e)) {
    run_push(e);
    return;
  } else if (!full && o_.arcs && fits_arc(e, centre, normal)) {
    // No line covers the run with e: an arc may (proven once it has kMinArcPoints points).
    arc_ = true;
    arc_centre_ = centre;
    arc_normal_ = normal;
    run_push(e);
    return;
  } else {
    flush();
  }
  run_push(e);
}

void PointReducer::replay_as_lines() {
  arc_ = false;
  replay_.clear();
  replay_.swap(run_);
  run_points_.clear();
  const bool arcs = o_.arcs;
  o_.arcs = false;
  for (const ClEvent& p : replay_)
    extend(p);
  o_.arcs = arcs;
  replay_.clear();
}

void PointReducer::flush_arc() {
  ClEvent end = std::move(run_.back());
  end.first_line = run_.front().first_line > 0 ? run_.front().first_line : run_.front().line;
  end.kind = ClEventKind::arc;
  end.origin = MoveOrigin::fitted_arc;
  end.arc_centre_mm = arc_centre_;
  end.arc_axis = arc_normal_;
  end.value = (anchor_p_ - arc_centre_).norm();
  // One tool axis along the arc, the start's: every point's is within half the angular
  // tolerance of it.
  end.tool_axis = anchor_axis_;
  anchor_p_ = end.p_mm;
  out_.push_back(std::move(end));
  ++moves_out_;
  ++arcs_out_;
  run_clear();
  arc_ = false;
}

void PointReducer::flush() {
  if (arc_) {
    if (static_cast<int>(run_.size()) >= kMinArcPoints) {
      flush_arc();
      return;
    }
    replay_as_lines();
  }
  if (run_.empty())
    return;
  ClEvent& end = run_.back();
  if (run_.size() > 1)
    end.first_line = run_.front().first_line > 0 ? run_.front().first_line : run_.front().line;
  anchor_p_ = end.p_mm;
  anchor_axis_ = end.tool_axis.normalized();
  out_.push_back(std::move(end));
  ++moves_out_;
  run_clear();
}

}  // namespace redpost
