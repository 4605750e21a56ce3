#include "convert_report_scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "abi_internal.hpp"
#include "scene_cell.hpp"

namespace redpost::run_report {

namespace {

namespace rep = redpost::report;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// The band next to each limit where the tracker pushes a joint back (NullSpaceGains::limit_zone),
// as a percentage of the joint's range: the mark on the limit margin's colour bar.
constexpr double kLimitZonePercent = 10.0;

// The order of the values SceneTrace gives each motion.
enum Quantity { kCondition, kAxisSpeed, kLimitMargin, kDeflection, kQuantities };

std::vector<rep::SceneQuantity> quantities() {
  std::vector<rep::SceneQuantity> q(kQuantities);
  q[kCondition] = {"1/kappa_F", "", true, kNaN, "switch threshold"};
  q[kAxisSpeed] = {"fastest axis", "% of its speed limit", false, 100.0, "the limit"};
  q[kLimitMargin] = {"closest joint limit", "% of the joint's range", true, kLimitZonePercent,
                     "limit zone"};
  q[kDeflection] = {"deflection normal to the wall", "mm", false, kNaN, "tolerance"};
  return q;
}

// The collision check's bodies for the page (scene3d.hpp): each shape in its body's frame; a
// mesh of more than kSceneMaxMeshTriangles triangles as its box.
std::vector<rep::SceneBody> scene_bodies(const std::vector<Body>& bodies) {
  std::vector<rep::SceneBody> out;
  for (const Body& b : bodies) {
    rep::SceneBody sb;
    sb.name = b.name;
    sb.role = b.is_tool() ? "tool" : b.role == BodyRole::cell ? "cell" : to_string(b.role);
    sb.frame = b.frame == kFrameTcp ? -2 : b.frame;
    for (const Shape& s : b.shapes) {
      rep::SceneShape ss;
      ss.kind = to_string(s.kind);
      ss.T = from_isometry(s.T_frame_shape);
      ss.radius_mm = s.radius_mm;
      ss.length_mm = s.length_mm;
      ss.size_mm = {s.size_mm.x(), s.size_mm.y(), s.size_mm.z()};
      if (s.kind == ShapeKind::mesh && s.mesh) {
        if (s.mesh->triangles.size() <= rep::kSceneMaxMeshTriangles) {
          for (const Eigen::Vector3d& v : s.mesh->vertices) {
            for (int k = 0; k < 3; ++k)
              ss.vertices.push_back(static_cast<float>(v[k]));
          }
          for (const auto& t : s.mesh->triangles) {
            for (int k : t)
              ss.triangles.push_back(static_cast<std::uint32_t>(k));
          }
        } else {
          // Too large for the page: its box, in the mesh's frame.
          Eigen::Vector3d lo = s.mesh->vertices.front(), hi = lo;
          for (const Eigen::Vector3d& v : s.mesh->vertices) {
            lo = lo.cwiseMin(v);
            hi = hi.cwiseMax(v);
          }
          Isometry T = s.T_frame_shape;
          T.translation() += T.linear() * (0.5 * (lo + hi));
          ss.kind = "box";
          ss.T = from_isometry(T);
          ss.size_mm = {hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z()};
        }
      }
      sb.shapes.push_back(std::move(ss));
    }
    out.push_back(std::move(sb));
  }
  return out;
}

}  // namespace

SceneTrace::SceneTrace(const rp_session* session)
    : cell_(scene_cell_of(session)), recorder_(cell_, quantities()) {}

void SceneTrace::on_motion(const rp_motion& m) {
  // Called from the session's observer, which must not throw: a motion of another chain (which
  // the session never sends) is left out rather than refused.
  if (m.joint_count != static_cast<int>(cell_.links.size()))
    return;
  double values[kQuantities];
  values[kCondition] = m.inv_condition;
  conditioning_threshold_ = m.conditioning_threshold;
  // The fastest axis of the motion; none where no axis has a speed limit.
  double fastest = 0.0;
  for (int i = 0; i < m.joint_count && i < 16; ++i)
    fastest = std::max(fastest, m.speed_fraction[i]);
  values[kAxisSpeed] = fastest > 0.0 ? 100.0 * fastest : kNaN;
  // The joint closest to a limit, as a share of its range (virtual joints have no limit that
  // matters to the machine).
  double margin = kNaN;
  for (int i = 0; i < m.joint_count && i < static_cast<int>(cell_.links.size()); ++i) {
    const rep::SceneLink& l = cell_.links[static_cast<std::size_t>(i)];
    if (l.type == rep::SceneLink::Type::virtual_spin || !(l.upper > l.lower))
      continue;
    const double share =
        100.0 * std::min(m.joints[i] - l.lower, l.upper - m.joints[i]) / (l.upper - l.lower);
    margin = std::isnan(margin) ? share : std::min(margin, share);
  }
  values[kLimitMargin] = margin;
  values[kDeflection] = m.has_deflection ? std::fabs(m.deflection_normal_mm) : kNaN;

  rep::SceneMotion s;
  s.index = m.index;
  s.cl_line = m.line;
  s.q = m.joints;
  s.joint_count = m.joint_count;
  // A host built against an older rp_motion (struct_size) has no tool fields.
  const bool has_tool = m.struct_size >= offsetof(rp_motion, tcp_shift_mm) + sizeof(double);
  s.tool_length_mm = has_tool ? m.tool_length_mm : kNaN;
  s.tcp_shift_mm = has_tool ? m.tcp_shift_mm : 0.0;
  for (int k = 0; k < 3; ++k)
    s.tcp_part_mm[k] = m.tcp[k];
  s.values = values;
  recorder_.add(s);
}

void SceneTrace::add_section(rep::HtmlReport& r, const rp_session* session,
                             const ClearanceTrace::Closest* closest) const {
  if (recorder_.motions() == 0)
    return;
  rep::Scene3d scene = recorder_.scene();
  if (session->post)
    scene.bodies = scene_bodies(session->post->collision_bodies());
  if (closest && closest->exact) {
    scene.closest.shown = true;
    scene.closest.a = closest->a;
    scene.closest.b = closest->b;
    scene.closest.label = fmt::format("{:.1f} mm, {}, motion {} (CL line {})", closest->mm,
                                      closest->pair, closest->motion, closest->line);
  }
  rp_deflection_summary ds{};
  ds.struct_size = sizeof ds;
  const bool deflection =
      rp_deflection_summary_get(session, &ds) == RP_OK && ds.mode != RP_DEFLECTION_OFF;
  for (rep::SceneQuantity& q : scene.quantities) {
    if (q.name == "1/kappa_F")
      q.threshold = conditioning_threshold_;
    if (q.name == "deflection normal to the wall" && deflection)
      q.threshold = ds.tolerance_mm;
  }
  r.add_section("The cell in 3D");
  r.add_paragraph(
      "The cell drawn from its DH chain at the written joint values: the arm (orange), the "
      "track and the table (grey), the tool at the TCP in force, and the program's toolpath on "
      "the table. Move the slider or press Play to run the program; choose what colours the "
      "toolpath below the view.");
  r.add_scene3d(scene);
}

}  // namespace redpost::run_report
