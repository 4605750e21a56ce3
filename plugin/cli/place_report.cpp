// The HTML report of `redpost place --report` (docs/placement.md, "Reading the report").
#include "place_report.hpp"

#include <cmath>
#include <filesystem>
#include <limits>

#include <fmt/format.h>

#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/report/html_report.hpp"
#include "redpost/report/scene3d.hpp"
#include "report/scene_cell.hpp"

namespace redpost::cli {

namespace {

namespace rep = redpost::report;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double theta_deg(const Placement& p) {
  const double q1 = std::sqrt(std::max(0.0, 1.0 - p.q4 * p.q4));
  return rad_to_deg(2.0 * std::atan2(p.q4, q1));
}

// Caro Figures 5.2 / 5.4: c_i over (path point, beta) in the postures a plan uses (one per
// segment), with that plan drawn over it. The best and the worst plan may use different
// postures on a segment, so each gets its own map: a line drawn over another posture's values
// would mislead.
rep::HeatMap cost_map_plot(const PlacementProblem& pb, const CostMap& map, const SpinPlan& plan,
                           const char* plan_name, const char* colour, const std::string& title) {
  rep::HeatMap hm;
  hm.title = title;
  hm.height = 320;
  hm.x = rep::make_axis("tool path point", "");
  hm.y = rep::make_axis("spin angle beta", "deg");
  hm.value = rep::make_axis("c_i (eq. 5.1)", "mm");
  hm.values.resize(map.betas, map.points);
  for (int i = 0; i < map.points; ++i) {
    hm.x_centres.push_back(i + 1);
    const int seg = pb.path()[static_cast<size_t>(i)].segment;
    const int mu = plan.mu[static_cast<size_t>(seg)];
    for (int b = 0; b < map.betas; ++b)
      hm.values(b, i) = map.c(i, b, mu);
  }
  for (int b = 0; b < map.betas; ++b)
    hm.y_centres.push_back(rad_to_deg(pb.grid().beta_rad(b)));
  // The plans as polylines, broken where beta wraps around (a jump of nearly 360 deg is a step
  // of a few degrees on the circle, not a sweep across the map).
  auto overlay = [&](const SpinPlan& drawn, const char* name, const char* line_colour) {
    rep::Series s;
    s.name = name;
    s.color = line_colour;
    s.line_width = 2.5;
    for (int i = 0; i < map.points; ++i) {
      const double beta = rad_to_deg(pb.grid().beta_rad(drawn.beta_index[static_cast<size_t>(i)]));
      const bool new_segment = i > 0 && pb.path()[static_cast<size_t>(i)].segment !=
                                            pb.path()[static_cast<size_t>(i - 1)].segment;
      if (!s.y.empty() && (new_segment || std::abs(beta - s.y.back()) > 180.0)) {
        s.x.push_back(i + 0.5);
        s.y.push_back(std::numeric_limits<double>::quiet_NaN());
      }
      s.x.push_back(i + 1);
      s.y.push_back(beta);
    }
    hm.overlays.push_back(std::move(s));
  };
  overlay(plan, plan_name, colour);
  return hm;
}

// The rows under the title: inputs, the search, and the best and worst placements.
void add_summary(rep::HtmlReport& html, const PlacementReportInput& in) {
  const PlacementProblem& pb = *in.problem;
  const PlacementStudy& st = *in.study;
  const PlacementJob& job = pb.job();
  html.add_summary("job", in.job_path);
  html.add_summary("cell", job.cell_file);
  html.add_summary("tool path",
                   fmt::format("{} points on {} segments", pb.path().size(), job.segments.size()));
  html.add_summary("spin grid", fmt::format("{} angles, {:.1f} deg apart", pb.grid().count,
                                            rad_to_deg(pb.grid().step_rad)));
  html.add_summary("placements evaluated",
                   fmt::format("{} (best search) + {} (worst search) in {:.1f} s",
                               st.best.evaluations, st.worst.evaluations, in.seconds));
  const Placement& b = st.best.placement;
  const Placement& w = st.worst.placement;
  html.add_summary("best placement",
                   fmt::format("O_W = ({:.1f}, {:.1f}, {:.1f}) mm in F0, Q4 = {:.4f} ({:.1f} deg)",
                               b.x_mm, b.y_mm, b.z_mm, b.q4, theta_deg(b)));
  html.add_summary("worst placement",
                   fmt::format("O_W = ({:.1f}, {:.1f}, {:.1f}) mm in F0, Q4 = {:.4f} ({:.1f} deg)",
                               w.x_mm, w.y_mm, w.z_mm, w.q4, theta_deg(w)));
}

// Caro Table 5.1: f_MQC, max c_i and the postures of the four cases, and their ratio.
void add_cases_section(rep::HtmlReport& html, const PlacementStudy& st) {
  html.add_section("The four cases (Caro Table 5.1)");
  rep::Table t;
  t.header = {"case",         "placement",           "spin plan", "f_MQC [mm] (eq. 5.3)",
              "max c_i [mm]", "postures per segment"};
  const char* placement_name[4] = {"best", "best", "worst", "worst"};
  const char* spin_name[4] = {"best", "worst", "best", "worst"};
  for (size_t c = 0; c < 4; ++c) {
    std::string mus;
    for (size_t s = 0; s < st.cases[c].mu.size(); ++s)
      mus += fmt::format("{}{}", s ? " " : "", st.cases[c].mu[s]);
    t.rows.push_back({rep::text(fmt::format("{} ({})", c + 1, PlacementStudy::kCaseNames[c])),
                      rep::text(placement_name[c]), rep::text(spin_name[c]),
                      rep::num(st.cases[c].f_mqc_mm, 4), rep::num(st.cases[c].max_c_mm, 4),
                      rep::text(mus)});
  }
  html.add_table(t);
  html.add_paragraph(fmt::format(
      "Case 4 / Case 1 = {:.2f} (the paper: 1.2 / 0.083 = 14.5 with its own workpiece and data).",
      st.cases[3].f_mqc_mm / st.cases[0].f_mqc_mm));
}

// c_i along the path in each of the four cases, in the postures and spin angles of its plan.
rep::LinePlot cases_along_path_plot(const PlacementReportInput& in) {
  const PlacementProblem& pb = *in.problem;
  const PlacementStudy& st = *in.study;
  rep::LinePlot plot;
  plot.title = "c_i along the path for the four cases";
  plot.x = rep::make_axis("tool path point", "");
  plot.y = rep::make_axis("c_i", "mm");
  const char* colours[4] = {"#2ca02c", "#98df8a", "#d62728", "#ff9896"};
  const CostMap* maps[4] = {in.map_best, in.map_best, in.map_worst, in.map_worst};
  for (size_t c = 0; c < 4; ++c) {
    rep::Series s;
    s.name = fmt::format("case {}", c + 1);
    s.color = colours[c];
    for (int i = 0; i < maps[c]->points; ++i) {
      const int seg = pb.path()[static_cast<size_t>(i)].segment;
      s.x.push_back(i + 1);
      s.y.push_back(maps[c]->c(i, st.cases[c].beta_index[static_cast<size_t>(i)],
                               st.cases[c].mu[static_cast<size_t>(seg)]));
    }
    plot.series.push_back(std::move(s));
  }
  return plot;
}

// Caro Figures 5.2 and 5.4: the c_i map of each case with its plan, then c_i along the path.
void add_cost_maps_section(rep::HtmlReport& html, const PlacementReportInput& in) {
  const PlacementProblem& pb = *in.problem;
  const PlacementStudy& st = *in.study;
  html.add_section("c_i over the path and the spin angle (Caro Figures 5.2 and 5.4)");
  html.add_paragraph(
      "Each column is a path point, each row a spin angle beta; the colour is the tool "
      "displacement c_i normal to the feed and the tool axis, in the posture the plan drawn on "
      "the map uses on that segment (the postures per segment are in the table above). Hatched "
      "cells cannot be used: no inverse kinematics within the limits, 1/kappa_F at or below "
      "the minimum, or c_i above c_max. The plans break at the segment corners, where the tool "
      "is lifted.");
  const char* kGreen = "#2ca02c";
  const char* kRed = "#d62728";
  html.add_plot(cost_map_plot(pb, *in.map_best, st.cases[0], "best spin plan (case 1)", kGreen,
                              "Best placement, best spin plan (Figure 5.2, green)"));
  html.add_plot(cost_map_plot(pb, *in.map_best, st.cases[1], "worst spin plan (case 2)", kRed,
                              "Best placement, worst spin plan (Figure 5.2, red)"));
  html.add_plot(cost_map_plot(pb, *in.map_worst, st.cases[2], "best spin plan (case 3)", kGreen,
                              "Worst placement, best spin plan (Figure 5.4, green)"));
  html.add_plot(cost_map_plot(pb, *in.map_worst, st.cases[3], "worst spin plan (case 4)", kRed,
                              "Worst placement, worst spin plan (Figure 5.4, red)"));
  html.add_plot(cases_along_path_plot(in));
}

// Caro Figure 5.1: the best f_MQC found so far by the minimising and the maximising search.
void add_optimiser_section(rep::HtmlReport& html, const PlacementStudy& st) {
  html.add_section("The optimiser (Caro Figure 5.1)");
  rep::LinePlot plot;
  plot.title = "Best f_MQC found so far";
  plot.x = rep::make_axis("placements evaluated", "");
  plot.y = rep::make_axis("f_MQC of the best spin plan", "mm");
  rep::Series lo, hi;
  lo.name = "minimising (best placement)";
  hi.name = "maximising (worst placement)";
  hi.right_axis = true;
  for (const ConvergencePoint& c : st.best.history) {
    lo.x.push_back(c.evaluations);
    lo.y.push_back(c.best_f_mqc_mm);
  }
  for (const ConvergencePoint& c : st.worst.history) {
    hi.x.push_back(c.evaluations);
    hi.y.push_back(c.best_f_mqc_mm);
  }
  plot.has_y2 = true;
  plot.y2 = rep::make_axis("f_MQC, worst search", "mm");
  plot.series.push_back(std::move(lo));
  plot.series.push_back(std::move(hi));
  html.add_plot(std::move(plot));
}

// The work volume in F0 from above, with the tool path and O_W at the best and worst placements.
void add_top_view_section(rep::HtmlReport& html, const PlacementReportInput& in) {
  const PlacementProblem& pb = *in.problem;
  const PlacementStudy& st = *in.study;
  html.add_section("Top view of the work volume (eqs. 5.13-5.14)");
  rep::XYView view;
  view.title = "Work volume and placements in F0 (top view)";
  view.x = rep::make_axis("x0", "mm");
  view.y = rep::make_axis("y0", "mm");
  const WorkVolume& v = pb.job().volume;
  rep::Rect r;
  r.x0 = v.x_min_mm;
  r.x1 = v.x_max_mm;
  r.y0 = v.y_min_mm;
  r.y1 = v.y_max_mm;
  r.name = "work volume";
  view.rects.push_back(r);
  auto contour = [&](const Placement& p, const char* name, const char* colour) {
    const Isometry T = workpiece_frame(p);
    rep::PointSet path;
    path.name = std::string(name) + " tool path";
    path.color = colour;
    path.connect = true;
    path.markers = false;
    for (const PathPoint& pt : pb.path()) {
      const Eigen::Vector3d q = T * pt.T_W_P.translation();
      path.x.push_back(q.x());
      path.y.push_back(q.y());
    }
    view.sets.push_back(std::move(path));
    rep::PointSet origin;
    origin.name = std::string(name) + " O_W";
    origin.color = colour;
    origin.marker_radius = 5.0;
    origin.x.push_back(p.x_mm);
    origin.y.push_back(p.y_mm);
    view.sets.push_back(std::move(origin));
  };
  contour(st.best.placement, "best", "#2ca02c");
  contour(st.worst.placement, "worst", "#d62728");
  view.width = 1240;
  view.height = 520;
  html.add_plot(std::move(view));
}

// The cell at the best placement running its best spin plan: the program `place` writes. The
// TCP the page checks its kinematics against is this side's forward kinematics of each posture.
void add_scene_section(rep::HtmlReport& html, const PlacementReportInput& in) {
  if (!in.q_path || in.q_path->empty())
    return;
  const PlacementProblem& pb = *in.problem;
  const Cell& cell = pb.cell();
  const SpinPlan& plan = in.study->cases[0];
  const Isometry T_B_W = cell.T_B_0 * workpiece_frame(in.study->best.placement);
  const Isometry T_W_B = T_B_W.inverse();
  std::vector<rep::SceneQuantity> quantities(3);
  quantities[0] = {"c_i (eq. 5.1)", "mm", false, pb.job().constraints.c_max_mm, "c_max"};
  quantities[1] = {"1/kappa_F", "", true, pb.job().constraints.inv_kappa_min, "the minimum"};
  quantities[2] = {"closest joint limit", "% of the joint's range", true, 10.0, "limit zone"};
  rep::Scene3dRecorder rec(run_report::scene_cell_of(cell, T_B_W), quantities);
  for (std::size_t i = 0; i < in.q_path->size() && i < pb.path().size(); ++i) {
    const JointVector& q = (*in.q_path)[i];
    const int seg = pb.path()[i].segment;
    Vector6d w_B;
    Eigen::Vector3d y_B;
    pb.point_load(T_B_W, static_cast<int>(i), w_B, y_B);
    double values[3];
    values[1] = kNaN;
    pb.deflection_mm(q, w_B, y_B, &values[1]);
    values[0] = in.map_best->c(static_cast<int>(i), plan.beta_index[i],
                               plan.mu[static_cast<std::size_t>(seg)]);
    values[2] = run_report::closest_limit(cell, q).percent;
    const Eigen::Vector3d tcp_W = T_W_B * tcp_pose(cell, q).translation();
    rep::SceneMotion m;
    m.index = static_cast<long>(i) + 1;
    m.cl_line = static_cast<int>(i) + 1;
    m.q = q.data();
    m.joint_count = static_cast<int>(q.size());
    m.tool_length_mm = cell.tools.reference_length_mm;
    for (int k = 0; k < 3; ++k)
      m.tcp_part_mm[k] = tcp_W[k];
    m.values = values;
    rec.add(m);
  }
  html.add_section("The cell in 3D: the best placement and its best spin plan");
  html.add_paragraph(
      "The cell drawn from its DH chain at the joints of the program written (the best "
      "placement's best plan, one motion per path point), with the workpiece's tool path on the "
      "table, coloured by c_i, 1/kappa_F or "
      "the closest joint limit.");
  rep::Scene3d scene = rec.scene();
  scene.line_label = "path point";
  html.add_scene3d(scene);
}

}  // namespace

std::string placement_report_html(const PlacementReportInput& in) {
  rep::HtmlReport html("redpost place: " + std::filesystem::path(in.job_path).filename().string());
  add_summary(html, in);
  add_cases_section(html, *in.study);
  add_cost_maps_section(html, in);
  add_optimiser_section(html, *in.study);
  add_top_view_section(html, in);
  add_scene_section(html, in);
  return html.html();
}

}  // namespace redpost::cli
