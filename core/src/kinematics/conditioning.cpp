#include "redpost/kinematics/conditioning.hpp"

#include <cassert>
#include <cmath>

namespace redpost {

namespace {

// tr(M^-1) through the Cholesky factor: M = L L^T, so tr(M^-1) = ||L^-1||_F^2. L^-1 is formed
// column by column with plain loops; Eigen's general triangular solve with a matrix right-hand
// side costs several times more at this size.
// The loops have constant bounds 6; unrolled, the whole function is straight-line code.
double inverse_condition_of_gram(const Eigen::Matrix<double, 6, 6>& M_lower) {
  double L[6][6] = {};
  double inv_diag[6];  // 1 / L(j, j): six divisions instead of thirty-six
  const double trace_M = M_lower.trace();
  _Pragma("GCC unroll 6") for (int j = 0; j < 6; ++j) {
    double d = M_lower(j, j);
    _Pragma("GCC unroll 6") for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    // A (numerically) singular M has a vanishing pivot; kappa_F is then infinite.
    if (!(d > 1e-14 * trace_M))
      return 0.0;
    L[j][j] = std::sqrt(d);
    inv_diag[j] = 1.0 / L[j][j];
    _Pragma("GCC unroll 6") for (int i = j + 1; i < 6; ++i) {
      double s = M_lower(i, j);
      _Pragma("GCC unroll 6") for (int k = 0; k < j; ++k) s -= L[i][k] * L[j][k];
      L[i][j] = s * inv_diag[j];
    }
  }
  double trace_inv = 0.0;
  _Pragma("GCC unroll 6") for (int c = 0; c < 6; ++c) {  // column c of L^-1 by forward substitution
    double x[6] = {};
    _Pragma("GCC unroll 6") for (int i = c; i < 6; ++i) {
      double s = i == c ? 1.0 : 0.0;
      _Pragma("GCC unroll 6") for (int k = c; k < i; ++k) s -= L[i][k] * x[k];
      x[i] = s * inv_diag[i];
      trace_inv += x[i] * x[i];
    }
  }
  return 6.0 / std::sqrt(trace_M * trace_inv);
}

double inverse_condition_of_columns(const Jacobian& J_B, int first, int count, double L) {
  assert(count >= 6 && L > 0.0);
  // M = J_N J_N^T (6x6), with the linear rows scaled by 1/L.
  // Lower triangle only, with plain loops (Eigen's rank update is general and slower here).
  Eigen::Matrix<double, 6, 6> M;
  double col[6];
  _Pragma("GCC unroll 6") for (int i = 0; i < 6; ++i)
      _Pragma("GCC unroll 6") for (int j = 0; j <= i; ++j) M(i, j) = 0.0;
  const double inv_L = 1.0 / L;
  _Pragma("GCC unroll 6") for (int c = first; c < first + count; ++c) {
    const double* Jc = J_B.data() + 6 * c;
    col[0] = Jc[0], col[1] = Jc[1], col[2] = Jc[2];
    col[3] = Jc[3] * inv_L, col[4] = Jc[4] * inv_L, col[5] = Jc[5] * inv_L;
    _Pragma("GCC unroll 6") for (int i = 0; i < 6; ++i)
        _Pragma("GCC unroll 6") for (int j = 0; j <= i; ++j) M(i, j) += col[i] * col[j];
  }
  return inverse_condition_of_gram(M);
}

}  // namespace

double inverse_condition_frobenius(const Jacobian& J_B, double characteristic_length_mm) {
  return inverse_condition_of_columns(J_B, 0, static_cast<int>(J_B.cols()),
                                      characteristic_length_mm);
}

double arm_inverse_condition(const Cell& cell, const Jacobian& J_B) {
  const ConditioningSpec& cs = cell.conditioning;
  if (!cs.declared())
    return inverse_condition_frobenius(J_B, cs.characteristic_length_mm);
  return inverse_condition_of_columns(J_B, cs.first, cs.count(), cs.characteristic_length_mm);
}

}  // namespace redpost
