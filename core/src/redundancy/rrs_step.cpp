#include "redpost/redundancy/rrs_step.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace redpost {

namespace {

// Householder QR of the n x 6 matrix A in place (n >= 6), Algorithm 2 step 2, LAPACK's dgeqr2
// written out for this one shape: Eigen's HouseholderQR takes its general blocked path for a
// run-time row count and costs about three times as much here, the largest part of a tracking
// step. Column k of the factorisation is one instantiation, so that every loop bound is a
// compile-time constant and the compiler unrolls the short loops completely.
template <int n, int k>
inline void householder_column(double (&A)[6][kMaxJoints], double (&tau)[6]) {
  double* a = A[k];
  double tail2 = 0.0;
  for (int i = k + 1; i < n; ++i)
    tail2 += a[i] * a[i];
  if (tail2 == 0.0) {  // already triangular in this column: H_k = I
    tau[k] = 0.0;
  } else {
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
  if constexpr (k < 5)
    householder_column<n, k + 1>(A, tau);
}

template <int n>
void householder_qr_n(double (&A)[6][kMaxJoints], double (&tau)[6]) {
  householder_column<n, 0>(A, tau);
}

// With the row count a compile-time constant the short inner loops unroll: about twice as fast
// as with a run-time n. Cells have 6 to 16 joints.
void householder_qr(double (&A)[6][kMaxJoints], double (&tau)[6], int n) {
  switch (n) {
    case 6:
      return householder_qr_n<6>(A, tau);
    case 7:
      return householder_qr_n<7>(A, tau);
    case 8:
      return householder_qr_n<8>(A, tau);
    case 9:
      return householder_qr_n<9>(A, tau);
    case 10:
      return householder_qr_n<10>(A, tau);
    case 11:
      return householder_qr_n<11>(A, tau);
    case 12:
      return householder_qr_n<12>(A, tau);
    case 13:
      return householder_qr_n<13>(A, tau);
    case 14:
      return householder_qr_n<14>(A, tau);
    case 15:
      return householder_qr_n<15>(A, tau);
    default:
      return householder_qr_n<16>(A, tau);
  }
}

// A lower bound on the smallest singular value of the upper-triangular U (6x6):
// sigma_min = 1 / ||U^-1||_2 >= 1 / ||U^-1||_F, and the bound is within a factor sqrt(6) of it.
// U^-1 is formed by back substitution, about a hundred flops and no iteration. Damping from a
// lower bound errs on the safe side: it may damp a little where sigma_min is just above eps.
double smallest_singular_value_bound(const double (&A)[6][kMaxJoints]) {
  double diag_max = 0.0, diag_min = std::numeric_limits<double>::infinity();
  _Pragma("GCC unroll 6") for (int k = 0; k < 6; ++k) {
    diag_max = std::max(diag_max, std::fabs(A[k][k]));
    diag_min = std::min(diag_min, std::fabs(A[k][k]));
  }
  if (!(diag_min > 1e-14 * diag_max))
    return 0.0;
  // Column c of U^-1 (upper triangular): solve U x = e_c for rows c..0. U(i, j) = A[j][i].
  // Six divisions instead of twenty-one: they are the slowest operations here.
  double inv_diag[6];
  _Pragma("GCC unroll 6") for (int k = 0; k < 6; ++k) inv_diag[k] = 1.0 / A[k][k];
  double frob2 = 0.0;
  _Pragma("GCC unroll 6") for (int c = 0; c < 6; ++c) {
    double x[6];
    _Pragma("GCC unroll 6") for (int i = c; i >= 0; --i) {
      double s = i == c ? 1.0 : 0.0;
      _Pragma("GCC unroll 6") for (int j = i + 1; j <= c; ++j) s -= A[j][i] * x[j];
      x[i] = s * inv_diag[i];
      frob2 += x[i] * x[i];
    }
  }
  return 1.0 / std::sqrt(frob2);
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

  // Steps 1-2: [Q R] = qr(J^T), U = R(1:6, :), kept in place: U(i, j) = A[j][i], i <= j.
  householder_qr(ws.A, ws.tau, n);

  // Step 4: U^T y1 = r by forward substitution, or its damped form near a singularity.
  info.sigma_min = smallest_singular_value_bound(ws.A);
  info.damping = 0.0;
  Vector6d y1;
  const double eps = settings.singular_threshold;
  if (info.sigma_min >= eps) {
    for (int i = 0; i < 6; ++i) {  // U^T is lower triangular: (U^T)(i, j) = U(j, i) = A[i][j]
      double s = r[i];
      for (int j = 0; j < i; ++j)
        s -= ws.A[i][j] * y1[j];
      y1[i] = s / ws.A[i][i];
    }
  } else {
    Eigen::Matrix<double, 6, 6> U = Eigen::Matrix<double, 6, 6>::Zero();
    for (int j = 0; j < 6; ++j)
      for (int i = 0; i <= j; ++i)
        U(i, j) = ws.A[j][i];
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
