// The placement job file (placement_job.hpp): a strict reader of its XML, one function per
// section. docs/placement.md.
#include "redpost/machining/placement_job.hpp"

#include <tinyxml2.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <set>
#include <string_view>
#include <system_error>

#include <nlopt.h>

#include "machining/machining_xml.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/machining/elastostatic.hpp"

namespace redpost {

int PlacementJob::point_count() const {
  int n = 0;
  for (const ContourSegment& s : segments)
    n += s.points;
  return n;
}

namespace {

using tinyxml2::XMLElement;

using JobReader = detail::MachiningXml;

void check_algorithm(const JobReader& r, const XMLElement* e, const char* attr,
                     const std::string& name, bool global) {
  // Derivative-free algorithms with bound constraints only: the objective (a DP over a grid,
  // posture switches, a feasibility penalty) has no gradient.
  static const std::set<std::string> kGlobal = {"GN_CRS2_LM", "GN_ISRES",    "GN_ESCH",
                                                "GN_DIRECT",  "GN_DIRECT_L", "GN_DIRECT_L_RAND"};
  static const std::set<std::string> kLocal = {"LN_BOBYQA", "LN_COBYLA", "LN_NELDERMEAD",
                                               "LN_SBPLX"};
  const auto& allowed = global ? kGlobal : kLocal;
  if (allowed.count(name) && nlopt_algorithm_from_string(name.c_str()) >= 0)
    return;
  std::string list;
  for (const std::string& a : allowed)
    list += (list.empty() ? "" : ", ") + a;
  r.fail(e, std::string("<optimiser> attribute '") + attr + "' = \"" + name +
                "\": not a supported NLopt algorithm (use " + list + (global ? "" : ", none") +
                ")");
}

// <cell>: the cell file, relative to the job file; it must suit the placement.
void read_cell(const JobReader& r, const XMLElement* root, PlacementJob& job) {
  const XMLElement* ce = r.child(root, "cell", true);
  r.only_attributes(ce, {"file"});
  const std::filesystem::path rel = r.required(ce, "file");
  const std::filesystem::path base = std::filesystem::path(job.source_file).parent_path();
  job.cell_file = (rel.is_absolute() ? rel : base / rel).lexically_normal().string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(job.cell_file, ec)) {
    r.fail(ce, "the cell file '" + job.cell_file + "' does not exist (paths are relative to " +
                   "the job file)");
  }
  job.cell = load_cell(job.cell_file);
  try {
    compliant_joints(job.cell);
  } catch (const Error& e) {
    r.fail(ce, "the cell '" + job.cell_file + "' cannot be used for placement: " + e.message());
  }
  if (!job.cell.conditioning.declared() || job.cell.conditioning.count() != 6)
    r.fail(ce, "the cell '" + job.cell_file + "' needs a <conditioning> over its six arm joints");
  int spins = 0;
  for (int i = 0; i < job.cell.size(); ++i)
    spins += job.cell.joint(i).type == JointType::virtual_spin;
  // The spin turns the TCP about the tool axis: nothing may move the TCP after it, a tool frame
  // may only turn it (caro2014_kr270_table's turns z to point from the tip to the spindle).
  if (spins != 1 || job.cell.joint(job.cell.size() - 1).type != JointType::virtual_spin ||
      job.cell.T_last_tcp.translation().norm() > 1e-9) {
    r.fail(ce, "the cell '" + job.cell_file + "' must end with its tool spin beta as the " +
                   "last joint (virtual; a tool frame after it may only turn the TCP), as "
                   "caro2014_kr270_table does");
  }
}

// <tool>: the milling tool.
void read_tool(const JobReader& r, const XMLElement* root, PlacementJob& job) {
  const XMLElement* te = r.child(root, "tool", true);
  r.only_attributes(te, {"diameter", "teeth"});
  job.milling.tool_diameter_mm = r.positive(te, "diameter", r.length_mm(te, "diameter"));
  job.milling.teeth = r.integer(te, "teeth", 0, 1, 100);
  if (job.milling.teeth == 0)
    r.required(te, "teeth");
}

// <cutting>: the cutting conditions and the side of the material.
void read_cutting(const JobReader& r, const XMLElement* root, PlacementJob& job) {
  const XMLElement* cu = r.child(root, "cutting", true);
  r.only_attributes(cu, {"spindle_rpm", "feed", "fz", "ap", "kt", "kr", "material"});
  job.spindle_rpm = r.positive(cu, "spindle_rpm", r.plain(cu, "spindle_rpm", 0.0));
  job.feed_mm_per_min =
      r.positive(cu, "feed", r.number(cu, "feed", {{"mm/min", 1.0}, {"m/min", 1000.0}}));
  job.milling.fz_mm = r.positive(cu, "fz", r.length_mm(cu, "fz"));
  job.milling.ap_mm = r.positive(cu, "ap", r.length_mm(cu, "ap"));
  job.milling.Kt_N_per_mm2 = r.positive(cu, "kt", r.plain(cu, "kt", 0.0));
  job.milling.Kr = r.plain(cu, "kr", 0.0);
  if (!cu->Attribute("kr") || job.milling.Kr < 0.0)
    r.fail(cu, "<cutting> needs kr >= 0 (radial / tangential force ratio)");
  {
    const std::string side = r.required(cu, "material");
    if (side == "left")
      job.material_side = 1;
    else if (side == "right")
      job.material_side = -1;
    else
      r.fail(cu, "<cutting> material must be left or right (of the feed direction)");
  }
}

// <contour>: the start point and the segments of the planar contour, each checked as milling
// conditions.
void read_contour(const JobReader& r, const XMLElement* root, PlacementJob& job) {
  const XMLElement* co = r.child(root, "contour", true);
  r.only_attributes(co, {"points_per_segment", "mode"});
  r.only_children(co, {"start", "segment"});
  const int default_points = r.integer(co, "points_per_segment", 20, 2, 10000);
  const MillingMode default_mode = detail::parse_mode(r, co, MillingMode::down);
  const XMLElement* st = r.child(co, "start", true);
  if (st != co->FirstChildElement())
    r.fail(st, "<start> must be the first element of <contour>");
  r.only_attributes(st, {"name", "x", "y", "z"});
  std::string prev_name = r.required(st, "name");
  Eigen::Vector3d prev(r.length_mm(st, "x"), r.length_mm(st, "y"), r.length_mm(st, "z", 0.0));
  std::set<std::string> names = {prev_name};
  for (const XMLElement* s = co->FirstChildElement("segment"); s;
       s = s->NextSiblingElement("segment")) {
    r.only_attributes(s, {"to", "x", "y", "z", "ae", "mode", "points"});
    ContourSegment seg;
    const std::string to = r.required(s, "to");
    if (!names.insert(to).second)
      r.fail(s, "point name '" + to + "' used twice in <contour>");
    seg.name = prev_name + to;
    seg.from_W_mm = prev;
    seg.to_W_mm =
        Eigen::Vector3d(r.length_mm(s, "x"), r.length_mm(s, "y"), r.length_mm(s, "z", prev.z()));
    if (std::fabs(seg.to_W_mm.z() - prev.z()) > 1e-9)
      r.fail(s, "segment " + seg.name + " leaves the contour's plane z_W: the tool axis is z_W, " +
                    "so the contour must be planar");
    if ((seg.to_W_mm - seg.from_W_mm).norm() < 1.0)
      r.fail(s, "segment " + seg.name + " is shorter than 1 mm");
    seg.ae_mm = r.positive(s, "ae", r.length_mm(s, "ae"));
    if (seg.ae_mm > job.milling.tool_diameter_mm)
      r.fail(s, "segment " + seg.name + ": ae exceeds the tool diameter");
    seg.mode = detail::parse_mode(r, s, default_mode);
    seg.points = r.integer(s, "points", default_points, 2, 10000);
    seg.source_line = s->GetLineNum();
    job.segments.push_back(seg);
    prev = seg.to_W_mm;
    prev_name = to;
  }
  if (job.segments.empty())
    r.fail(co, "<contour> needs at least one <segment>");
  for (const ContourSegment& seg : job.segments) {
    MillingConditions c = job.milling;
    c.ae_mm = seg.ae_mm;
    c.mode = seg.mode;
    c.material_side = job.material_side;
    try {
      validate(c);
    } catch (const Error& e) {
      r.fail(seg.source_line, "segment " + seg.name + ": " + e.message());
    }
  }
}

// <work_volume>: the bounds of problem (5.17).
void read_work_volume(const JobReader& r, const XMLElement* root, PlacementJob& job) {
  const XMLElement* wv = r.child(root, "work_volume", true);
  r.only_attributes(wv, {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max", "q4_min", "q4_max"});
  WorkVolume& v = job.volume;
  v.x_min_mm = r.length_mm(wv, "x_min");
  v.x_max_mm = r.length_mm(wv, "x_max");
  v.y_min_mm = r.length_mm(wv, "y_min");
  v.y_max_mm = r.length_mm(wv, "y_max");
  v.z_min_mm = r.length_mm(wv, "z_min");
  v.z_max_mm = r.length_mm(wv, "z_max");
  v.q4_min = r.plain(wv, "q4_min", -1.0);
  v.q4_max = r.plain(wv, "q4_max", 1.0);
  auto check_range = [&](double lo, double hi, const char* what) {
    if (!(lo <= hi))
      r.fail(wv, std::string("<work_volume> ") + what + ": min is above max (impossible bounds)");
  };
  check_range(v.x_min_mm, v.x_max_mm, "x");
  check_range(v.y_min_mm, v.y_max_mm, "y");
  check_range(v.z_min_mm, v.z_max_mm, "z");
  check_range(v.q4_min, v.q4_max, "q4");
  if (v.q4_min < -1.0 || v.q4_max > 1.0)
    r.fail(wv, "<work_volume> q4 must lie in [-1, 1] (eq. 5.17)");
}

// <constraints> (optional): the constraints of problem (5.17).
void read_constraints(const JobReader& r, const XMLElement* root, PlacementJob& job) {
  if (const XMLElement* c = r.child(root, "constraints", false)) {
    r.only_attributes(c, {"c_max", "inv_kappa_min", "complementary"});
    job.constraints.c_max_mm =
        r.positive(c, "c_max", r.length_mm(c, "c_max", job.constraints.c_max_mm));
    job.constraints.inv_kappa_min = r.plain(c, "inv_kappa_min", job.constraints.inv_kappa_min);
    if (job.constraints.inv_kappa_min < 0.0 || job.constraints.inv_kappa_min >= 1.0)
      r.fail(c, "<constraints> inv_kappa_min must lie in [0, 1)");
    job.constraints.complementary = r.boolean(c, "complementary", false);
  }
}

// <spin> (optional): the spin grid of the inner problem.
void read_spin(const JobReader& r, const XMLElement* root, PlacementJob& job) {
  if (const XMLElement* s = r.child(root, "spin", false)) {
    r.only_attributes(s, {"step", "max_step", "max_joint_step"});
    SpinSettings& sp = job.spin;
    sp.step_rad = r.positive(s, "step", r.angle_rad(s, "step", sp.step_rad));
    sp.max_step_rad = r.angle_rad(s, "max_step", sp.max_step_rad);
    sp.max_joint_step_rad =
        r.positive(s, "max_joint_step", r.angle_rad(s, "max_joint_step", sp.max_joint_step_rad));
    const double steps = 2.0 * kPi / sp.step_rad;
    if (std::fabs(steps - std::round(steps)) > 1e-6 || std::round(steps) < 4 ||
        std::round(steps) > 3600)
      r.fail(s, "<spin> step must divide 360 deg into 4 to 3600 equal steps");
    if (sp.max_step_rad < 0.0)
      r.fail(s, "<spin> max_step must not be negative");
  }
}

// <optimiser> (optional): the NLopt algorithms and their budgets.
void read_optimiser(const JobReader& r, const XMLElement* root, PlacementJob& job) {
  if (const XMLElement* o = r.child(root, "optimiser", false)) {
    r.only_attributes(o, {"global", "global_evaluations", "population", "local",
                          "local_evaluations", "seed", "history_batch", "threads"});
    OptimiserSettings& op = job.optimiser;
    if (o->Attribute("global"))
      op.global_algorithm = o->Attribute("global");
    check_algorithm(r, o, "global", op.global_algorithm, true);
    op.global_evaluations = r.integer(o, "global_evaluations", op.global_evaluations, 1, 10000000);
    op.global_population = r.integer(o, "population", op.global_population, 0, 100000);
    if (o->Attribute("local"))
      op.local_algorithm = o->Attribute("local");
    if (op.local_algorithm == "none")
      op.local_algorithm.clear();
    if (!op.local_algorithm.empty())
      check_algorithm(r, o, "local", op.local_algorithm, false);
    op.local_evaluations = r.integer(o, "local_evaluations", op.local_evaluations, 0, 10000000);
    op.seed = static_cast<unsigned>(r.integer(o, "seed", static_cast<int>(op.seed), 0, 2147483647));
    op.history_batch = r.integer(o, "history_batch", op.history_batch, 1, 10000000);
    op.threads = r.integer(o, "threads", op.threads, 1, 2);
  }
}

// <program> (optional): the KRL program written for the placement.
void read_program(const JobReader& r, const XMLElement* root, PlacementJob& job) {
  if (const XMLElement* p = r.child(root, "program", false)) {
    r.only_attributes(p, {"name", "retract"});
    if (p->Attribute("name")) {
      job.program.name = p->Attribute("name");
      job.program.name_line = p->GetLineNum();
    }
    job.program.retract_mm = r.length_mm(p, "retract", job.program.retract_mm);
    if (job.program.retract_mm < 0.0)
      r.fail(p, "<program> retract must not be negative");
  }
}

}  // namespace

PlacementJob parse_placement_job(const std::string& xml_text, const std::string& source_name) {
  const JobReader r(source_name);
  tinyxml2::XMLDocument doc;
  const XMLElement* root = r.parse(doc, xml_text, "placement_job");
  r.only_attributes(root, {"format"});
  if (std::string(r.required(root, "format")) != "1")
    r.fail(root, "unsupported <placement_job> format (this redpost reads format=\"1\")");
  r.only_children(root, {"cell", "tool", "cutting", "contour", "work_volume", "constraints", "spin",
                         "optimiser", "program"});

  PlacementJob job;
  job.source_file = source_name;

  read_cell(r, root, job);
  read_tool(r, root, job);
  read_cutting(r, root, job);
  read_contour(r, root, job);
  read_work_volume(r, root, job);
  read_constraints(r, root, job);
  read_spin(r, root, job);
  read_optimiser(r, root, job);
  read_program(r, root, job);
  return job;
}

PlacementJob load_placement_job(const std::string& path) {
  return parse_placement_job(read_text_file(path), path);
}

}  // namespace redpost
