// KRL template sets (definitions/krl/*.xml, format in docs/krl-templates.md).
//
// A template set holds the file skeletons and the format of every statement the writer emits;
// the C++ holds no KRL text. Placeholders are written {name}; the writer substitutes them and
// refuses a template that uses a placeholder the statement does not have.
#pragma once

#include <map>
#include <string>

namespace redpost {

// What a set's skeleton sets up for the controller's motion (<timing>, docs/timing.md): the
// time model's view of the program. Defaults: the controller's own, as assumed there.
struct KrlTimingSettings {
  double ptp_velocity_percent = 100.0;        // BAS (#VEL_PTP, n)
  double ptp_acceleration_percent = 100.0;    // BAS (#ACC_PTP, n)
  double path_acceleration_m_s2 = 2.0;        // $ACC.CP
  double orientation_velocity_deg_s = 200.0;  // $VEL.ORI1
  double interpolation_cycle_ms = 12.0;       // the controller's IPO cycle (KR C2 and KR C4)
  int advance = 3;  // $ADVANCE: motions the advance run prepares ahead (the skeleton's, or 3)
};

struct KrlTemplateSet {
  std::string name;         // e.g. krc4_lin
  std::string source_file;  // for messages

  // Skeletons, lines separated by '\n' (the writer ends every line with CRLF). {name} program
  // name, {date}, {body} the statements, {decls} the declarations of a split program's main,
  // {base}, {tool}, {apo_mm}, {header_comment} ... (the full list per file kind is in
  // docs/krl-templates.md).
  std::string src_file, dat_file;            // a program (the main one, or a part)
  std::string main_src_file, main_dat_file;  // the main program of a split program
  // Optional: a part that continues the cut the part before it ended in, where the byte budget
  // found no place out of the material. Without the INI fold and the BCO run of src_file, so
  // that the controller blends the last motion of the part before into its first (empty: such
  // a part is written with src_file and starts with an exact-stop PTP).
  std::string continued_src_file;

  // Statement formats, by name: "ptp_axes", "lin", "rapid", "vel", "comment", "cl_line",
  // "tool_change", "spindle_on", "spindle_off", "coolant_on", "coolant_off", "literal",
  // "call", "spline_begin", "spline_end", "spline_lin", "ext_axis" (one external axis in
  // {ext}), "call_decl" (one line of a split program's {decls}); see docs/krl-templates.md.
  std::map<std::string, std::string> statements;

  int position_decimals = 3;  // mm
  int angle_decimals = 4;     // deg
  int velocity_decimals = 5;  // m/s
  int external_decimals = 4;  // E1..E6, whether mm (track) or deg (table)
  int rpm_decimals = 0;       // spindle speed
  bool spline = false;        // motions are grouped into SPLINE blocks of spline_lin
  int max_spline_points = 100;
  // <limits max-bytes>: the largest .src a controller of this set loads (0: not given, the
  // writer's default applies; KrlProgramInfo::max_file_bytes overrides both).
  long max_file_bytes = 0;
  // <limits program-memory>: the bytes of programs the controller can hold loaded for this job
  // (its .src and .dat files together; 0: not given). A larger program is written with a
  // warning: it must be run one part at a time (docs/krl-templates.md, "Splitting").
  long program_memory_bytes = 0;
  KrlTimingSettings timing;
};

// Throws Error(io / bad_input) with file:line.
KrlTemplateSet load_krl_templates(const std::string& path);
KrlTemplateSet parse_krl_templates(const std::string& xml_text, const std::string& source_name);

}  // namespace redpost
