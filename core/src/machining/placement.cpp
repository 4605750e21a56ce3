#include "redpost/machining/placement.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <nlopt.h>

#include "redpost/io/error.hpp"
#include "redpost/kinematics/conditioning.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/jacobian.hpp"
#include "redpost/machining/cutting_force.hpp"
#include "redpost/machining/elastostatic.hpp"

namespace redpost {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

Isometry workpiece_frame(const Placement& p) {
  const double q4 = std::clamp(p.q4, -1.0, 1.0);
  const double q1 = std::sqrt(std::max(0.0, 1.0 - q4 * q4));
  Isometry T = Isometry::Identity();
  // Eq. 2.8 with the (2,1) entry 2 Q1 Q4: cos theta = 2 Q1^2 - 1, sin theta = 2 Q1 Q4.
  T.linear() << 2.0 * q1 * q1 - 1.0, -2.0 * q1 * q4, 0.0,  //
      2.0 * q1 * q4, 2.0 * q1 * q1 - 1.0, 0.0,             //
      0.0, 0.0, 1.0;
  T.translation() = Eigen::Vector3d(p.x_mm, p.y_mm, p.z_mm);
  return T;
}

std::vector<PathPoint> tool_path(const PlacementJob& job) {
  std::vector<PathPoint> path;
  path.reserve(static_cast<size_t>(job.point_count()));
  const double radius_mm = 0.5 * job.milling.tool_diameter_mm;
  const Eigen::Vector3d z_P = Eigen::Vector3d::UnitZ();  // the tool axis: z_W, towards the robot
  for (size_t s = 0; s < job.segments.size(); ++s) {
    const ContourSegment& seg = job.segments[s];
    const Eigen::Vector3d along = seg.to_W_mm - seg.from_W_mm;
    const double length_mm = along.norm();
    const Eigen::Vector3d x_P = along / length_mm;
    const Eigen::Vector3d y_P = z_P.cross(x_P);
    // The tool centre runs on the side away from the material.
    const Eigen::Vector3d offset = -static_cast<double>(job.material_side) * radius_mm * y_P;
    MillingConditions c = job.milling;
    c.ae_mm = seg.ae_mm;
    c.mode = seg.mode;
    c.material_side = job.material_side;
    const Eigen::Vector3d force_P_N = mean_cutting_force_N(c);
    for (int k = 0; k < seg.points; ++k) {
      PathPoint p;
      p.segment = static_cast<int>(s);
      p.T_W_P.linear().col(0) = x_P;
      p.T_W_P.linear().col(1) = y_P;
      p.T_W_P.linear().col(2) = z_P;
      p.T_W_P.translation() = seg.from_W_mm + (k + 0.5) / seg.points * along + offset;
      p.force_on_workpiece_P_N = force_P_N;
      path.push_back(p);
    }
  }
  return path;
}

// The TCP at a path point: F_Pi itself. Its z axis (the tool axis towards the robot) is the
// cell's TCP z (tip towards spindle); Caro's F7 = F_Pi Rx(pi) is the TCP turned back by the
// cell's tool frame.
Isometry tcp_target(const Cell& cell, const Isometry& T_0_W, const Isometry& T_W_P) {
  return cell.T_B_0 * T_0_W * T_W_P;
}

void CostMap::resize(int n_points, int n_betas) {
  points = n_points;
  betas = n_betas;
  const size_t cells = static_cast<size_t>(n_points) * static_cast<size_t>(n_betas) * 8;
  c_mm.assign(cells, kNaN);
  q_arm.resize(cells * 6);
  computed.assign(static_cast<size_t>(n_points), 0);
}

// ---------------------------------------------------------------------------------------------
// Dynamic programming over the beta grid.

namespace {

bool joints_continuous(const double* a, const double* b, const ContinuityLimits& lim) {
  for (int k = 0; k < 6; ++k) {
    double d = std::fabs(b[k] - a[k]);
    // Only a step beyond pi can be a wrap; the remainder is costly, so it is taken only then.
    if (d > kPi && lim.wraps[static_cast<size_t>(k)])
      d = std::fabs(std::remainder(d, 2.0 * kPi));
    if (!(d <= lim.max_joint_step_rad))
      return false;
  }
  return true;
}

}  // namespace

SpinPlan plan_spin(const CostMap& map, const std::vector<SegmentRange>& segments,
                   const ContinuityLimits& limits, PlanGoal goal, DpWorkspace& ws) {
  const int B = map.betas;
  // Objective of a partial plan: +sum c (best) or -sum c (worst); smaller is better.
  const double sign = goal == PlanGoal::best ? 1.0 : -1.0;
  const double inf = std::numeric_limits<double>::infinity();
  SpinPlan plan;
  plan.feasible = true;
  plan.beta_index.assign(static_cast<size_t>(map.points), -1);
  plan.mu.assign(segments.size(), 0);
  // Neighbours of b within the bound, each once, in increasing offset (deterministic ties).
  const bool all_neighbours = 2 * limits.max_beta_steps + 1 >= B;
  double total_c = 0.0;
  int total_points = 0;
  double max_c = 0.0;

  for (size_t s = 0; s < segments.size(); ++s) {
    const SegmentRange& seg = segments[s];
    total_points += seg.count;
    const size_t stride = static_cast<size_t>(B);
    ws.value.resize(static_cast<size_t>(seg.count) * stride * 8);
    ws.parent.resize(static_cast<size_t>(seg.count) * stride * 8);
    double best_total = inf;
    int best_mu = 0, best_last = -1;
    for (int mu = 1; mu <= kPostures; ++mu) {
      double* value = &ws.value[static_cast<size_t>(mu - 1) * seg.count * stride];
      int* parent = &ws.parent[static_cast<size_t>(mu - 1) * seg.count * stride];
      for (int b = 0; b < B; ++b) {
        const double c = map.c(seg.first, b, mu);
        value[b] = c == c ? sign * c : inf;
        parent[b] = -1;
      }
      for (int k = 1; k < seg.count; ++k) {
        const int i = seg.first + k;
        const double* prev = value + static_cast<size_t>(k - 1) * stride;
        double* cur = value + static_cast<size_t>(k) * stride;
        int* par = parent + static_cast<size_t>(k) * stride;
        for (int b = 0; b < B; ++b) {
          cur[b] = inf;
          par[b] = -1;
          const double c = map.c(i, b, mu);
          if (c != c)
            continue;
          const double* q_here = map.q(i, b, mu);
          double best = inf;
          int arg = -1;
          auto consider = [&](int bp) {
            if (!(prev[bp] < inf))
              return;
            if (!(prev[bp] < best || (prev[bp] == best && bp < arg)))
              return;
            if (!joints_continuous(map.q(i - 1, bp, mu), q_here, limits))
              return;
            best = prev[bp];
            arg = bp;
          };
          if (all_neighbours) {
            for (int bp = 0; bp < B; ++bp)
              consider(bp);
          } else {
            for (int d = -limits.max_beta_steps; d <= limits.max_beta_steps; ++d)
              consider(((b + d) % B + B) % B);
          }
          if (arg >= 0) {
            cur[b] = best + sign * c;
            par[b] = arg;
          }
        }
      }
      const double* last = value + static_cast<size_t>(seg.count - 1) * stride;
      for (int b = 0; b < B; ++b) {
        if (last[b] < best_total) {
          best_total = last[b];
          best_mu = mu;
          best_last = b;
        }
      }
    }
    if (best_last < 0) {
      plan.feasible = false;
      if (plan.infeasible_segment < 0)
        plan.infeasible_segment = static_cast<int>(s);
      continue;
    }
    plan.mu[s] = best_mu;
    const int* parent = &ws.parent[static_cast<size_t>(best_mu - 1) * seg.count * stride];
    int b = best_last;
    for (int k = seg.count - 1; k >= 0; --k) {
      const int i = seg.first + k;
      plan.beta_index[static_cast<size_t>(i)] = b;
      const double c = map.c(i, b, best_mu);
      total_c += c;
      max_c = std::max(max_c, c);
      b = parent[static_cast<size_t>(k) * stride + static_cast<size_t>(b)];
    }
  }
  if (plan.feasible) {
    plan.f_mqc_mm = total_c / std::max(1, total_points);
    plan.max_c_mm = max_c;
  } else {
    plan.f_mqc_mm = plan.max_c_mm = kNaN;
  }
  return plan;
}

// ---------------------------------------------------------------------------------------------
// The inner problem.

PlacementProblem::PlacementProblem(const PlacementJob& job) : job_(job) {
  const Cell& cell = job_.cell;
  ik_ = std::make_unique<ArmIk>(cell);
  compliant_ = compliant_joints(cell);
  if (compliant_ != ik_->arm_joints()) {
    throw Error(ErrorCode::bad_input,
                "placement: the joints with a <stiffness> must be the arm's A1..A6, in order");
  }
  for (size_t k = 0; k < 6; ++k)
    compliance_[k] = 1.0 / *cell.joint(compliant_[k]).stiffness;
  for (int i = 0; i < cell.size(); ++i) {
    if (cell.joint(i).type == JointType::virtual_spin)
      spin_joint_ = i;
  }
  if (spin_joint_ < 0)
    throw Error(ErrorCode::bad_input, "placement: the cell has no virtual spin joint (beta)");

  path_ = tool_path(job_);
  int first = 0;
  for (const ContourSegment& s : job_.segments) {
    segments_.push_back(SegmentRange{first, s.points});
    first += s.points;
  }
  grid_.count = static_cast<int>(std::lround(2.0 * kPi / job_.spin.step_rad));
  grid_.step_rad = 2.0 * kPi / grid_.count;
  continuity_.max_beta_steps =
      static_cast<int>(std::floor(job_.spin.max_step_rad / grid_.step_rad + 1e-9));
  continuity_.max_joint_step_rad = job_.spin.max_joint_step_rad;
  for (size_t k = 0; k < 6; ++k) {
    const Joint& j = cell.joint(ik_->arm_joints()[k]);
    continuity_.wraps[k] = j.upper - j.lower >= 2.0 * kPi - 1e-12;
  }
}

PlacementProblem::~PlacementProblem() = default;

void PlacementProblem::point_load(const Isometry& T_B_W, int i, Vector6d& w_B,
                                  Eigen::Vector3d& y_B) const {
  const PathPoint& p = path_[static_cast<size_t>(i)];
  const Eigen::Matrix3d R_B_P = T_B_W.linear() * p.T_W_P.linear();
  // The spindle receives the opposite of the force on the workpiece; it acts at the middle of
  // the engaged flutes, ap/2 above the tool tip along z_P, hence a moment about the TCP.
  const Eigen::Vector3d f_B = -(R_B_P * p.force_on_workpiece_P_N);
  const Eigen::Vector3d r_B = R_B_P.col(2) * (0.5 * job_.milling.ap_mm);
  w_B.head<3>() = r_B.cross(f_B);
  w_B.tail<3>() = f_B;
  y_B = R_B_P.col(1);
}

namespace {

// c_i at q with caller-owned buffers.
double deflection_at(const Cell& cell, const std::array<int, 6>& compliant,
                     const std::array<double, 6>& compliance, const PlacementConstraints& cons,
                     const JointVector& q, const Vector6d& w_B, const Eigen::Vector3d& y_B,
                     KinematicsData& data, Jacobian& J, double* inv_kappa) {
  forward_kinematics(cell, q, data, cons.complementary);
  tcp_jacobian(cell, data, J);
  const double ik = arm_inverse_condition(cell, J);
  if (inv_kappa)
    *inv_kappa = ik;
  if (!(ik > cons.inv_kappa_min))  // eq. 5.16
    return kNaN;
  Eigen::Vector3d dd;
  if (cons.complementary) {
    dd = tcp_displacement(cell, data, w_B, ElastostaticOptions{true}).tail<3>();
  } else {
    // Eq. 5.2 with K_C off: dX = J K_theta^-1 J^T w, K_theta diagonal, so only six dot products
    // (the same as tcp_displacement without K_C; test_placement checks it).
    dd.setZero();
    for (size_t k = 0; k < 6; ++k) {
      const auto col = J.col(compliant[k]);
      const double torque = col.dot(w_B);
      dd += (torque * compliance[k]) * col.tail<3>();
    }
  }
  // Eq. 5.1: z_7 x x_Pi = -z_Pi x x_Pi = -y_Pi; only |.| counts.
  return std::fabs(dd.dot(y_B));
}

}  // namespace

double PlacementProblem::deflection_mm(const JointVector& q, const Vector6d& w_B,
                                       const Eigen::Vector3d& y_B, double* inv_kappa) const {
  KinematicsData data;
  Jacobian J;
  return deflection_at(job_.cell, compliant_, compliance_, job_.constraints, q, w_B, y_B, data, J,
                       inv_kappa);
}

void PlacementProblem::fill_points(const Placement& p, CostMap& map, bool early_stop, int first,
                                   int stride, int& reached, int& first_failure) const {
  const Cell& cell = job_.cell;
  const Isometry T_B_W = cell.T_B_0 * workpiece_frame(p);
  const std::array<int, 6>& arm = ik_->arm_joints();
  KinematicsData data;
  Jacobian J;
  JointVector q_other = cell.home();
  Vector6d w_B;
  Eigen::Vector3d y_B;
  reached = 0;
  first_failure = -1;
  for (int i = first; i < map.points; i += stride) {
    const Isometry T_B_tcp = T_B_W * path_[static_cast<size_t>(i)].T_W_P;
    point_load(T_B_W, i, w_B, y_B);
    bool any = false;
    for (int b = 0; b < map.betas; ++b) {
      q_other[spin_joint_] = grid_.beta_rad(b);
      const ArmIkSolutions sol = ik_->solve(T_B_tcp, q_other);
      for (int mu = 1; mu <= kPostures; ++mu) {
        const size_t at = map.index(i, b, mu);
        const size_t m = static_cast<size_t>(mu - 1);
        double c = kNaN;
        if (sol.valid[m]) {
          c = deflection_at(cell, compliant_, compliance_, job_.constraints, sol.q[m], w_B, y_B,
                            data, J, nullptr);
          if (!(c <= job_.constraints.c_max_mm))  // eq. 5.12, per point
            c = kNaN;
          double* q = &map.q_arm[at * 6];
          for (size_t k = 0; k < 6; ++k)
            q[k] = sol.q[m][arm[k]];
        }
        map.c_mm[at] = c;
        any = any || c == c;
      }
    }
    map.computed[static_cast<size_t>(i)] = 1;
    if (any) {
      ++reached;
    } else if (first_failure < 0) {
      first_failure = i;
      if (early_stop)
        return;
    }
  }
}

int PlacementProblem::fill_cost_map(const Placement& p, CostMap& map, bool early_stop) const {
  const int n = static_cast<int>(path_.size());
  if (map.points != n || map.betas != grid_.count)
    map.resize(n, grid_.count);
  std::fill(map.computed.begin(), map.computed.end(), 0);
  int reached0 = 0, reached1 = 0, fail0 = -1, fail1 = -1;
  if (job_.optimiser.threads >= 2 && n >= 2) {
    // Points dealt by parity: each worker's work, and so the result, does not depend on timing.
    std::exception_ptr error;
    std::thread worker([&] {
      try {
        fill_points(p, map, early_stop, 1, 2, reached1, fail1);
      } catch (...) {
        error = std::current_exception();
      }
    });
    try {
      fill_points(p, map, early_stop, 0, 2, reached0, fail0);
    } catch (...) {
      worker.join();
      throw;
    }
    worker.join();
    if (error)
      std::rethrow_exception(error);
  } else {
    fill_points(p, map, early_stop, 0, 1, reached0, fail0);
  }
  return reached0 + reached1;
}

InnerResult PlacementProblem::solve(const Placement& p, InnerWorkspace& ws, bool with_worst) const {
  InnerResult r;
  const int n = static_cast<int>(path_.size());
  const int reached = fill_cost_map(p, ws.map, true);
  r.reached_fraction = static_cast<double>(reached) / n;
  if (reached < n)
    return r;
  r.best = plan_spin(ws.map, segments_, continuity_, PlanGoal::best, ws.dp);
  if (!r.best.feasible) {
    // Every point reachable but some segment has no continuous plan: nearly feasible.
    r.reached_fraction = 1.0 - 0.5 / n;
    return r;
  }
  r.feasible = true;
  if (with_worst)
    r.worst = plan_spin(ws.map, segments_, continuity_, PlanGoal::worst, ws.dp);
  return r;
}

std::vector<JointVector> PlacementProblem::joint_path(const Placement& p,
                                                      const SpinPlan& plan) const {
  if (!plan.feasible)
    throw Error(ErrorCode::bad_input, "placement: the spin plan is not feasible");
  const Cell& cell = job_.cell;
  const Isometry T_B_W = cell.T_B_0 * workpiece_frame(p);
  std::vector<JointVector> out;
  out.reserve(path_.size());
  JointVector q_other = cell.home();
  for (size_t s = 0; s < segments_.size(); ++s) {
    const SegmentRange& seg = segments_[s];
    const size_t m = static_cast<size_t>(plan.mu[s] - 1);
    for (int k = 0; k < seg.count; ++k) {
      const int i = seg.first + k;
      q_other[spin_joint_] = grid_.beta_rad(plan.beta_index[static_cast<size_t>(i)]);
      const Isometry T_B_tcp = T_B_W * path_[static_cast<size_t>(i)].T_W_P;
      // The 2 pi representatives nearest the previous point's: the unwrapped joint path.
      const ArmIkSolutions sol = ik_->solve(T_B_tcp, q_other, k > 0 ? &out.back() : nullptr);
      if (!sol.valid[m]) {
        throw Error(ErrorCode::internal,
                    fmt::format("placement: posture {} not valid at path point {}", m + 1, i + 1));
      }
      if (k > 0) {
        for (size_t a = 0; a < 6; ++a) {
          const int j = ik_->arm_joints()[a];
          const double step = std::fabs(sol.q[m][j] - out.back()[j]);
          if (step > continuity_.max_joint_step_rad + 1e-9) {
            throw Error(
                ErrorCode::bad_input,
                fmt::format("placement: joint {} would jump by {:.1f} deg at path point "
                            "{} (segment {}): it cannot unwind within its limits",
                            cell.joint(j).name, rad_to_deg(step), i + 1, job_.segments[s].name));
          }
        }
      }
      out.push_back(sol.q[m]);
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// The outer problem.

namespace {

constexpr double kPenalty = 1e3;  // mm: far above any f_MQC

struct SearchContext {
  const PlacementProblem* problem = nullptr;
  PlanGoal goal = PlanGoal::best;
  InnerWorkspace ws;
  int batch = 50;
  int evaluations = 0;
  int feasible = 0;
  double best_value = std::numeric_limits<double>::infinity();  // objective, smaller better
  double best_f = kNaN;
  std::array<double, 4> best_x{};
  std::vector<ConvergencePoint> history;
  std::exception_ptr error;
  nlopt_opt opt = nullptr;  // the run in progress, for nlopt_force_stop
};

Placement from_unit(const WorkVolume& v, const double* x) {
  Placement p;
  p.x_mm = v.x_min_mm + x[0] * (v.x_max_mm - v.x_min_mm);
  p.y_mm = v.y_min_mm + x[1] * (v.y_max_mm - v.y_min_mm);
  p.z_mm = v.z_min_mm + x[2] * (v.z_max_mm - v.z_min_mm);
  p.q4 = v.q4_min + x[3] * (v.q4_max - v.q4_min);
  return p;
}

double objective(unsigned n, const double* x, double* grad, void* data) {
  (void)n;
  (void)grad;  // derivative-free algorithms only
  auto* ctx = static_cast<SearchContext*>(data);
  try {
    std::array<double, 4> u;
    for (size_t k = 0; k < 4; ++k)
      u[k] = std::clamp(x[k], 0.0, 1.0);
    const Placement p = from_unit(ctx->problem->job().volume, u.data());
    const InnerResult r = ctx->problem->solve(p, ctx->ws, false);
    ++ctx->evaluations;
    double value;
    if (r.feasible) {
      ++ctx->feasible;
      const double f = r.best.f_mqc_mm;
      value = ctx->goal == PlanGoal::best ? f : -f;
      if (value < ctx->best_value) {
        ctx->best_value = value;
        ctx->best_f = f;
        ctx->best_x = u;
      }
    } else {
      // Graded: placements that reach more of the path are less bad.
      value = kPenalty * (2.0 - r.reached_fraction);
    }
    if (ctx->evaluations % ctx->batch == 0)
      ctx->history.push_back(ConvergencePoint{ctx->evaluations, ctx->best_f});
    return value;
  } catch (...) {
    ctx->error = std::current_exception();
    nlopt_force_stop(ctx->opt);
    return kPenalty * 3.0;
  }
}

void run_nlopt(SearchContext& ctx, const std::string& algorithm, int evaluations, int population,
               unsigned seed, std::array<double, 4>& x, double initial_step) {
  const nlopt_algorithm alg = nlopt_algorithm_from_string(algorithm.c_str());
  if (static_cast<int>(alg) < 0)
    throw Error(ErrorCode::bad_input, "unknown NLopt algorithm '" + algorithm + "'");
  nlopt_opt opt = nlopt_create(alg, 4);
  if (!opt)
    throw Error(ErrorCode::internal, "nlopt_create failed for " + algorithm);
  const double lb[4] = {0.0, 0.0, 0.0, 0.0};
  const double ub[4] = {1.0, 1.0, 1.0, 1.0};
  nlopt_set_lower_bounds(opt, lb);
  nlopt_set_upper_bounds(opt, ub);
  nlopt_set_min_objective(opt, objective, &ctx);
  nlopt_set_maxeval(opt, evaluations);
  if (population > 0)
    nlopt_set_population(opt, static_cast<unsigned>(population));
  if (initial_step > 0.0) {
    nlopt_set_initial_step1(opt, initial_step);
    nlopt_set_xtol_abs1(opt, 1e-5);
  }
  nlopt_srand(seed);
  double f = 0.0;
  // An exception in the objective stops the run (it cannot cross NLopt's C code): the callback
  // keeps it in ctx.error, rethrown here.
  ctx.opt = opt;
  nlopt_optimize(opt, x.data(), &f);
  ctx.opt = nullptr;
  nlopt_destroy(opt);
  if (ctx.error)
    std::rethrow_exception(ctx.error);
}

}  // namespace

PlacementSearch search_placement(const PlacementProblem& problem, PlanGoal goal,
                                 const OptimiserSettings& settings) {
  SearchContext ctx;
  ctx.problem = &problem;
  ctx.goal = goal;
  ctx.batch = std::max(1, settings.history_batch);

  std::array<double, 4> x = {0.5, 0.5, 0.5, 0.5};
  run_nlopt(ctx, settings.global_algorithm, settings.global_evaluations, settings.global_population,
            settings.seed, x, 0.0);
  if (ctx.feasible == 0) {
    const WorkVolume& v = problem.job().volume;
    throw Error(
        ErrorCode::unreachable,
        fmt::format("placement: no feasible placement found in {} evaluations of the work "
                    "volume x [{}, {}] y [{}, {}] z [{}, {}] mm, q4 [{}, {}]: the path "
                    "cannot be followed within the joint limits, 1/kappa_F > {} and "
                    "c_max = {} mm. Widen the work volume or relax the constraints",
                    ctx.evaluations, v.x_min_mm, v.x_max_mm, v.y_min_mm, v.y_max_mm, v.z_min_mm,
                    v.z_max_mm, v.q4_min, v.q4_max, problem.job().constraints.inv_kappa_min,
                    problem.job().constraints.c_max_mm));
  }
  if (!settings.local_algorithm.empty() && settings.local_evaluations > 0) {
    x = ctx.best_x;
    run_nlopt(ctx, settings.local_algorithm, settings.local_evaluations, 0, settings.seed, x, 0.02);
  }
  if (ctx.history.empty() || ctx.history.back().evaluations != ctx.evaluations)
    ctx.history.push_back(ConvergencePoint{ctx.evaluations, ctx.best_f});

  PlacementSearch out;
  out.placement = from_unit(problem.job().volume, ctx.best_x.data());
  out.inner = problem.solve(out.placement, ctx.ws, true);
  if (!out.inner.feasible)
    throw Error(ErrorCode::internal, "placement: the best placement is no longer feasible");
  out.history = std::move(ctx.history);
  out.evaluations = ctx.evaluations;
  out.feasible_evaluations = ctx.feasible;
  return out;
}

PlacementStudy run_placement_study(const PlacementProblem& problem,
                                   const OptimiserSettings& settings) {
  PlacementStudy study;
  study.best = search_placement(problem, PlanGoal::best, settings);
  study.worst = search_placement(problem, PlanGoal::worst, settings);
  study.cases = {study.best.inner.best, study.best.inner.worst, study.worst.inner.best,
                 study.worst.inner.worst};
  return study;
}

Placement random_placement(const WorkVolume& v, unsigned long long& state) {
  // splitmix64: small, fast and the same on every platform.
  auto next = [&state] {
    unsigned long long z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * (1.0 / 9007199254740992.0);
  };
  double u[4];
  for (double& x : u)
    x = next();
  return from_unit(v, u);
}

}  // namespace redpost
