// In-situ calibration from laser readings on three planes (Andres et al. 2011, Section 3).
// docs/calibration.md.
#include "redpost/calibration/calibration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <sstream>

#include <Eigen/SVD>
#include <unsupported/Eigen/AutoDiff>

#include "redpost/io/error.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/kuka_abc.hpp"
#include "redpost/redundancy/tracker.hpp"

namespace redpost {

namespace {

const char* field_name(DhField f) {
  switch (f) {
    case DhField::alpha:
      return "alpha";
    case DhField::a:
      return "a";
    case DhField::theta:
      return "theta";
    case DhField::d:
      return "d";
  }
  return "?";
}

double& field_ref(Joint& j, DhField f) {
  switch (f) {
    case DhField::alpha:
      return j.alpha_rad;
    case DhField::a:
      return j.a_mm;
    case DhField::theta:
      return j.theta_rad;
    case DhField::d:
      break;
  }
  return j.d_mm;
}

double field_value(const Joint& j, DhField f) {
  return field_ref(const_cast<Joint&>(j), f);
}

[[noreturn]] void fail(const std::string& message) {
  throw Error(ErrorCode::bad_input, message);
}

// The derivative vector has a fixed capacity: no heap allocation per operation, which makes W
// several times faster to build than with a dynamic vector.
constexpr int kMaxCalibrationParameters = 24;
using ADDerivatives = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxCalibrationParameters, 1>;
using AD = Eigen::AutoDiffScalar<ADDerivatives>;

// The DH parameters of every link as scalars of type S: the cell's values, with the calibrated
// ones replaced by `values` (seeded as AD variables when S is AD).
template <class S>
struct LinkParams {
  std::array<std::array<S, 4>, kMaxJoints> p;  // alpha, a, theta, d
};

template <class S>
Eigen::Matrix<S, 3, 3> to_s(const Eigen::Matrix3d& M) {
  return M.template cast<S>();
}

// TCP pose in {B} for joints q and link parameters P, as forward_kinematics() composes it:
// T_B_0, then per link [T_prev_link] * link(i), then T_last_tcp.
template <class S>
void tcp_frame(const Cell& cell, const JointVector& q, const LinkParams<S>& P,
               Eigen::Matrix<S, 3, 3>& R, Eigen::Matrix<S, 3, 1>& t) {
  R = to_s<S>(cell.T_B_0.linear());
  t = cell.T_B_0.translation().template cast<S>();
  auto compose = [&](const Eigen::Matrix<S, 3, 3>& Rl, const Eigen::Matrix<S, 3, 1>& tl) {
    t = (t + R * tl).eval();
    R = (R * Rl).eval();
  };
  auto rot_x = [](const S& ang) {
    Eigen::Matrix<S, 3, 3> M;
    using std::cos;
    using std::sin;
    const S c = cos(ang), s = sin(ang);
    M << S(1), S(0), S(0), S(0), c, -s, S(0), s, c;
    return M;
  };
  auto rot_z = [](const S& ang) {
    Eigen::Matrix<S, 3, 3> M;
    using std::cos;
    using std::sin;
    const S c = cos(ang), s = sin(ang);
    M << c, -s, S(0), s, c, S(0), S(0), S(0), S(1);
    return M;
  };
  const Eigen::Matrix<S, 3, 1> zero(S(0), S(0), S(0));
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    if (j.has_fixed_before)
      compose(to_s<S>(j.T_prev_link.linear()), j.T_prev_link.translation().template cast<S>());
    const auto& lp = P.p[static_cast<size_t>(i)];
    S theta = lp[2], d = lp[3];
    if (j.type == JointType::prismatic)
      d = d + S(q[i]);
    else
      theta = theta + S(q[i]);
    const Eigen::Matrix<S, 3, 1> tz(S(0), S(0), d), tx(lp[1], S(0), S(0));
    if (j.convention == DhConvention::standard) {
      compose(rot_z(theta), tz);
      compose(rot_x(lp[0]), tx);
    } else {
      compose(rot_x(lp[0]), tx);
      compose(rot_z(theta), tz);
    }
  }
  compose(to_s<S>(cell.T_last_tcp.linear()), cell.T_last_tcp.translation().template cast<S>());
}

template <class S>
S reading_of(const Eigen::Matrix<S, 3, 3>& R, const Eigen::Matrix<S, 3, 1>& t, PlaneAxis plane,
             const MeasurementModel& model) {
  const int k = static_cast<int>(plane);
  const S u_k = -R(k, 2);  // the beam is -z
  const S gap = S(model.plane_offset_mm[static_cast<size_t>(k)]) - t(k);
  if (model.approximate)
    return u_k < S(0) ? S(-gap) : gap;
  return gap / u_k;
}

double value_of(const AD& x) {
  return x.value();
}

void check_incidence(double u_k, PlaneAxis plane, const MeasurementModel& model) {
  if (!(std::abs(u_k) >= model.min_incidence_cos)) {
    std::ostringstream m;
    m << "the laser beam is nearly parallel to the plane " << to_string(plane) << " = "
      << model.plane_offset_mm[static_cast<size_t>(plane)] << " (cosine to its normal "
      << std::abs(u_k) << " < " << model.min_incidence_cos << "): no reading";
    fail(m.str());
  }
}

}  // namespace

// ---- Parameters -----------------------------------------------------------------------------

std::string CalibrationParameter::name() const {
  return "link" + std::to_string(link) + "." + field_name(field);
}

CalibrationParameter parse_calibration_parameter(const std::string& name, const Cell& cell) {
  const std::string bad = "bad calibration parameter '" + name +
                          "': expected link<i>.<alpha|a|theta|d> with i in 1.." +
                          std::to_string(cell.size());
  if (name.rfind("link", 0) != 0)
    fail(bad);
  const size_t dot = name.find('.');
  if (dot == std::string::npos || dot == 4)
    fail(bad);
  const std::string index = name.substr(4, dot - 4), field = name.substr(dot + 1);
  if (!std::all_of(index.begin(), index.end(), [](char c) { return c >= '0' && c <= '9'; }) ||
      index.size() > 3)
    fail(bad);
  CalibrationParameter p;
  p.link = std::stoi(index);
  if (p.link < 1 || p.link > cell.size())
    fail(bad);
  if (field == "alpha")
    p.field = DhField::alpha;
  else if (field == "a")
    p.field = DhField::a;
  else if (field == "theta")
    p.field = DhField::theta;
  else if (field == "d")
    p.field = DhField::d;
  else
    fail(bad);
  return p;
}

std::vector<CalibrationParameter> parse_calibration_parameters(const std::string& list,
                                                               const Cell& cell) {
  std::vector<CalibrationParameter> out;
  std::set<std::string> seen;
  std::string item;
  std::istringstream in(list);
  while (std::getline(in, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item.empty())
      continue;
    CalibrationParameter p = parse_calibration_parameter(item, cell);
    if (!seen.insert(p.name()).second)
      fail("calibration parameter '" + item + "' given twice");
    out.push_back(p);
  }
  if (out.empty())
    return default_calibration_parameters();
  return out;
}

std::vector<CalibrationParameter> default_calibration_parameters() {
  return {{1, DhField::alpha}, {1, DhField::a},     {1, DhField::theta},
          {1, DhField::d},     {2, DhField::theta}, {2, DhField::d}};
}

Eigen::VectorXd parameter_values(const Cell& cell,
                                 const std::vector<CalibrationParameter>& params) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(params.size()));
  for (size_t i = 0; i < params.size(); ++i) {
    if (params[i].link < 1 || params[i].link > cell.size())
      fail("calibration parameter " + params[i].name() + ": no such link in the cell");
    v[static_cast<Eigen::Index>(i)] = field_value(cell.joint(params[i].link - 1), params[i].field);
  }
  return v;
}

Cell apply_parameters(const Cell& cell, const std::vector<CalibrationParameter>& params,
                      const Eigen::VectorXd& values) {
  if (values.size() != static_cast<Eigen::Index>(params.size()))
    throw Error(ErrorCode::internal, "apply_parameters: one value per parameter expected");
  Cell out = cell;
  for (size_t i = 0; i < params.size(); ++i) {
    if (params[i].link < 1 || params[i].link > cell.size())
      fail("calibration parameter " + params[i].name() + ": no such link in the cell");
    field_ref(out.joints[static_cast<size_t>(params[i].link - 1)], params[i].field) =
        values[static_cast<Eigen::Index>(i)];
  }
  finalize_cell(out);
  return out;
}

// ---- Measurement model ----------------------------------------------------------------------

const char* to_string(PlaneAxis plane) {
  switch (plane) {
    case PlaneAxis::x:
      return "x";
    case PlaneAxis::y:
      return "y";
    case PlaneAxis::z:
      return "z";
  }
  return "?";
}

double laser_reading(const Isometry& T_B_tcp, PlaneAxis plane, const MeasurementModel& model) {
  const Eigen::Matrix3d R = T_B_tcp.linear();
  const Eigen::Vector3d t = T_B_tcp.translation();
  check_incidence(-R(static_cast<int>(plane), 2), plane, model);
  return reading_of<double>(R, t, plane, model);
}

// ---- Plan -----------------------------------------------------------------------------------

Isometry commanded_frame(PlaneAxis plane, const Eigen::Vector3d& p_on_plane, double stand_off_mm) {
  KukaAbc abc;  // eqs. 2-4
  if (plane == PlaneAxis::x)
    abc = {0.0, -90.0, 0.0};
  else if (plane == PlaneAxis::y)
    abc = {0.0, 0.0, -90.0};
  Isometry T = frame_from_xyzabc(p_on_plane.x(), p_on_plane.y(), p_on_plane.z(), abc);
  // The beam is -z: the TCP stands off the plane by stand_off against the beam, along +z.
  T.translation() += stand_off_mm * T.linear().col(2);
  return T;
}

JointVector joints_for_commanded_frame(const Cell& nominal, const std::vector<int>& external_joints,
                                       const std::vector<double>& external_values,
                                       const Isometry& T_B_commanded, int perturbed_starts,
                                       std::uint64_t seed) {
  if (external_values.size() != external_joints.size())
    fail("calibration: " + std::to_string(external_values.size()) + " values for " +
         std::to_string(external_joints.size()) + " external joints");
  // Tracker::solve_first_pose starts from the cell's home (with the locked joints at their home
  // values too), so the solver's cell gets the external values as those joints' home. The
  // geometry is the nominal one, untouched.
  Cell solver_cell = nominal;
  TrackerOptions topt;
  for (size_t e = 0; e < external_joints.size(); ++e) {
    const int idx = external_joints[e];
    if (idx < 0 || idx >= nominal.size())
      fail("calibration: external joint index " + std::to_string(idx) + " out of range");
    topt.locked.set(static_cast<size_t>(idx));
    solver_cell.joints[static_cast<size_t>(idx)].home = external_values[e];
  }
  const JointVector start = solver_cell.home();
  if (!within_limits(nominal, start))
    fail("calibration: external joint values beyond the joints' limits");
  topt.q_ref = start;
  Tracker tracker(solver_cell, topt);
  tracker.reset(start);
  const PoseResult r =
      tracker.solve_first_pose(TcpTarget::frame(T_B_commanded), perturbed_starts, seed);
  if (r.status != PoseStatus::converged) {
    const Eigen::Vector3d p = T_B_commanded.translation();
    std::ostringstream m;
    m << "the commanded frame at " << p.x() << ", " << p.y() << ", " << p.z()
      << " mm cannot be reached: " << to_string(r.status);
    throw Error(ErrorCode::unreachable, m.str());
  }
  // The first solution may sit on a joint limit (a joint is locked there when the solver meets
  // it). The spin about the beam is free (the reading does not depend on it), so let the
  // null-space goals (centring, limit avoidance) move the posture off the limits while the TCP
  // stays on the commanded frame: track the same target until the posture settles.
  // Only postures near a limit need it (the others are left as solved, which is also fast).
  auto near_limit = [&nominal, &topt](const JointVector& q) {
    for (int j = 0; j < nominal.size(); ++j) {
      const Joint& jt = nominal.joint(j);
      if (topt.locked.test(static_cast<size_t>(j)) || jt.type == JointType::virtual_spin)
        continue;
      const double margin = jt.type == JointType::prismatic ? 5.0 : deg_to_rad(5.0);
      if (q[j] - jt.lower < margin || jt.upper - q[j] < margin)
        return true;
    }
    return false;
  };
  tracker.reset(r.q);
  JointVector q = r.q;
  for (int k = 0; k < 400 && near_limit(q); ++k) {
    const PoseResult s = tracker.track(TcpTarget::frame(T_B_commanded));
    if (s.status != PoseStatus::converged)
      break;
    const double moved = (s.q - q).cwiseAbs().maxCoeff();
    q = s.q;
    if (moved < 1e-9)
      break;
  }
  return q;
}

std::vector<CalibrationPoint> plan_calibration(const Cell& nominal,
                                               const CalibrationPlanOptions& options) {
  if (options.grid < 1)
    fail("calibration plan: the grid needs at least 1 x 1 points");
  std::vector<CalibrationPoint> points;
  const int n = options.grid;
  auto lerp = [n](double lo, double hi, int i) {
    return n == 1 ? 0.5 * (lo + hi) : lo + (hi - lo) * i / (n - 1);
  };
  const double w = options.half_width_mm;
  const auto& off = options.model.plane_offset_mm;
  for (size_t c = 0; c < options.configurations.size(); ++c) {
    const auto& config = options.configurations[c];
    for (int k = 0; k < 3; ++k) {
      if (!options.planes[static_cast<size_t>(k)])
        continue;
      const auto plane = static_cast<PlaneAxis>(k);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          if (options.alternate_configurations &&
              static_cast<size_t>(i + j) % options.configurations.size() != c)
            continue;
          Eigen::Vector3d p;
          const double u = lerp(-w, w, i);
          if (plane == PlaneAxis::x)
            p = {off[0], u, lerp(options.z_min_mm, options.z_max_mm, j)};
          else if (plane == PlaneAxis::y)
            p = {u, off[1], lerp(options.z_min_mm, options.z_max_mm, j)};
          else
            p = {u, lerp(-w, w, j), off[2]};
          CalibrationPoint pt;
          pt.plane = plane;
          pt.configuration = static_cast<int>(c);
          pt.T_B_commanded = commanded_frame(plane, p, options.stand_off_mm);
          try {
            pt.q = joints_for_commanded_frame(nominal, options.external_joints, config,
                                              pt.T_B_commanded, options.perturbed_starts,
                                              options.seed);
          } catch (const Error& e) {
            throw Error(e.code(), "calibration plan: point " + std::to_string(points.size() + 1) +
                                      " (configuration " + std::to_string(c + 1) + ", plane " +
                                      to_string(plane) + "): " + e.message());
          }
          pt.reading_mm = options.stand_off_mm;  // the nominal reading
          points.push_back(pt);
        }
    }
  }
  return points;
}

void simulate_readings(const Cell& true_cell, std::vector<CalibrationPoint>& points,
                       double sigma_mm, std::uint64_t seed, const MeasurementModel& model) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (auto& pt : points) {
    const double e = noise(rng);
    pt.reading_mm = laser_reading(tcp_pose(true_cell, pt.q), pt.plane, model) + sigma_mm * e;
  }
}

// ---- Identification -------------------------------------------------------------------------

Eigen::MatrixXd observation_matrix(const Cell& cell,
                                   const std::vector<CalibrationParameter>& params,
                                   const Eigen::VectorXd& values,
                                   const std::vector<CalibrationPoint>& points,
                                   const MeasurementModel& model, Eigen::VectorXd* predicted) {
  const auto mp = static_cast<Eigen::Index>(params.size());
  if (values.size() != mp)
    throw Error(ErrorCode::internal, "observation_matrix: one value per parameter expected");
  if (mp > kMaxCalibrationParameters)
    fail("calibration: at most " + std::to_string(kMaxCalibrationParameters) +
         " parameters can be identified at once, " + std::to_string(mp) + " were given");
  LinkParams<AD> P;
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    P.p[static_cast<size_t>(i)] = {AD(j.alpha_rad), AD(j.a_mm), AD(j.theta_rad), AD(j.d_mm)};
  }
  for (Eigen::Index k = 0; k < mp; ++k) {
    const auto& prm = params[static_cast<size_t>(k)];
    if (prm.link < 1 || prm.link > cell.size())
      fail("calibration parameter " + prm.name() + ": no such link in the cell");
    P.p[static_cast<size_t>(prm.link - 1)][static_cast<size_t>(prm.field)] = AD(values[k], mp, k);
  }
  const auto np = static_cast<Eigen::Index>(points.size());
  Eigen::MatrixXd W(np, mp);
  if (predicted)
    predicted->resize(np);
  Eigen::Matrix<AD, 3, 3> R;
  Eigen::Matrix<AD, 3, 1> t;
  for (Eigen::Index i = 0; i < np; ++i) {
    const auto& pt = points[static_cast<size_t>(i)];
    if (pt.q.size() != cell.size())
      fail("calibration point " + std::to_string(i + 1) + ": " + std::to_string(pt.q.size()) +
           " joint values for a cell of " + std::to_string(cell.size()));
    tcp_frame<AD>(cell, pt.q, P, R, t);
    check_incidence(-value_of(R(static_cast<int>(pt.plane), 2)), pt.plane, model);
    const AD r = reading_of<AD>(R, t, pt.plane, model);
    if (r.derivatives().size() == mp)
      W.row(i) = r.derivatives().transpose();
    else
      W.row(i).setZero();
    if (predicted)
      (*predicted)[i] = r.value();
  }
  return W;
}

namespace {

std::string join_names(const std::vector<std::string>& names) {
  std::string s;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0)
      s += (i + 1 == names.size()) ? " and " : ", ";
    s += names[i];
  }
  return s;
}

// The column scaling of W: each column divided by its norm. A column that is zero to rounding
// (below 1e-9 of the largest; e.g. cos(pi/2) = 6e-17 times a lever) is left unscaled, so that it
// stays (nearly) zero and shows as unobservable instead of being blown up to unit length.
Eigen::VectorXd column_norms(const Eigen::MatrixXd& W) {
  Eigen::VectorXd s = W.colwise().norm().transpose();
  const double largest = s.size() > 0 ? s.maxCoeff() : 0.0;
  for (Eigen::Index j = 0; j < s.size(); ++j)
    if (!(s[j] > 1e-9 * largest))
      s[j] = 1.0;
  return s;
}

}  // namespace

std::string ObservabilityReport::summary() const {
  std::string s;
  for (const auto& u : unobservable) {
    if (!s.empty())
      s += "; ";
    s += u.description;
  }
  return s;
}

ObservabilityReport analyse_observability(const Eigen::MatrixXd& W,
                                          const std::vector<CalibrationParameter>& params,
                                          double rank_tolerance) {
  ObservabilityReport rep;
  const Eigen::Index mp = W.cols();
  const Eigen::MatrixXd Ws = W * column_norms(W).cwiseInverse().asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Ws, Eigen::ComputeFullV);
  rep.singular_values = svd.singularValues();
  if (mp == 0)
    return rep;
  const double smax = rep.singular_values[0];
  rep.rank = 0;
  for (Eigen::Index k = 0; k < rep.singular_values.size(); ++k)
    if (rep.singular_values[k] > rank_tolerance * smax)
      ++rep.rank;
  const Eigen::Index smin_index = rep.singular_values.size() - 1;
  rep.condition_number = rep.singular_values[smin_index] > 0.0
                             ? smax / rep.singular_values[smin_index]
                             : std::numeric_limits<double>::infinity();
  if (rep.singular_values.size() < mp) {  // fewer rows than parameters
    rep.condition_number = std::numeric_limits<double>::infinity();
  }
  if (rep.rank == mp)
    return rep;
  rep.condition_number = std::numeric_limits<double>::infinity();

  // Null space of the scaled W.
  const Eigen::MatrixXd N = svd.matrixV().rightCols(mp - rep.rank);
  // 1. Parameters that lie (almost) entirely in the null space: not observable at all.
  std::vector<Eigen::Index> rest;
  for (Eigen::Index j = 0; j < mp; ++j) {
    if (N.row(j).squaredNorm() > 1.0 - 1e-3) {
      UnobservableCombination u;
      u.parameters = {params[static_cast<size_t>(j)].name()};
      u.direction = Eigen::VectorXd::Unit(mp, j);
      u.description = u.parameters[0] + " is not observable";
      rep.unobservable.push_back(u);
    } else {
      rest.push_back(j);
    }
  }
  // 2. The other null directions, among the remaining parameters: combinations of which only
  // a part is seen.
  if (rest.empty())
    return rep;
  Eigen::MatrixXd Wr(Ws.rows(), static_cast<Eigen::Index>(rest.size()));
  for (size_t c = 0; c < rest.size(); ++c)
    Wr.col(static_cast<Eigen::Index>(c)) = Ws.col(rest[c]);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd_r(Wr, Eigen::ComputeFullV);
  const Eigen::VectorXd& sr = svd_r.singularValues();
  const auto nr = static_cast<Eigen::Index>(rest.size());
  for (Eigen::Index k = 0; k < nr; ++k) {
    const double sk = k < sr.size() ? sr[k] : 0.0;
    if (sk > rank_tolerance * smax)
      continue;
    const Eigen::VectorXd v = svd_r.matrixV().col(k);
    UnobservableCombination u;
    u.direction = Eigen::VectorXd::Zero(mp);
    const double vmax = v.cwiseAbs().maxCoeff();
    for (Eigen::Index c = 0; c < nr; ++c) {
      u.direction[rest[static_cast<size_t>(c)]] = v[c];
      if (std::abs(v[c]) > 0.1 * vmax)
        u.parameters.push_back(params[static_cast<size_t>(rest[static_cast<size_t>(c)])].name());
    }
    u.description = u.parameters.size() == 1 ? u.parameters[0] + " is not observable"
                                             : join_names(u.parameters) + " cannot be separated";
    rep.unobservable.push_back(u);
  }
  return rep;
}

const char* to_string(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::none:
      return "none";
    case RobustLoss::huber:
      return "huber";
    case RobustLoss::cauchy:
      return "cauchy";
  }
  return "none";
}

RobustLoss parse_robust_loss(const std::string& name) {
  if (name == "none")
    return RobustLoss::none;
  if (name == "huber")
    return RobustLoss::huber;
  if (name == "cauchy")
    return RobustLoss::cauchy;
  fail("unknown loss '" + name + "' (use none, huber or cauchy)");
}

namespace {

// The tuning constants that give 95 % efficiency on Gaussian noise.
constexpr double kHuberK = 1.345;
constexpr double kCauchyC = 2.385;

// rho(r / s), scaled so that it equals (r/s)^2 for small residuals (the least-squares cost).
double robust_rho(RobustLoss loss, double u) {
  const double a = std::abs(u);
  switch (loss) {
    case RobustLoss::huber:
      return a <= kHuberK ? u * u : 2.0 * kHuberK * a - kHuberK * kHuberK;
    case RobustLoss::cauchy:
      return kCauchyC * kCauchyC * std::log1p(u * u / (kCauchyC * kCauchyC));
    case RobustLoss::none:
      break;
  }
  return u * u;
}

// The IRLS weight rho'(u) / (2u): the step of a weighted least-squares problem with these
// weights is the Gauss-Newton step of the robust cost.
double robust_weight(RobustLoss loss, double u) {
  const double a = std::abs(u);
  switch (loss) {
    case RobustLoss::huber:
      return a <= kHuberK ? 1.0 : kHuberK / a;
    case RobustLoss::cauchy:
      return 1.0 / (1.0 + u * u / (kCauchyC * kCauchyC));
    case RobustLoss::none:
      break;
  }
  return 1.0;
}

double median_of(std::vector<double> v) {
  if (v.empty())
    return 0.0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  double m = v[mid];
  if (v.size() % 2 == 0)
    m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
  return m;
}

// The residual scale: given, or 1.4826 MAD (a consistent estimate of sigma for Gaussian noise
// that a minority of outliers does not move).
double residual_scale(const CalibrationOptions& o, const Eigen::VectorXd& r) {
  if (o.loss_scale_mm > 0.0)
    return o.loss_scale_mm;
  std::vector<double> v(r.data(), r.data() + r.size());
  const double med = median_of(v);
  for (double& x : v)
    x = std::abs(x - med);
  return std::max(1.4826 * median_of(v), 1e-4);
}

double robust_cost(const CalibrationOptions& o, const Eigen::VectorXd& r, double scale) {
  if (o.loss == RobustLoss::none)
    return r.squaredNorm();
  double c = 0.0;
  for (Eigen::Index i = 0; i < r.size(); ++i)
    c += robust_rho(o.loss, r[i] / scale);
  return c * scale * scale;
}

Eigen::VectorXd robust_weights(const CalibrationOptions& o, const Eigen::VectorXd& r,
                               double scale) {
  Eigen::VectorXd w = Eigen::VectorXd::Ones(r.size());
  if (o.loss != RobustLoss::none)
    for (Eigen::Index i = 0; i < r.size(); ++i)
      w[i] = robust_weight(o.loss, r[i] / scale);
  return w;
}

}  // namespace

CalibrationResult calibrate(const Cell& nominal, const std::vector<CalibrationParameter>& params,
                            const std::vector<CalibrationPoint>& points,
                            const CalibrationOptions& options) {
  if (params.empty())
    fail("calibration: no parameters to identify");
  const auto mp = static_cast<Eigen::Index>(params.size());
  const auto np = static_cast<Eigen::Index>(points.size());
  if (np < mp)
    fail("calibration: " + std::to_string(np) + " readings cannot identify " + std::to_string(mp) +
         " parameters");
  CalibrationResult res;
  res.parameters = params;
  res.initial = parameter_values(nominal, params);
  Eigen::VectorXd beta = res.initial;
  Eigen::VectorXd readings(np);
  for (Eigen::Index i = 0; i < np; ++i)
    readings[i] = points[static_cast<size_t>(i)].reading_mm;

  Eigen::VectorXd pred;
  Eigen::MatrixXd W = observation_matrix(nominal, params, beta, points, options.model, &pred);
  Eigen::VectorXd r = readings - pred;  // Delta p of eq. 8
  res.rms_before_mm = std::sqrt(r.squaredNorm() / static_cast<double>(np));
  res.value_history.push_back(beta);
  res.rms_history_mm.push_back(res.rms_before_mm);
  // Least squares: weights 1 and the plain sum of squares. A robust loss reweights the rows at
  // every iteration (IRLS) with the scale of that iteration.
  double scale = residual_scale(options, r);
  Eigen::VectorXd w = robust_weights(options, r, scale);
  double cost = robust_cost(options, r, scale);

  ObservabilityReport obs = analyse_observability(W, params, options.rank_tolerance);
  if (obs.rank_deficient() && !options.allow_partial) {
    fail("calibration: the readings cannot identify every parameter (rank " +
         std::to_string(obs.rank) + " of " + std::to_string(mp) + "): " + obs.summary());
  }

  double lambda = 0.0;  // Levenberg-Marquardt damping, in column-scaled coordinates
  for (int it = 0; it < options.max_iterations; ++it) {
    const Eigen::VectorXd sqrt_w = w.cwiseSqrt();
    const Eigen::MatrixXd Wr = sqrt_w.asDiagonal() * W;
    const Eigen::VectorXd D = column_norms(Wr);
    const Eigen::MatrixXd Ws = Wr * D.cwiseInverse().asDiagonal();
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(Ws, Eigen::ComputeThinU | Eigen::ComputeThinV);
    const Eigen::VectorXd& s = svd.singularValues();
    const double smax = s.size() > 0 ? s[0] : 0.0;
    const Eigen::VectorXd Utr = svd.matrixU().transpose() * sqrt_w.cwiseProduct(r);
    bool accepted = false;
    for (int attempt = 0; attempt < 40 && !accepted; ++attempt) {
      // Eq. 9 (lambda = 0): dbeta = W^+ dp, through the SVD of the scaled W; with lambda > 0
      // the Levenberg-Marquardt step (Ws^T Ws + lambda I)^-1 Ws^T dp.
      Eigen::VectorXd g(s.size());
      for (Eigen::Index k = 0; k < s.size(); ++k)
        g[k] = s[k] > options.rank_tolerance * smax ? s[k] / (s[k] * s[k] + lambda) * Utr[k] : 0.0;
      const Eigen::VectorXd step = D.cwiseInverse().cwiseProduct(svd.matrixV() * g);
      const Eigen::VectorXd beta_new = beta + step;
      Eigen::VectorXd pred_new;
      Eigen::MatrixXd W_new =
          observation_matrix(nominal, params, beta_new, points, options.model, &pred_new);
      const Eigen::VectorXd r_new = readings - pred_new;
      const double cost_new = robust_cost(options, r_new, scale);
      // Eq. 10 and the absolute step tolerance.
      bool small = true;
      for (Eigen::Index j = 0; j < mp; ++j)
        if (!(std::abs(step[j]) <
              std::max(options.relative_step * std::abs(beta[j] - res.initial[j]),
                       options.absolute_step)))
          small = false;
      if (cost_new <= cost) {
        beta = beta_new;
        W = std::move(W_new);
        r = r_new;
        ++res.iterations;
        res.value_history.push_back(beta);
        res.rms_history_mm.push_back(std::sqrt(r.squaredNorm() / static_cast<double>(np)));
        scale = residual_scale(options, r);
        w = robust_weights(options, r, scale);
        cost = robust_cost(options, r, scale);
        accepted = true;
        lambda = lambda * 0.1 < 1e-12 * smax * smax ? 0.0 : lambda * 0.1;
        if (small) {
          res.converged = true;
          break;
        }
      } else if (small) {
        // A step below the tolerance that no longer lowers the cost: rounding level.
        res.converged = true;
        break;
      } else {
        lambda = lambda == 0.0 ? 1e-4 * smax * smax : 10.0 * lambda;
      }
    }
    if (res.converged || !accepted)
      break;
  }

  res.values = beta;
  res.residuals_mm = r;
  res.rms_after_mm = std::sqrt(r.squaredNorm() / static_cast<double>(np));
  res.weights = w;
  for (Eigen::Index i = 0; i < np; ++i)
    if (w[i] < 0.5)
      res.outliers.push_back(static_cast<int>(i));
  // The statistics of a robust fit use the weighted rows: an outlier's small weight keeps it
  // from inflating sigma_hat (a down-weighted reading counts as a fraction of one).
  const Eigen::VectorXd sqrt_w_final = w.cwiseSqrt();
  W = sqrt_w_final.asDiagonal() * W;
  const double weighted_ss = sqrt_w_final.cwiseProduct(r).squaredNorm();
  res.observability = analyse_observability(W, params, options.rank_tolerance);
  const int rank = res.observability.rank;
  const double dof = static_cast<double>(np - rank);
  // Least squares: sigma_hat^2 = RSS / (np - rank). A robust fit reports the robust scale
  // (1.4826 MAD of the residuals, corrected for the degrees of freedom): a weighted RSS would
  // still carry the down-weighted outliers' share.
  if (options.loss == RobustLoss::none) {
    res.sigma_hat_mm = dof > 0 ? std::sqrt(weighted_ss / dof) : 0.0;
  } else {
    CalibrationOptions mad = options;
    mad.loss_scale_mm = 0.0;
    res.sigma_hat_mm =
        dof > 0 ? residual_scale(mad, r) * std::sqrt(static_cast<double>(np) / dof) : 0.0;
  }

  // Standard errors: sigma_hat^2 (W^T W)^-1, through the SVD of the scaled W. A parameter with
  // a component in the null space (partial calibration) has none.
  {
    const Eigen::VectorXd D = column_norms(W);
    const Eigen::MatrixXd Ws = W * D.cwiseInverse().asDiagonal();
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(Ws, Eigen::ComputeFullV);
    const Eigen::VectorXd& s = svd.singularValues();
    res.standard_errors.resize(mp);
    for (Eigen::Index j = 0; j < mp; ++j) {
      double var = 0.0;
      bool in_null = false;
      for (Eigen::Index k = 0; k < mp; ++k) {
        const double vjk = svd.matrixV()(j, k);
        if (k < rank)
          var += vjk * vjk / (s[k] * s[k]);
        else if (std::abs(vjk) > 1e-6)
          in_null = true;
      }
      res.standard_errors[j] = in_null ? std::numeric_limits<double>::quiet_NaN()
                                       : res.sigma_hat_mm * std::sqrt(var) / D[j];
    }
  }
  res.calibrated = apply_parameters(nominal, params, beta);
  return res;
}

// ---- Validation -----------------------------------------------------------------------------

std::vector<int> external_joint_indices(const Cell& cell) {
  std::vector<int> out;
  for (int i = 0; i < cell.size(); ++i)
    if (cell.joint(i).axis.kind == AxisKind::external)
      out.push_back(i);
  return out;
}

std::vector<CalibrationPoint> plan_validation(const Cell& nominal,
                                              const ValidationPlanOptions& options) {
  if (options.points < 1)
    fail("validation plan: at least one point is needed");
  const std::vector<int> ext =
      options.external_joints.empty() ? external_joint_indices(nominal) : options.external_joints;
  std::vector<std::pair<double, double>> ranges = options.ranges;
  if (ranges.empty()) {
    for (int j : ext) {
      const Joint& jt = nominal.joint(j);
      // The paper's section 3.3: theta_M in [0, pi], d_L in [0, 1000] mm.
      if (jt.type == JointType::prismatic)
        ranges.emplace_back(0.0, 1000.0);
      else
        ranges.emplace_back(0.0, kPi);
    }
  }
  if (ranges.size() != ext.size())
    fail("validation plan: " + std::to_string(ranges.size()) + " ranges for " +
         std::to_string(ext.size()) + " external joints");
  for (size_t k = 0; k < ext.size(); ++k) {
    const Joint& jt = nominal.joint(ext[k]);
    ranges[k].first = std::max(ranges[k].first, jt.lower);
    ranges[k].second = std::min(ranges[k].second, jt.upper);
    if (!(ranges[k].first <= ranges[k].second))
      fail("validation plan: the range of joint '" + jt.name + "' lies outside its limits");
  }
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto& off = options.model.plane_offset_mm;
  const double w = options.half_width_mm;
  std::vector<CalibrationPoint> points;
  points.reserve(static_cast<size_t>(options.points));
  for (int i = 0; i < options.points; ++i) {
    std::vector<double> config(ext.size());
    for (size_t k = 0; k < ext.size(); ++k)
      config[k] = ranges[k].first + (ranges[k].second - ranges[k].first) * unit(rng);
    const double u = -w + 2.0 * w * unit(rng);
    const double v = unit(rng);
    Eigen::Vector3d p;
    if (options.plane == PlaneAxis::x)
      p = {off[0], u, options.z_min_mm + (options.z_max_mm - options.z_min_mm) * v};
    else if (options.plane == PlaneAxis::y)
      p = {u, off[1], options.z_min_mm + (options.z_max_mm - options.z_min_mm) * v};
    else
      p = {u, -w + 2.0 * w * v, off[2]};
    CalibrationPoint pt;
    pt.plane = options.plane;
    pt.configuration = i;
    pt.T_B_commanded = commanded_frame(options.plane, p, options.stand_off_mm);
    try {
      pt.q = joints_for_commanded_frame(nominal, ext, config, pt.T_B_commanded,
                                        options.perturbed_starts, options.seed);
    } catch (const Error& e) {
      throw Error(e.code(), "validation plan: point " + std::to_string(i + 1) + ": " + e.message());
    }
    pt.reading_mm = options.stand_off_mm;
    points.push_back(pt);
  }
  return points;
}

DistanceStatistics distance_statistics(const Eigen::VectorXd& d) {
  DistanceStatistics st;
  st.count = static_cast<int>(d.size());
  if (d.size() == 0)
    return st;
  const double n = static_cast<double>(d.size());
  st.mean_mm = d.mean();
  st.rms_mm = std::sqrt(d.squaredNorm() / n);
  st.std_mm = d.size() > 1 ? std::sqrt((d.array() - st.mean_mm).square().sum() / (n - 1.0)) : 0.0;
  st.max_abs_mm = d.cwiseAbs().maxCoeff();
  return st;
}

ValidationResult validate_calibration(const Cell& nominal, const Cell& calibrated,
                                      const std::vector<CalibrationPoint>& points,
                                      const MeasurementModel& model) {
  ValidationResult v;
  const auto n = static_cast<Eigen::Index>(points.size());
  v.before_mm.resize(n);
  v.after_mm.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const CalibrationPoint& pt = points[static_cast<size_t>(i)];
    v.before_mm[i] = pt.reading_mm - laser_reading(tcp_pose(nominal, pt.q), pt.plane, model);
    v.after_mm[i] = pt.reading_mm - laser_reading(tcp_pose(calibrated, pt.q), pt.plane, model);
  }
  v.before = distance_statistics(v.before_mm);
  v.after = distance_statistics(v.after_mm);
  return v;
}

}  // namespace redpost
