// The bodies that must not collide, as plain data (docs/collision.md): the cell's links, the
// tool's cutter, shank and holder, and the set-up's fixtures and part.
//
// A body is a list of convex primitives or triangle meshes, each with its pose in the frame the
// body moves with: the cell's {B} (the table top of the reference cell, where the part sits),
// the frame after one joint's link (as forward_kinematics() computes T_B_link), or the TCP of
// the tool in use. Lengths in mm.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "redpost/collision/stl.hpp"
#include "redpost/kinematics/types.hpp"

namespace redpost {

enum class ShapeKind {
  sphere,    // radius_mm about the shape frame's origin
  capsule,   // the segment from -length/2 to +length/2 on the shape frame's z, swept by radius
  cylinder,  // a solid cylinder on z from -length/2 to +length/2, radius_mm
  box,       // centred, edges size_mm along the shape frame's axes
  mesh,      // a triangle mesh (an STL), its vertices in the shape frame
};

const char* to_string(ShapeKind kind);

struct Shape {
  ShapeKind kind = ShapeKind::sphere;
  Isometry T_frame_shape = Isometry::Identity();  // the shape in its body's frame
  double radius_mm = 0.0;
  double length_mm = 0.0;
  Eigen::Vector3d size_mm = Eigen::Vector3d::Zero();
  std::shared_ptr<const TriangleMesh> mesh;
  int line = 0;  // where it is defined (cell file), 0 for made bodies

  // A sphere around the whole shape, in the body's frame: what the motion bound and the cheap
  // lower bound of a distance use.
  Eigen::Vector3d bound_centre() const;
  double bound_radius() const;
};

// Frames a body can move with besides a joint's (a joint's is its chain index, 0 .. n-1).
inline constexpr int kFrameBase = -1;  // the cell's {B}; the set-up bodies are placed in it
inline constexpr int kFrameTcp = -2;   // the TCP of the tool in use (the tool's bodies)

enum class BodyRole {
  cell,     // a link of the cell (its <collision> bodies)
  cutter,   // the tool's flute: the only body that may touch the part
  shank,    // the tool between the flute and the holder
  holder,   // the tool holder, up to the spindle's gauge line
  fixture,  // a clamp, a vise, a riser: nothing moving may come near it
  part,     // the finished part: only the cutter's flute may touch it
};

const char* to_string(BodyRole role);

struct Body {
  std::string name;  // "link_2", "spindle", "fixture vise.stl", "part", "holder"
  BodyRole role = BodyRole::cell;
  int frame = kFrameBase;
  std::vector<Shape> shapes;
  std::string source;  // the file that defines it
  int line = 0;

  bool is_tool() const {
    return role == BodyRole::cutter || role == BodyRole::shank || role == BodyRole::holder;
  }
  bool is_setup() const { return role == BodyRole::fixture || role == BodyRole::part; }
  // The body's bounding sphere in its frame: the union of its shapes' spheres.
  void bounding_sphere(Eigen::Vector3d& centre, double& radius) const;
};

}  // namespace redpost
