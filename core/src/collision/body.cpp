// Bounding spheres of shapes and bodies (body.hpp).
#include "redpost/collision/body.hpp"

#include <algorithm>
#include <cmath>

namespace redpost {

const char* to_string(ShapeKind kind) {
  switch (kind) {
    case ShapeKind::sphere:
      return "sphere";
    case ShapeKind::capsule:
      return "capsule";
    case ShapeKind::cylinder:
      return "cylinder";
    case ShapeKind::box:
      return "box";
    case ShapeKind::mesh:
      return "mesh";
  }
  return "?";
}

const char* to_string(BodyRole role) {
  switch (role) {
    case BodyRole::cell:
      return "cell";
    case BodyRole::cutter:
      return "cutter";
    case BodyRole::shank:
      return "shank";
    case BodyRole::holder:
      return "holder";
    case BodyRole::fixture:
      return "fixture";
    case BodyRole::part:
      return "part";
  }
  return "?";
}

namespace {

// The centre and radius of a sphere around a mesh's vertices (in the mesh's frame): the centre
// of their box and the farthest vertex from it. Not the smallest sphere, but within sqrt(3) of
// it, and computed once per mesh.
void mesh_sphere(const TriangleMesh& mesh, Eigen::Vector3d& centre, double& radius) {
  if (mesh.vertices.empty()) {
    centre.setZero();
    radius = 0.0;
    return;
  }
  Eigen::Vector3d lo = mesh.vertices.front(), hi = lo;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  centre = 0.5 * (lo + hi);
  double r2 = 0.0;
  for (const Eigen::Vector3d& v : mesh.vertices)
    r2 = std::max(r2, (v - centre).squaredNorm());
  radius = std::sqrt(r2);
}

}  // namespace

Eigen::Vector3d Shape::bound_centre() const {
  if (kind == ShapeKind::mesh && mesh) {
    Eigen::Vector3d c;
    double r = 0.0;
    mesh_sphere(*mesh, c, r);
    return T_frame_shape * c;
  }
  return T_frame_shape.translation();
}

double Shape::bound_radius() const {
  switch (kind) {
    case ShapeKind::sphere:
      return radius_mm;
    case ShapeKind::capsule:
      return 0.5 * length_mm + radius_mm;
    case ShapeKind::cylinder:
      return std::hypot(0.5 * length_mm, radius_mm);
    case ShapeKind::box:
      return 0.5 * size_mm.norm();
    case ShapeKind::mesh: {
      Eigen::Vector3d c;
      double r = 0.0;
      if (mesh)
        mesh_sphere(*mesh, c, r);
      return r;
    }
  }
  return 0.0;
}

void Body::bounding_sphere(Eigen::Vector3d& centre, double& radius) const {
  if (shapes.empty()) {
    centre.setZero();
    radius = 0.0;
    return;
  }
  // The centre of the shapes' spheres' box, and the farthest reach of any sphere from it.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const Shape& s : shapes) {
    const Eigen::Vector3d c = s.bound_centre();
    const double r = s.bound_radius();
    lo = lo.cwiseMin(c - Eigen::Vector3d::Constant(r));
    hi = hi.cwiseMax(c + Eigen::Vector3d::Constant(r));
  }
  centre = 0.5 * (lo + hi);
  radius = 0.0;
  for (const Shape& s : shapes)
    radius = std::max(radius, (s.bound_centre() - centre).norm() + s.bound_radius());
}

}  // namespace redpost
