// The cutting file (cutting_conditions.hpp): a strict reader of its XML, and the milling
// conditions of one move from an entry and what the CL file says. docs/deflection.md.
#include "redpost/machining/cutting_conditions.hpp"

#include <tinyxml2.h>

#include <cmath>
#include <set>

#include <fmt/format.h>

#include "machining/machining_xml.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"

namespace redpost {

namespace {

using detail::MachiningXml;
using tinyxml2::XMLElement;

// Bounds a value must meet to be meant: beyond them it is a typo or a unit slip.
constexpr double kMaxKt_N_per_mm2 = 20000.0;  // hardened steel is about 4000
constexpr double kMaxKr = 10.0;
constexpr double kMaxToolMm = 1000.0;
constexpr double kMaxRpm = 200000.0;

void bounded(const MachiningXml& r, const XMLElement* e, const char* attr, double v, double lo,
             double hi, bool lo_open) {
  if ((lo_open ? !(v > lo) : !(v >= lo)) || !(v <= hi)) {
    r.fail(e,
           fmt::format("<{}> attribute '{}' = \"{}\": must be {} {:g} and at most {:g}", e->Name(),
                       attr, e->Attribute(attr), lo_open ? "above" : "at least", lo, hi));
  }
}

// ae or ap: "5" or "5mm" (mm), "0.005m", or "50%" of the tool's diameter.
void engagement(const MachiningXml& r, const XMLElement* e, const char* attr, double& mm,
                double& fraction, double max_fraction) {
  const char* text = e->Attribute(attr);
  if (!text)
    return;
  const std::string t = text;
  if (t.find('%') != std::string::npos) {
    fraction = r.number(e, attr, {{"%", 0.01}});
    bounded(r, e, attr, fraction, 0.0, max_fraction, true);
    mm = std::numeric_limits<double>::quiet_NaN();
  } else {
    mm = r.length_mm(e, attr);
    bounded(r, e, attr, mm, 0.0, kMaxToolMm, true);
  }
}

// The attributes of <defaults> and <operation>: each one given overrides `c`.
void read_conditions(const MachiningXml& r, const XMLElement* e, CuttingConditions& c) {
  c.source_line = e->GetLineNum();
  c.teeth = r.integer(e, "teeth", c.teeth, 1, 100);
  engagement(r, e, "ae", c.ae_mm, c.ae_fraction, 1.0);
  engagement(r, e, "ap", c.ap_mm, c.ap_fraction, 10.0);
  if (e->Attribute("kt")) {
    c.Kt_N_per_mm2 = r.number(e, "kt", {{"", 1.0}, {"N/mm2", 1.0}});
    bounded(r, e, "kt", c.Kt_N_per_mm2, 0.0, kMaxKt_N_per_mm2, true);
  }
  if (e->Attribute("kr")) {
    c.Kr = r.plain(e, "kr", 0.0);
    bounded(r, e, "kr", c.Kr, 0.0, kMaxKr, false);
  }
  if (const char* m = e->Attribute("material")) {
    c.material = m;
    // A named material without its coefficients would silently cut Al7075-T6.
    if (!e->Attribute("kt") || !e->Attribute("kr"))
      r.fail(e, "<" + std::string(e->Name()) + "> names a material: give its kt and kr too");
  }
  c.mode = detail::parse_mode(r, e, c.mode);
  if (e->Attribute("diameter")) {
    c.diameter_mm = r.length_mm(e, "diameter");
    bounded(r, e, "diameter", c.diameter_mm, 0.0, kMaxToolMm, true);
  }
  if (e->Attribute("spindle_rpm")) {
    c.spindle_rpm = r.plain(e, "spindle_rpm", 0.0);
    bounded(r, e, "spindle_rpm", c.spindle_rpm, 0.0, kMaxRpm, true);
  }
}

}  // namespace

const CuttingConditions& CuttingTable::for_operation(const std::string& name) const {
  for (const CuttingOperation& op : operations) {
    if (op.name == name)
      return op.conditions;
  }
  return defaults;
}

CuttingTable parse_cutting_table(const std::string& xml_text, const std::string& source_name) {
  const MachiningXml r(source_name);
  tinyxml2::XMLDocument doc;
  const XMLElement* root = r.parse(doc, xml_text, "cutting");
  r.only_attributes(root, {"format"});
  if (std::string(r.required(root, "format")) != "1")
    r.fail(root, "<cutting> format must be \"1\"");
  r.only_children(root, {"defaults", "operation"});
  CuttingTable table;
  table.source_file = source_name;
  if (const XMLElement* d = r.child(root, "defaults", false)) {
    r.only_attributes(
        d, {"teeth", "ae", "ap", "kt", "kr", "material", "mode", "diameter", "spindle_rpm"});
    read_conditions(r, d, table.defaults);
  }
  std::set<std::string> names;
  for (const XMLElement* o = root->FirstChildElement("operation"); o;
       o = o->NextSiblingElement("operation")) {
    r.only_attributes(o, {"name", "teeth", "ae", "ap", "kt", "kr", "material", "mode", "diameter",
                          "spindle_rpm"});
    CuttingOperation op;
    op.name = r.required(o, "name");
    if (op.name.empty())
      r.fail(o, "<operation> name is empty");
    if (!names.insert(op.name).second)
      r.fail(o, "operation '" + op.name + "' is given twice");
    op.conditions = table.defaults;
    read_conditions(r, o, op.conditions);
    table.operations.push_back(std::move(op));
  }
  return table;
}

CuttingTable load_cutting_table(const std::string& path) {
  return parse_cutting_table(read_text_file(path), path);
}

int material_side_for(MillingMode mode, bool clockwise) {
  // spindle_sense = up_side * material_side (cutting_force.cpp), all +-1.
  const int up_side = mode == MillingMode::up ? 1 : -1;
  return (clockwise ? 1 : -1) * up_side;
}

MillingConditions milling_conditions(const CuttingConditions& c, double cl_diameter_mm,
                                     double cl_spindle_rpm, bool clockwise,
                                     double feed_mm_per_min) {
  MillingConditions m;
  m.tool_diameter_mm = std::isfinite(c.diameter_mm) ? c.diameter_mm : cl_diameter_mm;
  if (!(m.tool_diameter_mm > 0.0) || !std::isfinite(m.tool_diameter_mm)) {
    throw Error(ErrorCode::bad_input,
                "the cutting force needs the tool's diameter, and the CL file gives none for "
                "this tool (CUTTER, TLDATA): give diameter in the cutting file (--cutting)");
  }
  const double rpm = std::isfinite(c.spindle_rpm) ? c.spindle_rpm : cl_spindle_rpm;
  if (!(rpm > 0.0) || !std::isfinite(rpm)) {
    throw Error(ErrorCode::bad_input,
                "the cutting force needs the spindle speed, and no SPINDL with a speed came "
                "before this cutting move: give it in the CL file, or spindle_rpm in the "
                "cutting file (--cutting)");
  }
  if (!(feed_mm_per_min > 0.0) || !std::isfinite(feed_mm_per_min)) {
    throw Error(
        ErrorCode::bad_input,
        fmt::format("the cutting force needs a feed above 0 (got {:g} mm/min)", feed_mm_per_min));
  }
  m.teeth = c.teeth;
  m.fz_mm = feed_mm_per_min / (rpm * c.teeth);
  m.ae_mm = std::isfinite(c.ae_mm) ? c.ae_mm : c.ae_fraction * m.tool_diameter_mm;
  m.ap_mm = std::isfinite(c.ap_mm) ? c.ap_mm : c.ap_fraction * m.tool_diameter_mm;
  m.Kt_N_per_mm2 = c.Kt_N_per_mm2;
  m.Kr = c.Kr;
  m.mode = c.mode;
  m.material_side = material_side_for(c.mode, clockwise);
  if (m.ae_mm > m.tool_diameter_mm * (1.0 + 1e-12)) {
    throw Error(ErrorCode::bad_input,
                fmt::format("ae {:g} mm is more than the tool's diameter {:g} mm: a cut cannot "
                            "be wider than the tool (ae = diameter is a slot)",
                            m.ae_mm, m.tool_diameter_mm));
  }
  m.ae_mm = std::min(m.ae_mm, m.tool_diameter_mm);
  validate(m);
  return m;
}

}  // namespace redpost
