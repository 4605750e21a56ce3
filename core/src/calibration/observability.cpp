// The observation matrix W of the calibration by automatic differentiation through the
// forward kinematics, and the analysis of what it leaves unobservable (observability.hpp).
// docs/calibration.md.
#include "redpost/calibration/observability.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/SVD>
#include <unsupported/Eigen/AutoDiff>

#include "calibration/column_scaling.hpp"
#include "calibration/fail.hpp"
#include "calibration/reading_model.hpp"
#include "redpost/io/error.hpp"

namespace redpost {

namespace {

using detail::fail_bad_input;

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

double value_of(const AD& x) {
  return x.value();
}

std::string join_names(const std::vector<std::string>& names) {
  std::string s;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i > 0)
      s += (i + 1 == names.size()) ? " and " : ", ";
    s += names[i];
  }
  return s;
}

}  // namespace

Eigen::MatrixXd observation_matrix(const Cell& cell,
                                   const std::vector<CalibrationParameter>& params,
                                   const Eigen::VectorXd& values,
                                   const std::vector<CalibrationPoint>& points,
                                   const MeasurementModel& model, Eigen::VectorXd* predicted) {
  const auto mp = static_cast<Eigen::Index>(params.size());
  if (values.size() != mp)
    throw Error(ErrorCode::internal, "observation_matrix: one value per parameter expected");
  if (mp > kMaxCalibrationParameters)
    fail_bad_input("calibration: at most " + std::to_string(kMaxCalibrationParameters) +
                   " parameters can be identified at once, " + std::to_string(mp) + " were given");
  LinkParams<AD> P;
  for (int i = 0; i < cell.size(); ++i) {
    const Joint& j = cell.joint(i);
    P.p[static_cast<size_t>(i)] = {AD(j.alpha_rad), AD(j.a_mm), AD(j.theta_rad), AD(j.d_mm)};
  }
  for (Eigen::Index k = 0; k < mp; ++k) {
    const auto& prm = params[static_cast<size_t>(k)];
    if (prm.link < 1 || prm.link > cell.size())
      fail_bad_input("calibration parameter " + prm.name() + ": no such link in the cell");
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
      fail_bad_input("calibration point " + std::to_string(i + 1) + ": " +
                     std::to_string(pt.q.size()) + " joint values for a cell of " +
                     std::to_string(cell.size()));
    tcp_frame<AD>(cell, pt.q, P, R, t);
    detail::check_incidence(-value_of(R(static_cast<int>(pt.plane), 2)), pt.plane, model);
    const AD r = detail::reading_of<AD>(R, t, pt.plane, model);
    if (r.derivatives().size() == mp)
      W.row(i) = r.derivatives().transpose();
    else
      W.row(i).setZero();
    if (predicted)
      (*predicted)[i] = r.value();
  }
  return W;
}

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
  const Eigen::MatrixXd Ws = W * detail::column_norms(W).cwiseInverse().asDiagonal();
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

}  // namespace redpost
