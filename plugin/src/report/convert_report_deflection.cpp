// The "Deflection" section of the convert report (see convert_report_deflection.hpp).
#include "convert_report_deflection.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace redpost::run_report {

namespace {

namespace rep = redpost::report;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRadToDeg = 57.295779513082320876798;

// The operations together: the table's last row and the warnings.
struct Totals {
  long motions = 0;
  double sum_sq = 0.0, sum_sq_normal = 0.0;  // of |d| and |d_n| over the moves (for the RMS)
  double max_mm = 0.0, max_normal_mm = 0.0;
  int max_normal_line = 0;
  double max_rotation_rad = 0.0, max_force_N = 0.0;
  long over = 0, over_after = 0;
  double max_residual_normal_mm = 0.0, max_compensation_mm = 0.0;

  void add(const rp_deflection_info& f) {
    motions += f.motions;
    sum_sq += f.rms_mm * f.rms_mm * static_cast<double>(f.motions);
    sum_sq_normal += f.rms_normal_mm * f.rms_normal_mm * static_cast<double>(f.motions);
    max_mm = std::max(max_mm, f.max_mm);
    if (f.max_normal_mm > max_normal_mm || max_normal_line == 0) {
      max_normal_mm = std::max(max_normal_mm, f.max_normal_mm);
      max_normal_line = f.max_normal_line;
    }
    max_rotation_rad = std::max(max_rotation_rad, f.max_rotation_rad);
    max_force_N = std::max(max_force_N, f.max_force_N);
    over += f.over_tolerance;
    over_after += f.over_tolerance_after;
    max_residual_normal_mm = std::max(max_residual_normal_mm, f.max_residual_normal_mm);
    max_compensation_mm = std::max(max_compensation_mm, f.max_compensation_mm);
  }
  double rms_mm() const { return motions > 0 ? std::sqrt(sum_sq / motions) : kNaN; }
  double rms_normal_mm() const { return motions > 0 ? std::sqrt(sum_sq_normal / motions) : kNaN; }
};

rep::HLine hline(double y, std::string name, std::string color) {
  rep::HLine h;
  h.y = y;
  h.name = std::move(name);
  h.color = std::move(color);
  return h;
}

rep::Series series_of(std::string name, rep::XYSeries data, std::string color) {
  rep::Series s;
  s.name = std::move(name);
  s.x = std::move(data.x);
  s.y = std::move(data.y);
  s.color = std::move(color);
  return s;
}

std::string lines_text(int first, int last) {
  return first == last ? fmt::format("{}", first) : fmt::format("{}-{}", first, last);
}

// What was done, against what, and with which model.
void add_intro(rep::HtmlReport& r, const rp_deflection_summary& s) {
  const bool comp = s.mode == RP_DEFLECTION_COMPENSATE;
  std::string text =
      comp ? "The deflection of the tool under the cutting force was compensated: every cutting "
             "target was moved against the predicted deflection until the deflected tool lands "
             "on the CL point (a fixed point per move)."
           : "The deflection of the tool under the cutting force was predicted at every cutting "
             "move; the program is written unchanged.";
  text += fmt::format(
      " Its component along the machined wall's normal (+: the tool cuts too deep, -: it leaves "
      "material) is judged against the tolerance of {:g} mm either way. Model: the elastostatic "
      "joint-stiffness model of the arm at the posture written, loaded with the Tlusty-MacNeil "
      "mean cutting force of each move (docs/deflection.md).",
      s.tolerance_mm);
  r.add_paragraph(text);
}

std::vector<rep::TableCell> table_row(std::string name, std::string lines, bool comp,
                                      const rp_deflection_info& f) {
  std::vector<rep::TableCell> row = {
      rep::text(std::move(name)),   rep::text(std::move(lines)),
      rep::count(f.motions),        rep::num(f.max_mm, 3),
      rep::num(f.rms_mm, 3),        rep::num(f.max_normal_mm, 3),
      rep::num(f.rms_normal_mm, 3), rep::count(f.max_normal_line),
      rep::count(f.over_tolerance), rep::num(kRadToDeg * f.max_rotation_rad, 4),
      rep::num(f.max_force_N, 0)};
  if (comp) {
    row.push_back(rep::num(f.max_residual_normal_mm, 4));
    row.push_back(rep::count(f.over_tolerance_after));
    row.push_back(rep::num(f.max_compensation_mm, 3));
  }
  return row;
}

// One row per CL operation with a load (and one for all of them when there are several).
Totals add_operations_table(rep::HtmlReport& r, const rp_session* session,
                            const rp_deflection_summary& s) {
  const bool comp = s.mode == RP_DEFLECTION_COMPENSATE;
  rep::Table t;
  t.caption = fmt::format(
      "Per CL operation, over its cutting moves with a load. |d|: the deflection of the TCP; "
      "|d_n|: its component along the wall's normal; over: moves with |d_n| above {:g} mm{}.",
      s.tolerance_mm,
      comp ? "; residual: the error the model leaves after compensation, along the normal" : "");
  t.header = {"operation",    "CL lines",           "moves",          "max |d| [mm]",
              "RMS |d| [mm]", "max |d_n| [mm]",     "RMS |d_n| [mm]", "max |d_n| at line",
              "over",         "max rotation [deg]", "max force [N]"};
  if (comp) {
    t.header.insert(t.header.end(),
                    {"max residual |d_n| [mm]", "over after", "max compensation [mm]"});
  }
  Totals all;
  int first = 0, last = 0;
  for (int i = 0; i < s.operations; ++i) {
    rp_deflection_info f{};
    f.struct_size = sizeof f;
    if (rp_deflection_get(session, i, &f) != RP_OK)
      break;
    all.add(f);
    first = i == 0 ? f.first_line : std::min(first, f.first_line);
    last = std::max(last, f.last_line);
    t.rows.push_back(table_row(*f.operation ? f.operation : "(no operation)",
                               lines_text(f.first_line, f.last_line), comp, f));
  }
  if (t.rows.size() > 1) {
    rp_deflection_info f{};
    f.motions = all.motions;
    f.max_mm = all.max_mm;
    f.rms_mm = all.rms_mm();
    f.max_normal_mm = all.max_normal_mm;
    f.rms_normal_mm = all.rms_normal_mm();
    f.max_normal_line = all.max_normal_line;
    f.over_tolerance = all.over;
    f.max_rotation_rad = all.max_rotation_rad;
    f.max_force_N = all.max_force_N;
    f.max_residual_normal_mm = all.max_residual_normal_mm;
    f.over_tolerance_after = all.over_after;
    f.max_compensation_mm = all.max_compensation_mm;
    t.rows.push_back(table_row("all operations", lines_text(first, last), comp, f));
  }
  r.add_table(t);
  return all;
}

// The moves left out of the table, the fixed point's work, and a warning for what is out of
// tolerance (before compensation when predicting, after it when compensating).
void add_notes(rep::HtmlReport& r, const rp_deflection_summary& s, const Totals& all) {
  const bool comp = s.mode == RP_DEFLECTION_COMPENSATE;
  std::string text = fmt::format(
      "{} cutting move(s) without a modelled load (plunges, drilling, the spindle off) are not "
      "counted.",
      s.unloaded_moves);
  if (comp) {
    text += fmt::format(
        " Fixed point: {} iteration(s) beyond the first over the program, at most {} for one "
        "move.",
        s.compensation_iterations, s.max_compensation_iterations);
  }
  r.add_paragraph(text);
  if (!comp && all.over > 0) {
    r.add_warning(fmt::format(
        "{} of {} cutting moves deflect more than {:g} mm along the wall's normal (up to "
        "{:.3f} mm, at CL line {}): the part is out of tolerance there; --compensate moves the "
        "cutting targets against the deflection.",
        all.over, all.motions, s.tolerance_mm, all.max_normal_mm, all.max_normal_line));
  }
  if (comp && all.over_after > 0) {
    r.add_warning(fmt::format(
        "{} of {} cutting moves stay more than {:g} mm off along the wall's normal after "
        "compensation (the model's residual reaches {:.4f} mm).",
        all.over_after, all.motions, s.tolerance_mm, all.max_residual_normal_mm));
  }
}

// The signed normal deflection along the motions between the tolerance lines, and under
// compensate the residual the model leaves, on the same scale.
void add_normal_plot(rep::HtmlReport& r, const rp_deflection_summary& s, const rep::Axis& x,
                     const rep::MinMaxDecimator& normal, const rep::MinMaxDecimator& residual) {
  const bool comp = s.mode == RP_DEFLECTION_COMPENSATE;
  rep::LinePlot p;
  p.title = comp ? "Deflection along the wall's normal, before and after compensation "
                   "(+: too deep, -: material left; gaps: rapids)"
                 : "Predicted deflection along the wall's normal (+: too deep, -: material left; "
                   "gaps: rapids)";
  p.x = x;
  p.y = rep::make_axis("normal deflection", "mm");
  p.series.push_back(
      series_of(comp ? "before compensation (predicted deflection)" : "predicted deflection",
                normal.result(), "#1f77b4"));
  if (comp) {
    p.series.push_back(
        series_of("after compensation (model residual)", residual.result(), "#2ca02c"));
  }
  p.hlines.push_back(hline(
      s.tolerance_mm, fmt::format("tolerance +{:g} mm (too deep)", s.tolerance_mm), "#d62728"));
  p.hlines.push_back(hline(-s.tolerance_mm,
                           fmt::format("tolerance -{:g} mm (material left)", s.tolerance_mm),
                           "#d62728"));
  r.add_plot(std::move(p));
}

// Under compensate: the residual alone, on its own scale (next to the deflection it is a
// line on zero).
void add_residual_plot(rep::HtmlReport& r, const rep::Axis& x,
                       const rep::MinMaxDecimator& residual) {
  rep::LinePlot p;
  p.title = "After compensation: the model's residual, on its own scale";
  p.x = x;
  p.y = rep::make_axis("residual", "mm");
  p.series.push_back(
      series_of("after compensation (model residual)", residual.result(), "#2ca02c"));
  p.width = 620;
  p.height = 300;
  r.add_plot(std::move(p));
}

// The magnitude of the mean cutting force of each move.
void add_force_plot(rep::HtmlReport& r, const rep::Axis& x, const rep::MinMaxDecimator& force,
                    bool beside) {
  rep::LinePlot p;
  p.title = "Mean cutting force of each cutting move (gaps: rapids)";
  p.x = x;
  p.y = rep::make_axis("|F|", "N");
  p.y.min = 0.0;
  rep::Series s = series_of("cutting force", force.result(), "#8c564b");
  // Headroom above the highest force: a constant force would otherwise run along the frame.
  double top = 0.0;
  for (double f : s.y) {
    if (std::isfinite(f))
      top = std::max(top, f);
  }
  if (top > 0.0)
    p.y.max = 1.15 * top;
  p.series.push_back(std::move(s));
  p.width = beside ? 620 : 1240;
  p.height = 300;
  r.add_plot(std::move(p));
}

}  // namespace

DeflectionTrace::DeflectionTrace(int buckets)
    : normal_(buckets), residual_normal_(buckets), force_(buckets) {}

void DeflectionTrace::on_motion(const rp_motion& m) {
  const double x = static_cast<double>(m.index);
  if (m.has_deflection) {
    normal_.push(x, m.deflection_normal_mm);
    residual_normal_.push(x, m.residual_normal_mm);
    force_.push(x, m.cutting_force_N);
    gap_pending_ = true;
  } else if (m.kind != RP_MOTION_LIN && gap_pending_) {
    // One break per stretch of rapids: the lines do not join two cuts across them.
    normal_.push(x, kNaN);
    residual_normal_.push(x, kNaN);
    force_.push(x, kNaN);
    gap_pending_ = false;
  }
}

void DeflectionTrace::add_section(rep::HtmlReport& r, const rp_session* session,
                                  const rep::Axis& motions) const {
  rp_deflection_summary s{};
  s.struct_size = sizeof s;
  if (rp_deflection_summary_get(session, &s) != RP_OK || s.mode == RP_DEFLECTION_OFF)
    return;
  const bool comp = s.mode == RP_DEFLECTION_COMPENSATE;
  r.add_section(comp ? "Deflection under the cutting force, compensated"
                     : "Deflection under the cutting force, predicted");
  add_intro(r, s);
  if (s.operations == 0) {
    r.add_paragraph(
        "No cutting move with a load: plunges, drilling and moves with the spindle off have "
        "none.");
    return;
  }
  const Totals all = add_operations_table(r, session, s);
  add_notes(r, s, all);
  if (normal_.sample_count() == 0)
    return;
  if (const std::size_t width = normal_.bucket_width(); width > 1) {
    r.add_paragraph(fmt::format(
        "In the plots each point pair is the lowest and highest value of {} consecutive cutting "
        "moves.",
        width));
  }
  add_normal_plot(r, s, motions, normal_, residual_normal_);
  if (comp)
    add_residual_plot(r, motions, residual_normal_);
  add_force_plot(r, motions, force_, comp);
}

}  // namespace redpost::run_report
