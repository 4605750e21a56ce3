// The tool's bodies: cutter, shank and holder as cylinders stacked along the tool axis
// (docs/tools.md, "Geometry"; docs/collision.md).
//
// In the TCP frame of the tool, whose z axis points from the tip towards the spindle: the
// cutter from the tip (z = 0) up the flute, the shank from there to the holder, the holder up to
// the spindle's gauge line (z = length). Only the cutter's flute may touch the part.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "redpost/collision/body.hpp"

namespace redpost {

struct ToolGeometry {
  static constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
  double length_mm = kUnknown;  // from the gauge line to the tip
  double diameter_mm = kUnknown;
  double flute_length_mm = kUnknown;
  double shank_diameter_mm = kUnknown;  // NaN: the cutter's diameter
  double holder_diameter_mm = kUnknown;
  double holder_length_mm = kUnknown;  // down from the gauge line
  std::string name;                    // for the bodies' names ("tool 3")
};

// The cylinders of the tool, each a Body on kFrameTcp. What is unknown is left out, and `note`
// (if given) says what that leaves unchecked: without a diameter there is no body at all;
// without a flute length the whole tool below the holder is taken as cutter (the cutter may
// touch the part, so the shank is not kept clear of it); without a length and a flute length
// the cutter is taken three diameters long.
std::vector<Body> tool_bodies(const ToolGeometry& tool, std::string* note = nullptr);

}  // namespace redpost
