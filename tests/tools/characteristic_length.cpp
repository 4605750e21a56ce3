// Computes the characteristic length L of a cell's arm, as Angeles defines it: the L for which
// the best-conditioned posture of the arm is as well conditioned as possible,
//
//   L* = argmax_L  max_q  1/kappa_F(J_N(q, L)).
//
// A seeded random search over postures within the limits, refined by coordinate descent, for
// each L on a grid, then a golden-section refinement in L. Prints L*, the best 1/kappa_F and the
// posture (controller axes). Usage: characteristic_length CELL.xml [samples]
#include <cstdio>
#include <cstdlib>
#include <random>

#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/kinematics/conditioning.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/jacobian.hpp"

using namespace redpost;

namespace {

struct Best {
  double inv_kappa = 0.0;
  JointVector q;
};

double evaluate(const Cell& cell, const JointVector& q, double L, KinematicsData& data,
                Jacobian& J) {
  forward_kinematics(cell, q, data);
  tcp_jacobian(cell, data, J);
  const ConditioningSpec& cs = cell.conditioning;
  return inverse_condition_frobenius(J.middleCols(cs.first, cs.count()), L);
}

Best best_posture(const Cell& cell, double L, int samples, unsigned seed) {
  std::mt19937_64 rng(seed);
  KinematicsData data;
  Jacobian J;
  Best best;
  const ConditioningSpec& cs = cell.conditioning;
  for (int s = 0; s < samples; ++s) {
    JointVector q = cell.home();
    for (int i = cs.first; i <= cs.last; ++i) {
      q[i] = std::uniform_real_distribution<double>(cell.joint(i).lower, cell.joint(i).upper)(rng);
    }
    double v = evaluate(cell, q, L, data, J);
    // Coordinate descent from the sample.
    for (double step = 0.2; step > 1e-4; step *= 0.5) {
      bool improved = true;
      while (improved) {
        improved = false;
        for (int i = cs.first; i <= cs.last; ++i) {
          for (double dir : {-1.0, 1.0}) {
            JointVector t = q;
            t[i] += dir * step;
            if (t[i] < cell.joint(i).lower || t[i] > cell.joint(i).upper)
              continue;
            const double vt = evaluate(cell, t, L, data, J);
            if (vt > v) {
              v = vt;
              q = t;
              improved = true;
            }
          }
        }
      }
    }
    if (v > best.inv_kappa)
      best = {v, q};
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s CELL.xml [samples]\n", argv[0]);
    return 2;
  }
  const Cell cell = load_cell(argv[1]);
  if (!cell.conditioning.declared()) {
    std::fprintf(stderr, "%s has no <conditioning> block\n", argv[1]);
    return 2;
  }
  const int samples = argc > 2 ? std::atoi(argv[2]) : 40;
  double lo = 50, hi = 3000;
  // Golden-section search on L (the best conditioning is unimodal in L for these arms; the grid
  // printed first shows it).
  for (double L = lo; L <= hi; L *= 1.5) {
    std::printf("L = %7.1f mm  best 1/kappa_F = %.4f\n", L,
                best_posture(cell, L, samples, 1).inv_kappa);
  }
  const double g = 0.6180339887498949;
  double a = lo, b = hi, c = b - g * (b - a), d = a + g * (b - a);
  double fc = best_posture(cell, c, samples, 1).inv_kappa;
  double fd = best_posture(cell, d, samples, 1).inv_kappa;
  while (b - a > 1.0) {
    if (fc > fd) {
      b = d, d = c, fd = fc, c = b - g * (b - a), fc = best_posture(cell, c, samples, 1).inv_kappa;
    } else {
      a = c, c = d, fc = fd, d = a + g * (b - a), fd = best_posture(cell, d, samples, 1).inv_kappa;
    }
  }
  const double L = 0.5 * (a + b);
  const Best best = best_posture(cell, L, samples, 1);
  std::printf("characteristic length L* = %.0f mm, best 1/kappa_F = %.4f at axes", L,
              best.inv_kappa);
  for (int i = cell.conditioning.first; i <= cell.conditioning.last; ++i) {
    std::printf(" %.1f", to_axis_value(cell.joint(i), best.q[i]));
  }
  std::printf("\n");
  return 0;
}
