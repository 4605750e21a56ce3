// Tool changes in a post session (PostSession::Impl, post/session_impl.hpp; docs/tools.md):
// the tool's TOOL_DATA and length from the tool table (or, without one, TOOL_DATA[n] and the CL
// file's length), the tracker moved onto that tool's TCP, and the change itself: a retract
// along the tool axis to the clearance plane, the template's tool change, $TOOL, and a PTP
// approach to the next move.
#include <cmath>

#include "post/session_impl.hpp"
#include "redpost/io/error.hpp"

namespace redpost {

namespace {

// A tool length the CL file states and a table's that differ by more than this are reported.
constexpr double kLengthMismatchMm = 0.5;
// No milling tool is 2 m long: a larger length is a typo (and 1e300 put the TCP at infinity).
constexpr double kMaxToolLengthMm = 2000.0;
// The tool table's bound on a diameter (cell_xml.cpp): a CL file's larger one is a typo, and a
// cutter of 1e300 mm left the clearance check no distance to work with.
constexpr double kMaxToolDiameterMm = 500.0;

}  // namespace

void PostSession::Impl::tool_change(int number, const std::string& name, double cl_length_mm,
                                    int cl_line) {
  const SourceLocation at{o.source_name, cl_line, 0};
  if (number < 0)
    throw Error(ErrorCode::bad_input, fmt::format("tool number {} is not valid", number), at);
  if (!std::isfinite(cl_length_mm) || cl_length_mm < 0.0 || cl_length_mm > kMaxToolLengthMm) {
    throw Error(ErrorCode::bad_input,
                fmt::format("tool {}: length {:g} mm is not valid: a tool length is a number of "
                            "mm from 0 to {:g}",
                            number, cl_length_mm, kMaxToolLengthMm),
                at);
  }
  if (!std::isnan(tool_diameter_mm) &&
      !(tool_diameter_mm >= 0.0 && tool_diameter_mm <= kMaxToolDiameterMm)) {
    throw Error(ErrorCode::bad_input,
                fmt::format("tool {}: diameter {:g} mm is not valid: a tool diameter is a number "
                            "of mm from 0 to {:g} (NaN: not given)",
                            number, tool_diameter_mm, kMaxToolDiameterMm),
                at);
  }
  const ToolTable& table = o.tools.tools.empty() ? cell.tools : o.tools;
  KrlToolChange change;
  change.number = number;
  change.name = name;
  double length_mm = cl_length_mm;
  if (!table.tools.empty()) {
    const ToolEntry* entry = table.find(number);
    if (!entry) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("tool {}{} is not in the tool table of {}: add <tool number=\"{}\" "
                              "data=\"...\" length=\"...\"/> for it (docs/tools.md)",
                              number, name.empty() ? "" : " (" + name + ")", table.source, number),
                  at);
    }
    if (cl_length_mm > 0.0 && std::fabs(cl_length_mm - entry->length_mm) > kLengthMismatchMm) {
      summary.warnings.push_back(fmt::format(
          "{}:{}: tool {}: the CL file gives a length of {:.3f} mm, the tool table ({}:{}) {:.3f} "
          "mm; the table's is used",
          o.source_name, cl_line, number, cl_length_mm, table.source, entry->line,
          entry->length_mm));
    }
    change.tool_data = entry->tool_data;
    length_mm = entry->length_mm;
    if (change.name.empty())
      change.name = entry->name;
  } else {
    if (number < 1 || number > kMaxToolData) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("tool {}: without a tool table tool n is TOOL_DATA[n], which exists "
                              "for n = 1 to {} only; give a tool table that maps tool {} to a "
                              "TOOL_DATA index (--tools FILE, docs/tools.md)",
                              number, kMaxToolData, number),
                  at);
    }
    change.tool_data = number;
    summary.warnings.push_back(fmt::format(
        "{}:{}: tool {}: no tool table, so TOOL_DATA[{}] with {}: make sure the controller's "
        "TOOL_DATA[{}] is this tool (docs/tools.md)",
        o.source_name, cl_line, number, number,
        cl_length_mm > 0.0 ? fmt::format("the CL file's length {:.3f} mm", cl_length_mm)
                           : std::string("the cell's TCP (the CL file gives no length)"),
        number));
  }
  change.tool = fmt::format("TOOL_DATA[{}]", change.tool_data);
  // $LOAD: the table's entry for the tool, else the cell's, else (0) the tool's own number.
  const ToolEntry* entry = table.tools.empty() ? nullptr : table.find(number);
  change.load_data = entry && entry->load_data > 0 ? entry->load_data : cell.controller.load_data;

  // A longer tool would have its tip that much lower where the old one stopped: the old tool
  // first backs off along its axis by the difference (and up to the clearance plane).
  const double old_length =
      std::isnan(active_length_mm) ? cell.tools.reference_length_mm : active_length_mm;
  const double new_length = length_mm > 0.0 ? length_mm : cell.tools.reference_length_mm;
  const double longer = std::isfinite(old_length) && std::isfinite(new_length)
                            ? std::max(0.0, new_length - old_length)
                            : 0.0;
  if (started)
    retract_for_tool_change(cl_line, longer);
  writer.tool_change(change);
  // The change itself (a HALT, or the cell's routine) stops the robot for a time the program
  // does not know.
  timing_stop(0.0);
  ++summary.untimed_tool_changes;
  use_tool_cell(number, length_mm, cl_line);
  tool_number = number;
  active_length_mm = new_length;
  collision_tool(entry, new_length, number, cl_line);
  // After the change (a routine may take the robot to the changer) the next move is an approach.
  approach_pending = started;
}

// The tracker on the TCP of a tool `length_mm` long (0: unknown, the cell's own TCP).
void PostSession::Impl::use_tool_cell(int number, double length_mm, int cl_line) {
  const Cell* next = &cell;
  if (length_mm > 0.0 && cell.tools.has_reference()) {
    next = nullptr;
    for (const auto& [n, c] : tool_cells) {
      if (n == number)
        next = &c;
    }
    if (!next) {
      tool_cells.emplace_back(number, cell_for_tool(cell, length_mm));
      next = &tool_cells.back().second;
    }
  } else if (length_mm > 0.0) {
    // Without a reference length the TCP cannot follow a tool's length: one length is taken as
    // the cell's TCP, another is refused (it would cut as deep as the first tool).
    if (std::isnan(first_length_mm)) {
      first_length_mm = length_mm;
      first_length_line = cl_line;
    } else if (std::fabs(length_mm - first_length_mm) > kLengthMismatchMm) {
      throw Error(
          ErrorCode::bad_input,
          fmt::format("tool {} is {:.3f} mm long and the tool of line {} {:.3f} mm, but the "
                      "cell gives no reference tool length, so its TCP cannot follow the "
                      "change: add <tool-table reference-length=\"...\"/> to the cell "
                      "{} (docs/tools.md)",
                      number, length_mm, first_length_line, first_length_mm, cell.source_file),
          SourceLocation{o.source_name, cl_line, 0});
    }
  }
  if (next == active_cell)
    return;
  const JointVector q = tracker.q();
  active_cell = next;
  tracker = Tracker(*active_cell, o.tracker);
  tracker.reset(q);
  spin_last = last_pure_spin(*active_cell);
}

// Before a tool change the tool leaves the part along its own axis, a straight move the CL data
// imply since the tool came in along that axis: up to the clearance plane where one is known and
// the tool is below it, and further by `longer_mm`, how much longer the next tool is, so that
// the new tip starts where the old one would have been.
void PostSession::Impl::retract_for_tool_change(int cl_line, double longer_mm) {
  double distance = longer_mm;
  if (const std::optional<ClearancePlane> plane = plane_for(nullptr)) {
    const double h = plane->height(last_cl_point);
    const double rise = plane->normal.dot(last_cl_axis);
    if (h < 0.0 && rise > 0.1)
      distance += -h / rise;
  }
  if (!(distance > 1e-6))
    return;
  const Eigen::Vector3d up = last_cl_point + distance * last_cl_axis;
  set_speed(o.rapid_velocity_m_per_s, false);
  const TcpTarget target = target_in_B(up, last_cl_axis, cl_line);
  // No plan covers this move: under the whole-path plan the external axes stay where the cut
  // left them (Algorithm 1's centring would swing them towards home in the air, and the next
  // tool's approach back), and the arm keeps its posture as near as the line allows.
  hold_unplanned = true;
  track_line(target, cl_line, false);
  hold_unplanned = false;
  tracker.stop_following();
  emit_line(cl_line);
  last_target = target;
  remember_cl(up, last_cl_axis);
}

}  // namespace redpost
