// The cutting conditions of a conversion (issue 20; `redpost convert --cutting FILE`, format in
// docs/deflection.md): what the force model of cutting_force.hpp needs beyond what the CL file
// says. The CL file gives the tool's diameter (CUTTER, TLDATA), the spindle speed (SPINDL) and
// the feed (FEDRAT); this gives the teeth, the engagement, the material and the milling mode,
// with defaults and per-operation entries matched by the CL operation's name.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "redpost/machining/cutting_force.hpp"

namespace redpost {

struct CuttingConditions {
  int teeth = 4;
  // Radial width and axial depth of cut: in mm where given so (finite), else the fraction of the
  // tool's diameter.
  double ae_mm = std::numeric_limits<double>::quiet_NaN();
  double ae_fraction = 0.5;  // half immersion
  double ap_mm = std::numeric_limits<double>::quiet_NaN();
  double ap_fraction = 0.25;
  double Kt_N_per_mm2 = kAl7075T6_Kt_N_per_mm2;
  double Kr = kAl7075T6_Kr;
  std::string material = "Al7075-T6";
  MillingMode mode = MillingMode::down;
  // Overrides of what the CL file says; NaN: the CL file's value.
  double diameter_mm = std::numeric_limits<double>::quiet_NaN();
  double spindle_rpm = std::numeric_limits<double>::quiet_NaN();
  int source_line = 0;  // the line of the cutting file that gave them (0: the built-in defaults)
};

struct CuttingOperation {
  std::string name;  // the CL operation's name, matched exactly
  CuttingConditions conditions;
};

struct CuttingTable {
  std::string source_file;  // "": the built-in defaults, no file
  CuttingConditions defaults;
  std::vector<CuttingOperation> operations;

  // The entry for the CL operation `name`, else the defaults.
  const CuttingConditions& for_operation(const std::string& name) const;
};

// Loads and checks a cutting file. Throws Error(bad_input) with file:line for anything malformed,
// unknown, non-finite or out of range; Error(io) when it cannot be read.
CuttingTable load_cutting_table(const std::string& path);
CuttingTable parse_cutting_table(const std::string& xml_text, const std::string& source_name);

// The material side (MillingConditions::material_side) that `mode` implies for a spindle turning
// clockwise seen from the robot (M3, APT's CLW) or the other way: down-milling clockwise leaves
// the material on the -y side of F_P (cutting_force.hpp).
int material_side_for(MillingMode mode, bool clockwise);

// The milling conditions of one cutting move: the entry, the CL file's tool diameter, spindle
// speed and feed (fz = feed / (rpm teeth)). Throws Error(bad_input) saying what is missing or
// inconsistent (the caller adds where).
MillingConditions milling_conditions(const CuttingConditions& c, double cl_diameter_mm,
                                     double cl_spindle_rpm, bool clockwise, double feed_mm_per_min);

}  // namespace redpost
