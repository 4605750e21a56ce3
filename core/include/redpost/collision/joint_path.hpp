// The path of one written motion in joint space, as the controller runs it (docs/collision.md,
// "Between the poses"): a PTP moves every axis linearly (KUKA's synchronous PTP); a LIN moves
// the TCP on a straight line with the orientation slerped at the same pace, the external axes
// linearly, the arm in the posture (Status) it starts in; a CIRC the same on the circle through
// its start, auxiliary and end points.
#pragma once

#include "redpost/kinematics/arm_ik.hpp"
#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/circle.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost {

class JointPath {
 public:
  virtual ~JointPath() = default;
  // The joints at s in [0, 1] (DH units, chain order; virtual joints at 0 for a Cartesian
  // motion, since the controller knows no spin). False where the motion cannot be followed
  // there (the arm leaves its reach or its limits in its posture): a check must fail then.
  virtual bool at(double s, JointVector& q) const = 0;
  // True when q(s) is exactly linear in s: the bound between two samples needs no allowance.
  virtual bool joint_linear() const { return false; }
  // How far any point of a moving body may stray from where the joint path puts it (mm): the
  // blend of $APO.CDIS around a corner, a spline's distance from its chord. 0 for most.
  double allowance_mm = 0.0;
  // The blended corner at the motion's start (KUKA's approximate positioning, $APO.CDIS): the
  // controller cuts the corner between the motion before and this one, within $APO.CDIS of it.
  // To first order a configuration of the blend is the corner's plus a share of the step into
  // each motion's first (or last) $APO.CDIS, the shares at most the sine of half the corner's
  // angle (the blend's distance from the written path at the corner); so each pair may stray by
  // blend_fraction of this motion's bound and blend_fraction_before of the one before's
  // (docs/collision.md, "Blends"). The corner at the end is the next motion's start.
  double blend_fraction = 0.0;
  double blend_fraction_before = 0.0;
};

// A PTP from q0 to q1.
class JointLinePath : public JointPath {
 public:
  JointLinePath(const JointVector& q0, const JointVector& q1) : q0_(q0), q1_(q1) {}
  bool at(double s, JointVector& q) const override {
    q = q0_ + s * (q1_ - q0_);
    return true;
  }
  bool joint_linear() const override { return true; }

 private:
  JointVector q0_, q1_;
};

// A LIN (or CIRC, given the circle) from q0 to q1 as the controller interpolates it, solved with
// the arm's closed form for q0's Status. The solver and the cell must outlive the path.
class CartesianPath : public JointPath {
 public:
  // A straight line.
  CartesianPath(const ArmIk& ik, const Cell& cell, const JointVector& q0, const JointVector& q1);
  // An arc on `circle` (in {B}) from q0's TCP to q1's.
  CartesianPath(const ArmIk& ik, const Cell& cell, const JointVector& q0, const JointVector& q1,
                const Circle& circle_B);
  bool at(double s, JointVector& q) const override;

 private:
  const ArmIk* ik_;
  const Cell* cell_;
  JointVector q0_, q1_;
  Isometry T0_, T1_;
  Eigen::Quaterniond r0_, r1_;
  int status_ = 0;
  bool arc_ = false;
  Circle circle_;
};

}  // namespace redpost
