// The collision scene: pairs, poses, distances through FCL, and the motion bound (scene.hpp).
//
// FCL (Debian's libfcl-dev 0.7) is used for one thing: the distance between two convex
// primitives or a primitive and a triangle mesh (GJK through libccd, BVH traversal for meshes).
// Its continuous collision is not used (docs/collision.md says why); everything FCL is kept in
// this file.
#include "redpost/collision/scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/narrowphase/distance.h>

#include "redpost/io/error.hpp"

namespace redpost {

struct BodyGeometry {
  struct Part {
    std::shared_ptr<fcl::CollisionGeometryd> fcl;
    Isometry T_body_shape = Isometry::Identity();
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // bounding sphere, body frame
    double radius = 0.0;
    // A box around the shape in its own frame (centre, half edges): with the other shape's
    // sphere, a far tighter bound than two spheres for long or flat shapes (a jaw, a link).
    Eigen::Vector3d box_centre = Eigen::Vector3d::Zero(), box_half = Eigen::Vector3d::Zero();
    const TriangleMesh* mesh = nullptr;  // for the inside test (kept alive by the Body)
    std::shared_ptr<const TriangleMesh> mesh_owner;
    bool closed = false;  // every edge shared by exactly two triangles
    bool bvh = false;     // a triangle hierarchy (not one convex body)
  };
  std::vector<Part> parts;
};

namespace {

bool closed_mesh(const TriangleMesh& m) {
  std::map<std::pair<int, int>, int> edges;
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) {
      const int a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  }
  for (const auto& [e, n] : edges) {
    if (n != 2)
      return false;
  }
  return !edges.empty();
}

// The faces of a mesh that is convex, each turned counter-clockwise seen from outside (FCL's
// Convex encoding: n, then n indices); empty when some vertex lies outside a face's plane.
std::vector<int> convex_faces(const TriangleMesh& m) {
  std::vector<int> faces;
  double extent = 0.0;
  for (const Eigen::Vector3d& v : m.vertices)
    extent = std::max(extent, v.cwiseAbs().maxCoeff());
  const double tol = 1e-9 * std::max(1.0, extent);
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d& a = m.vertices[static_cast<std::size_t>(t[0])];
    const Eigen::Vector3d n = (m.vertices[static_cast<std::size_t>(t[1])] - a)
                                  .cross(m.vertices[static_cast<std::size_t>(t[2])] - a)
                                  .normalized();
    bool above = false, below = false;
    for (const Eigen::Vector3d& v : m.vertices) {
      const double h = n.dot(v - a);
      above = above || h > tol;
      below = below || h < -tol;
    }
    if (above && below)
      return {};
    faces.push_back(3);
    // Counter-clockwise from outside: the other vertices below the face's normal.
    if (above) {
      faces.insert(faces.end(), {t[0], t[2], t[1]});
    } else {
      faces.insert(faces.end(), {t[0], t[1], t[2]});
    }
  }
  return faces;
}

std::shared_ptr<fcl::CollisionGeometryd> make_fcl(const Shape& s) {
  switch (s.kind) {
    case ShapeKind::sphere:
      return std::make_shared<fcl::Sphered>(s.radius_mm);
    case ShapeKind::capsule:
      return std::make_shared<fcl::Capsuled>(s.radius_mm, s.length_mm);
    case ShapeKind::cylinder:
      return std::make_shared<fcl::Cylinderd>(s.radius_mm, s.length_mm);
    case ShapeKind::box:
      return std::make_shared<fcl::Boxd>(s.size_mm.x(), s.size_mm.y(), s.size_mm.z());
    case ShapeKind::mesh: {
      // A convex mesh (a jaw, a clamp block, a riser) is one convex body for GJK, far cheaper
      // than a triangle hierarchy; its closedness is checked by the caller.
      if (closed_mesh(*s.mesh)) {
        std::vector<int> faces = convex_faces(*s.mesh);
        if (!faces.empty()) {
          const int n = static_cast<int>(s.mesh->triangles.size());
          return std::make_shared<fcl::Convexd>(
              std::make_shared<const std::vector<Eigen::Vector3d>>(s.mesh->vertices), n,
              std::make_shared<const std::vector<int>>(std::move(faces)));
        }
      }
      auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
      std::vector<fcl::Triangle> tris;
      tris.reserve(s.mesh->triangles.size());
      for (const auto& t : s.mesh->triangles)
        tris.emplace_back(static_cast<std::size_t>(t[0]), static_cast<std::size_t>(t[1]),
                          static_cast<std::size_t>(t[2]));
      model->beginModel(static_cast<int>(tris.size()), static_cast<int>(s.mesh->vertices.size()));
      model->addSubModel(s.mesh->vertices, tris);
      model->endModel();
      return model;
    }
  }
  return nullptr;
}

std::shared_ptr<const BodyGeometry> make_geometry(const Body& b) {
  auto g = std::make_shared<BodyGeometry>();
  for (const Shape& s : b.shapes) {
    if (s.kind == ShapeKind::mesh && (!s.mesh || s.mesh->triangles.empty()))
      throw Error(ErrorCode::internal, "a mesh shape without triangles in body " + b.name);
    BodyGeometry::Part p;
    p.fcl = make_fcl(s);
    p.T_body_shape = s.T_frame_shape;
    p.centre = s.bound_centre();
    p.radius = s.bound_radius();
    switch (s.kind) {
      case ShapeKind::sphere:
        p.box_half = Eigen::Vector3d::Constant(s.radius_mm);
        break;
      case ShapeKind::capsule:
        p.box_half = Eigen::Vector3d(s.radius_mm, s.radius_mm, 0.5 * s.length_mm + s.radius_mm);
        break;
      case ShapeKind::cylinder:
        p.box_half = Eigen::Vector3d(s.radius_mm, s.radius_mm, 0.5 * s.length_mm);
        break;
      case ShapeKind::box:
        p.box_half = 0.5 * s.size_mm;
        break;
      case ShapeKind::mesh: {
        Eigen::Vector3d lo = s.mesh->vertices.front(), hi = lo;
        for (const Eigen::Vector3d& v : s.mesh->vertices) {
          lo = lo.cwiseMin(v);
          hi = hi.cwiseMax(v);
        }
        p.box_centre = 0.5 * (lo + hi);
        p.box_half = 0.5 * (hi - lo);
        break;
      }
    }
    if (s.kind == ShapeKind::mesh) {
      p.mesh = s.mesh.get();
      p.mesh_owner = s.mesh;
      p.closed = closed_mesh(*s.mesh);
      p.bvh = p.fcl->getObjectType() == fcl::OT_BVH;
    }
    g->parts.push_back(std::move(p));
  }
  return g;
}

// Frames from which the TCP is reached through virtual joints only: the flange and spindle of
// the reference cells (the tool's spin is no physical motion).
bool rigid_with_tcp(const Cell& cell, int frame) {
  if (frame == kFrameTcp)
    return true;
  if (frame < 0)
    return false;
  for (int j = frame + 1; j < cell.size(); ++j) {
    if (cell.joint(j).type != JointType::virtual_spin)
      return false;
  }
  return true;
}

// A virtual joint whose axis is the TCP's z axis through the TCP: turning it turns the tool's
// bodies (cylinders on that axis) into themselves.
bool spins_about_tool_axis(const Cell& cell, int j) {
  KinematicsData data;
  forward_kinematics(cell, cell.home(), data);
  const Eigen::Vector3d z = data.z_B_joint[static_cast<std::size_t>(j)];
  const Eigen::Vector3d p = data.p_B_joint[static_cast<std::size_t>(j)];
  const Eigen::Vector3d z_tcp = data.T_B_tcp.linear().col(2);
  const Eigen::Vector3d o = data.T_B_tcp.translation();
  return z.cross(z_tcp).norm() < 1e-9 && (o - p).cross(z).norm() < 1e-6;
}

// Is every shape of `body` round about the axis of joint k, the joint right after the body's
// frame (a rotary table top about the table's axis)? Then turning joint k moves nothing of the
// body, and a pair of it with a body that k carries is as far apart at every angle of k
// (d(A, R_k B) = d(R_k^-1 A, B) = d(A, B)). The axis is fixed in the body's frame (no joint
// between them); it is checked at two postures all the same.
bool round_about_next_joint(const Cell& cell, const Body& body, int k) {
  if (body.frame == kFrameTcp || k != body.frame + 1 || k >= cell.size() ||
      cell.joint(k).type == JointType::prismatic || body.shapes.empty())
    return false;
  const auto axis_in_frame = [&](const JointVector& q, Eigen::Vector3d& p, Eigen::Vector3d& z) {
    KinematicsData data;
    forward_kinematics(cell, q, data, true);
    const Isometry T_B_frame = body.frame == kFrameBase
                                   ? Isometry::Identity()
                                   : data.T_B_link[static_cast<std::size_t>(body.frame)];
    const auto ku = static_cast<std::size_t>(k);
    z = T_B_frame.linear().transpose() * data.z_B_joint[ku];
    p = T_B_frame.inverse() * data.p_B_joint[ku];
  };
  Eigen::Vector3d p, z, p2, z2;
  axis_in_frame(cell.home(), p, z);
  JointVector moved = cell.home();
  for (int j = 0; j < cell.size(); ++j)
    moved[j] += 0.3 + 0.1 * j;  // any other posture: DH units, radians or mm alike
  axis_in_frame(moved, p2, z2);
  const auto on_axis = [&](const Eigen::Vector3d& x) { return (x - p).cross(z).norm() < 1e-6; };
  if (z.cross(z2).norm() > 1e-9 || !on_axis(p2))
    return false;
  for (const Shape& s : body.shapes) {
    const Eigen::Vector3d centre = s.T_frame_shape.translation();
    const Eigen::Vector3d along = s.T_frame_shape.linear().col(2);
    const bool round = s.kind == ShapeKind::sphere ||
                       ((s.kind == ShapeKind::cylinder || s.kind == ShapeKind::capsule) &&
                        along.cross(z).norm() < 1e-9);
    if (!round || !on_axis(centre))
      return false;
  }
  return true;
}

// Moller-Trumbore: does the ray from o along d cross the triangle (a, b, c) at t > 0?
bool ray_hits(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
              const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::fabs(det) < 1e-14)
    return false;
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = o - a;
  const double u = s.dot(p) * inv;
  if (u < 0.0 || u > 1.0)
    return false;
  const Eigen::Vector3d qv = s.cross(e1);
  const double v = d.dot(qv) * inv;
  if (v < 0.0 || u + v > 1.0)
    return false;
  return e2.dot(qv) * inv > 0.0;
}

// Whether the point (in the mesh's frame) is inside the closed mesh: the parity of a ray's
// crossings, by the majority of three rays in unrelated directions (a ray through an edge or a
// vertex, where two triangles meet, may count one crossing twice).
bool point_inside(const TriangleMesh& m, const Eigen::Vector3d& p) {
  const Eigen::Vector3d dirs[3] = {Eigen::Vector3d(0.3127, 0.7049, 0.6373).normalized(),
                                   Eigen::Vector3d(-0.8311, 0.2113, 0.5146).normalized(),
                                   Eigen::Vector3d(0.1709, -0.5477, -0.8190).normalized()};
  int odd = 0;
  for (const Eigen::Vector3d& d : dirs) {
    int crossings = 0;
    for (const auto& t : m.triangles) {
      crossings += ray_hits(p, d, m.vertices[static_cast<std::size_t>(t[0])],
                            m.vertices[static_cast<std::size_t>(t[1])],
                            m.vertices[static_cast<std::size_t>(t[2])]);
    }
    odd += crossings % 2;
  }
  return odd >= 2;
}

// FCL 0.7's nearest points in {B}, a for the first shape and b for the second. FCL is not
// consistent here (docs/collision.md, "FCL"; test_scene checks every pairing): between convex
// shapes it gives them in {B} in the order asked; between a triangle hierarchy and a shape it
// gives the hierarchy's point first whatever the order, in {B}, but for a sphere in the shapes'
// own frames (its sphere-triangle special case).
void nearest_points(const fcl::DistanceResultd& r, const BodyGeometry::Part& pa, const Isometry& Ta,
                    const BodyGeometry::Part& pb, const Isometry& Tb, Eigen::Vector3d& a,
                    Eigen::Vector3d& b) {
  a = r.nearest_points[0];
  b = r.nearest_points[1];
  if (pa.bvh == pb.bvh)
    return;
  const BodyGeometry::Part& shape = pa.bvh ? pb : pa;
  Eigen::Vector3d on_mesh = r.nearest_points[0], on_shape = r.nearest_points[1];
  if (shape.fcl->getNodeType() == fcl::GEOM_SPHERE) {
    on_mesh = (pa.bvh ? Ta : Tb) * on_mesh;
    on_shape = (pa.bvh ? Tb : Ta) * on_shape;
  }
  a = pa.bvh ? on_mesh : on_shape;
  b = pa.bvh ? on_shape : on_mesh;
}

// The distance from a sphere (centre in {B}, radius) to the part's box placed at T_B_shape, less
// the radius: a lower bound of the sphere's distance to the shape inside the box.
double sphere_to_box(const Eigen::Vector3d& c_B, double radius, const Isometry& T_B_shape,
                     const BodyGeometry::Part& part) {
  const Eigen::Vector3d local = T_B_shape.linear().transpose() * (c_B - T_B_shape.translation());
  const Eigen::Vector3d out = ((local - part.box_centre).cwiseAbs() - part.box_half).cwiseMax(0.0);
  return out.norm() - radius;
}

}  // namespace

CollisionScene::CollisionScene(const Cell& cell, std::vector<Body> bodies,
                               const std::vector<std::pair<int, int>>& allowed,
                               const CollisionScene* shared, int shared_count)
    : cell_(&cell), bodies_(std::move(bodies)) {
  const int n = body_count();
  for (int i = 0; i < n; ++i) {
    const Body& b = bodies_[static_cast<std::size_t>(i)];
    if (b.frame >= cell.size() || b.frame < kFrameTcp)
      throw Error(ErrorCode::internal, "body " + b.name + " on a frame the cell does not have");
    geometry_.push_back(shared && i < shared_count ? shared->geometry_[static_cast<std::size_t>(i)]
                                                   : make_geometry(b));
    Eigen::Vector3d c;
    double r = 0.0;
    b.bounding_sphere(c, r);
    centre_.push_back(c);
    radius_.push_back(r);
    std::vector<int> movers;
    const int last = b.frame == kFrameTcp ? cell.size() - 1 : b.frame;
    for (int j = 0; j <= last; ++j) {
      const bool tool_spin = b.frame == kFrameTcp &&
                             cell.joint(j).type == JointType::virtual_spin &&
                             spins_about_tool_axis(cell, j);
      if (!tool_spin)
        movers.push_back(j);
    }
    movers_.push_back(std::move(movers));
  }
  const auto is_allowed = [&](int a, int b) {
    return std::find(allowed.begin(), allowed.end(), std::make_pair(a, b)) != allowed.end() ||
           std::find(allowed.begin(), allowed.end(), std::make_pair(b, a)) != allowed.end();
  };
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      const Body& A = bodies_[static_cast<std::size_t>(a)];
      const Body& B = bodies_[static_cast<std::size_t>(b)];
      if (is_allowed(a, b) || A.frame == B.frame || (A.is_tool() && B.is_tool()))
        continue;
      if ((A.is_tool() && B.role == BodyRole::cell && rigid_with_tcp(cell, B.frame)) ||
          (B.is_tool() && A.role == BodyRole::cell && rigid_with_tcp(cell, A.frame)))
        continue;
      if ((A.role == BodyRole::cutter && B.role == BodyRole::part) ||
          (B.role == BodyRole::cutter && A.role == BodyRole::part))
        continue;
      pairs_.push_back({a, b});
      // The frames in chain order: {B} first (-1), the TCP last (n).
      const auto order = [&](int frame) { return frame == kFrameTcp ? cell.size() : frame; };
      const bool a_first = order(A.frame) <= order(B.frame);
      pair_mover_.push_back(a_first ? b : a);
      // The first joint that moves the later body against the nearer one, but the nearer one's
      // own axis where it is round about it: that joint's turn changes no distance.
      const int from = std::min(order(A.frame), order(B.frame)) + 1;
      const bool round = round_about_next_joint(cell, a_first ? A : B, from);
      pair_from_.push_back(round ? from + 1 : from);
    }
  }
  row_ = static_cast<std::size_t>(cell.size()) + 1;
}

CollisionScene::~CollisionScene() = default;

std::string CollisionScene::pair_name(int pair) const {
  const BodyPair& p = pairs_[static_cast<std::size_t>(pair)];
  return body(p.a).name + " vs " + body(p.b).name;
}

void CollisionScene::prepare(ScenePoses& poses) const {
  poses.T_B_body.assign(bodies_.size(), Isometry::Identity());
  poses.centre_B.assign(bodies_.size(), Eigen::Vector3d::Zero());
}

void CollisionScene::place(const KinematicsData& data, ScenePoses& poses) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const int f = bodies_[i].frame;
    poses.T_B_body[i] = f == kFrameBase  ? Isometry::Identity()
                        : f == kFrameTcp ? data.T_B_tcp
                                         : data.T_B_link[static_cast<std::size_t>(f)];
    poses.centre_B[i] = poses.T_B_body[i] * centre_[i];
  }
}

void CollisionScene::set_pose(int body, const Isometry& T_B_body, ScenePoses& poses) const {
  const auto i = static_cast<std::size_t>(body);
  poses.T_B_body[i] = T_B_body;
  poses.centre_B[i] = T_B_body * centre_[i];
}

double CollisionScene::distance(int pair, const ScenePoses& poses, double exact_below_mm,
                                Proximity* where) const {
  const BodyPair& p = pairs_[static_cast<std::size_t>(pair)];
  const auto ia = static_cast<std::size_t>(p.a), ib = static_cast<std::size_t>(p.b);
  // The whole bodies' spheres first: most pairs are far apart most of the time.
  const double whole = (poses.centre_B[ia] - poses.centre_B[ib]).norm() - radius_[ia] - radius_[ib];
  if (whole >= exact_below_mm) {
    if (where)
      *where = Proximity{whole, poses.centre_B[ia], poses.centre_B[ib], false};
    return whole;
  }
  const BodyGeometry& ga = *geometry_[ia];
  const BodyGeometry& gb = *geometry_[ib];
  // Shape by shape: a sphere bound where it is enough, FCL where it is not.
  double bound = std::numeric_limits<double>::infinity();
  struct Candidate {
    double bound;
    std::size_t i, j;
  };
  Candidate close[64];
  std::size_t n_close = 0;
  std::vector<Candidate> more;
  for (std::size_t i = 0; i < ga.parts.size(); ++i) {
    const BodyGeometry::Part& pa = ga.parts[i];
    const Eigen::Vector3d ca = poses.T_B_body[ia] * pa.centre;
    for (std::size_t j = 0; j < gb.parts.size(); ++j) {
      const BodyGeometry::Part& pb = gb.parts[j];
      const Eigen::Vector3d cb = poses.T_B_body[ib] * pb.centre;
      double lb = (ca - cb).norm() - pa.radius - pb.radius;
      if (lb < exact_below_mm) {
        // Each shape's sphere against the other's box: still a lower bound, often far tighter.
        lb = std::max(lb, sphere_to_box(cb, pb.radius, poses.T_B_body[ia] * pa.T_body_shape, pa));
        lb = std::max(lb, sphere_to_box(ca, pa.radius, poses.T_B_body[ib] * pb.T_body_shape, pb));
      }
      bound = std::min(bound, lb);
      if (lb < exact_below_mm) {
        if (n_close < 64)
          close[n_close++] = {lb, i, j};
        else
          more.push_back({lb, i, j});
      }
    }
  }
  if (bound >= exact_below_mm) {
    if (where)
      *where = Proximity{bound, poses.centre_B[ia], poses.centre_B[ib], false};
    return bound;
  }
  for (std::size_t k = 0; k < n_close; ++k)
    more.push_back(close[k]);
  std::sort(more.begin(), more.end(),
            [](const Candidate& x, const Candidate& y) { return x.bound < y.bound; });
  double best = std::numeric_limits<double>::infinity();
  fcl::DistanceRequestd request(where != nullptr);
  for (const Candidate& c : more) {
    if (c.bound >= best)
      break;
    const BodyGeometry::Part& pa = ga.parts[c.i];
    const BodyGeometry::Part& pb = gb.parts[c.j];
    const Isometry Ta = poses.T_B_body[ia] * pa.T_body_shape;
    const Isometry Tb = poses.T_B_body[ib] * pb.T_body_shape;
    fcl::DistanceResultd result;
    const double d = fcl::distance(pa.fcl.get(), Ta, pb.fcl.get(), Tb, request, result);
    if (d < best) {
      best = d;
      if (where) {
        *where = Proximity{d, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), true};
        nearest_points(result, pa, Ta, pb, Tb, where->point_a_B, where->point_b_B);
      }
    }
  }
  return best;
}

bool CollisionScene::inside(int pair, const ScenePoses& poses) const {
  const BodyPair& p = pairs_[static_cast<std::size_t>(pair)];
  for (int side = 0; side < 2; ++side) {
    const auto im = static_cast<std::size_t>(side == 0 ? p.a : p.b);
    const auto io = static_cast<std::size_t>(side == 0 ? p.b : p.a);
    for (const BodyGeometry::Part& m : geometry_[im]->parts) {
      if (!m.mesh || !m.closed)
        continue;
      const Isometry T_mesh_B = (poses.T_B_body[im] * m.T_body_shape).inverse();
      for (const BodyGeometry::Part& o : geometry_[io]->parts) {
        // A point of the other body: a primitive's centre, a mesh's first vertex.
        const Eigen::Vector3d local =
            o.mesh ? Eigen::Vector3d(o.T_body_shape * o.mesh->vertices.front())
                   : Eigen::Vector3d(o.T_body_shape.translation());
        const Eigen::Vector3d c = poses.T_B_body[io] * local;
        if (point_inside(*m.mesh, T_mesh_B * c))
          return true;
      }
    }
  }
  return false;
}

void CollisionScene::motion_bounds(const KinematicsData& data, const ScenePoses& poses,
                                   const JointVector& dq, std::vector<double>& from) const {
  const Cell& cell = *cell_;
  const int n = cell.size();
  from.assign(bodies_.size() * row_, 0.0);
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const std::vector<int>& movers = movers_[b];
    const Eigen::Vector3d& c = poses.centre_B[b];
    double* row = from.data() + b * row_;
    // From the last joint that moves the body to the first: D_k, the farthest any of its
    // points gets from axis k along the motion, is its distance now plus what the joints after
    // k move it (their contributions so far); joint k then moves it by |dq_k| D_k.
    double later = 0.0;
    int next = n;  // row entries from here on are filled
    for (auto it = movers.rbegin(); it != movers.rend(); ++it) {
      const int k = *it;
      for (int e = next - 1; e > k; --e)
        row[e] = later;
      next = k + 1;
      const double step = std::fabs(dq[k]);
      if (step > 0.0) {
        if (cell.joint(k).type == JointType::prismatic) {
          later += step;
        } else {
          const auto ku = static_cast<std::size_t>(k);
          const double from_axis = (c - data.p_B_joint[ku]).cross(data.z_B_joint[ku]).norm();
          later += step * (from_axis + radius_[b] + later);
        }
      }
      row[k] = later;
      next = k;
    }
    for (int e = next - 1; e >= 0; --e)
      row[e] = later;
  }
}

}  // namespace redpost
