// Fixtures and the part from STL files (setup.hpp).
#include "redpost/collision/setup.hpp"

namespace redpost {

namespace {

Body mesh_body(const std::string& path, BodyRole role, const Isometry& T_B_part) {
  const std::size_t slash = path.find_last_of('/');
  const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  Shape s;
  s.kind = ShapeKind::mesh;
  s.mesh = std::make_shared<TriangleMesh>(load_stl(path));
  s.T_frame_shape = T_B_part;
  Body b;
  b.name = std::string(to_string(role)) + " " + base;
  b.role = role;
  b.frame = kFrameBase;
  b.source = path;
  b.shapes.push_back(std::move(s));
  return b;
}

}  // namespace

std::vector<Body> setup_bodies(const SetupFiles& files, const Isometry& T_B_part) {
  std::vector<Body> out;
  for (const std::string& f : files.fixtures)
    out.push_back(mesh_body(f, BodyRole::fixture, T_B_part));
  if (!files.part.empty())
    out.push_back(mesh_body(files.part, BodyRole::part, T_B_part));
  return out;
}

}  // namespace redpost
