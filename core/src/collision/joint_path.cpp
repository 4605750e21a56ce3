// The controller's paths in joint space (joint_path.hpp).
#include "redpost/collision/joint_path.hpp"

#include <cmath>

#include "redpost/kinematics/forward_kinematics.hpp"
#include "redpost/kinematics/status_turn.hpp"

namespace redpost {

namespace {

// The joints with every virtual one at 0: the controller's $TOOL knows no spin.
JointVector physical(const Cell& cell, JointVector q) {
  for (int i = 0; i < cell.size(); ++i) {
    if (cell.joint(i).type == JointType::virtual_spin)
      q[i] = 0.0;
  }
  return q;
}

}  // namespace

CartesianPath::CartesianPath(const ArmIk& ik, const Cell& cell, const JointVector& q0,
                             const JointVector& q1)
    : ik_(&ik), cell_(&cell), q0_(physical(cell, q0)), q1_(physical(cell, q1)) {
  T0_ = tcp_pose(cell, q0_);
  T1_ = tcp_pose(cell, q1_);
  r0_ = Eigen::Quaterniond(T0_.linear());
  r1_ = Eigen::Quaterniond(T1_.linear());
  status_ = status_turn(cell, ik.status_model(), q0_).status;
}

CartesianPath::CartesianPath(const ArmIk& ik, const Cell& cell, const JointVector& q0,
                             const JointVector& q1, const Circle& circle_B)
    : CartesianPath(ik, cell, q0, q1) {
  arc_ = true;
  circle_ = circle_B;
}

bool CartesianPath::at(double s, JointVector& q) const {
  if (s <= 0.0) {
    q = q0_;
    return true;
  }
  // The end is where the motion was written to; the replay's own solution there is the same
  // posture (the writer proved it, or the check finds the written end elsewhere).
  if (s >= 1.0) {
    q = q1_;
    return true;
  }
  JointVector q_other = q0_ + s * (q1_ - q0_);  // the external axes: linear
  Isometry T = Isometry::Identity();
  T.linear() = r0_.slerp(s, r1_).toRotationMatrix();
  T.translation() =
      arc_ ? circle_.at(s) : Eigen::Vector3d((1.0 - s) * T0_.translation() + s * T1_.translation());
  // The branch of A4 and A6 (beyond 360 deg of range) nearest the chord.
  const ArmIkSolutions sol = ik_->solve(T, q_other, &q_other, status_);
  const auto mu = static_cast<std::size_t>(status_);
  if (!sol.valid[mu])
    return false;
  q = sol.q[mu];
  // The solver takes the 2*pi-equivalent of A4 and A6 within the limits nearest the chord; one
  // more than half a turn from it means the nearest, which the controller's continuous path
  // takes, lies beyond a limit: the controller stops at its software limit switch there.
  for (int i = 0; i < cell_->size(); ++i) {
    if (cell_->joint(i).type == JointType::revolute && std::abs(q[i] - q_other[i]) > kPi)
      return false;
  }
  return true;
}

}  // namespace redpost
