// The report of `redpost calibrate plan --report` (calibrate_report.hpp; docs/calibration.md,
// "The plan's report").
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "calibrate_report.hpp"
#include "redpost/kinematics/conditioning.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/jacobian.hpp"
#include "redpost/report/html_report.hpp"
#include "redpost/report/scene3d.hpp"
#include "report/scene_cell.hpp"

namespace redpost::cli {

namespace {

namespace rep = redpost::report;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kPlaneColours[3] = {"#d62728", "#2ca02c", "#1f77b4"};  // x, y, z

void add_points_table(rep::HtmlReport& html, const CalibrationPlanReportInput& in) {
  const std::size_t configs = std::max<std::size_t>(in.configurations, 1);
  std::vector<std::array<long, 3>> count(configs, {0, 0, 0});
  for (const CalibrationPoint& p : *in.points) {
    const std::size_t c =
        std::min<std::size_t>(static_cast<std::size_t>(p.configuration), configs - 1);
    ++count[c][static_cast<std::size_t>(p.plane)];
  }
  rep::Table t;
  t.caption = in.configurations ? "Points per plane and configuration of the external joints"
                                : "Validation points per plane (random external joints)";
  t.header = {"configuration", "plane x", "plane y", "plane z", "all"};
  for (std::size_t c = 0; c < configs; ++c) {
    t.rows.push_back({rep::text(in.configurations ? std::to_string(c + 1) : "random"),
                      rep::count(count[c][0]), rep::count(count[c][1]), rep::count(count[c][2]),
                      rep::count(count[c][0] + count[c][1] + count[c][2])});
  }
  html.add_table(t);
}

// One translucent rectangle per plane, over its points with a margin (the grid's extent).
std::vector<rep::SceneRect> plane_rects(const std::vector<CalibrationPoint>& points) {
  std::vector<rep::SceneRect> rects;
  constexpr double kMarginMm = 40.0;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    for (const CalibrationPoint& p : points) {
      if (static_cast<int>(p.plane) != k)
        continue;
      lo = lo.cwiseMin(p.T_B_commanded.translation());
      hi = hi.cwiseMax(p.T_B_commanded.translation());
    }
    if (!(lo.x() <= hi.x()))
      continue;
    const int u = (k + 1) % 3, v = (k + 2) % 3;
    rep::SceneRect r;
    r.corner[static_cast<std::size_t>(k)] = 0.5 * (lo[k] + hi[k]);
    r.corner[static_cast<std::size_t>(u)] = lo[u] - kMarginMm;
    r.corner[static_cast<std::size_t>(v)] = lo[v] - kMarginMm;
    r.edge_u[static_cast<std::size_t>(u)] = hi[u] - lo[u] + 2 * kMarginMm;
    r.edge_v[static_cast<std::size_t>(v)] = hi[v] - lo[v] + 2 * kMarginMm;
    r.colour = kPlaneColours[k];
    r.name = std::string("plane ") + "xyz"[k];
    rects.push_back(r);
  }
  return rects;
}

// The cell at every point's posture, the points on the planes.
void add_scene_section(rep::HtmlReport& html, const CalibrationPlanReportInput& in) {
  const Cell& cell = *in.cell;
  std::vector<rep::SceneQuantity> quantities(3);
  quantities[0] = {"plane (x 0, y 1, z 2)", "", true, kNaN, "", true};
  quantities[1] = {"1/kappa_F", "", true, kNaN, ""};
  quantities[2] = {"closest joint limit", "% of the joint's range", true, 10.0, "limit zone"};
  rep::Scene3dRecorder rec(run_report::scene_cell_of(cell, Isometry::Identity()), quantities);
  KinematicsData data;
  Jacobian J(6, cell.size());
  for (std::size_t i = 0; i < in.points->size(); ++i) {
    const CalibrationPoint& p = (*in.points)[i];
    forward_kinematics(cell, p.q, data);
    double values[3] = {static_cast<double>(p.plane), kNaN,
                        run_report::closest_limit(cell, p.q).percent};
    if (cell.conditioning.declared()) {
      tcp_jacobian(cell, data, J);
      values[1] = arm_inverse_condition(cell, J);
    }
    rep::SceneMotion m;
    m.index = static_cast<long>(i) + 1;
    m.cl_line = static_cast<int>(i) + 1;
    m.q = p.q.data();
    m.joint_count = cell.size();
    m.tool_length_mm = cell.tools.reference_length_mm;
    // The page checks its kinematics against this side's: the TCP the nominal cell reaches.
    for (int k = 0; k < 3; ++k)
      m.tcp_part_mm[k] = data.T_B_tcp.translation()[k];
    m.values = values;
    rec.add(m);
  }
  rep::Scene3d scene = rec.scene();
  scene.path_as_points = true;
  scene.path_name = "measurement points";
  scene.line_label = "point";
  scene.rects = plane_rects(*in.points);
  html.add_section("The cell at the measurement points");
  html.add_paragraph(
      "The nominal cell drawn from its DH chain at each point's joints, in the order the program "
      "visits them (the readout's point number is the readings template's), "
      "with the measurement planes (x red, y green, z blue) and their points on the table. "
      "Watch the arm, the track and the table before running the program in T1.");
  html.add_scene3d(scene);
}

}  // namespace

std::string calibration_plan_report_html(const CalibrationPlanReportInput& in) {
  rep::HtmlReport html("redpost calibrate plan: " +
                       std::filesystem::path(in.cell_path).filename().string());
  html.add_summary("cell", in.cell_path);
  html.add_summary("points", std::to_string(in.points->size()));
  html.add_summary("configurations", in.configurations ? std::to_string(in.configurations)
                                                       : std::string("random (validation points)"));
  html.add_section("The points");
  add_points_table(html, in);
  long near = 0;
  std::string which;
  for (std::size_t i = 0; i < in.points->size(); ++i) {
    const run_report::LimitMargin m = run_report::closest_limit(*in.cell, (*in.points)[i].q);
    if (m.percent < 5.0) {
      which += fmt::format("{}{} ({} at {:.1f} %)", near ? ", " : "", i + 1,
                           in.cell->joint(m.joint).name, m.percent);
      ++near;
    }
  }
  if (near > 0)
    html.add_warning(
        fmt::format("{} point(s) run a joint within 5 % of its range of a limit: {}", near, which));
  add_scene_section(html, in);
  return html.html();
}

}  // namespace redpost::cli
