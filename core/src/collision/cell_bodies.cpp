// The <collision> element of a cell file (cell_bodies.hpp).
#include "redpost/collision/cell_bodies.hpp"

#include <tinyxml2.h>

#include <cmath>
#include <set>
#include <string_view>

#include "io/strict_xml.hpp"
#include "kinematics/definition_reader.hpp"
#include "redpost/collision/convex_hull.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"

namespace redpost {

namespace {

using detail::DefinitionReader;
using tinyxml2::XMLElement;

// Primitives larger than this are typos (a cell is a few metres across).
constexpr double kMaxShapeMm = 1e5;

std::string beside(const std::string& file, const std::string& name) {
  if (name.empty() || name.front() == '/')
    return name;
  const std::size_t slash = file.find_last_of('/');
  return slash == std::string::npos ? name : file.substr(0, slash + 1) + name;
}

double positive(const DefinitionReader& r, const XMLElement* e, const char* attr) {
  r.required(e, attr);
  const double v = r.length_mm(e, attr, 0.0);
  if (!(v > 0.0) || v > kMaxShapeMm) {
    r.fail(e, std::string("<") + e->Name() + "> " + attr + " must be > 0 and at most 100 m (" +
                  std::to_string(v) + " mm)");
  }
  return v;
}

Eigen::Vector3d point(const DefinitionReader& r, const XMLElement* e, const char* x, const char* y,
                      const char* z) {
  return {r.length_mm(e, x, 0.0), r.length_mm(e, y, 0.0), r.length_mm(e, z, 0.0)};
}

Isometry pose(const DefinitionReader& r, const XMLElement* e) {
  const KukaAbc abc{rad_to_deg(r.angle_rad(e, "a", 0.0)), rad_to_deg(r.angle_rad(e, "b", 0.0)),
                    rad_to_deg(r.angle_rad(e, "c", 0.0))};
  return frame_from_xyzabc(r.length_mm(e, "x", 0.0), r.length_mm(e, "y", 0.0),
                           r.length_mm(e, "z", 0.0), abc);
}

// A capsule or cylinder between two points: its frame on the segment's middle, z along it.
void between(const DefinitionReader& r, const XMLElement* e, Shape& s) {
  r.only_attributes(e, {"x1", "y1", "z1", "x2", "y2", "z2", "radius"});
  const Eigen::Vector3d p1 = point(r, e, "x1", "y1", "z1"), p2 = point(r, e, "x2", "y2", "z2");
  s.radius_mm = positive(r, e, "radius");
  s.length_mm = (p2 - p1).norm();
  if (s.kind == ShapeKind::cylinder && !(s.length_mm > 1e-6))
    r.fail(e, "<cylinder> from a point to the same point: give two different ends");
  const Eigen::Vector3d z =
      s.length_mm > 1e-9 ? Eigen::Vector3d((p2 - p1) / s.length_mm) : Eigen::Vector3d::UnitZ();
  s.T_frame_shape = Isometry::Identity();
  s.T_frame_shape.linear() =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), z).toRotationMatrix();
  s.T_frame_shape.translation() = 0.5 * (p1 + p2);
}

// <convex x y z a b c> around its <point x y z/> children, or <convex file="..."/> around an
// STL's vertices: the hull's closed mesh, which the scene makes one convex body.
void read_convex(const DefinitionReader& r, const XMLElement* e, Shape& s) {
  r.only_attributes(e, {"file", "x", "y", "z", "a", "b", "c"});
  s.kind = ShapeKind::mesh;
  s.T_frame_shape = pose(r, e);
  std::vector<Eigen::Vector3d> points;
  std::string what;
  if (e->Attribute("file")) {
    if (e->FirstChildElement())
      r.fail(e, "<convex> has a file and <point> elements: give one or the other");
    const std::string file = beside(r.source(), e->Attribute("file"));
    try {
      points = load_stl(file).vertices;
    } catch (const Error& err) {
      r.fail(e, "<convex file=\"" + std::string(e->Attribute("file")) +
                    "\">: " + format_error(err.where(), err.message()));
    }
    what = "<convex file=\"" + std::string(e->Attribute("file")) + "\">";
  } else {
    for (const XMLElement* p = e->FirstChildElement(); p; p = p->NextSiblingElement()) {
      if (std::string_view(p->Name()) != "point")
        r.fail(p, "unknown element <" + std::string(p->Name()) + "> in <convex> (known: point)");
      r.only_attributes(p, {"x", "y", "z"});
      for (const char* axis : {"x", "y", "z"})
        r.required(p, axis);
      points.push_back(point(r, p, "x", "y", "z"));
      if (points.back().cwiseAbs().maxCoeff() > kMaxShapeMm)
        r.fail(p, "<point> more than 100 m from its frame's origin: a typo, or metres for mm?");
    }
    what = "<convex>";
  }
  try {
    s.mesh = std::make_shared<TriangleMesh>(convex_hull(points, what));
  } catch (const Error& err) {
    r.fail(e, err.message());
  }
}

Shape read_shape(const DefinitionReader& r, const XMLElement* e) {
  Shape s;
  s.line = e->GetLineNum();
  const std::string_view n = e->Name();
  if (n == "sphere") {
    r.only_attributes(e, {"x", "y", "z", "radius"});
    s.kind = ShapeKind::sphere;
    s.T_frame_shape.translation() = point(r, e, "x", "y", "z");
    s.radius_mm = positive(r, e, "radius");
  } else if (n == "capsule" || n == "cylinder") {
    s.kind = n == "capsule" ? ShapeKind::capsule : ShapeKind::cylinder;
    between(r, e, s);
  } else if (n == "box") {
    r.only_attributes(e, {"x", "y", "z", "a", "b", "c", "dx", "dy", "dz"});
    s.kind = ShapeKind::box;
    s.T_frame_shape = pose(r, e);
    s.size_mm = {positive(r, e, "dx"), positive(r, e, "dy"), positive(r, e, "dz")};
  } else if (n == "mesh") {
    r.only_attributes(e, {"file", "x", "y", "z", "a", "b", "c"});
    s.kind = ShapeKind::mesh;
    s.T_frame_shape = pose(r, e);
    const std::string file = beside(r.source(), r.required(e, "file"));
    try {
      s.mesh = std::make_shared<TriangleMesh>(load_stl(file));
    } catch (const Error& err) {
      // The STL's own place first, then the line of the cell file that names it.
      r.fail(e, "<mesh file=\"" + std::string(e->Attribute("file")) +
                    "\">: " + format_error(err.where(), err.message()));
    }
  } else if (n == "convex") {
    read_convex(r, e, s);
  } else {
    r.fail(e, "unknown element <" + std::string(n) +
                  "> in <body> (known: sphere, capsule, cylinder, box, mesh, convex)");
  }
  return s;
}

// The frame a body's link attribute names: base or a joint before any virtual one.
int body_frame(const DefinitionReader& r, const XMLElement* e, const Cell& cell) {
  const std::string link = r.required(e, "link");
  if (link == "base")
    return kFrameBase;
  const int i = cell.find_joint(link);
  if (i < 0) {
    r.fail(e, "<body> link \"" + link +
                  "\": no joint of that name (use base or a joint's name: the frame after its "
                  "link)");
  }
  for (int k = 0; k <= i; ++k) {
    if (cell.joint(k).type == JointType::virtual_spin) {
      r.fail(e, "<body> link \"" + link + "\" moves with the virtual joint '" + cell.joint(k).name +
                    "' (the tool's free spin, which the robot never makes): attach the body to "
                    "the joint before it, with its pose in that frame");
    }
  }
  return i;
}

int body_index(const DefinitionReader& r, const XMLElement* e, const char* attr,
               const CellBodies& out) {
  const std::string name = r.required(e, attr);
  for (std::size_t b = 0; b < out.bodies.size(); ++b) {
    if (out.bodies[b].name == name)
      return static_cast<int>(b);
  }
  r.fail(e, "<allow> " + std::string(attr) + "=\"" + name +
                "\": no <body> of that name (an <allow> comes after the bodies it names)");
}

}  // namespace

CellBodies parse_cell_bodies(const Cell& cell, const std::string& xml_text,
                             const std::string& source_name) {
  DefinitionReader r(source_name);
  tinyxml2::XMLDocument doc;
  const XMLElement* root = r.parse(doc, xml_text, "cell");
  CellBodies out;
  const XMLElement* c = root->FirstChildElement("collision");
  if (!c)
    return out;
  out.declared = true;
  r.only_attributes(c, {});
  std::set<std::string> names;
  for (const XMLElement* e = c->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string_view n = e->Name();
    if (n == "body") {
      r.only_attributes(e, {"name", "link"});
      Body b;
      b.name = r.required(e, "name");
      if (b.name.empty())
        r.fail(e, "<body> name is empty");
      if (!names.insert(b.name).second)
        r.fail(e, "<body> name \"" + b.name + "\" used twice");
      b.frame = body_frame(r, e, cell);
      b.source = source_name;
      b.line = e->GetLineNum();
      for (const XMLElement* s = e->FirstChildElement(); s; s = s->NextSiblingElement())
        b.shapes.push_back(read_shape(r, s));
      if (b.shapes.empty())
        r.fail(e, "<body name=\"" + b.name + "\"> has no shape (sphere, capsule, ...)");
      out.bodies.push_back(std::move(b));
    } else if (n == "allow") {
      r.only_attributes(e, {"a", "b"});
      const int a = body_index(r, e, "a", out), b = body_index(r, e, "b", out);
      if (a == b)
        r.fail(e, "<allow> names the same body twice");
      out.allowed.emplace_back(std::min(a, b), std::max(a, b));
    } else {
      r.fail(e, "unknown element <" + std::string(n) + "> in <collision> (known: body, allow)");
    }
  }
  return out;
}

CellBodies load_cell_bodies(const Cell& cell) {
  if (cell.source_file.empty())
    return {};
  return parse_cell_bodies(cell, read_text_file(cell.source_file), cell.source_file);
}

}  // namespace redpost
