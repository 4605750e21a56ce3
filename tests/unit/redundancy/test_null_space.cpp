// Secondary goals: the analytic gradient of 1/kappa_F against finite differences, and the
// limit-avoidance motion against its definition.
#include <random>

#include "catch_compat.hpp"
#include "redpost/kinematics/conditioning.hpp"
#include "redpost/kinematics/jacobian.hpp"
#include "redpost/redundancy/null_space.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {
double arm_condition(const Cell& cell, const JointVector& q) {
  KinematicsData data;
  Jacobian J;
  forward_kinematics(cell, q, data);
  tcp_jacobian(cell, data, J);
  return arm_inverse_condition(cell, J);
}
}  // namespace

TEST_CASE("null space: gradient of 1/kappa_F equals central finite differences") {
  std::mt19937_64 rng(51);
  for (const char* name : test::kShippedCells) {
    const Cell cell = test::shipped_cell(name);
    KinematicsData data;
    Jacobian J;
    JointVector grad;
    for (int k = 0; k < 300; ++k) {
      const JointVector q = test::random_posture(cell, rng);
      forward_kinematics(cell, q, data);
      tcp_jacobian(cell, data, J);
      if (arm_inverse_condition(cell, J) < 0.02)
        continue;  // too close to singular for FD
      inverse_condition_gradient(cell, data, J, grad);
      for (int i = 0; i < cell.size(); ++i) {
        const double h = cell.joint(i).type == JointType::prismatic ? 1e-3 : 1e-6;
        JointVector qp = q, qm = q;
        qp[i] += h;
        qm[i] -= h;
        const double fd = (arm_condition(cell, qp) - arm_condition(cell, qm)) / (2 * h);
        INFO(name << " joint " << i);
        CHECK(grad[i] == Approx(fd).margin(1e-6).epsilon(1e-5));
      }
    }
  }
}

TEST_CASE("null space: table and track do not change the arm's conditioning") {
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  std::mt19937_64 rng(52);
  KinematicsData data;
  Jacobian J;
  JointVector grad;
  for (int k = 0; k < 100; ++k) {
    const JointVector q = test::random_posture(cell, rng);
    forward_kinematics(cell, q, data);
    tcp_jacobian(cell, data, J);
    inverse_condition_gradient(cell, data, J, grad);
    CHECK(grad[0] == 0.0);
    CHECK(grad[1] == 0.0);
    // theta_7 turns the TCP about its own axis: kappa_F does not depend on it either.
    CHECK(std::abs(grad[8]) < 1e-9);
  }
}

TEST_CASE("null space: limit avoidance pushes inwards only inside the zone") {
  const Cell cell = test::shipped_cell("kr15_2");
  JointVector q = cell.home(), h;
  limit_avoidance(cell, q, 0.1, 0.1, h);
  CHECK(h.cwiseAbs().maxCoeff() == 0.0);  // home is far from every limit
  const Joint& j = cell.joint(1);
  const double range = j.upper - j.lower;
  q[1] = j.lower + 0.02 * range;  // inside the 10 % zone at the lower end
  limit_avoidance(cell, q, 0.1, 0.1, h);
  CHECK(h[1] == Approx(0.1 * 0.08 * range));
  q[1] = j.upper - 0.05 * range;
  limit_avoidance(cell, q, 0.1, 0.1, h);
  CHECK(h[1] == Approx(-0.1 * 0.05 * range));
  int joint = -1;
  CHECK(smallest_limit_margin(cell, q, &joint) == Approx(0.05));
  CHECK(joint == 1);
}
