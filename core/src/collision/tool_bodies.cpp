// The tool's cylinders (tool_bodies.hpp).
#include "redpost/collision/tool_bodies.hpp"

#include <cmath>

namespace redpost {

namespace {

Body cylinder_body(const std::string& name, BodyRole role, double z0, double z1, double d) {
  Shape s;
  s.kind = ShapeKind::cylinder;
  s.radius_mm = 0.5 * d;
  s.length_mm = z1 - z0;
  s.T_frame_shape.translation() = Eigen::Vector3d(0.0, 0.0, 0.5 * (z0 + z1));
  Body b;
  b.name = name;
  b.role = role;
  b.frame = kFrameTcp;
  b.shapes.push_back(s);
  return b;
}

bool known(double v) {
  return std::isfinite(v) && v > 0.0;
}

}  // namespace

std::vector<Body> tool_bodies(const ToolGeometry& t, std::string* note) {
  std::vector<Body> out;
  const std::string who = t.name.empty() ? "the tool" : t.name;
  if (!known(t.diameter_mm)) {
    if (note)
      *note = who + " has no diameter: none of its bodies is checked";
    return out;
  }
  const bool holder = known(t.holder_diameter_mm) && known(t.holder_length_mm);
  const double holder_from =
      known(t.length_mm) ? t.length_mm - (holder ? t.holder_length_mm : 0.0) : 0.0;
  double flute = t.flute_length_mm;
  std::string missing;
  if (!known(flute)) {
    if (known(t.length_mm) && holder_from > 0.0) {
      flute = holder_from;
      missing =
          "no flute length: the whole tool below the holder is taken as cutter, which may "
          "touch the part";
    } else {
      flute = 3.0 * t.diameter_mm;
      missing = "no length or flute length: the cutter is taken three diameters long";
    }
  }
  out.push_back(cylinder_body(who + " cutter", BodyRole::cutter, 0.0, flute, t.diameter_mm));
  if (known(t.length_mm) && holder_from > flute + 1e-6) {
    const double d = known(t.shank_diameter_mm) ? t.shank_diameter_mm : t.diameter_mm;
    out.push_back(cylinder_body(who + " shank", BodyRole::shank, flute, holder_from, d));
  }
  if (holder && known(t.length_mm)) {
    out.push_back(cylinder_body(who + " holder", BodyRole::holder, holder_from, t.length_mm,
                                t.holder_diameter_mm));
  } else {
    missing += std::string(missing.empty() ? "" : "; ") + "no holder";
  }
  if (note && !missing.empty())
    *note = who + ": " + missing + " (docs/tools.md, \"Geometry\")";
  return out;
}

}  // namespace redpost
