// The clearance as a null-space goal (redundancy/clearance_goal.hpp).
#include "redpost/redundancy/clearance_goal.hpp"

#include <algorithm>
#include <cmath>

namespace redpost {

ClearanceGoal::ClearanceGoal(const CollisionScene& scene, double influence_mm, double gain)
    : scene_(&scene), influence_mm_(influence_mm), gain_(gain) {
  scene.prepare(poses_);
}

void ClearanceGoal::gradient(const JointVector& q, JointVector& g) const {
  const Cell& cell = scene_->cell();
  g.setZero(cell.size());
  depth_ = 0.0;
  JointVector qp = q;
  for (int i = 0; i < cell.size(); ++i) {
    if (cell.joint(i).type == JointType::virtual_spin)
      qp[i] = 0.0;
  }
  forward_kinematics(cell, qp, data_, true);
  scene_->place(data_, poses_);
  for (std::size_t p = 0; p < scene_->pairs().size(); ++p) {
    Proximity where;
    const double d = scene_->distance(static_cast<int>(p), poses_, influence_mm_, &where);
    if (!(d < influence_mm_) || !where.exact)
      continue;
    Eigen::Vector3d n = where.point_b_B - where.point_a_B;
    const BodyPair& pair = scene_->pairs()[p];
    if (n.norm() < 1e-9 || d <= 0.0) {
      // Touching or overlapping: the nearest points say little; apart along the centres.
      n = poses_.centre_B[static_cast<std::size_t>(pair.b)] -
          poses_.centre_B[static_cast<std::size_t>(pair.a)];
    }
    if (n.norm() < 1e-9)
      continue;
    n.normalize();
    const double weight = (influence_mm_ - d) / influence_mm_;
    depth_ = std::max(depth_, weight);
    // dp/dq_i of a point carried by joint i: z_i x (p - p_i) (revolute), z_i (prismatic).
    const auto add_body = [&](int body, const Eigen::Vector3d& point, double sign) {
      for (int i : scene_->movers(body)) {
        const auto iu = static_cast<std::size_t>(i);
        const Eigen::Vector3d& z = data_.z_B_joint[iu];
        const Eigen::Vector3d v = cell.joint(i).type == JointType::prismatic
                                      ? z
                                      : Eigen::Vector3d(z.cross(point - data_.p_B_joint[iu]));
        g[i] += sign * weight * n.dot(v);
      }
    };
    add_body(pair.b, where.point_b_B, 1.0);
    add_body(pair.a, where.point_a_B, -1.0);
  }
}

void ClearanceGoal::add(const JointVector& q, JointVector& h) const {
  if (!active_)
    return;
  JointVector g;
  gradient(q, g);
  // W^-1 grad, scaled to the gain in the weighted norm (as the other goals are capped in it),
  // times how deep the closest pair is in the zone: the push grows as the bodies close in.
  const Cell& cell = scene_->cell();
  double norm2 = 0.0;
  for (int i = 0; i < cell.size(); ++i)
    norm2 += g[i] * g[i] / cell.joint(i).weight;
  if (!(norm2 > 0.0))
    return;
  const double scale = gain_ * std::min(1.0, depth_) / std::sqrt(norm2);
  for (int i = 0; i < cell.size(); ++i)
    h[i] += scale * g[i] / cell.joint(i).weight;
}

}  // namespace redpost
