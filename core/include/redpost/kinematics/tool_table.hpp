// The tools of a cell as its controller knows them (docs/tools.md): for each CL tool number the
// TOOL_DATA index whose TCP the program selects, and the tool's length along its axis, from
// which the tracker's TCP for that tool is made.
//
// A cell file may hold a table (<tool-table> in <cell>), a job may bring its own file
// (redpost convert --tools FILE.xml, root <tool-table>); without entries the CL tool number n is
// TOOL_DATA[n] and the CL file's length is used (with a warning). The cell's reference length is
// the tool length its chain's TCP stands for: a tool longer by L puts the TCP L further from the
// spindle along the tool axis.
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace redpost {

struct Cell;

// KUKA controllers have TOOL_DATA[1] .. TOOL_DATA[16] by default, and as many LOAD_DATA.
inline constexpr int kMaxToolData = 16;
inline constexpr int kMaxLoadData = 16;

struct ToolEntry {
  int number = 0;     // the CL tool number (LOADTL/n, LOAD/TOOL,n)
  int tool_data = 0;  // TOOL_DATA index, 1 .. kMaxToolData
  // LOAD_DATA index of the spindle with this tool ($LOAD), 1 .. kMaxLoadData; 0: the cell's
  // default (ControllerSettings::load_data), else tool_data, as KUKA's BAS (#TOOL, n) pairs them.
  int load_data = 0;
  double length_mm = 0.0;  // along the tool axis, from the spindle's gauge line to the tip
  // The tool's bodies for the collision checks (docs/tools.md, "Geometry"), stacked along the
  // tool axis from the tip: the cutter (its flute, which alone may touch the part), the shank,
  // the holder up to the gauge line. NaN: not given (the CL file's diameter, or no body).
  double diameter_mm = std::numeric_limits<double>::quiet_NaN();
  double flute_length_mm = std::numeric_limits<double>::quiet_NaN();
  double shank_diameter_mm = std::numeric_limits<double>::quiet_NaN();  // NaN: the diameter's
  double holder_diameter_mm = std::numeric_limits<double>::quiet_NaN();
  double holder_length_mm = std::numeric_limits<double>::quiet_NaN();  // from the gauge line
  std::string name;  // for comments and messages (may be empty)
  int line = 0;      // where it is defined
};

struct ToolTable {
  std::string source;  // the file the entries come from ("" if none)
  // The tool length the cell's chain TCP stands for (cells only); NaN if the cell gives none.
  double reference_length_mm = std::numeric_limits<double>::quiet_NaN();
  std::vector<ToolEntry> tools;

  const ToolEntry* find(int number) const;
  bool has_reference() const { return reference_length_mm == reference_length_mm; }
};

// The cell with the TCP of a tool of `length_mm`: the TCP moved by (length - reference) away from
// the spindle, along -z of the TCP frame (z points from the tip towards the spindle,
// docs/conventions.md). The cell must have a reference length.
Cell cell_for_tool(const Cell& cell, double length_mm);

// Reads a tool table file (root <tool-table>, docs/tools.md). Throws Error with file:line.
ToolTable load_tool_table(const std::string& path);
ToolTable parse_tool_table(const std::string& xml_text, const std::string& source_name);

}  // namespace redpost
