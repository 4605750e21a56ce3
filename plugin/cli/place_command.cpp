// `redpost place`: stiffness-aware workpiece placement and tool-spin planning (Caro 2014
// chapter 5, issue 8; docs/placement.md).
//
//   redpost place JOB.xml -o DIR [--json OUT.json] [--seed N]
//
// Writes into DIR: placement.csv (the two placements and the four cases of Table 5.1),
// plans.csv (beta and mu per path point for the four cases), cmap_best.csv and cmap_worst.csv
// (c_i over path point and beta at the two placements), convergence.csv, and the KRL program of
// the best placement with its best spin plan. Everything is computed first and every file is
// renamed into place only when complete.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "commands.hpp"
#include "definitions.hpp"
#include "place_report.hpp"
#include "redpost/io/durable_write.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/output_target.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "redpost/krl/template.hpp"
#include "redpost/krl/writer.hpp"
#include "redpost/machining/cutting_force.hpp"
#include "redpost/machining/placement.hpp"
#include "redpost/machining/placement_job.hpp"

namespace redpost::cli {

namespace {

struct PlaceArgs {
  std::string job;
  std::string out;
  std::string json;
  std::string krl_path;
  std::string report;
  long long seed = -1;
};

std::string num(double v, int decimals = 6) {
  if (!std::isfinite(v))
    return "";
  const std::string s = fmt::format("{:.{}f}", v, decimals);
  return s == fmt::format("-{:.{}f}", 0.0, decimals) ? s.substr(1) : s;
}

std::string jnum(double v) {
  return std::isfinite(v) ? fmt::format("{}", v == 0.0 ? 0.0 : v) : "null";
}

double theta_deg(const Placement& p) {
  const double q1 = std::sqrt(std::max(0.0, 1.0 - p.q4 * p.q4));
  return rad_to_deg(2.0 * std::atan2(p.q4, q1));
}

std::string placement_csv(const PlacementProblem& pb, const PlacementStudy& st) {
  std::string s = "case,x_mm,y_mm,z_mm,q4,theta_deg,f_mqc_mm,max_c_mm";
  for (const ContourSegment& seg : pb.job().segments)
    s += ",mu_" + seg.name;
  s += '\n';
  for (size_t c = 0; c < 4; ++c) {
    const Placement& p = c < 2 ? st.best.placement : st.worst.placement;
    const SpinPlan& plan = st.cases[c];
    s += fmt::format("{},{},{},{},{},{},{},{}", PlacementStudy::kCaseNames[c], num(p.x_mm, 3),
                     num(p.y_mm, 3), num(p.z_mm, 3), num(p.q4, 6), num(theta_deg(p), 3),
                     num(plan.f_mqc_mm, 6), num(plan.max_c_mm, 6));
    for (int mu : plan.mu)
      s += fmt::format(",{}", mu);
    s += '\n';
  }
  return s;
}

std::string plans_csv(const PlacementProblem& pb, const PlacementStudy& st, const CostMap& map_best,
                      const CostMap& map_worst) {
  std::string s = "point,segment,x_W_mm,y_W_mm";
  for (const char* name : PlacementStudy::kCaseNames)
    s += fmt::format(",{0}_beta_deg,{0}_mu,{0}_c_mm", name);
  s += '\n';
  for (size_t i = 0; i < pb.path().size(); ++i) {
    const PathPoint& p = pb.path()[i];
    s += fmt::format("{},{},{},{}", i + 1, pb.job().segments[static_cast<size_t>(p.segment)].name,
                     num(p.T_W_P.translation().x(), 3), num(p.T_W_P.translation().y(), 3));
    for (size_t c = 0; c < 4; ++c) {
      const SpinPlan& plan = st.cases[c];
      const CostMap& map = c < 2 ? map_best : map_worst;
      const int b = plan.beta_index[i];
      const int mu = plan.mu[static_cast<size_t>(p.segment)];
      s += fmt::format(",{},{},{}", num(rad_to_deg(pb.grid().beta_rad(b)), 3), mu,
                       num(map.c(static_cast<int>(i), b, mu), 6));
    }
    s += '\n';
  }
  return s;
}

// c_i over (point, beta): every posture, and the one of the best plan's segment.
std::string cost_map_csv(const PlacementProblem& pb, const CostMap& map, const SpinPlan& best,
                         const SpinPlan& worst) {
  std::string s = "point,segment,beta_deg,mu_plan,c_mm,best_plan,worst_plan";
  for (int mu = 1; mu <= kPostures; ++mu)
    s += fmt::format(",c_mu{}_mm", mu);
  s += '\n';
  for (int i = 0; i < map.points; ++i) {
    const int seg = pb.path()[static_cast<size_t>(i)].segment;
    const int mu_plan = best.mu[static_cast<size_t>(seg)];
    for (int b = 0; b < map.betas; ++b) {
      s += fmt::format(
          "{},{},{},{},{},{},{}", i + 1, pb.job().segments[static_cast<size_t>(seg)].name,
          num(rad_to_deg(pb.grid().beta_rad(b)), 3), mu_plan, num(map.c(i, b, mu_plan), 6),
          best.beta_index[static_cast<size_t>(i)] == b ? 1 : 0,
          worst.beta_index[static_cast<size_t>(i)] == b ? 1 : 0);
      for (int mu = 1; mu <= kPostures; ++mu)
        s += "," + num(map.c(i, b, mu), 6);
      s += '\n';
    }
  }
  return s;
}

std::string convergence_csv(const PlacementStudy& st) {
  std::string s = "search,evaluations,best_f_mqc_mm\n";
  for (const ConvergencePoint& c : st.best.history)
    s += fmt::format("best,{},{}\n", c.evaluations, num(c.best_f_mqc_mm, 6));
  for (const ConvergencePoint& c : st.worst.history)
    s += fmt::format("worst,{},{}\n", c.evaluations, num(c.best_f_mqc_mm, 6));
  return s;
}

std::string study_json(const PlacementStudy& st, double seconds) {
  auto placement = [](const Placement& p) {
    return fmt::format("{{\"x_mm\": {}, \"y_mm\": {}, \"z_mm\": {}, \"q4\": {}}}", jnum(p.x_mm),
                       jnum(p.y_mm), jnum(p.z_mm), jnum(p.q4));
  };
  auto history = [](const std::vector<ConvergencePoint>& h) {
    std::string s = "[";
    for (size_t k = 0; k < h.size(); ++k)
      s += fmt::format("{}{{\"evaluations\": {}, \"best_f_mqc_mm\": {}}}", k ? ", " : "",
                       h[k].evaluations, jnum(h[k].best_f_mqc_mm));
    return s + "]";
  };
  std::string s = "{\n";
  s += "  \"placement\": " + placement(st.best.placement) + ",\n";
  s += "  \"worst_placement\": " + placement(st.worst.placement) + ",\n";
  s += "  \"cases\": {\n";
  for (size_t c = 0; c < 4; ++c) {
    s += fmt::format("    \"{}\": {{\"f_mqc_mm\": {}, \"max_c_mm\": {}, \"mu\": [",
                     PlacementStudy::kCaseNames[c], jnum(st.cases[c].f_mqc_mm),
                     jnum(st.cases[c].max_c_mm));
    for (size_t k = 0; k < st.cases[c].mu.size(); ++k)
      s += fmt::format("{}{}", k ? ", " : "", st.cases[c].mu[k]);
    s += fmt::format("]}}{}\n", c < 3 ? "," : "");
  }
  s += "  },\n";
  s += fmt::format("  \"ratio_case4_case1\": {},\n",
                   jnum(st.cases[3].f_mqc_mm / st.cases[0].f_mqc_mm));
  s += "  \"convergence\": {\n";
  s += fmt::format("    \"best\": {{\"evaluations\": {}, \"feasible\": {}, \"history\": {}}},\n",
                   st.best.evaluations, st.best.feasible_evaluations, history(st.best.history));
  s += fmt::format("    \"worst\": {{\"evaluations\": {}, \"feasible\": {}, \"history\": {}}}\n",
                   st.worst.evaluations, st.worst.feasible_evaluations, history(st.worst.history));
  s += "  },\n";
  s += fmt::format("  \"seconds\": {}\n}}\n", jnum(std::round(seconds * 1000.0) / 1000.0));
  return s;
}

// The KRL program of the best placement with its best spin plan: per segment an approach from
// `retract` mm above along z_W, the cut, and the retract; $BASE is the workpiece frame F_W.
void write_program(const PlacementProblem& pb, const Placement& placement, const SpinPlan& plan,
                   const std::vector<JointVector>& q_path, const KrlTemplateSet& templates,
                   const std::string& dir) {
  const PlacementJob& job = pb.job();
  const Cell& cell = pb.cell();
  const Isometry T_B_W = cell.T_B_0 * workpiece_frame(placement);
  const ArmStatusModel arm = make_arm_status_model(cell);
  const KukaAbc abc = abc_from_rotation(T_B_W.linear());

  KrlProgramInfo info;
  info.name = job.program.name;
  info.output_dir = dir;
  info.header_comment = fmt::format(
      "redpost place, cell {}, $BASE = F_W: X {:.3f} Y {:.3f} Z {:.3f} A {:.4f} B "
      "{:.4f} C {:.4f}",
      cell.name, T_B_W.translation().x(), T_B_W.translation().y(), T_B_W.translation().z(),
      abc.a_deg, abc.b_deg, abc.c_deg);
  KrlWriter writer(templates, info);

  auto physical = [&](const JointVector& q) {
    JointVector q0 = q;
    q0[pb.spin_joint()] = 0.0;  // $TOOL is F7: the controller knows nothing of the spin
    return T_B_W.inverse(Eigen::Isometry) * tcp_pose(cell, q0);
  };
  auto emit = [&](KrlMotionKind kind, const JointVector& q) {
    KrlMotion m;
    m.kind = kind;
    m.axes = to_controller_axes(cell, q);
    m.T_base_tcp = physical(q);
    m.status_turn = status_turn(cell, arm, q);
    writer.motion(m);
  };
  // Above the point by the retract distance, same spin and posture; nullopt-like flag if the
  // arm cannot get there.
  auto lifted = [&](int i, const JointVector& q_near, int mu, JointVector& q_out) {
    Isometry T_W_P = pb.path()[static_cast<size_t>(i)].T_W_P;
    T_W_P.translation().z() += job.program.retract_mm;
    JointVector q_other = q_near;
    const ArmIkSolutions sol =
        pb.ik().solve(tcp_target(cell, workpiece_frame(placement), T_W_P), q_other, &q_near);
    if (!sol.valid[static_cast<size_t>(mu - 1)])
      return false;
    q_out = sol.q[static_cast<size_t>(mu - 1)];
    return true;
  };

  MillingConditions mc = job.milling;
  mc.material_side = job.material_side;
  mc.mode = job.segments.front().mode;
  mc.ae_mm = job.segments.front().ae_mm;
  writer.comment(fmt::format("best placement: O_W = ({:.3f}, {:.3f}, {:.3f}) mm in F0, Q4 = {:.6f}",
                             placement.x_mm, placement.y_mm, placement.z_mm, placement.q4));
  writer.comment(fmt::format("f_MQC = {:.4f} mm, max c_i = {:.4f} mm (Caro eq. 5.3, 5.12)",
                             plan.f_mqc_mm, plan.max_c_mm));
  writer.spindle(job.spindle_rpm, spindle_sense(mc) > 0);
  bool first = true;
  for (size_t s = 0; s < pb.segments().size(); ++s) {
    const SegmentRange& seg = pb.segments()[s];
    const int mu = plan.mu[s];
    writer.comment(
        fmt::format("segment {}: posture {} (Status {})", job.segments[s].name, mu, mu - 1));
    JointVector q_up;
    const JointVector& q_first = q_path[static_cast<size_t>(seg.first)];
    const bool has_up = job.program.retract_mm > 0.0 && lifted(seg.first, q_first, mu, q_up);
    emit(first ? KrlMotionKind::ptp_axes : KrlMotionKind::rapid, has_up ? q_up : q_first);
    if (first)
      writer.velocity(job.feed_mm_per_min / 60000.0);
    first = false;
    for (int k = 0; k < seg.count; ++k)
      emit(KrlMotionKind::lin, q_path[static_cast<size_t>(seg.first + k)]);
    const int last = seg.first + seg.count - 1;
    JointVector q_end_up;
    if (job.program.retract_mm > 0.0 &&
        lifted(last, q_path[static_cast<size_t>(last)], mu, q_end_up))
      emit(KrlMotionKind::lin, q_end_up);
  }
  writer.spindle(0.0, true);
  writer.finish();
}

int run_place(const PlaceArgs& args) {
  const std::vector<NamedPath> outputs = {{"--json", args.json}, {"--report", args.report}};
  for (const NamedPath& o : outputs) {
    if (!o.path.empty())
      check_output_target(o.path, o.role);
  }
  check_distinct_files({{"the placement job", args.job}, {"--krl", args.krl_path}}, outputs);
  PlacementJob job = load_placement_job(args.job);
  // The program is written after the optimisation: a name it cannot take is refused now.
  if (const std::string why = krl_program_name_problem(job.program.name); !why.empty()) {
    throw Error(ErrorCode::bad_input, "<program> name '" + job.program.name + "' " + why,
                SourceLocation{args.job, job.program.name_line, 0});
  }
  if (args.seed >= 0)
    job.optimiser.seed = static_cast<unsigned>(args.seed);
  const KrlTemplateSet templates =
      load_krl_templates(args.krl_path.empty() ? default_krl_template() : args.krl_path);
  const PlacementProblem problem(job);

  const auto t0 = std::chrono::steady_clock::now();
  const PlacementStudy st = run_placement_study(problem, job.optimiser);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::vector<JointVector> q_path = problem.joint_path(st.best.placement, st.cases[0]);

  // Everything in memory first: a failure leaves DIR as it was.
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(args.out, ec);
  if (ec)
    throw Error(ErrorCode::io,
                fmt::format("cannot create the directory '{}': {}", args.out, ec.message()));
  const fs::path dir(args.out);
  CostMap map_best, map_worst;
  problem.fill_cost_map(st.best.placement, map_best, false);
  problem.fill_cost_map(st.worst.placement, map_worst, false);
  std::vector<TextOutput> files = {
      {(dir / "placement.csv").string(), placement_csv(problem, st)},
      {(dir / "plans.csv").string(), plans_csv(problem, st, map_best, map_worst)},
      {(dir / "cmap_best.csv").string(), cost_map_csv(problem, map_best, st.cases[0], st.cases[1])},
      {(dir / "cmap_worst.csv").string(),
       cost_map_csv(problem, map_worst, st.cases[2], st.cases[3])},
      {(dir / "convergence.csv").string(), convergence_csv(st)},
  };
  if (!args.json.empty())
    files.push_back({args.json, study_json(st, seconds)});
  if (!args.report.empty()) {
    PlacementReportInput in;
    in.job_path = args.job;
    in.problem = &problem;
    in.study = &st;
    in.map_best = &map_best;
    in.map_worst = &map_worst;
    in.q_path = &q_path;
    in.seconds = seconds;
    files.push_back({args.report, placement_report_html(in)});
  }
  write_program(problem, st.best.placement, st.cases[0], q_path, templates, args.out);
  write_text_files(files);

  const Placement& b = st.best.placement;
  const Placement& w = st.worst.placement;
  fmt::print("best placement:  O_W = ({:.1f}, {:.1f}, {:.1f}) mm in F0, Q4 = {:.4f} ({:.1f} deg)\n",
             b.x_mm, b.y_mm, b.z_mm, b.q4, theta_deg(b));
  fmt::print("worst placement: O_W = ({:.1f}, {:.1f}, {:.1f}) mm in F0, Q4 = {:.4f} ({:.1f} deg)\n",
             w.x_mm, w.y_mm, w.z_mm, w.q4, theta_deg(w));
  fmt::print("{:<28} {:>12} {:>12}\n", "case", "f_MQC [mm]", "max c [mm]");
  for (size_t c = 0; c < 4; ++c)
    fmt::print("{:<28} {:>12.4f} {:>12.4f}\n", PlacementStudy::kCaseNames[c], st.cases[c].f_mqc_mm,
               st.cases[c].max_c_mm);
  fmt::print("case 4 / case 1: {:.2f}\n", st.cases[3].f_mqc_mm / st.cases[0].f_mqc_mm);
  fmt::print("{} + {} placements evaluated in {:.1f} s; output in {}\n", st.best.evaluations,
             st.worst.evaluations, seconds, args.out);
  return kExitOk;
}

}  // namespace

Runner add_place_command(CLI::App& app) {
  auto args = std::make_shared<PlaceArgs>();
  CLI::App* c = app.add_subcommand(
      "place",
      "Workpiece placement and tool-spin planning against the arm's compliance (Caro et al. "
      "2014; docs/placement.md)");
  c->add_option("job", args->job, "Placement job (XML)")->required();
  c->add_option("-o,--output", args->out, "Output directory")->required();
  c->add_option("--json", args->json,
                "Write the placement, the four cases and the convergence "
                "history as JSON to this file");
  c->add_option("--seed", args->seed, "Optimiser seed (overrides the job's)")
      ->check(non_negative_number());
  c->add_option("--krl", args->krl_path, "KRL template set (XML); default krc4_lin");
  c->add_option("--report", args->report,
                "Write an HTML report: the c_i maps with the spin plans, the optimiser's "
                "convergence, the four cases, a top view of the work volume");
  return [args] { return run_place(*args); };
}

}  // namespace redpost::cli
