// The front door's drilling cycles and NURBS (ClExpander::Impl, cl/expander_impl.hpp): a cycle's
// definition and each of its holes expanded into moves, and a NURBS's knot vector completed and
// split into chords (the evaluation is in cl/nurbs_curve.hpp).
#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "cl/expander_impl.hpp"

namespace redpost {

using Eigen::Vector3d;

namespace {

// More pecks in one hole than a drill would ever make (a 100 mm hole in 10 um pecks): a typo in
// the peck depths, which would otherwise write millions of motions per hole.
constexpr double kMaxPecks = 10'000;

// The largest length of a cycle (mm): the CL reader's bound on any value.
constexpr double kMaxLengthMm = 1e7;

std::string fmt_mm(double v) {
  return fmt::format("{:.6g}", v);
}

}  // namespace

// ===========================================================================================
// Drilling cycles

void ClExpander::Impl::interrupt_cycle(int line) {
  if (cycle.active) {
    cycle.active = false;
    cycle.interrupted = true;
    cycle.interrupted_line = line;
  }
}

// Motion after an interrupted cycle (see DrillCycle::interrupted) is refused.
void ClExpander::Impl::check_cycle_not_interrupted(const ClEvent& e) const {
  if (!cycle.interrupted)
    return;
  // Not "add CYCLE/OFF before the tool change": the points after it are usually the next
  // tool's holes (on the part's surface), and as plain moves the tool would be dragged across
  // the part between them.
  fail(e.line,
       "the CYCLE of line " + std::to_string(cycle.line) + " was still on when the tool changed " +
           "at line " + std::to_string(cycle.interrupted_line) +
           " (no CYCLE/OFF): redpost cannot tell whether this " + word_of(e) +
           " is a hole of that cycle or a plain move, and will not guess. Fix it in the CAM "
           "system: end the cycle where its last hole is done (the tool retracts to RTRCTO), "
           "and give the next tool's holes a CYCLE/ of their own after its LOAD/TOOL. Do not "
           "only insert CYCLE/OFF before the tool change: points on the part's surface would "
           "then become plain moves between the holes, through the part");
}

// A cycle's definition, checked as a whole: what a hole needs to be expanded safely.
void ClExpander::Impl::on_cycle(const ClEvent& e) {
  const ClCycle& c = e.cycle;
  const std::string name = e.text.empty() ? std::string("CYCLE/DRILL") : e.text;
  const auto length = [&](double v, const char* what, bool positive) {
    if (!std::isfinite(v) || v < 0.0 || (positive && v == 0.0) || v > kMaxLengthMm) {
      fail(e.line, fmt::format("{}: {} must be a length of {} to {:g} mm, got {}", name, what,
                               positive ? "more than 0" : "0", kMaxLengthMm, v));
    }
    return v;
  };
  if (std::isnan(c.depth_mm) || std::isnan(c.clearance_mm))
    fail(e.line, name + " needs FEDTO (the depth) and RAPTO (the clearance) to be expanded safely");
  DrillCycle d;
  d.line = e.line;
  d.name = name;
  d.deep = c.deep;
  d.depth_mm = length(c.depth_mm, "FEDTO (the depth below the hole point)", false);
  d.clearance_mm = length(c.clearance_mm, "RAPTO (the clearance above the hole point)", false);
  d.retract_mm =
      std::isnan(c.retract_mm)
          ? d.clearance_mm
          : length(c.retract_mm, "RTRCTO (the retract height above the hole point)", false);
  if (std::isnan(c.feed_mm_per_min)) {
    if (!feed_known)
      fail(e.line, name + " gives no feed (MMPM, IPM, MMPR or IPR) and no FEDRAT came before it");
    d.feed_mm_per_min = feed_mm_per_min;
  } else {
    if (!std::isfinite(c.feed_mm_per_min) || !(c.feed_mm_per_min > 0.0) ||
        c.feed_mm_per_min > kMaxLengthMm)
      fail(e.line, fmt::format("{}: the feed must be > 0 and at most {:g} mm/min, got {}", name,
                               kMaxLengthMm, c.feed_mm_per_min));
    d.feed_mm_per_min = c.feed_mm_per_min;
  }
  // Seconds at the hole bottom, written as the template set's dwell (WAIT SEC).
  if (!(c.dwell_s >= 0.0) || c.dwell_s > kMaxDwellSeconds) {
    fail(e.line, fmt::format("{}: DWELL must be 0 to {:g} seconds, got {}", name, kMaxDwellSeconds,
                             c.dwell_s));
  }
  d.dwell_s = c.dwell_s;
  if (d.deep) {
    const bool has_first = !std::isnan(c.first_peck_mm);
    if (!has_first && d.depth_mm > 0.0) {
      fail(e.line, name +
                       " gives no peck depth (1STPECK, SUBPECK): redpost will not guess one for a "
                       "pecking cycle");
    }
    d.first_peck_mm = has_first ? length(c.first_peck_mm, "1STPECK", true) : 1.0;
    d.next_peck_mm = std::isnan(c.next_peck_mm) ? d.first_peck_mm
                     : has_first                ? length(c.next_peck_mm, "SUBPECK", true)
                                                : 1.0;
  }
  if (d.depth_mm == 0.0)
    warn("FEDTO0", e.line, name + " has FEDTO 0: its holes are only touched, not drilled");
  d.defined = true;
  d.active = true;
  cycle = d;
}

// A hole at `p` (its point, on the surface) along `a`: travel at the retract height, rapid to
// the clearance, feed down in one go or in pecks (rapid out to the clearance and back down to
// the clearance above the last peck's bottom between them), rapid out to the retract height.
void ClExpander::Impl::on_hole(const ClEvent& e, const Vector3d& p, const Vector3d& a) {
  if (!p.allFinite() || !a.allFinite() || !(a.norm() > 1e-9))
    fail(e.line, "a hole with a point or a tool axis that is not a finite, non-zero vector");
  hole_point = p;
  hole_pecks = 1;
  if (cycle.deep && cycle.depth_mm > cycle.first_peck_mm) {
    const double more =
        std::ceil((cycle.depth_mm - cycle.first_peck_mm) / cycle.next_peck_mm - 1e-9);
    if (more + 1.0 > kMaxPecks) {
      fail(cycle.line,
           fmt::format("this pecking cycle needs {:.0f} pecks per hole, more than the {:.0f} "
                       "redpost writes: check the peck depths of the CYCLE record "
                       "(1STPECK {:.6g} mm, SUBPECK {:.6g} mm, depth {:.6g} mm)",
                       std::min(more + 1.0, 1e15), kMaxPecks, cycle.first_peck_mm,
                       cycle.next_peck_mm, cycle.depth_mm));
    }
    hole_pecks = 1 + static_cast<long>(more);
  }
  hole_peck = 0;
  hole_phase = HolePhase::travel;
  gen_axis = a;
  gen_line = e.line;
  axis = a;
  generator = Generator::hole;
}

double ClExpander::Impl::peck_depth(long k) const {
  if (!cycle.deep)
    return cycle.depth_mm;
  return std::min(cycle.depth_mm,
                  cycle.first_peck_mm + static_cast<double>(k) * cycle.next_peck_mm);
}

// A move of the cycle, left out when it would not move.
void ClExpander::Impl::hole_move(double above_mm, bool rapid) {
  const Vector3d q = hole_point + above_mm * gen_axis;
  if (pos_known && (q - pos).norm() <= 1e-9)
    return;
  ClEvent& m = emit_kind(ClEventKind::move, gen_line);
  m.p_mm = q;
  m.tool_axis = gen_axis;
  m.origin = MoveOrigin::cycle;
  m.rapid = rapid;
  m.has_clearance = true;
  m.clearance_p_mm = hole_point + cycle.clearance_mm * gen_axis;
  pos = q;
  pos_known = true;
}

void ClExpander::Impl::run_hole() {
  while (out.size() < kBatch && hole_phase != HolePhase::done) {
    switch (hole_phase) {
      case HolePhase::travel:
        hole_move(cycle.retract_mm, true);
        hole_phase = HolePhase::approach;
        break;
      case HolePhase::approach:
        hole_move(cycle.clearance_mm, true);
        hole_phase = HolePhase::feed_on;
        break;
      case HolePhase::feed_on:
        emit_kind(ClEventKind::feed, gen_line).value = cycle.feed_mm_per_min;
        hole_phase = HolePhase::cut;
        break;
      case HolePhase::reenter:
        hole_move(cycle.clearance_mm - peck_depth(hole_peck - 1), true);
        hole_phase = HolePhase::cut;
        break;
      case HolePhase::cut:
        hole_move(-peck_depth(hole_peck), false);
        hole_phase = hole_peck + 1 < hole_pecks ? HolePhase::peck_out : HolePhase::dwell;
        break;
      case HolePhase::dwell:
        if (cycle.dwell_s > 0.0)
          emit_kind(ClEventKind::dwell, gen_line).value = cycle.dwell_s;
        hole_phase = HolePhase::feed_off;
        break;
      case HolePhase::peck_out:
        hole_move(cycle.clearance_mm, true);
        ++hole_peck;
        hole_phase = HolePhase::reenter;
        break;
      case HolePhase::feed_off:
        if (feed_known)
          emit_kind(ClEventKind::feed, gen_line).value = feed_mm_per_min;
        hole_phase = HolePhase::retract;
        break;
      case HolePhase::retract:
        hole_move(cycle.retract_mm, true);
        hole_phase = HolePhase::done;
        break;
      case HolePhase::done:
        break;
    }
  }
  if (hole_phase == HolePhase::done)
    generator = Generator::none;
}

// ===========================================================================================
// NURBS

void ClExpander::Impl::fail_nurbs(const std::string& message) const {
  fail(gen_line, "NURBS: " + message);
}

// Builds the full clamped knot vector from what the event gives, checks it and starts the
// curve's generator. Two forms (docs/cl-format.md, "NURBS"):
// - complete: the list starts with `order` equal knots and ends with `order` equal knots;
//   the control points are all given (the first must be the current position) or all but
//   the first (which is the current position);
// - NX: the `order` leading knots (0) and `order - 1` of the trailing ones are left out and
//   the first control point is the current position, so K knots and C control points give
//   order = C + 2 - K; the list must start above 0 and end at 1.
void ClExpander::Impl::on_nurbs(const ClEvent& e) {
  check_cycle_not_interrupted(e);
  if (cycle.active)
    fail(e.line, "NURBS while a CYCLE is active: give CYCLE/OFF first");
  gen_line = e.line;
  if (!pos_known)
    fail_nurbs("needs a start point, but no position is known yet");
  const std::vector<double>& knots = e.nurbs_knots;
  const std::size_t k_count = knots.size();
  const std::size_t c_count = e.nurbs_points.size();
  if (k_count == 0 || c_count == 0)
    fail_nurbs("needs KNOT/ and CNTRL/ records, got " + std::to_string(k_count) + " knots and " +
               std::to_string(c_count) + " control points");
  for (std::size_t i = 0; i < k_count; ++i) {
    if (!std::isfinite(knots[i]))
      fail_nurbs("knot " + std::to_string(i + 1) + " is not a finite number");
    if (i > 0 && knots[i] < knots[i - 1]) {
      fail_nurbs("knot " + fmt_mm(knots[i]) + " is smaller than the one before it (" +
                 fmt_mm(knots[i - 1]) + "): knots must not decrease");
    }
  }
  std::size_t lead = 1;
  while (lead < k_count && knots[lead] == knots[0])
    ++lead;
  curve.knots.clear();
  curve.points.clear();
  bool start_written = false;
  const std::string counts =
      std::to_string(k_count) + " knots and " + std::to_string(c_count) + " control points";
  if (lead >= 2) {
    curve.order = static_cast<int>(lead);
    if (k_count == c_count + lead) {
      start_written = true;
    } else if (k_count != c_count + 1 + lead) {
      fail_nurbs(counts + " do not fit a complete knot vector of order " + std::to_string(lead) +
                 " (it needs " + std::to_string(c_count + lead) +
                 " or, with the current position as first point, " +
                 std::to_string(c_count + 1 + lead) + " knots)");
    }
    curve.knots.assign(knots.begin(), knots.end());
  } else {
    const long order = static_cast<long>(c_count) + 2 - static_cast<long>(k_count);
    if (!(knots.front() > 0.0) || std::fabs(knots.back() - 1.0) > 1e-9) {
      fail_nurbs(
          "the knots neither start with a repeated value (a complete knot vector) nor "
          "run from above 0 to 1 (the NX form without the end knots): cannot tell the "
          "curve's order");
    }
    if (order < 2 || order > detail::kMaxNurbsOrder) {
      fail_nurbs(counts + " give order " + std::to_string(order) +
                 " in the NX form (order = " + "control points + 2 - knots); expected 2 to " +
                 std::to_string(detail::kMaxNurbsOrder));
    }
    curve.order = static_cast<int>(order);
    curve.knots.assign(static_cast<std::size_t>(order), 0.0);
    curve.knots.insert(curve.knots.end(), knots.begin(), knots.end() - 1);
    curve.knots.insert(curve.knots.end(), static_cast<std::size_t>(order), knots.back());
  }
  if (curve.order > detail::kMaxNurbsOrder)
    fail_nurbs("order " + std::to_string(curve.order) + " is above the supported " +
               std::to_string(detail::kMaxNurbsOrder));
  if (!start_written)
    curve.points.push_back({pos.x(), pos.y(), pos.z(), 1.0});
  for (const ClNurbsPoint& c : e.nurbs_points) {
    const Vector3d p = in_frame_point(Vector3d(c.x, c.y, c.z));
    if (!p.allFinite() || !std::isfinite(c.w))
      fail_nurbs("a control point or weight that is not a finite number");
    if (!(c.w > 0.0))
      fail_nurbs("a NURBS weight must be > 0, got " + fmt_mm(c.w));
    curve.points.push_back({c.w * p.x(), c.w * p.y(), c.w * p.z(), c.w});
  }
  check_knot_runs();
  if (start_written) {
    const double gap = (curve.cartesian(0) - pos).norm();
    if (gap > opt.point_match_tolerance_mm) {
      fail_nurbs("the curve starts " + fmt_mm(gap) +
                 " mm away from the current position (its first CNTRL/ must be the point "
                 "the tool is at; tolerance " +
                 fmt_mm(opt.point_match_tolerance_mm) + " mm)");
    }
  }
  gen_axis = in_frame_vector(e.tool_axis);
  gen_rapid = e.rapid;
  curve_chords.start(curve, opt.chordal_tolerance_mm);
  curve_chord_count = 0;
  generator = Generator::nurbs;
  pos = curve.cartesian(curve.points.size() - 1);
  axis = gen_axis;
}

// Clamped ends (order equal knots at each end) and interior knots repeated at most `degree`
// times, so that the curve is continuous and every span formula is defined.
void ClExpander::Impl::check_knot_runs() const {
  const std::vector<double>& u = curve.knots;
  const std::size_t order = static_cast<std::size_t>(curve.order);
  const std::size_t n = curve.points.size();
  if (n < order)
    fail_nurbs("order " + std::to_string(order) + " needs at least " + std::to_string(order) +
               " control points, got " + std::to_string(n));
  std::size_t i = 0;
  while (i < u.size()) {
    std::size_t j = i;
    while (j < u.size() && u[j] == u[i])
      ++j;
    const std::size_t run = j - i;
    const bool at_start = i == 0;
    const bool at_end = j == u.size();
    if ((at_start || at_end) && run != order) {
      fail_nurbs(std::string("the knot vector must ") + (at_start ? "start" : "end") +
                 " with exactly " + std::to_string(order) + " equal knots (order " +
                 std::to_string(order) + "), got " + std::to_string(run));
    }
    if (!at_start && !at_end && run >= order) {
      fail_nurbs("the interior knot " + fmt_mm(u[i]) + " is repeated " + std::to_string(run) +
                 " times; at most " + std::to_string(order - 1) + " keeps the curve continuous");
    }
    i = j;
  }
}

void ClExpander::Impl::run_nurbs() {
  Vector3d p;
  while (out.size() < kBatch) {
    if (!curve_chords.next(p)) {
      generator = Generator::none;
      return;
    }
    // The chords come one at a time, so the bound is checked as they come: a curve that needs
    // more fails at its line before the program grows by gigabytes.
    if (++curve_chord_count > kMaxCurveChords) {
      fail(gen_line, fmt::format("this NURBS needs more than the {} chords a curve may have, "
                                 "at a chordal tolerance of {:.6g} mm: raise --chordal-tol",
                                 kMaxCurveChords, opt.chordal_tolerance_mm));
    }
    ClEvent& m = emit_kind(ClEventKind::move, gen_line);
    m.p_mm = p;
    m.tool_axis = gen_axis;
    m.origin = MoveOrigin::nurbs;
    m.rapid = gen_rapid;
  }
}

}  // namespace redpost
