// The geometric Jacobian at the TCP, expressed in {B}, rows [omega; v] (Andres eq. 14).
//
// Column i is [z_i; z_i x (p_tcp - p_i)] for a revolute or virtual joint and [0; z_i] for a
// prismatic one, z_i and p_i being the joint's axis and a point on it. Linear rows are in mm per
// unit joint rate (mm/rad or mm/mm).
#pragma once

#include "redpost/kinematics/forward_kinematics.hpp"

namespace redpost {

// Uses the frames in `data` (call forward_kinematics first). J is resized to 6 x cell.size().
void tcp_jacobian(const Cell& cell, const KinematicsData& data, Jacobian& J_B);

}  // namespace redpost
