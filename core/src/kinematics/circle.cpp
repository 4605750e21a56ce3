#include "redpost/kinematics/circle.hpp"

#include <cmath>

#include <Eigen/Geometry>

#include "redpost/kinematics/types.hpp"

namespace redpost {

Eigen::Vector3d Circle::at(double s) const {
  const double phi = s * sweep;
  return centre + radius * (std::cos(phi) * u + std::sin(phi) * v);
}

bool circle_through(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    Circle& out) {
  const Eigen::Vector3d ab = b - a, ac = c - a;
  const Eigen::Vector3d n = ab.cross(ac);
  const double n2 = n.squaredNorm();
  if (!(n2 > 1e-12))
    return false;
  // The circumcentre of the triangle a, b, c.
  out.centre = a + (ac.squaredNorm() * n.cross(ab) + ab.squaredNorm() * ac.cross(n)) / (2.0 * n2);
  out.normal = n / std::sqrt(n2);
  out.radius = (a - out.centre).norm();
  out.u = (a - out.centre) / out.radius;
  out.v = out.normal.cross(out.u);
  const Eigen::Vector3d rc = c - out.centre;
  double phi = std::atan2(rc.dot(out.v), rc.dot(out.u));
  if (phi <= 0.0)
    phi += 2.0 * kPi;  // from a through b (positive sense about n) to c
  out.sweep = phi;
  return true;
}

}  // namespace redpost
