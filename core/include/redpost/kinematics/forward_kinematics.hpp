// Forward kinematics of a Cell: the pose of every joint frame and of the TCP in {B}.
//
// Pinocchio style: a free function over the read-only Cell and a caller-owned workspace.
// Nothing is allocated; the cost is one sincos and about thirty flops per link.
#pragma once

#include <array>

#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost {

struct KinematicsData {
  // Frame i of the chain (after link i) expressed in {B}. For standard DH this is the frame
  // whose z axis carries joint i+1.
  std::array<Isometry, kMaxJoints> T_B_link;
  // Axis (unit) and a point on the axis of each joint, in {B}, as the Jacobian needs them.
  std::array<Eigen::Vector3d, kMaxJoints> z_B_joint;
  std::array<Eigen::Vector3d, kMaxJoints> p_B_joint;
  Isometry T_B_tcp = Isometry::Identity();
  int joint_count = 0;

  // Every frame starts as the identity: forward_kinematics() then writes only the top three
  // rows, and the constant bottom row (0 0 0 1) is never rewritten.
  KinematicsData() { T_B_link.fill(Isometry::Identity()); }
};

// Fills `data` for the joint values q (DH units, chain order). q.size() must be cell.size().
// With link_frames = false, T_B_link is left as it was: the joint axes, the points on them and
// the TCP (all the Jacobian needs) are still computed, a little faster, as the tracker does.
void forward_kinematics(const Cell& cell, const JointVector& q, KinematicsData& data,
                        bool link_frames = true);

// Convenience: the TCP pose only.
Isometry tcp_pose(const Cell& cell, const JointVector& q);

}  // namespace redpost
