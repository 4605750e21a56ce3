// The clearance as a secondary goal of Algorithm 1 (docs/collision.md, "The tracker"): where two
// bodies that must stay apart come within `influence_mm`, a joint motion that moves them apart,
// in the form of Andres eq. 13's terms: h = k W^-1 grad(d) summed over the close pairs, each
// weighted by how far into the zone it is. grad(d) is the distance's gradient: for the nearest
// points p_a, p_b and n = (p_b - p_a) / |p_b - p_a|, dd/dq_i = n . (dp_b/dq_i - dp_a/dq_i), a
// joint that moves both bodies alike adding nothing. The null-space projection (rrs_step) keeps
// the TCP on its target, so the redundancy alone steers clear. The motion is W^-1 grad(d) scaled
// to `gain` in the weighted norm times the closest pair's depth in the zone (0 at its edge, 1 at
// contact), like the limits' term, so that it neither vanishes nor swamps the others.
#pragma once

#include "redpost/collision/scene.hpp"
#include "redpost/redundancy/null_space.hpp"

namespace redpost {

class ClearanceGoal : public ExtraGoal {
 public:
  // The scene must outlive the goal. Gain per pose (weighted metric, as the limits' k_lim).
  ClearanceGoal(const CollisionScene& scene, double influence_mm, double gain = 0.01);
  // Off (the default) the goal costs nothing: the session turns it on where the last motion
  // written came within the influence of some pair.
  void set_active(bool active) { active_ = active; }
  bool active() const { return active_; }
  void add(const JointVector& q, JointVector& h) const override;
  // The gradient alone (mm per DH unit) for the pairs within the influence, summed with their
  // weights; for the tests, which compare it with finite differences.
  void gradient(const JointVector& q, JointVector& g) const;

 private:
  const CollisionScene* scene_;
  double influence_mm_;
  double gain_;
  bool active_ = false;
  mutable double depth_ = 0.0;  // of the closest pair in the zone, 0..1 (gradient())
  mutable ScenePoses poses_;
  mutable KinematicsData data_;
};

}  // namespace redpost
