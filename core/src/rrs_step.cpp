#include "redpost/rrs_step.hpp"

#include <cmath>

namespace redpost {

namespace {

// Householder QR of the n x 6 matrix A in place (n >= 6), Algorithm 2 step 2. Written out for
// this one size: Eigen's HouseholderQR takes its general blocked path for a run-time row count
// and costs about three times as much here, the largest part of a tracking step.
void householder_qr(double (&A)[6][kMaxJoints], double (&tau)[6], int n) {
  for (int k = 0; k < 6; ++k) {
    double* a = A[k];
    double tail2 = 0.0;
    for (int i = k + 1; i < n; ++i)
      tail2 += a[i] * a[i];
    if (tail2 == 0.0) {  // already triangular in this column: H_k = I
      tau[k] = 0.0;
      continue;
    }
    const double alpha = a[k];
    const double beta = -std::copysign(std::sqrt(alpha * alpha + tail2), alpha);
    tau[k] = (beta - alpha) / beta;
    const double scale = 1.0 / (alpha - beta);
    for (int i = k + 1; i < n; ++i)
      a[i] *= scale;  // v = [1; a(k+1:n) / (alpha - beta)]
    a[k] = beta;
    for (int j = k + 1; j < 6; ++j) {  // A(:, j) -= tau v (v^T A(:, j))
      double* c = A[j];
      double w = c[k];
      for (int i = k + 1; i < n; ++i)
        w += a[i] * c[i];
      w *= tau[k];
      c[k] -= w;
      for (int i = k + 1; i < n; ++i)
        c[i] -= w * a[i];
    }
  }
}

// Smallest singular value of the upper-triangular U (6x6) by inverse iteration on U^T U: each
// step is two triangular solves, no factorisation. A rough estimate is enough to set the
// damping, and it never exceeds the true value by much: the iteration's Rayleigh quotient
// approaches sigma_min^2 from above.
double smallest_singular_value(const Eigen::Matrix<double, 6, 6>& U) {
  const double diag_min = U.diagonal().cwiseAbs().minCoeff();
  const double diag_max = U.diagonal().cwiseAbs().maxCoeff();
  if (!(diag_min > 1e-14 * diag_max))
    return 0.0;
  Eigen::Matrix<double, 6, 1> x = Eigen::Matrix<double, 6, 1>::Constant(1.0 / std::sqrt(6.0));
  double growth = 0.0;
  for (int k = 0; k < 4; ++k) {
    Eigen::Matrix<double, 6, 1> y = U.transpose().triangularView<Eigen::Lower>().solve(x);
    U.triangularView<Eigen::Upper>().solveInPlace(y);
    growth = y.norm();  // -> 1 / sigma_min^2
    x = y / growth;
  }
  return 1.0 / std::sqrt(growth);
}

}  // namespace

void rrs_step(const Jacobian& J_B, const Vector6d& dt, const JointVector& h,
              const JointVector& inv_sqrt_w, const RrsSettings& settings, RrsWorkspace& ws,
              JointVector& dq, RrsStepInfo& info) {
  const int n = static_cast<int>(J_B.cols());
  const double inv_L = 1.0 / settings.characteristic_length_mm;

  // A = Jw^T = (S J W^-1/2)^T, and the scaled task r = S dt.
  for (int i = 0; i < n; ++i) {
    const double s = inv_sqrt_w[i];
    for (int k = 0; k < 3; ++k) {
      ws.A[k][i] = s * J_B(k, i);
      ws.A[k + 3][i] = s * inv_L * J_B(k + 3, i);
    }
  }
  Vector6d r;
  r.head<3>() = dt.head<3>();
  r.tail<3>() = inv_L * dt.tail<3>();

  // h~ = W^1/2 h: the null-space motion expressed in the weighted coordinates y = W^1/2 q.
  ws.h_w.resize(n);
  for (int i = 0; i < n; ++i)
    ws.h_w[i] = inv_sqrt_w[i] > 0.0 ? h[i] / inv_sqrt_w[i] : 0.0;

  // Step 3: r = dt - J h~ (before A is overwritten by its factorisation).
  for (int k = 0; k < 6; ++k) {
    double s = 0.0;
    for (int i = 0; i < n; ++i)
      s += ws.A[k][i] * ws.h_w[i];
    r[k] -= s;
  }

  // Steps 1-2: [Q R] = qr(J^T), U = R(1:6, :).
  householder_qr(ws.A, ws.tau, n);
  Eigen::Matrix<double, 6, 6> U = Eigen::Matrix<double, 6, 6>::Zero();
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i <= j; ++i)
      U(i, j) = ws.A[j][i];

  // Step 4: U^T y1 = r by forward substitution, or its damped form near a singularity.
  info.sigma_min = smallest_singular_value(U);
  info.damping = 0.0;
  Vector6d y1;
  const double eps = settings.singular_threshold;
  if (info.sigma_min >= eps) {
    y1 = U.transpose().triangularView<Eigen::Lower>().solve(r);
  } else {
    const double ratio = info.sigma_min / eps;
    const double lambda2 = (1.0 - ratio * ratio) * settings.max_damping * settings.max_damping;
    info.damping = std::sqrt(lambda2);
    Eigen::Matrix<double, 6, 6> M = U.transpose() * U;
    M.diagonal().array() += lambda2;
    y1 = U * M.llt().solve(r);
  }

  // Steps 5-7: y = [y1; 0], k = Q y, dy = k + h~, with Q = H_0 H_1 ... H_5 applied from H_5 down.
  ws.y.setZero(n);
  ws.y.head<6>() = y1;
  for (int k = 5; k >= 0; --k) {
    const double* v = ws.A[k];
    double w = ws.y[k];
    for (int i = k + 1; i < n; ++i)
      w += v[i] * ws.y[i];
    w *= ws.tau[k];
    ws.y[k] -= w;
    for (int i = k + 1; i < n; ++i)
      ws.y[i] -= w * v[i];
  }
  ws.y += ws.h_w;

  // Back to joint units: dq = W^-1/2 dy.
  dq.resize(n);
  for (int i = 0; i < n; ++i)
    dq[i] = inv_sqrt_w[i] * ws.y[i];
}

}  // namespace redpost
