// The set-up's bodies: fixtures and the part, from STL files in the CL frame (docs/collision.md,
// "The set-up"). The CAM system exports them in the frame its toolpath is in, so they sit where
// the CL points do: placed in the cell's {B} by the same T_B_part.
#pragma once

#include <string>
#include <vector>

#include "redpost/collision/body.hpp"

namespace redpost {

struct SetupFiles {
  std::vector<std::string> fixtures;  // no moving body may come near a fixture
  std::string part;                   // "": none; only the cutter's flute may touch the part
};

// One body per file, on kFrameBase, its mesh placed by T_B_part; named "fixture NAME.stl" and
// "part NAME.stl". Throws Error (io, bad_input) with the file and line or byte offset.
std::vector<Body> setup_bodies(const SetupFiles& files, const Isometry& T_B_part);

}  // namespace redpost
