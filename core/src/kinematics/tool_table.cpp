// Tool tables and the TCP of each tool (redpost/kinematics/tool_table.hpp, docs/tools.md).
#include "redpost/kinematics/tool_table.hpp"

#include <cmath>

#include "redpost/io/error.hpp"
#include "redpost/kinematics/cell.hpp"

namespace redpost {

const ToolEntry* ToolTable::find(int number) const {
  for (const ToolEntry& t : tools) {
    if (t.number == number)
      return &t;
  }
  return nullptr;
}

Cell cell_for_tool(const Cell& cell, double length_mm) {
  if (!cell.tools.has_reference()) {
    throw Error(ErrorCode::internal, "cell_for_tool: the cell gives no reference tool length");
  }
  if (!std::isfinite(length_mm) || !(length_mm > 0.0))
    throw Error(ErrorCode::internal, "cell_for_tool: the tool length must be > 0");
  const double longer_mm = length_mm - cell.tools.reference_length_mm;
  Cell out = cell;
  if (longer_mm == 0.0)
    return out;
  // The tip moves away from the spindle: along -z of the TCP frame. When the chain ends with a
  // link whose last factor is Tz(d) of a non-prismatic joint and no tool frame follows, the
  // offset folds into that d (the fast spin-only TCP of the post session stays available);
  // otherwise it is appended to the tool frame.
  Joint& last = out.joints[static_cast<size_t>(out.joint_count - 1)];
  const bool ends_in_tz =
      last.convention == DhConvention::modified || (last.a_mm == 0.0 && last.alpha_rad == 0.0);
  if (!out.has_tcp_frame && ends_in_tz && last.type != JointType::prismatic) {
    last.d_mm -= longer_mm;
  } else {
    out.T_last_tcp = out.T_last_tcp * Eigen::Translation3d(0.0, 0.0, -longer_mm);
  }
  finalize_cell(out);
  return out;
}

}  // namespace redpost
