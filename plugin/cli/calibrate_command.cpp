// `redpost calibrate`: in-situ calibration of the external axes from laser readings on three
// planes (issue 7, docs/calibration.md).
//
//   redpost calibrate plan --cell C.xml [--grid 6] [--configs "0,700;45,300"]
//                          [--validation N] -o DIR
//   redpost calibrate simulate --cell C.xml --true TRUE.xml [--noise-mm 0.035] -o R.csv
//   redpost calibrate --cell C.xml --readings R.csv [--validate V.csv] [--loss huber]
//                     [--json J] [-o CALIBRATED.xml]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "calibrate_report.hpp"
#include "commands.hpp"
#include "definitions.hpp"
#include "redpost/calibration/identification.hpp"
#include "redpost/calibration/observability.hpp"
#include "redpost/calibration/parameters.hpp"
#include "redpost/calibration/plan.hpp"
#include "redpost/calibration/program.hpp"
#include "redpost/calibration/readings_csv.hpp"
#include "redpost/calibration/validation.hpp"
#include "redpost/io/durable_write.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/output_target.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/krl/template.hpp"

namespace redpost::cli {

namespace {

struct PlanArgs {
  std::string cell_path;
  int grid = 6;
  double stand_off_mm = 0.0;
  std::string configs;
  double half_width_mm = 200.0;
  double z_min_mm = 150.0;
  double z_max_mm = 450.0;
  int validation = 0;  // > 0: random validation points instead of the meshes
  std::uint64_t validation_seed = 7;
  std::string out;
  // plan only: the KRL program
  std::string templates;
  double dwell_s = 2.0;
  double retract_mm = 100.0;
  std::string tool = "TOOL_DATA[2]";
  std::string base = "BASE_DATA[1]";
  std::string report;  // plan only: the HTML report with the 3D view
};

struct SimulateArgs {
  PlanArgs plan;
  std::string true_path;
  double noise_mm = 0.035;
  std::uint64_t seed = 1;
  std::string form = "pose";
};

struct CalibrateArgs {
  std::string cell_path;
  std::string readings;
  std::string validate;
  std::string params;
  bool allow_partial = false;
  std::string loss = "none";
  double loss_scale_mm = 0.0;
  std::string json;
  std::string report;
  std::string out;
};

double parse_double(const std::string& text, const std::string& what) {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v))
      return v;
  } catch (const std::exception&) {
  }
  throw Error(ErrorCode::bad_input, fmt::format("{}: '{}' is not a number", what, text));
}

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t");
  if (b == std::string::npos)
    return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// "0,700;45,300": one configuration per ';', values in the order of the external joints,
// revolute joints in deg, prismatic ones in mm.
std::vector<std::vector<double>> parse_configs(const std::string& text, const Cell& cell,
                                               const std::vector<int>& external) {
  std::vector<std::vector<double>> out;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t semi = text.find(';', start);
    const std::string item =
        trim(text.substr(start, semi == std::string::npos ? std::string::npos : semi - start));
    start = semi == std::string::npos ? text.size() + 1 : semi + 1;
    if (item.empty())
      continue;
    std::vector<double> values;
    size_t s = 0;
    while (s <= item.size()) {
      const size_t comma = item.find(',', s);
      const std::string v =
          trim(item.substr(s, comma == std::string::npos ? std::string::npos : comma - s));
      s = comma == std::string::npos ? item.size() + 1 : comma + 1;
      values.push_back(parse_double(v, "--configs"));
    }
    if (values.size() != external.size()) {
      std::string names;
      for (size_t k = 0; k < external.size(); ++k)
        names += (k ? ", " : "") + cell.joint(external[k]).name;
      throw Error(ErrorCode::bad_input,
                  fmt::format("--configs: '{}' has {} values, expected {} (one per external "
                              "joint: {})",
                              item, values.size(), external.size(), names));
    }
    for (size_t k = 0; k < values.size(); ++k) {
      if (cell.joint(external[k]).type != JointType::prismatic)
        values[k] = deg_to_rad(values[k]);
    }
    out.push_back(values);
  }
  if (out.empty())
    throw Error(ErrorCode::bad_input, "--configs: no configuration given");
  return out;
}

CalibrationPlanOptions plan_options(const PlanArgs& args, const Cell& cell) {
  CalibrationPlanOptions opt;
  opt.external_joints = external_joint_indices(cell);
  if (opt.external_joints.empty())
    throw Error(ErrorCode::bad_input,
                fmt::format("calibrate: the cell '{}' maps no joint to an external axis (E1..E6): "
                            "there is nothing to calibrate",
                            cell.name));
  if (args.configs.empty() && opt.external_joints.size() != 2)
    throw Error(ErrorCode::bad_input,
                fmt::format("calibrate: the cell has {} external joints; give their "
                            "configurations with --configs",
                            opt.external_joints.size()));
  // 3 planes x grid^2 points per configuration, each a measurement of a few seconds on the
  // cell: 50 x 50 is already hours of measuring, and a larger grid is a typo.
  constexpr int kMaxGrid = 50;
  if (args.grid < 2 || args.grid > kMaxGrid) {
    throw Error(ErrorCode::bad_input,
                fmt::format("--grid: {} is outside 2 to {} (a grid x grid mesh per plane)",
                            args.grid, kMaxGrid));
  }
  opt.grid = args.grid;
  opt.stand_off_mm = args.stand_off_mm;
  if (!(args.half_width_mm > 0.0) || !(args.z_min_mm < args.z_max_mm))
    throw Error(ErrorCode::bad_input, "--half-width must be > 0 and --z-min below --z-max (mm)");
  opt.half_width_mm = args.half_width_mm;
  opt.z_min_mm = args.z_min_mm;
  opt.z_max_mm = args.z_max_mm;
  if (!args.configs.empty())
    opt.configurations = parse_configs(args.configs, cell, opt.external_joints);
  return opt;
}

// The points of the plan: the meshes of eqs. 2-4, or with --validation N random points on the
// table plane with random external joints (the paper's section 3.3).
std::vector<CalibrationPoint> planned_points(const PlanArgs& args, const Cell& cell,
                                             const CalibrationPlanOptions& opt) {
  if (args.validation < 0)
    throw Error(ErrorCode::bad_input, "--validation must not be negative");
  if (args.validation == 0)
    return plan_calibration(cell, opt);
  ValidationPlanOptions v;
  v.points = args.validation;
  v.external_joints = opt.external_joints;
  v.stand_off_mm = opt.stand_off_mm;
  v.half_width_mm = opt.half_width_mm;
  v.z_min_mm = opt.z_min_mm;
  v.z_max_mm = opt.z_max_mm;
  v.seed = args.validation_seed;
  return plan_validation(cell, v);
}

int run_plan(const PlanArgs& args) {
  if (!args.report.empty()) {
    check_output_target(args.report, "--report");
    check_output_folder(args.report, "--report");
    check_distinct_files({{"--cell", args.cell_path}}, {{"--report", args.report}});
  }
  const Cell cell = load_cell(args.cell_path);
  const CalibrationPlanOptions opt = plan_options(args, cell);
  const KrlTemplateSet templates =
      load_krl_templates(args.templates.empty() ? default_krl_template() : args.templates);
  const std::vector<CalibrationPoint> points = planned_points(args, cell, opt);
  // Made before anything is written: a report that cannot be made leaves DIR as it was.
  std::string report;
  if (!args.report.empty()) {
    CalibrationPlanReportInput in;
    in.cell_path = args.cell_path;
    in.cell = &cell;
    in.points = &points;
    in.configurations = args.validation > 0 ? 0 : opt.configurations.size();
    report = calibration_plan_report_html(in);
  }
  std::error_code ec;
  std::filesystem::create_directories(args.out, ec);
  if (ec)
    throw Error(ErrorCode::io,
                fmt::format("cannot create the directory '{}': {}", args.out, ec.message()));
  const bool validation = args.validation > 0;
  CalibrationProgramOptions popt;
  popt.name = validation ? "calib_validate" : "calib_plan";
  popt.output_dir = args.out;
  popt.dwell_s = args.dwell_s;
  popt.retract_mm = args.retract_mm;
  popt.tool = args.tool;
  popt.base = args.base;
  popt.external_joints = opt.external_joints;
  popt.header_comment = fmt::format("redpost calibrate plan, cell {}, {} points{}", cell.name,
                                    points.size(), validation ? " (validation)" : "");
  const std::vector<std::string> programs =
      write_calibration_program(cell, points, templates, popt);
  ReadingsWriteOptions wopt;
  wopt.form = ReadingsForm::commanded_pose;
  wopt.external_joints = opt.external_joints;
  wopt.blank_distances = true;
  wopt.point_numbers = true;
  const std::string path = (std::filesystem::path(args.out) /
                            (validation ? "validation_template.csv" : "readings_template.csv"))
                               .string();
  write_text_file(path, format_readings_csv(cell, points, wopt));
  if (validation)
    fmt::print("{} validation points (random external joints, seed {}): {}\n", points.size(),
               args.validation_seed, path);
  else
    fmt::print("{} points ({} configurations, {}x{} grids): {}\n", points.size(),
               opt.configurations.size(), opt.grid, opt.grid, path);
  for (const std::string& src : programs)
    fmt::print("KRL program: {}\n", src);
  if (!args.report.empty()) {
    write_text_file(args.report, report);
    fmt::print("report: {}\n", args.report);
  }
  // Points that run a joint close to its limit are legal but leave no room for the error being
  // calibrated: say which, so that they are watched in T1 first.
  std::string near;
  int count = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    for (int j = 0; j < cell.size(); ++j) {
      const Joint& jt = cell.joint(j);
      if (jt.axis.kind != AxisKind::arm)
        continue;
      const double margin = std::min(points[i].q[j] - jt.lower, jt.upper - points[i].q[j]);
      if (margin < deg_to_rad(2.0)) {
        near += fmt::format("{}{} ({} {:.1f} deg from its limit)", count ? ", " : "", i + 1,
                            axis_name(jt.axis), rad_to_deg(margin));
        ++count;
        break;
      }
    }
  }
  std::fflush(stdout);
  if (count > 0)
    fmt::print(stderr,
               "redpost: warning: {} point(s) run an arm joint within 2 deg of its limit: {}; "
               "run them in T1 first\n",
               count, near);
  return kExitOk;
}

int run_simulate(const SimulateArgs& args) {
  check_output_target(args.plan.out, "-o");
  check_distinct_files({{"--cell", args.plan.cell_path}, {"--true", args.true_path}},
                       {{"-o", args.plan.out}});
  const Cell cell = load_cell(args.plan.cell_path);
  const Cell truth = load_cell(args.true_path);
  if (truth.size() != cell.size())
    throw Error(ErrorCode::bad_input, fmt::format("--true: the cell has {} joints, '{}' has {}",
                                                  cell.size(), args.true_path, truth.size()));
  if (!(args.noise_mm >= 0.0))
    throw Error(ErrorCode::bad_input, "--noise-mm must not be negative");
  const CalibrationPlanOptions opt = plan_options(args.plan, cell);
  std::vector<CalibrationPoint> points = planned_points(args.plan, cell, opt);
  simulate_readings(truth, points, args.noise_mm, args.seed, opt.model);
  ReadingsWriteOptions wopt;
  if (args.form == "pose")
    wopt.form = ReadingsForm::commanded_pose;
  else if (args.form == "joints")
    wopt.form = ReadingsForm::joints;
  else
    throw Error(ErrorCode::bad_input, "--form must be 'pose' or 'joints'");
  wopt.external_joints = opt.external_joints;
  wopt.point_numbers = true;
  write_text_file(args.plan.out, format_readings_csv(cell, points, wopt));
  fmt::print("{} simulated readings (noise {} mm, seed {}): {}\n", points.size(), args.noise_mm,
             args.seed, args.plan.out);
  return kExitOk;
}

// JSON number: shortest round-trip form; NaN and infinities as null.
std::string jnum(double v) {
  if (!std::isfinite(v))
    return "null";
  if (v == 0.0)
    v = 0.0;
  return fmt::format("{}", v);
}

std::string jstr(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\')
      out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<int>(c));
      continue;
    }
    out += c;
  }
  return out + '"';
}

std::string stats_json(const DistanceStatistics& st) {
  return fmt::format(
      "{{\"count\": {}, \"mean_mm\": {}, \"rms_mm\": {}, \"std_mm\": {}, \"max_abs_mm\": {}}}",
      st.count, jnum(st.mean_mm), jnum(st.rms_mm), jnum(st.std_mm), jnum(st.max_abs_mm));
}

std::string result_json(const CalibrationResult& r, const CalibrationOptions& opt,
                        const ValidationResult* validation) {
  std::string s = "{\n  \"parameters\": {";
  for (size_t j = 0; j < r.parameters.size(); ++j)
    s += fmt::format("{}\n    {}: {}", j ? "," : "", jstr(r.parameters[j].name()),
                     jnum(r.values[static_cast<Eigen::Index>(j)]));
  s += "\n  },\n  \"initial\": {";
  for (size_t j = 0; j < r.parameters.size(); ++j)
    s += fmt::format("{}\n    {}: {}", j ? "," : "", jstr(r.parameters[j].name()),
                     jnum(r.initial[static_cast<Eigen::Index>(j)]));
  s += "\n  },\n  \"standard_errors\": {";
  for (size_t j = 0; j < r.parameters.size(); ++j)
    s += fmt::format("{}\n    {}: {}", j ? "," : "", jstr(r.parameters[j].name()),
                     jnum(r.standard_errors[static_cast<Eigen::Index>(j)]));
  s += fmt::format("\n  }},\n  \"iterations\": {},\n  \"converged\": {},\n", r.iterations,
                   r.converged ? "true" : "false");
  s += fmt::format("  \"rms_before_mm\": {},\n  \"rms_after_mm\": {},\n  \"sigma_hat_mm\": {},\n",
                   jnum(r.rms_before_mm), jnum(r.rms_after_mm), jnum(r.sigma_hat_mm));
  s += "  \"singular_values\": [";
  const Eigen::VectorXd& sv = r.observability.singular_values;
  for (Eigen::Index k = 0; k < sv.size(); ++k)
    s += (k ? ", " : "") + jnum(sv[k]);
  s += fmt::format("],\n  \"condition_number\": {},\n  \"rank\": {},\n  \"unobservable\": [",
                   jnum(r.observability.condition_number), r.observability.rank);
  for (size_t k = 0; k < r.observability.unobservable.size(); ++k)
    s += (k ? ", " : "") + jstr(r.observability.unobservable[k].description);
  s += "],\n";
  s += fmt::format("  \"loss\": {},\n  \"outliers\": [", jstr(to_string(opt.loss)));
  for (size_t k = 0; k < r.outliers.size(); ++k)
    s += fmt::format("{}{}", k ? ", " : "", r.outliers[k] + 1);  // 1-based reading numbers
  s += "],\n  \"residuals\": " + stats_json(distance_statistics(r.residuals_mm)) + ",\n";
  s += "  \"history\": [";
  for (size_t k = 0; k < r.value_history.size(); ++k) {
    s += fmt::format("{}\n    {{\"iteration\": {}, \"rms_mm\": {}, \"parameters\": {{",
                     k ? "," : "", k, jnum(r.rms_history_mm[k]));
    for (size_t j = 0; j < r.parameters.size(); ++j)
      s += fmt::format("{}{}: {}", j ? ", " : "", jstr(r.parameters[j].name()),
                       jnum(r.value_history[k][static_cast<Eigen::Index>(j)]));
    s += "}}";
  }
  s += "\n  ]";
  if (validation) {
    s += ",\n  \"validation\": {\n    \"before\": " + stats_json(validation->before) +
         ",\n    \"after\": " + stats_json(validation->after) + "\n  }";
  }
  s += "\n}\n";
  return s;
}

std::string with_unit(const CalibrationParameter& p, double v) {
  return p.is_angle() ? fmt::format("{:.9f} rad", v) : fmt::format("{:.6f} mm", v);
}

int run_calibrate(const CalibrateArgs& args) {
  if (args.cell_path.empty() || args.readings.empty())
    throw Error(ErrorCode::bad_input,
                "calibrate: --cell and --readings are required (or use 'calibrate plan' or "
                "'calibrate simulate'; see --help)");
  // An output over an input, or over another output, would destroy it: refused before reading.
  const std::vector<NamedPath> outputs = {
      {"-o", args.out}, {"--json", args.json}, {"--report", args.report}};
  for (const NamedPath& o : outputs) {
    if (!o.path.empty())
      check_output_target(o.path, o.role);
  }
  check_distinct_files(
      {{"--cell", args.cell_path}, {"--readings", args.readings}, {"--validate", args.validate}},
      outputs);
  const Cell cell = load_cell(args.cell_path);
  const std::vector<CalibrationParameter> params = parse_calibration_parameters(args.params, cell);
  const std::vector<CalibrationPoint> points = load_readings_csv(args.readings, cell);
  // Read the validation file before the (longer) identification: a bad file fails fast.
  std::vector<CalibrationPoint> vpoints;
  if (!args.validate.empty())
    vpoints = load_readings_csv(args.validate, cell);
  CalibrationOptions opt;
  opt.allow_partial = args.allow_partial;
  opt.loss = parse_robust_loss(args.loss);
  if (!(args.loss_scale_mm >= 0.0) || !std::isfinite(args.loss_scale_mm))
    throw Error(ErrorCode::bad_input, "--loss-scale must be a number >= 0 (0: estimated)");
  opt.loss_scale_mm = args.loss_scale_mm;
  const CalibrationResult r = calibrate(cell, params, points, opt);
  ValidationResult validation;
  if (!vpoints.empty())
    validation = validate_calibration(cell, r.calibrated, vpoints, opt.model);

  fmt::print("{} readings, {} parameters\n", points.size(), params.size());
  fmt::print("{:<12} {:>18} {:>18} {:>14} {:>12}\n", "parameter", "before", "after", "change",
             "std. error");
  for (size_t j = 0; j < params.size(); ++j) {
    const auto i = static_cast<Eigen::Index>(j);
    const CalibrationParameter& p = params[j];
    const double change = r.values[i] - r.initial[i];
    const double se = r.standard_errors[i];
    fmt::print("{:<12} {:>18} {:>18} {:>14} {:>12}\n", p.name(), with_unit(p, r.initial[i]),
               with_unit(p, r.values[i]),
               p.is_angle() ? fmt::format("{:+.5f} deg", rad_to_deg(change))
                            : fmt::format("{:+.5f} mm", change),
               !std::isfinite(se) ? std::string("-")
               : p.is_angle()     ? fmt::format("{:.5f} deg", rad_to_deg(se))
                                  : fmt::format("{:.5f} mm", se));
  }
  fmt::print("iterations: {}{}\n", r.iterations, r.converged ? "" : " (did not converge)");
  fmt::print("RMS of the residuals: {:.6f} mm before, {:.6f} mm after\n", r.rms_before_mm,
             r.rms_after_mm);
  std::string sv;
  for (Eigen::Index k = 0; k < r.observability.singular_values.size(); ++k)
    sv += fmt::format("{}{:.6g}", k ? " " : "", r.observability.singular_values[k]);
  fmt::print("singular values of the scaled W: {} (condition number {:.4g}, rank {} of {})\n", sv,
             r.observability.condition_number, r.observability.rank, params.size());
  if (r.observability.rank_deficient())
    fmt::print("not identified (partial calibration): {}\n", r.observability.summary());
  if (opt.loss != RobustLoss::none) {
    std::string list;
    for (size_t k = 0; k < r.outliers.size(); ++k)
      list += fmt::format("{}{}", k ? ", " : "", r.outliers[k] + 1);
    fmt::print("{} loss: {} reading(s) weighted below 0.5{}{}\n", to_string(opt.loss),
               r.outliers.size(), r.outliers.empty() ? "" : ": rows ", list);
  }
  if (!vpoints.empty()) {
    auto line = [](const char* when, const DistanceStatistics& st) {
      fmt::print(
          "validation {} ({} readings): mean {:+.4f} mm, RMS {:.4f} mm, std {:.4f} mm, "
          "max |d| {:.4f} mm\n",
          when, st.count, st.mean_mm, st.rms_mm, st.std_mm, st.max_abs_mm);
    };
    line("before", validation.before);
    line("after ", validation.after);
  }
  if (!args.json.empty())
    write_text_file(args.json, result_json(r, opt, vpoints.empty() ? nullptr : &validation));
  if (!args.report.empty()) {
    CalibrationReportInput in;
    in.cell_path = args.cell_path;
    in.readings_path = args.readings;
    in.validation_path = args.validate;
    in.readings = static_cast<int>(points.size());
    in.result = &r;
    in.options = &opt;
    in.validation = vpoints.empty() ? nullptr : &validation;
    write_calibration_report(args.report, in);
    fmt::print("report: {}\n", args.report);
  }
  if (!args.out.empty()) {
    const std::time_t now = std::time(nullptr);
    char date[32] = "";
    std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
    std::string changed;
    for (size_t j = 0; j < params.size(); ++j) {
      const auto i = static_cast<Eigen::Index>(j);
      changed += fmt::format(
          "{}{} {}", j ? ", " : "", params[j].name(),
          params[j].is_angle() ? fmt::format("{:+.6f} deg", rad_to_deg(r.values[i] - r.initial[i]))
                               : fmt::format("{:+.6f} mm", r.values[i] - r.initial[i]));
    }
    const std::string comment = fmt::format(
        "calibrated by redpost calibrate on {} from {} ({} readings): RMS {:.4f} mm before, "
        "{:.4f} mm after, {} iterations; changes: {}",
        date, std::filesystem::path(args.readings).filename().string(), points.size(),
        r.rms_before_mm, r.rms_after_mm, r.iterations, changed);
    write_text_file(args.out, calibrated_cell_xml(read_text_file(args.cell_path), args.cell_path,
                                                  params, r.values, comment));
    fmt::print("calibrated cell: {}\n", args.out);
  }
  return kExitOk;
}

}  // namespace

Runner add_calibrate_command(CLI::App& app) {
  auto cal = std::make_shared<CalibrateArgs>();
  auto plan = std::make_shared<PlanArgs>();
  auto sim = std::make_shared<SimulateArgs>();

  CLI::App* c = app.add_subcommand(
      "calibrate",
      "Calibrate the external axes from laser readings on the planes x, y, z = 0 of the base "
      "frame (Andres et al. 2011; docs/calibration.md). Without a subcommand: identify the "
      "parameters from a readings file.");
  c->require_subcommand(0, 1);
  c->add_option("--cell", cal->cell_path, "Nominal cell definition (XML)");
  c->add_option("--readings", cal->readings,
                "Readings CSV: plane,distance,x,y,z,a,b,c,q1,q2 or plane,distance,q1..qn");
  c->add_option("--params", cal->params,
                "Parameters to identify, comma-separated link<i>.<alpha|a|theta|d> (default: "
                "link1.alpha,link1.a,link1.theta,link1.d,link2.theta,link2.d)");
  c->add_flag("--allow-partial", cal->allow_partial,
              "On rank deficiency, identify only the observable combinations instead of refusing");
  c->add_option("--validate", cal->validate,
                "Validation readings (same CSV forms), taken with the nominal model: reports the "
                "mean, RMS and std of the distances before and after calibration");
  c->add_option("--loss", cal->loss,
                "none (least squares, default), huber or cauchy: robust to outlying readings");
  c->add_option("--loss-scale", cal->loss_scale_mm,
                "Residual scale of the robust loss, mm (default 0: estimated from the residuals)");
  c->add_option("--json", cal->json, "Write the result as JSON to this file");
  c->add_option("--report", cal->report,
                "Write an HTML report (parameters and RMS per iteration, singular values, "
                "validation histograms)");
  c->add_option("-o,--output", cal->out,
                "Write the calibrated cell: the --cell file with only the identified <dh> values "
                "changed and a comment recording the date and RMS");

  auto add_plan_options = [](CLI::App* s, PlanArgs& a) {
    s->add_option("--cell", a.cell_path, "Nominal cell definition (XML)")->required();
    s->add_option("--grid", a.grid, "A grid x grid mesh per plane (default 6)");
    s->add_option("--stand-off", a.stand_off_mm,
                  "Distance of the commanded TCP from its plane, mm (default 0)");
    s->add_option("--configs", a.configs,
                  "External configurations, ';'-separated, values in chain order, revolute in "
                  "deg, prismatic in mm (default \"0,700;45,300\")");
    s->add_option("--half-width", a.half_width_mm,
                  "Half width of the meshes in the planes, mm (default 200)");
    s->add_option("--z-min", a.z_min_mm, "Lowest mesh row on the x and y planes, mm (default 150)");
    s->add_option("--z-max", a.z_max_mm,
                  "Highest mesh row on the x and y planes, mm (default 450)");
    s->add_option("--validation", a.validation,
                  "Instead of the meshes: N validation points on the table plane (z) with random "
                  "external joints (theta_M in [0, 180] deg, d_L in [0, 1000] mm)");
    s->add_option("--validation-seed", a.validation_seed,
                  "Seed of the validation points (default 7)");
  };
  CLI::App* p = c->add_subcommand(
      "plan",
      "Plan the measurement: writes the KRL program DIR/calib_plan.src/.dat that visits every "
      "point, and DIR/readings_template.csv with the same point numbers and the distance "
      "column to fill in (with --validation: calib_validate.* and validation_template.csv)");
  add_plan_options(p, *plan);
  p->add_option("-o,--output", plan->out, "Output directory")->required();
  p->add_option("--templates", plan->templates,
                "KRL template set (XML; default: the shipped krc4_lin)");
  p->add_option("--dwell", plan->dwell_s,
                "Seconds to wait at each point for the reading (default 2; 0 writes HALT)");
  p->add_option("--retract", plan->retract_mm,
                "Approach/retract distance along the beam before and after each plane, mm "
                "(default 100)");
  p->add_option("--tool", plan->tool, "$TOOL of the laser sensor (default TOOL_DATA[2])");
  p->add_option("--base", plan->base, "$BASE (default BASE_DATA[1])");
  p->add_option("--report", plan->report,
                "Write an HTML report: the points per plane and configuration, and the cell in 3D "
                "visiting every point over the three planes");

  CLI::App* s = c->add_subcommand(
      "simulate", "Synthetic readings of the plan from a perturbed 'true' cell, for trials");
  add_plan_options(s, sim->plan);
  s->add_option("--true", sim->true_path, "The 'true' cell definition (XML)")->required();
  s->add_option("--noise-mm", sim->noise_mm, "Gaussian sensor noise sigma, mm (default 0.035)");
  s->add_option("--seed", sim->seed, "Noise seed (default 1)");
  s->add_option("--form", sim->form,
                "pose: commanded pose and external joints (default); joints: every joint");
  s->add_option("-o,--output", sim->plan.out, "Readings CSV to write")->required();

  return [cal, plan, sim, p, s] {
    if (p->parsed())
      return run_plan(*plan);
    if (s->parsed())
      return run_simulate(*sim);
    return run_calibrate(*cal);
  };
}

}  // namespace redpost::cli
