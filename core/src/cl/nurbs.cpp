// The CL reader's NURBS: the NURBS/ block with its KNOT/ and CNTRL/ records, the knot vector
// built and checked, and the curve's chords given out in batches (ClReader::Impl,
// cl/reader_impl.hpp; the evaluation is in cl/nurbs_curve.hpp).
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cl/nurbs_curve.hpp"
#include "cl/reader_impl.hpp"

namespace redpost {

namespace {

std::string fmt_mm(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6);
  return std::string(buf, r.ptr);
}

}  // namespace

void ClReader::Impl::on_nurbs() {
  check_cycle_not_interrupted();
  split_fields();
  if (!fields.empty())
    fail_at(fields[0].offset, "NURBS/ takes no values (its data follow in KNOT/ and CNTRL/)");
  if (cycle.active)
    fail_word("NURBS while a CYCLE is active: give CYCLE/OFF first");
  if (!pos_known)
    fail_word("NURBS needs a start point, but no position is known yet");
  current_axis();
  collecting_nurbs = true;
  nurbs_line = record_line;
  nurbs_knots.clear();
  nurbs_points.clear();
}

void ClReader::Impl::on_knot() {
  split_fields();
  if (fields.empty())
    fail_word("KNOT/ needs at least one value");
  if (!nurbs_points.empty())
    fail_word("KNOT/ after CNTRL/: all knots must come before the control points");
  for (const Field& f : fields) {
    const double k = number(f);
    if (!nurbs_knots.empty() && k < nurbs_knots.back()) {
      fail_at(f.offset, "knot " + std::string(f.text) + " is smaller than the one before it (" +
                            fmt_mm(nurbs_knots.back()) + "): knots must not decrease");
    }
    nurbs_knots.push_back(k);
  }
}

void ClReader::Impl::on_cntrl() {
  split_fields();
  expect_count(3, 4, "3 values (x,y,z) or 4 (x,y,z,weight)");
  const Vector3d p = in_frame_point(point(0));
  double w = 1.0;
  if (fields.size() == 4) {
    w = number(fields[3]);
    if (!(w > 0.0))
      fail_at(fields[3].offset, "a NURBS weight must be > 0, got " + std::string(fields[3].text));
  }
  nurbs_points.push_back({w * p.x(), w * p.y(), w * p.z(), w});
}

void ClReader::Impl::fail_nurbs(const std::string& message) const {
  fail_line(nurbs_line, "NURBS: " + message);
}

// Builds the full clamped knot vector from what the file gives, checks it and starts the
// curve's generator. Two forms (docs/cl-format.md, "NURBS"):
// - complete: the list starts with `order` equal knots and ends with `order` equal knots;
//   the control points are all written (the first must be the current position) or all but
//   the first (which is the current position);
// - NX: the `order` leading knots (0) and `order - 1` of the trailing ones are left out and
//   the first control point is the current position, so K knots and C CNTRL records give
//   order = C + 2 - K; the list must start above 0 and end at 1.
void ClReader::Impl::finish_nurbs() {
  collecting_nurbs = false;
  const std::size_t k_count = nurbs_knots.size();
  const std::size_t c_count = nurbs_points.size();
  if (k_count == 0 || c_count == 0)
    fail_nurbs("needs KNOT/ and CNTRL/ records, got " + std::to_string(k_count) + " knots and " +
               std::to_string(c_count) + " control points");
  std::size_t lead = 1;
  while (lead < k_count && nurbs_knots[lead] == nurbs_knots[0])
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
    curve.knots.assign(nurbs_knots.begin(), nurbs_knots.end());
  } else {
    const long order = static_cast<long>(c_count) + 2 - static_cast<long>(k_count);
    if (!(nurbs_knots.front() > 0.0) || std::fabs(nurbs_knots.back() - 1.0) > 1e-9) {
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
    curve.knots.insert(curve.knots.end(), nurbs_knots.begin(), nurbs_knots.end() - 1);
    curve.knots.insert(curve.knots.end(), static_cast<std::size_t>(order), nurbs_knots.back());
  }
  if (curve.order > detail::kMaxNurbsOrder)
    fail_nurbs("order " + std::to_string(curve.order) + " is above the supported " +
               std::to_string(detail::kMaxNurbsOrder));
  if (!start_written)
    curve.points.push_back({pos.x(), pos.y(), pos.z(), 1.0});
  curve.points.insert(curve.points.end(), nurbs_points.begin(), nurbs_points.end());
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
  gen_axis = axis;  // on_nurbs() made sure it is known
  gen_rapid = take_rapid();
  gen_line = nurbs_line;
  curve_chords.start(curve, opt.chordal_tolerance_mm);
  curve_chord_count = 0;
  generator = Generator::nurbs;
  pos = curve.cartesian(curve.points.size() - 1);
}

// Clamped ends (order equal knots at each end) and interior knots repeated at most `degree`
// times, so that the curve is continuous and every span formula is defined.
void ClReader::Impl::check_knot_runs() const {
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

void ClReader::Impl::run_nurbs() {
  Vector3d p;
  while (queue.size() < kBatch) {
    if (!curve_chords.next(p)) {
      generator = Generator::none;
      return;
    }
    // The chords come one at a time, so the bound is checked as they come: a curve that needs
    // more fails at its line before the program grows by gigabytes.
    if (++curve_chord_count > kMaxCurveChords) {
      fail_line(gen_line, fmt::format("this NURBS needs more than the {} chords a curve may have, "
                                      "at a chordal tolerance of {:.6g} mm: raise --chordal-tol",
                                      kMaxCurveChords, opt.chordal_tolerance_mm));
    }
    push_move(p, gen_axis, MoveOrigin::nurbs, gen_rapid, gen_line);
  }
}

}  // namespace redpost
