#include "redpost/kinematics/cell_xml.hpp"

#include <tinyxml2.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <system_error>
#include <vector>

#include "io/strict_xml.hpp"
#include "kinematics/definition_reader.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/kinematics/kuka_abc.hpp"

namespace redpost {

namespace {

using tinyxml2::XMLElement;

using Reader = detail::DefinitionReader;
using detail::kMaxAngleDeg;
using detail::kMaxLengthMm;
constexpr double kMaxStiffness = 1e15;  // N*mm/rad
constexpr double kMaxToolLengthMm = 2000.0;

JointType parse_type(const Reader& r, const XMLElement* e) {
  const std::string t = r.required(e, "type");
  if (t == "revolute")
    return JointType::revolute;
  if (t == "prismatic")
    return JointType::prismatic;
  if (t == "virtual")
    return JointType::virtual_spin;
  r.fail(e, "unknown joint type '" + t + "' (use revolute, prismatic or virtual)");
}

DhConvention parse_convention(const Reader& r, const XMLElement* e, const char* attr,
                              DhConvention fallback) {
  const char* t = e->Attribute(attr);
  if (!t)
    return fallback;
  const std::string v = t;
  if (v == "standard")
    return DhConvention::standard;
  if (v == "modified")
    return DhConvention::modified;
  r.fail(e, "unknown DH convention '" + v + "' (use standard or modified)");
}

ControllerAxis parse_axis(const Reader& r, const XMLElement* e, const Joint& j) {
  r.only_attributes(e, {"name", "sign", "offset"});
  ControllerAxis axis;
  const std::string name = r.required(e, "name");
  if (name == "none") {
    if (e->Attribute("sign") || e->Attribute("offset")) {
      r.fail(e, "an <axis name=\"none\"> takes no sign or offset");
    }
    return axis;
  }
  if (name.size() != 2 || (name[0] != 'A' && name[0] != 'E') || name[1] < '1' || name[1] > '6') {
    r.fail(e, "unknown controller axis '" + name + "' (use A1..A6, E1..E6 or none)");
  }
  if (j.type == JointType::virtual_spin) {
    r.fail(e, "joint '" + j.name + "' is virtual (the tool's free spin) and cannot drive axis " +
                  name + "; use <axis name=\"none\"/> or leave it out");
  }
  axis.kind = name[0] == 'A' ? AxisKind::arm : AxisKind::external;
  axis.number = name[1] - '0';
  if (e->Attribute("sign")) {
    const double s = r.plain(e, "sign", 1e9);
    if (s != 1.0 && s != -1.0)
      r.fail(e, "<axis> sign must be 1 or -1");
    axis.sign = s;
  }
  // The offset is in controller units: deg for a revolute joint, mm for a prismatic one.
  if (e->Attribute("offset")) {
    axis.offset = j.type == JointType::prismatic ? r.length_mm(e, "offset", 0.0)
                                                 : rad_to_deg(r.angle_rad(e, "offset", 0.0));
  }
  return axis;
}

// Reads a joint value given in DH units (default) or controller-axis units (in="axis").
double joint_value(const Reader& r, const XMLElement* e, const char* attr, const Joint& j,
                   bool in_axis_units) {
  if (!e->Attribute(attr))
    r.required(e, attr);
  if (j.type == JointType::prismatic) {
    const double v = r.length_mm(e, attr, 0.0);
    return in_axis_units ? from_axis_value(j, v) : v;
  }
  const double v = r.angle_rad(e, attr, 0.0);
  return in_axis_units ? from_axis_value(j, rad_to_deg(v)) : v;
}

bool axis_units(const Reader& r, const XMLElement* e) {
  const char* t = e->Attribute("in");
  if (!t)
    return false;
  const std::string v = t;
  if (v == "dh")
    return false;
  if (v == "axis")
    return true;
  r.fail(e, "<" + std::string(e->Name()) + "> in=\"" + v + "\": use in=\"dh\" or in=\"axis\"");
}

std::string unit_of(const Joint& j) {
  return j.type == JointType::prismatic ? "mm" : "deg";
}
double show(const Joint& j, double v) {
  return j.type == JointType::prismatic ? v : rad_to_deg(v);
}
std::string fmt_num(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

// <speed velocity=".." acceleration=".."/>: the axis's largest speed and acceleration, in
// controller units (deg/s and deg/s^2 for a revolute joint, mm/s and mm/s^2 for a prismatic
// one; rad and m units may be named). Both are needed: the time model and the plan use both.
void read_speed(const Reader& r, const XMLElement* e, Joint& j) {
  r.only_attributes(e, {"velocity", "acceleration"});
  if (j.type == JointType::virtual_spin) {
    r.fail(e, "joint '" + j.name +
                  "' is virtual (the tool's free spin): it drives no axis and has no <speed>");
  }
  r.required(e, "velocity");
  r.required(e, "acceleration");
  const bool prismatic = j.type == JointType::prismatic;
  // Bounds far beyond any machine: a typo (an extra zero is fine, three are not meant).
  const double v = prismatic ? r.number(e, "velocity", e->Attribute("velocity"),
                                        {{"mm/s", 1.0}, {"m/s", 1000.0}}, 1e5)
                             : r.number(e, "velocity", e->Attribute("velocity"),
                                        {{"deg/s", kPi / 180.0}, {"rad/s", 1.0}}, deg_to_rad(1e5));
  const double a = prismatic
                       ? r.number(e, "acceleration", e->Attribute("acceleration"),
                                  {{"mm/s2", 1.0}, {"m/s2", 1000.0}}, 1e6)
                       : r.number(e, "acceleration", e->Attribute("acceleration"),
                                  {{"deg/s2", kPi / 180.0}, {"rad/s2", 1.0}}, deg_to_rad(1e6));
  if (!(v > 0.0))
    r.fail(e, "the velocity of joint '" + j.name + "' must be > 0");
  if (!(a > 0.0))
    r.fail(e, "the acceleration of joint '" + j.name + "' must be > 0");
  j.max_velocity = v;
  j.max_acceleration = a;
}

Joint parse_joint(const Reader& r, const XMLElement* e, DhConvention cell_convention) {
  r.only_attributes(e, {"name", "type", "dh"});
  Joint j;
  j.source_line = e->GetLineNum();
  j.name = r.required(e, "name");
  if (j.name.empty())
    r.fail(e, "a joint needs a non-empty name");
  j.type = parse_type(r, e);
  j.convention = parse_convention(r, e, "dh", cell_convention);

  for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const std::string n = c->Name();
    if (n != "dh" && n != "limits" && n != "home" && n != "weight" && n != "axis" &&
        n != "stiffness" && n != "speed") {
      r.fail(c, "unknown element <" + n + "> in joint '" + j.name +
                    "' (known: dh, limits, home, weight, axis, stiffness, speed)");
    }
  }

  const XMLElement* dh = r.child(e, "dh", true);
  r.only_attributes(dh, {"alpha", "a", "theta", "d"});
  for (const char* attr : {"alpha", "a", "theta", "d"})
    r.required(dh, attr);
  j.alpha_rad = r.angle_rad(dh, "alpha", 0.0);
  j.a_mm = r.length_mm(dh, "a", 0.0);
  j.theta_rad = r.angle_rad(dh, "theta", 0.0);
  j.d_mm = r.length_mm(dh, "d", 0.0);

  // The axis mapping comes first: limits and home may be given in controller units.
  if (const XMLElement* a = r.child(e, "axis", false))
    j.axis = parse_axis(r, a, j);

  const XMLElement* lim = r.child(e, "limits", true);
  r.only_attributes(lim, {"min", "max", "in"});
  const bool lim_axis = axis_units(r, lim);
  double lo = joint_value(r, lim, "min", j, lim_axis);
  double hi = joint_value(r, lim, "max", j, lim_axis);
  if (lim_axis && j.axis.sign < 0)
    std::swap(lo, hi);  // a sign flip swaps the ends
  if (lo > hi) {
    r.fail(lim, "<limits> of joint '" + j.name + "': min " + fmt_num(show(j, lo)) + " > max " +
                    fmt_num(show(j, hi)) + " " + unit_of(j) + " (DH units)");
  }
  j.lower = lo;
  j.upper = hi;

  const XMLElement* home = r.child(e, "home", true);
  r.only_attributes(home, {"value", "in"});
  j.home = joint_value(r, home, "value", j, axis_units(r, home));
  if (j.home < j.lower || j.home > j.upper) {
    r.fail(home, "home of joint '" + j.name + "' is " + fmt_num(show(j, j.home)) + " " +
                     unit_of(j) + ", outside its limits [" + fmt_num(show(j, j.lower)) + ", " +
                     fmt_num(show(j, j.upper)) + "] (DH units)");
  }

  if (const XMLElement* w = r.child(e, "weight", false)) {
    r.only_attributes(w, {"value"});
    j.weight = r.plain(w, "value", 1e12);
    if (!(j.weight > 0.0))
      r.fail(w, "the weight of joint '" + j.name + "' must be > 0");
  }

  if (const XMLElement* sp = r.child(e, "speed", false))
    read_speed(r, sp, j);

  if (const XMLElement* s = r.child(e, "stiffness", false)) {
    r.only_attributes(s, {"value", "unit"});
    const std::string unit = s->Attribute("unit") ? s->Attribute("unit") : "";
    double factor = 0.0;
    if (j.type == JointType::prismatic) {
      if (unit == "N/mm" || unit.empty())
        factor = 1.0;
      if (unit == "N/m")
        factor = 1e-3;
    } else {
      // Internal unit: N*mm/rad.
      if (unit == "Nm/rad" || unit.empty())
        factor = 1e3;
      if (unit == "kNm/rad")
        factor = 1e6;
      if (unit == "MNm/rad")
        factor = 1e9;
    }
    if (factor == 0.0) {
      r.fail(s, "unknown stiffness unit '" + unit + "' for a " +
                    (j.type == JointType::prismatic ? "prismatic joint (use N/mm or N/m)"
                                                    : "rotary joint (use Nm/rad, kNm/rad or "
                                                      "MNm/rad)"));
    }
    const double k = r.plain(s, "value", 1e300) * factor;
    if (k > kMaxStiffness) {
      r.fail(s, "the stiffness of joint '" + j.name + "' has a magnitude too large to be meant");
    }
    if (!(k > 0.0))
      r.fail(s, "the stiffness of joint '" + j.name + "' must be > 0");
    j.stiffness = k;
  }
  return j;
}

// A whole number attribute in [lo, hi].
int whole(const Reader& r, const XMLElement* e, const char* attr, int lo, int hi) {
  const double v = r.plain(e, attr, 1e9);
  if (v != std::floor(v) || v < lo || v > hi) {
    r.fail(e, std::string("<") + e->Name() + "> attribute '" + attr +
                  "' must be a whole number "
                  "from " +
                  std::to_string(lo) + " to " + std::to_string(hi) + ", got " +
                  r.required(e, attr));
  }
  return static_cast<int>(v);
}

// A KRL name: a letter, then letters, digits and '_', at most 24 characters.
bool krl_name(const std::string& s) {
  if (s.empty() || s.size() > 24 || !std::isalpha(static_cast<unsigned char>(s[0])))
    return false;
  for (char c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_')
      return false;
  }
  return true;
}

// The optional geometry of a <tool> (docs/tools.md, "Geometry"): every length > 0 and at most
// the limits below; the flute and the holder fit within the tool's length together.
void read_tool_geometry(const Reader& r, const XMLElement* t, ToolEntry& entry) {
  const auto read = [&](const char* attr, double max_mm, double& out) {
    if (!t->Attribute(attr))
      return;
    out = r.length_mm(t, attr, 0.0);
    if (!(out > 0.0) || out > max_mm) {
      r.fail(t, "tool " + std::to_string(entry.number) + ": " + attr + " must be > 0 and at most " +
                    fmt_num(max_mm) + " mm");
    }
  };
  read("diameter", 500.0, entry.diameter_mm);
  read("flute-length", kMaxToolLengthMm, entry.flute_length_mm);
  read("shank-diameter", 500.0, entry.shank_diameter_mm);
  read("holder-diameter", 1000.0, entry.holder_diameter_mm);
  read("holder-length", kMaxToolLengthMm, entry.holder_length_mm);
  const bool holder = t->Attribute("holder-diameter") || t->Attribute("holder-length");
  if (holder && !(t->Attribute("holder-diameter") && t->Attribute("holder-length")))
    r.fail(t, "tool " + std::to_string(entry.number) +
                  ": a holder needs both holder-diameter and holder-length");
  const double flute = std::isnan(entry.flute_length_mm) ? 0.0 : entry.flute_length_mm;
  const double held = std::isnan(entry.holder_length_mm) ? 0.0 : entry.holder_length_mm;
  if (flute + held > entry.length_mm + 1e-9) {
    r.fail(t, "tool " + std::to_string(entry.number) + ": flute-length " + fmt_num(flute) +
                  " mm and holder-length " + fmt_num(held) + " mm do not fit in its length " +
                  fmt_num(entry.length_mm) + " mm (from the gauge line to the tip)");
  }
  if ((t->Attribute("flute-length") || t->Attribute("shank-diameter")) && !t->Attribute("diameter"))
    r.fail(t, "tool " + std::to_string(entry.number) +
                  ": flute-length and shank-diameter need the cutter's diameter");
}

// <tool-table>: in a cell (with its reference-length) or as a file's root (entries only).
ToolTable read_tool_table(const Reader& r, const XMLElement* e, bool in_cell) {
  r.only_attributes(e, in_cell ? std::initializer_list<std::string_view>{"reference-length"}
                               : std::initializer_list<std::string_view>{});
  ToolTable table;
  table.source = r.source();
  if (in_cell && e->Attribute("reference-length")) {
    table.reference_length_mm = r.length_mm(e, "reference-length", 0.0);
    if (!(table.reference_length_mm > 0.0) || table.reference_length_mm > kMaxToolLengthMm) {
      r.fail(e, "<tool-table> reference-length must be > 0 and at most 2000 mm");
    }
  }
  for (const XMLElement* t = e->FirstChildElement(); t; t = t->NextSiblingElement()) {
    if (std::string_view(t->Name()) != "tool")
      r.fail(t, std::string("unknown element <") + t->Name() + "> in <tool-table> (known: tool)");
    r.only_attributes(t, {"number", "data", "load-data", "length", "name", "diameter",
                          "flute-length", "shank-diameter", "holder-diameter", "holder-length"});
    ToolEntry entry;
    entry.line = t->GetLineNum();
    entry.number = whole(r, t, "number", 0, 1000000);
    entry.tool_data = whole(r, t, "data", 1, kMaxToolData);
    if (t->Attribute("load-data"))
      entry.load_data = whole(r, t, "load-data", 1, kMaxLoadData);
    r.required(t, "length");
    entry.length_mm = r.length_mm(t, "length", 0.0);
    if (!(entry.length_mm > 0.0) || entry.length_mm > kMaxToolLengthMm)
      r.fail(t,
             "tool " + std::to_string(entry.number) + ": length must be > 0 and at most 2000 mm");
    if (const char* n = t->Attribute("name"))
      entry.name = n;
    read_tool_geometry(r, t, entry);
    for (const ToolEntry& other : table.tools) {
      if (other.number == entry.number) {
        r.fail(t, "tool " + std::to_string(entry.number) + " is given twice (first at line " +
                      std::to_string(other.line) + ")");
      }
    }
    table.tools.push_back(std::move(entry));
  }
  return table;
}

// <controller>: the base's kinematic coupling, the tool change routine (docs/cell-format.md).
ControllerSettings read_controller(const Reader& r, const XMLElement* e, const Cell& cell) {
  r.only_attributes(e, {"base-data", "load-data", "tool-change-routine"});
  ControllerSettings c;
  if (e->Attribute("base-data"))
    c.base_data = whole(r, e, "base-data", 1, 32);
  if (e->Attribute("load-data"))
    c.load_data = whole(r, e, "load-data", 1, kMaxLoadData);
  if (const char* routine = e->Attribute("tool-change-routine")) {
    c.tool_change_routine = routine;
    if (!krl_name(c.tool_change_routine)) {
      r.fail(e, "tool-change-routine \"" + c.tool_change_routine +
                    "\" is not a KRL name (a letter, then letters, digits and _, at most 24)");
    }
  }
  for (const XMLElement* k = e->FirstChildElement(); k; k = k->NextSiblingElement()) {
    if (std::string_view(k->Name()) != "kinematic")
      r.fail(k,
             std::string("unknown element <") + k->Name() + "> in <controller> (known: kinematic)");
    r.only_attributes(k, {"axis", "type", "machine-def", "ex-ax-data"});
    const std::string axis = r.required(k, "axis"), type = r.required(k, "type");
    int joint = -1;
    for (int i = 0; i < cell.size(); ++i) {
      if (cell.joint(i).axis.kind == AxisKind::external && axis_name(cell.joint(i).axis) == axis)
        joint = i;
    }
    if (joint < 0)
      r.fail(k,
             "<kinematic axis=\"" + axis + "\">: no joint of the cell drives that external axis");
    if (type == "base") {
      if (c.coupled_base_joint >= 0)
        r.fail(k, "two base kinematics: the base can turn with one only");
      c.coupled_base_joint = joint;
      c.machine_def = k->Attribute("machine-def") ? whole(r, k, "machine-def", 2, 64) : 2;
      c.ex_ax_data = k->Attribute("ex-ax-data") ? whole(r, k, "ex-ax-data", 1, 6) : 1;
    } else if (type == "robroot") {
      if (c.robroot_joint >= 0)
        r.fail(k, "two ROBROOT kinematics");
      if (k->Attribute("machine-def") || k->Attribute("ex-ax-data"))
        r.fail(k, "machine-def and ex-ax-data belong to a base kinematic");
      c.robroot_joint = joint;
    } else {
      r.fail(k, "<kinematic> type \"" + type + "\" is unknown (base or robroot)");
    }
  }
  return c;
}

// Speeds are all or nothing: the time model and the plan need every axis's limits, and a cell
// that gives some but forgets one is a mistake to name, not a limit to guess.
void check_speeds(const Reader& r, const XMLElement* root, const Cell& cell) {
  int with = -1, without = -1;
  for (int i = 0; i < cell.joint_count; ++i) {
    const Joint& j = cell.joint(i);
    if (j.type == JointType::virtual_spin)
      continue;
    if (j.has_speed() && with < 0)
      with = i;
    if (!j.has_speed() && without < 0)
      without = i;
  }
  if (with < 0 || without < 0)
    return;
  const Joint& missing = cell.joint(without);
  const std::string axis = missing.axis.mapped() ? " (" + axis_name(missing.axis) + ")" : "";
  std::string msg = "joint '" + missing.name + "'" + axis + " has no <speed> while joint '" +
                    cell.joint(with).name +
                    "' has one: give every axis its velocity and acceleration (<speed "
                    "velocity=\"..\" acceleration=\"..\"/>, docs/cell-format.md), or none";
  // The joint's own line: find its element again.
  for (const XMLElement* e = root->FirstChildElement("joint"); e;
       e = e->NextSiblingElement("joint")) {
    if (e->GetLineNum() == missing.source_line)
      r.fail(e, msg);
  }
  r.fail(root, msg);
}

}  // namespace

ToolTable parse_tool_table(const std::string& xml_text, const std::string& source_name) {
  Reader r(source_name);
  tinyxml2::XMLDocument doc;
  const XMLElement* root = r.parse(doc, xml_text, "tool-table");
  if (root->Attribute("reference-length")) {
    r.fail(root,
           "reference-length belongs in the cell file: it is the tool length of the "
           "cell's TCP");
  }
  return read_tool_table(r, root, false);
}

ToolTable load_tool_table(const std::string& path) {
  return parse_tool_table(read_text_file(path), path);
}

Cell parse_cell(const std::string& xml_text, const std::string& source_name) {
  Reader r(source_name);
  tinyxml2::XMLDocument doc;
  const XMLElement* root = r.parse(doc, xml_text, "cell");
  r.only_attributes(root, {"name", "format", "dh"});
  if (const char* f = root->Attribute("format"); f && std::string(f) != "1") {
    r.fail(root, std::string("unsupported cell format \"") + f + "\" (this redpost reads 1)");
  }

  Cell cell;
  cell.source_file = source_name;
  cell.name = r.required(root, "name");
  const DhConvention convention = parse_convention(r, root, "dh", DhConvention::standard);

  Isometry pending = Isometry::Identity();  // <fixed> frames waiting for the next joint
  bool have_pending = false;
  bool seen_tool = false, seen_base = false, seen_cond = false;
  const XMLElement* cond = nullptr;
  const XMLElement* controller = nullptr;
  const XMLElement* tool_table = nullptr;
  const XMLElement* collision = nullptr;
  std::set<std::string> names;
  std::map<std::string, std::string> axis_owner;  // axis name -> joint

  for (const XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string n = e->Name();
    if (seen_tool && (n == "joint" || n == "fixed")) {
      r.fail(e, "<" + n + "> after <tool>: the tool frame ends the chain");
    }
    if (n == "base") {
      if (seen_base || cell.joint_count > 0 || have_pending) {
        r.fail(e, "<base> must come once, before the first joint");
      }
      seen_base = true;
      cell.T_B_0 = r.frame(e);
    } else if (n == "joint") {
      if (cell.joint_count == kMaxJoints) {
        r.fail(e, "too many joints: redpost handles at most " + std::to_string(kMaxJoints));
      }
      Joint j = parse_joint(r, e, convention);
      if (!names.insert(j.name).second)
        r.fail(e, "joint name '" + j.name + "' used twice");
      if (j.axis.mapped()) {
        const auto [owner, fresh] = axis_owner.emplace(axis_name(j.axis), j.name);
        if (!fresh) {
          r.fail(e->FirstChildElement("axis"), "controller axis " + axis_name(j.axis) +
                                                   " is mapped to two joints, '" + owner->second +
                                                   "' and '" + j.name + "'");
        }
      }
      j.T_prev_link = pending;
      j.has_fixed_before = have_pending;
      pending = Isometry::Identity();
      have_pending = false;
      cell.joints[static_cast<size_t>(cell.joint_count++)] = std::move(j);
    } else if (n == "fixed") {
      pending = pending * r.frame(e);
      have_pending = true;
    } else if (n == "tool") {
      seen_tool = true;
      pending = pending * r.frame(e);
      have_pending = true;
    } else if (n == "conditioning") {
      if (seen_cond)
        r.fail(e, "<conditioning> given twice");
      seen_cond = true;
      cond = e;
    } else if (n == "controller") {
      if (controller)
        r.fail(e, "<controller> given twice");
      controller = e;
    } else if (n == "tool-table") {
      if (tool_table)
        r.fail(e, "<tool-table> given twice");
      tool_table = e;
    } else if (n == "collision") {
      // The cell's bodies: read by collision/cell_bodies.hpp, which knows their form.
      if (collision)
        r.fail(e, "<collision> given twice");
      collision = e;
    } else {
      r.fail(e, "unknown element <" + n +
                    "> in <cell> (known: base, joint, fixed, tool, conditioning, controller, "
                    "tool-table, collision)");
    }
  }
  if (cell.joint_count == 0)
    r.fail(root, "the cell has no <joint>");
  check_speeds(r, root, cell);
  cell.T_last_tcp = pending;

  if (cond) {
    r.only_attributes(cond, {"first", "last", "length"});
    const std::string first = r.required(cond, "first"), last = r.required(cond, "last");
    cell.conditioning.first = cell.find_joint(first);
    cell.conditioning.last = cell.find_joint(last);
    if (cell.conditioning.first < 0)
      r.fail(cond, "<conditioning> first: no joint '" + first + "'");
    if (cell.conditioning.last < 0)
      r.fail(cond, "<conditioning> last: no joint '" + last + "'");
    if (cell.conditioning.last < cell.conditioning.first) {
      r.fail(cond, "<conditioning> first joint '" + first + "' comes after last joint '" + last +
                       "' in the chain");
    }
    if (cell.conditioning.count() < 6) {
      r.fail(cond, "<conditioning> must span at least 6 joints (from '" + first + "' to '" + last +
                       "' is " + std::to_string(cell.conditioning.count()) + ")");
    }
    r.required(cond, "length");
    cell.conditioning.characteristic_length_mm = r.length_mm(cond, "length", 0.0);
    if (!(cell.conditioning.characteristic_length_mm > 0.0)) {
      r.fail(cond, "<conditioning> length must be > 0 mm");
    }
  }
  if (controller)
    cell.controller = read_controller(r, controller, cell);
  if (tool_table)
    cell.tools = read_tool_table(r, tool_table, true);
  finalize_cell(cell);
  return cell;
}

Cell load_cell(const std::string& path) {
  return parse_cell(read_text_file(path), path);
}

}  // namespace redpost
