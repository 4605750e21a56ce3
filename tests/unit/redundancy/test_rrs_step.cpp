// Algorithm 2 against an independent weighted pseudo-inverse computed by SVD.
#include <Eigen/SVD>
#include <random>

#include "catch_compat.hpp"
#include "redpost/redundancy/rrs_step.hpp"

using namespace redpost;

namespace {

Jacobian random_jacobian(int n, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Jacobian J(6, n);
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < 3; ++r)
      J(r, c) = g(rng);
    for (int r = 3; r < 6; ++r)
      J(r, c) = 500.0 * g(rng);  // mm per rad, as a real arm
  }
  return J;
}

// dq = W^-1/2 [ pinv(Jw) S dt + (I - pinv(Jw) Jw) W^1/2 h ], Jw = S J W^-1/2, by SVD.
Eigen::VectorXd reference_step(const Jacobian& J, const Vector6d& dt, const JointVector& h,
                               const JointVector& inv_sqrt_w, double L) {
  const int n = static_cast<int>(J.cols());
  Eigen::MatrixXd S = Eigen::MatrixXd::Identity(6, 6);
  S.bottomRightCorner(3, 3) /= L;
  const Eigen::MatrixXd Winv = inv_sqrt_w.head(n).asDiagonal();
  const Eigen::MatrixXd Jw = S * J * Winv;
  const Eigen::MatrixXd pinv = Jw.completeOrthogonalDecomposition().pseudoInverse();
  Eigen::VectorXd hw(n);
  for (int i = 0; i < n; ++i)
    hw[i] = inv_sqrt_w[i] > 0 ? h[i] / inv_sqrt_w[i] : 0.0;
  const Eigen::VectorXd y = pinv * (S * dt) + (Eigen::MatrixXd::Identity(n, n) - pinv * Jw) * hw;
  return Winv * y;
}

}  // namespace

TEST_CASE("rrs: Algorithm 2 equals the weighted pseudo-inverse solution with its null space") {
  std::mt19937_64 rng(31);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> w(0.1, 10.0);
  RrsSettings settings;
  settings.characteristic_length_mm = 400.0;
  settings.singular_threshold = 1e-9;  // exact Algorithm 2: no damping for these random J
  RrsWorkspace ws;
  for (int trial = 0; trial < 500; ++trial) {
    const int n = 6 + trial % 11;  // 6..16 joints
    const Jacobian J = random_jacobian(n, rng);
    Vector6d dt;
    for (int r = 0; r < 6; ++r)
      dt[r] = r < 3 ? 0.01 * g(rng) : g(rng);
    JointVector h(n), inv_sqrt_w(n);
    for (int i = 0; i < n; ++i) {
      h[i] = 0.05 * g(rng);
      inv_sqrt_w[i] = 1.0 / std::sqrt(w(rng));
    }
    JointVector dq;
    RrsStepInfo info;
    rrs_step(J, dt, h, inv_sqrt_w, settings, ws, dq, info);
    const Eigen::VectorXd ref = reference_step(J, dt, h, inv_sqrt_w, 400.0);
    REQUIRE(info.damping == 0.0);
    CHECK((dq - ref).norm() < 1e-9 * (1.0 + ref.norm()));
    // The task is met exactly and the null-space motion does not disturb it.
    CHECK((J * dq - dt).norm() < 1e-9);
  }
}

TEST_CASE("rrs: the null-space term lies in the null space of J") {
  std::mt19937_64 rng(32);
  std::normal_distribution<double> g(0.0, 1.0);
  RrsSettings settings;
  RrsWorkspace ws;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 9;
    const Jacobian J = random_jacobian(n, rng);
    Vector6d dt = Vector6d::Zero();
    JointVector h(n), ones = JointVector::Ones(n), dq;
    for (int i = 0; i < n; ++i)
      h[i] = g(rng);
    RrsStepInfo info;
    rrs_step(J, dt, h, ones, settings, ws, dq, info);
    CHECK((J * dq).norm() < 1e-9 * h.norm() * 500.0);
    CHECK(dq.norm() > 0.1 * h.norm());  // and it is not just zero: n - 6 = 3 free directions
  }
}

TEST_CASE("rrs: a locked joint does not move") {
  std::mt19937_64 rng(33);
  std::normal_distribution<double> g(0.0, 1.0);
  RrsSettings settings;
  RrsWorkspace ws;
  const int n = 9;
  const Jacobian J = random_jacobian(n, rng);
  Vector6d dt;
  for (int r = 0; r < 6; ++r)
    dt[r] = g(rng);
  JointVector h(n), w = JointVector::Ones(n), dq;
  for (int i = 0; i < n; ++i)
    h[i] = g(rng);
  w[1] = 0.0;
  w[4] = 0.0;
  RrsStepInfo info;
  rrs_step(J, dt, h, w, settings, ws, dq, info);
  CHECK(dq[1] == 0.0);
  CHECK(dq[4] == 0.0);
  CHECK((J * dq - dt).norm() < 1e-9);
}

TEST_CASE("rrs: the step stays bounded at and near a singularity") {
  // Two columns that become parallel: sigma_min -> 0. Undamped, |dq| ~ 1/sigma_min.
  std::mt19937_64 rng(34);
  Jacobian J = random_jacobian(6, rng);
  RrsSettings settings;
  settings.characteristic_length_mm = 500.0;
  RrsWorkspace ws;
  Vector6d dt;
  dt << 0.01, -0.02, 0.015, 3, -2, 1;
  JointVector h = JointVector::Zero(6), w = JointVector::Ones(6), dq;
  double largest = 0.0;
  for (double eps : {1e-1, 1e-2, 1e-3, 1e-5, 1e-8, 1e-12, 0.0}) {
    Jacobian Js = J;
    Js.col(5) = J.col(4) + eps * J.col(3);
    RrsStepInfo info;
    rrs_step(Js, dt, h, w, settings, ws, dq, info);
    INFO("eps " << eps << " sigma_min " << info.sigma_min << " |dq| " << dq.norm());
    CHECK(std::isfinite(dq.norm()));
    largest = std::max(largest, dq.norm());
    if (eps <= 1e-5)
      CHECK(info.damping > 0.0);
  }
  // With the variable damping, sigma / (sigma^2 + lambda^2) <= 1/eps + 1/(2 lambda_max) for every
  // sigma, so |y| (= |dq| here, W = I) is bounded by that gain times |S dt|, singular or not.
  const double r_norm = std::hypot(dt.head<3>().norm(), dt.tail<3>().norm() / 500.0);
  const double gain = 1.0 / settings.singular_threshold + 1.0 / (2 * settings.max_damping);
  CHECK(largest < gain * r_norm);
}
