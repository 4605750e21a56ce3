// The HTML report of `redpost calibrate --report` (docs/calibration.md, "Report").
#include "calibrate_report.hpp"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "redpost/io/durable_write.hpp"
#include "redpost/report/html_report.hpp"

namespace redpost::cli {

namespace {

namespace rep = redpost::report;

// A parameter's value in the unit people read it in: deg for angles, mm for lengths.
double display(const CalibrationParameter& p, double v) {
  return p.is_angle() ? rad_to_deg(v) : v;
}
const char* display_unit(const CalibrationParameter& p) {
  return p.is_angle() ? "deg" : "mm";
}

std::vector<double> to_vector(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

// The rows under the title: inputs, iterations, residuals, conditioning, loss.
void add_summary(rep::HtmlReport& html, const CalibrationReportInput& in) {
  const CalibrationResult& r = *in.result;
  html.add_summary("cell", in.cell_path);
  html.add_summary("readings", fmt::format("{} ({} readings)", in.readings_path, in.readings));
  if (in.validation)
    html.add_summary("validation readings", fmt::format("{} ({} readings)", in.validation_path,
                                                        in.validation->before.count));
  html.add_summary("parameters", std::to_string(r.parameters.size()));
  html.add_summary("iterations",
                   fmt::format("{}{}", r.iterations,
                               r.converged ? " (converged, eq. 10)" : " (did NOT converge)"));
  html.add_summary("RMS of the residuals", fmt::format("{:.4f} mm before, {:.4f} mm after",
                                                       r.rms_before_mm, r.rms_after_mm));
  html.add_summary("sigma hat", fmt::format("{:.4f} mm", r.sigma_hat_mm));
  html.add_summary("condition number of the scaled W",
                   fmt::format("{:.4g} (rank {} of {})", r.observability.condition_number,
                               r.observability.rank, r.parameters.size()));
  html.add_summary("loss", to_string(in.options->loss));
}

// No convergence, a partial calibration, and the readings the robust loss weighted down.
void add_warnings(rep::HtmlReport& html, const CalibrationResult& r,
                  const CalibrationOptions& options) {
  if (!r.converged)
    html.add_warning(
        "The identification did not meet the stopping rule of eq. 10 within the "
        "iteration limit: do not use the result.");
  if (r.observability.rank_deficient())
    html.add_warning("Partial calibration: " + r.observability.summary() +
                     ". These directions kept their nominal values.");
  if (!r.outliers.empty()) {
    std::string rows;
    for (size_t k = 0; k < r.outliers.size(); ++k)
      rows += fmt::format("{}{}", k ? ", " : "", r.outliers[k] + 1);
    html.add_warning(
        fmt::format("{} reading(s) weighted below 0.5 by the {} loss (rows {}): "
                    "re-measure them if possible.",
                    r.outliers.size(), to_string(options.loss), rows));
  }
}

// Nominal, calibrated, change and standard error of every parameter.
rep::Table parameter_table(const CalibrationResult& r) {
  rep::Table t;
  t.header = {"parameter", "unit",           "nominal",      "calibrated",
              "change",    "standard error", "change / s.e."};
  for (size_t j = 0; j < r.parameters.size(); ++j) {
    const auto i = static_cast<Eigen::Index>(j);
    const CalibrationParameter& p = r.parameters[j];
    const double change = display(p, r.values[i] - r.initial[i]);
    const double se = display(p, r.standard_errors[i]);
    t.rows.push_back({rep::text(p.name()), rep::text(display_unit(p)),
                      rep::num(display(p, r.initial[i]), 6), rep::num(display(p, r.values[i]), 6),
                      rep::num(change, 6), rep::num(se, 6),
                      rep::num(std::isfinite(se) && se > 0.0 ? change / se : NAN, 1)});
  }
  return t;
}

// Figure 8 of the paper: parameter j's value per iteration, as the change from nominal.
rep::LinePlot parameter_history_plot(const CalibrationResult& r, size_t j) {
  const CalibrationParameter& p = r.parameters[j];
  rep::LinePlot plot;
  plot.title = p.name() + " per iteration";
  plot.x = rep::make_axis("iteration", "");
  plot.y = rep::make_axis("change from nominal", display_unit(p));
  rep::Series s;
  s.name = p.name();
  s.markers = true;
  for (size_t k = 0; k < r.value_history.size(); ++k) {
    s.x.push_back(static_cast<double>(k));
    s.y.push_back(display(p, r.value_history[k][static_cast<Eigen::Index>(j)] -
                                 r.initial[static_cast<Eigen::Index>(j)]));
  }
  plot.series.push_back(std::move(s));
  plot.width = 420;
  plot.height = 260;
  return plot;
}

// The parameters: the table, then every parameter per iteration.
void add_parameters_section(rep::HtmlReport& html, const CalibrationResult& r) {
  html.add_section("Identified parameters");
  html.add_table(parameter_table(r));
  for (size_t j = 0; j < r.parameters.size(); ++j)
    html.add_plot(parameter_history_plot(r, j));
}

// The residual RMS per iteration, the singular values, and the residuals left.
void add_convergence_section(rep::HtmlReport& html, const CalibrationResult& r) {
  html.add_section("Convergence");
  {
    rep::LinePlot plot;
    plot.title = "RMS of the residuals per iteration";
    plot.x = rep::make_axis("iteration", "");
    plot.y = rep::make_axis("RMS of the residuals", "mm", true);
    rep::Series s;
    s.name = "RMS";
    s.markers = true;
    for (size_t k = 0; k < r.rms_history_mm.size(); ++k) {
      s.x.push_back(static_cast<double>(k));
      s.y.push_back(r.rms_history_mm[k]);
    }
    plot.series.push_back(std::move(s));
    plot.width = 620;
    plot.height = 320;
    html.add_plot(std::move(plot));
  }
  {
    rep::BarPlot bars;
    bars.title = "Singular values of the column-scaled W";
    bars.x_label = "index";
    bars.y = rep::make_axis("singular value", "", true);
    for (Eigen::Index k = 0; k < r.observability.singular_values.size(); ++k) {
      bars.categories.push_back(fmt::format("s{}", k + 1));
      bars.values.push_back(r.observability.singular_values[k]);
    }
    html.add_plot(std::move(bars));
  }
  {
    rep::Histogram h;
    h.title = "Residuals of the calibration readings after identification";
    h.x = rep::make_axis("reading - model", "mm");
    rep::HistogramSet set;
    set.name = "after";
    set.values = to_vector(r.residuals_mm);
    h.sets.push_back(std::move(set));
    h.width = 1240;
    html.add_plot(std::move(h));
  }
}

// Validation (Figure 9): the distances left before and after, as a table and histograms.
void add_validation_section(rep::HtmlReport& html, const ValidationResult& v) {
  html.add_section("Validation (paper section 3.3)");
  html.add_paragraph(
      "Distances left on the validation points: 'before' is what the laser saw against the "
      "nominal model, 'after' against the calibrated model at the same joints (the error a "
      "controller using the calibrated cell would leave, to first order).");
  rep::Table vt;
  vt.header = {"", "readings", "mean [mm]", "RMS [mm]", "std [mm]", "max |d| [mm]"};
  for (const auto& [name, st] :
       {std::pair<const char*, const DistanceStatistics*>{"before", &v.before},
        {"after", &v.after}})
    vt.rows.push_back({rep::text(name), rep::count(st->count), rep::num(st->mean_mm, 4),
                       rep::num(st->rms_mm, 4), rep::num(st->std_mm, 4),
                       rep::num(st->max_abs_mm, 4)});
  html.add_table(vt);
  rep::Histogram h;
  h.title = "Validation distances before and after calibration";
  h.x = rep::make_axis("distance", "mm");
  rep::HistogramSet before, after;
  before.name = "before";
  before.values = to_vector(v.before_mm);
  after.name = "after";
  after.values = to_vector(v.after_mm);
  h.sets.push_back(std::move(before));
  h.sets.push_back(std::move(after));
  h.width = 1240;
  html.add_plot(std::move(h));
}

}  // namespace

void write_calibration_report(const std::string& path, const CalibrationReportInput& in) {
  const CalibrationResult& r = *in.result;
  rep::HtmlReport html("redpost calibrate: " +
                       std::filesystem::path(in.cell_path).filename().string());
  add_summary(html, in);
  add_warnings(html, r, *in.options);
  add_parameters_section(html, r);
  add_convergence_section(html, r);
  if (in.validation)
    add_validation_section(html, *in.validation);
  write_text_file(path, html.html());
}

}  // namespace redpost::cli
