// The "Clearance between bodies" section of the convert report (convert_report_clearance.hpp).
#include "convert_report_clearance.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace redpost::run_report {

namespace rep = redpost::report;

ClearanceTrace::ClearanceTrace(int buckets) : buckets_(buckets), others_(buckets) {}

void ClearanceTrace::on_motion(const rp_motion& m) {
  const double x = static_cast<double>(m.index);
  if (std::isnan(m.clearance_mm))
    return;  // nothing checked
  ++checked_motions_;
  // Every pair's series gets a gap where another pair (or none within reach) was the closest.
  const std::string pair = m.clearance_pair ? m.clearance_pair : "";
  std::size_t k = names_.size();
  if (std::isfinite(m.clearance_mm) && !pair.empty()) {
    for (k = 0; k < names_.size() && names_[k] != pair; ++k) {
    }
    if (k == names_.size() && names_.size() < kMaxPairs) {
      names_.push_back(pair);
      per_pair_.emplace_back(buckets_);
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < per_pair_.size(); ++i)
    per_pair_[i].push(x, i == k ? m.clearance_mm : nan);
  const bool other = std::isfinite(m.clearance_mm) && !pair.empty() && k >= names_.size();
  others_.push(x, other ? m.clearance_mm : nan);
  others_used_ = others_used_ || other;
  if (std::isfinite(m.clearance_mm) && (!has_closest_ || m.clearance_mm < closest_.mm)) {
    has_closest_ = true;
    closest_.pair = pair;
    closest_.motion = m.index;
    closest_.line = m.line;
    closest_.mm = m.clearance_mm;
    closest_.exact = m.clearance_exact != 0;
    for (int i = 0; i < 3; ++i) {
      closest_.a[static_cast<std::size_t>(i)] = m.clearance_point_a[i];
      closest_.b[static_cast<std::size_t>(i)] = m.clearance_point_b[i];
    }
  }
}

void ClearanceTrace::add_section(rep::HtmlReport& r, const rp_session* session,
                                 const rep::Axis& motions) const {
  rp_collision_summary c{};
  c.struct_size = sizeof c;
  if (rp_collision_get(session, &c) != RP_OK || !c.checked)
    return;
  r.add_section("Clearance between bodies");
  std::string text = fmt::format(
      "{} bodies (the cell's, the tool's and the set-up's) in {} pairs that may not touch were "
      "kept at least {:g} mm apart along every motion, as the controller runs it, with a proven "
      "bound between the poses (docs/collision.md); the least proven distance is {:.2f} mm.",
      c.bodies, c.pairs, c.margin_mm, c.proven_clearance_mm);
  if (has_closest_) {
    text += fmt::format(
        " The closest approach computed: {:.2f} mm between {} at motion {} (CL "
        "line {}).",
        closest_.mm, closest_.pair, closest_.motion, closest_.line);
  } else {
    text += fmt::format(" No pair came within {:g} mm of the margin.", 25.0);
  }
  r.add_paragraph(text);
  if (per_pair_.empty())
    return;
  rep::LinePlot p;
  p.title = "Closest approach per motion, by the pair that has it";
  p.x = motions;
  p.y = rep::make_axis("distance", "mm");
  p.y.min = 0.0;
  static const char* const kColors[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd",
                                        "#8c564b", "#e377c2", "#17becf", "#bcbd22"};
  for (std::size_t i = 0; i < per_pair_.size(); ++i) {
    rep::XYSeries data = per_pair_[i].result();
    rep::Series s;
    s.name = names_[i];
    s.x = std::move(data.x);
    s.y = std::move(data.y);
    s.color = kColors[i % 8];
    s.markers = true;
    p.series.push_back(std::move(s));
  }
  if (others_used_) {
    rep::XYSeries data = others_.result();
    rep::Series s;
    s.name = "other pairs";
    s.x = std::move(data.x);
    s.y = std::move(data.y);
    s.color = "#7f7f7f";
    s.markers = true;
    p.series.push_back(std::move(s));
  }
  rep::HLine margin;
  margin.y = c.margin_mm;
  margin.name = fmt::format("margin {:g} mm", c.margin_mm);
  p.hlines.push_back(margin);
  r.add_plot(std::move(p));
}

}  // namespace redpost::run_report
