// The cell's own bodies, from the <collision> element of its definition file
// (docs/cell-format.md, "<collision>"; docs/collision.md).
//
//   <collision>
//     <body name="table" link="base">           base: the cell's {B}; else a joint's name: the
//       <cylinder x1 y1 z1 x2 y2 z2 radius/>    frame after that joint's link (T_B_link)
//     </body>
//     <body name="link_2" link="theta_2">
//       <capsule x1 y1 z1 x2 y2 z2 radius/>     a segment swept by a sphere
//       <sphere x y z radius/>
//       <box x y z a b c dx dy dz/>             centre, KUKA A B C (deg), edge lengths
//       <mesh file="spindle.stl" x y z a b c/>  an STL (mm), beside the cell file
//       <convex x y z a b c>                    the convex hull of the points (or file="...stl":
//         <point x y z/> ...                    of its vertices), convex_hull.hpp
//       </convex>
//     </body>
//     <allow a="link_1" b="link_2"/>            never checked: they always touch
//   </collision>
//
// Lengths in mm, angles in degrees (units may be named, as everywhere in the file). A body
// moves with a physical link: one on the frame of a virtual joint (the tool's free spin), or of
// a joint after one, is refused, since its place would depend on a spin the robot never makes.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "redpost/collision/body.hpp"
#include "redpost/kinematics/cell.hpp"

namespace redpost {

struct CellBodies {
  std::vector<Body> bodies;
  // Pairs of bodies (indices into `bodies`) never checked against each other.
  std::vector<std::pair<int, int>> allowed;
  bool declared = false;  // the file has a <collision> element
};

// The bodies of the cell's definition file (cell.source_file). A cell without <collision> has
// none (declared false). Throws Error(bad_input) with file:line for every mistake.
CellBodies load_cell_bodies(const Cell& cell);

// The same from the text of the cell file; mesh files are looked up beside `source_name`.
CellBodies parse_cell_bodies(const Cell& cell, const std::string& xml_text,
                             const std::string& source_name);

}  // namespace redpost
