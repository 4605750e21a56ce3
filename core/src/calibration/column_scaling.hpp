// The column scaling of the observation matrix W, shared by the observability analysis and the
// steps of the identification (internal to core; not installed).
#pragma once

#include <Eigen/Core>

namespace redpost::detail {

// The column scaling of W: each column divided by its norm. A column that is zero to rounding
// (below 1e-9 of the largest; e.g. cos(pi/2) = 6e-17 times a lever) is left unscaled, so that it
// stays (nearly) zero and shows as unobservable instead of being blown up to unit length.
inline Eigen::VectorXd column_norms(const Eigen::MatrixXd& W) {
  Eigen::VectorXd s = W.colwise().norm().transpose();
  const double largest = s.size() > 0 ? s.maxCoeff() : 0.0;
  for (Eigen::Index j = 0; j < s.size(); ++j)
    if (!(s[j] > 1e-9 * largest))
      s[j] = 1.0;
  return s;
}

}  // namespace redpost::detail
