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
#include <cstdint>

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/status_turn.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost {

struct ArmIkSolutions {
  // Index mu - 1. Full chain joint vectors: the arm joints solved, every other joint copied from
  // q_other. Meaningful only where exists[mu - 1].
  std::array<JointVector, 8> q;
  // The posture exists mathematically (the wrist point is within reach for this shoulder and
  // elbow choice).
  std::array<bool, 8> exists{};
  // It exists, every arm joint is within its limits, and FK(q) reproduces the target (round
  // trip below 1e-6 mm and 1e-9 rad; not checked under RoundTrip::skip).
  std::array<bool, 8> valid{};
};

// The links around the arm at one setting of the joints outside it (q_other): the chain before
// A1 (ArmBefore, from the joints before it only) and after A6 (ArmAfter). solve() composes them
// itself; a caller that solves many targets at few settings (the whole-path planner: a
// keyframe's lattice nodes share a handful of table, track and spin values) composes each once
// (before_arm, after_arm) and solves with them.
struct ArmBefore {
  Isometry T_B_pre = Isometry::Identity();  // {B} <- the frame the A1 link starts from
  Isometry T_C_B = Isometry::Identity();    // {C} at q_other <- {B}
};
struct ArmAfter {
  Isometry T_6_tcp = Isometry::Identity();   // last arm link frame <- TCP
  Isometry T_tcp_C6 = Isometry::Identity();  // TCP <- {C} carried by A6 at the reference
};

// Whether solve() checks each posture by forward kinematics through the cell's own links.
enum class RoundTrip { check, skip };

// The arm's geometry, extracted from the cell once. Throws Error(bad_input) naming the reason
// when the cell does not map A1..A6, or its arm is not of this class (axes 4, 5, 6 not meeting
// in one point, A2 not parallel to A3, A1 not perpendicular to A2).
//
// The solver keeps a pointer to the cell: the cell must outlive it.
class ArmIk {
 public:
  explicit ArmIk(const Cell& cell);

  // All eight postures reaching the TCP frame T_B_tcp (in {B}). For joints whose range exceeds
  // 360 deg (A4, A6, sometimes A1) the 2*pi-equivalent value within the limits nearest to
  // q_near (the cell's home when null) is chosen. No allocation.
  // only_status >= 0 (a KUKA Status, 0..7): only that posture is filled in and checked; the
  // others may still be marked as existing but are never valid (the whole-path planner asks for
  // one posture per lattice node, and the round trip is most of a solve's time).
  ArmIkSolutions solve(const Isometry& T_B_tcp, const JointVector& q_other,
                       const JointVector* q_near = nullptr, int only_status = -1) const;

  // The same with the surroundings of q_other composed beforehand (bit for bit the same
  // solutions). RoundTrip::skip leaves out the forward kinematics check: valid then means the
  // posture exists and is within the limits. The closed form is exact but for the reach's
  // clamp (about 1e-7 mm) and the wrist's singular case, where the check never fails
  // (test_arm_ik compares both ways); a caller that skips it must check the motion itself (the
  // planner's nodes are followed by the tracker, which checks every pose).
  ArmIkSolutions solve(const Isometry& T_B_tcp, const ArmBefore& before, const ArmAfter& after,
                       const JointVector& q_other, const JointVector* q_near, int only_status,
                       RoundTrip round_trip) const;
  void before_arm(const JointVector& q_other, ArmBefore& before) const;
  void after_arm(const JointVector& q_other, ArmAfter& after) const;

  const ArmStatusModel& status_model() const { return status_model_; }
  // Unique to each constructed solver (a copy keeps it: it solves alike), so that a cache of
  // its results is not taken for another solver's at the same address (surroundings_memo.hpp).
  std::uint64_t instance() const { return instance_; }
  const std::array<int, 6>& arm_joints() const { return arm_joints_; }  // chain index of A1..A6

 private:
  // The arm in its canonical frame {C}: origin on the A1 axis at the foot of the common
  // perpendicular to A2, z along A1, x "forward" as status_turn() defines it, all at the
  // reference posture (arm DH values 0, A5 = 0). See arm_ik.cpp for how it is extracted.
  struct Geometry {
    JointVector q_home;  // the cell's home: q_near when none is given
    JointVector q_ref;   // full chain, arm at the reference posture
    std::array<double, 6> q_arm_ref{};
    Isometry T_C_a0 = Isometry::Identity();        // {C} <- a0 (link frame of A1 at q_ref)
    Isometry T_pre_C = Isometry::Identity();       // frame before the A1 link <- {C}
    Isometry T_6ref_inv_C = Isometry::Identity();  // M0^-1 * T_a0_C (M0: a0 -> link A6 at q_ref)
    Eigen::Vector3d wrist_C = Eigen::Vector3d::Zero();      // wrist point W0 in {C}
    Eigen::Matrix3d E_wrist = Eigen::Matrix3d::Identity();  // [w5 x w4, w5, w4] in {C}
    double a1_mm = 0.0;                 // A1 axis -> A2 axis (plane coordinate of the A2 axis)
    double sigma2 = 1.0;                // A2 axis = sigma2 * y_C
    double sigma3 = 1.0;                // A3 axis = sigma3 * A2 axis
    double epsilon6 = 1.0;              // A6 axis = epsilon6 * A4 axis at the reference
    double l2_mm = 0.0, l3_mm = 0.0;    // |A2->A3|, |A3->wrist| in the arm plane
    double arg_l2 = 0.0, arg_l3 = 0.0;  // their directions in the arm plane
  };

  const Cell* cell_ = nullptr;
  ArmStatusModel status_model_;
  std::array<int, 6> arm_joints_{};
  Geometry g_;
  std::uint64_t instance_ = 0;
};

}  // namespace redpost
