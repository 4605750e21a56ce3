// The KRL writer's compiled form of a template set: the statements it emits, by kind, and the
// lines of the four file skeletons, checked as the loader checks a template file (a set may
// also be built by hand).
#pragma once

#include <array>
#include <iterator>
#include <string_view>
#include <vector>

#include "krl/format.hpp"
#include "redpost/krl/template.hpp"

namespace redpost::krl {

enum class Stmt {
  ptp_axes,
  rapid,
  lin,
  ext_axis,
  vel,
  comment,
  cl_line,
  tool_change,
  spindle_on,
  spindle_off,
  coolant_on,
  coolant_off,
  literal,
  call,
  call_decl,
  spline_begin,
  spline_lin,
  spline_end,
  tool_change_manual,
  tool_select,
  base_static,
  base_coupled,
  dwell,
  circ,
  spline_spl,
  spline_lin_vel,
  spline_spl_vel,
  bco_ptp,
  count_
};
inline constexpr std::string_view kStmtNames[] = {"ptp_axes",
                                                  "rapid",
                                                  "lin",
                                                  "ext_axis",
                                                  "vel",
                                                  "comment",
                                                  "cl_line",
                                                  "tool_change",
                                                  "spindle_on",
                                                  "spindle_off",
                                                  "coolant_on",
                                                  "coolant_off",
                                                  "literal",
                                                  "call",
                                                  "call_decl",
                                                  "spline_begin",
                                                  "spline_lin",
                                                  "spline_end",
                                                  "tool_change_manual",
                                                  "tool_select",
                                                  "base_static",
                                                  "base_coupled",
                                                  "dwell",
                                                  "circ",
                                                  "spline_spl",
                                                  "spline_lin_vel",
                                                  "spline_spl_vel",
                                                  "bco_ptp"};
static_assert(std::size(kStmtNames) == static_cast<size_t>(Stmt::count_));

constexpr std::string_view stmt_name(Stmt s) {
  return kStmtNames[static_cast<size_t>(s)];
}

// A skeleton line: text with placeholders, or the place of a block ({body}, {decls},
// {frames}).
struct SkeletonLine {
  Compiled text;
  Ph block = Ph::count_;
};
using Skeleton = std::vector<SkeletonLine>;

struct CompiledTemplates {
  std::array<Compiled, static_cast<size_t>(Stmt::count_)> stmt;   // empty where not used
  std::array<bool, static_cast<size_t>(Stmt::count_)> present{};  // the set has it
  Skeleton src, dat, main_src, main_dat;
  Skeleton continued_src;   // empty: the set has none
  bool wants_date = false;  // a skeleton line has {date}

  const Compiled& operator[](Stmt s) const { return stmt[static_cast<size_t>(s)]; }
  bool has(Stmt s) const { return present[static_cast<size_t>(s)]; }
};

// Throws Error(bad_input) naming the set and its source file for a missing statement, an
// unknown or misplaced placeholder, max_spline_points < 1, or a skeleton without its {body}.
CompiledTemplates compile_templates(const KrlTemplateSet& templates);

}  // namespace redpost::krl
