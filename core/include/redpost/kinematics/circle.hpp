// The circle through three points, as a KUKA controller reads a CIRC: from the start a through
// the auxiliary point b to the end c (docs/krl-templates.md, "CIRC").
#pragma once

#include <Eigen/Core>

namespace redpost {

struct Circle {
  Eigen::Vector3d centre, normal, u, v;  // normal by the order a -> b -> c; u towards a
  double radius = 0.0;
  double sweep = 0.0;  // the angle from a through b to c, in (0, 2 pi] (rad)
  // The point at the fraction s of the sweep (0: a, 1: c).
  Eigen::Vector3d at(double s) const;
  double length() const { return radius * sweep; }
};

// False when the points are (nearly) on one line: no circle, the controller refuses the CIRC.
bool circle_through(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    Circle& out);

}  // namespace redpost
