// The convex hull of a point set, as a closed triangle mesh (qhull, Debian's libqhull-dev).
//
// What a cell's <convex> body is (docs/cell-format.md): a link, a spindle or a motor drawn as
// the hull of points measured on it or of an STL's vertices. The hull bounds every point, so a
// clearance to it is a clearance to whatever those points enclose; and a closed convex mesh is
// what the scene turns into one convex body for GJK (docs/collision.md), drawn as its triangles.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "redpost/collision/stl.hpp"

namespace redpost {

// The hull of `points` (mm): its vertices (a subset of the points), and triangles wound
// counter-clockwise seen from outside, every edge shared by two of them. Faces of more than
// three vertices (a box's sides) come as several triangles in one plane. `source` names the
// points in messages. Throws Error(bad_input) when the points span no volume (fewer than four,
// or all on one plane or line within 1e-9 of their extent), and for a non-finite coordinate.
TriangleMesh convex_hull(const std::vector<Eigen::Vector3d>& points, const std::string& source);

}  // namespace redpost
