// Closed-form inverse kinematics of a 6R arm with a spherical wrist and the KUKA offsets (a1
// between A1 and A2, a2 the link arm, the A3-A4 offset c, the forearm length l), all eight
// postures (Caro 2014 section 5.2, issue 8). docs/placement.md gives the derivation.
//
// The arm is the six joints the cell maps to A1..A6. Joints before the arm (track, table) and
// after it (the virtual spin, fixed tool frames) take the values given in q_other, so the same
// solver serves the Andres cell with its externals held and the Caro cell with beta fixed.
//
// Posture numbering: mu = 1 + KUKA Status (status_turn.hpp): bit 0 overhead area, bit 1 elbow,
// bit 2 A5 < 0. Solution mu therefore has status_turn(cell, model, q).status == mu - 1.
#pragma once

#include <array>

#include "redpost/cell.hpp"
#include "redpost/status_turn.hpp"
#include "redpost/types.hpp"

namespace redpost {

struct ArmIkSolutions {
  // Index mu - 1. Full chain joint vectors: the arm joints solved, every other joint copied from
  // q_other.
  std::array<JointVector, 8> q;
  // The posture exists mathematically (the wrist point is within reach for this shoulder and
  // elbow choice).
  std::array<bool, 8> exists{};
  // It exists, every arm joint is within its limits, and FK(q) reproduces the target (round
  // trip below 1e-6 mm and 1e-9 rad).
  std::array<bool, 8> valid{};
};

// The arm's geometry, extracted from the cell once. Throws Error(bad_input) naming the reason
// when the cell does not map A1..A6, or its arm is not of this class (axes 4, 5, 6 not meeting
// in one point, A2 not parallel to A3, A1 not perpendicular to A2).
class ArmIk {
 public:
  explicit ArmIk(const Cell& cell);

  // All eight postures reaching the TCP frame T_B_tcp (in {B}). For joints whose range exceeds
  // 360 deg (A4, A6, sometimes A1) the 2*pi-equivalent value within the limits nearest to
  // q_near (the cell's home when null) is chosen. No allocation.
  ArmIkSolutions solve(const Isometry& T_B_tcp, const JointVector& q_other,
                       const JointVector* q_near = nullptr) const;

  const ArmStatusModel& status_model() const { return status_model_; }
  const std::array<int, 6>& arm_joints() const { return arm_joints_; }  // chain index of A1..A6

 private:
  const Cell* cell_ = nullptr;
  ArmStatusModel status_model_;
  std::array<int, 6> arm_joints_{};
  // Geometry in the arm's own frame (filled by the constructor; see arm_ik.cpp).
  struct Geometry;
  std::array<double, 32> geometry_{};
};

}  // namespace redpost
