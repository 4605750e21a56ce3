// Shared by the KRL template loader and the KRL writer: the placeholders each statement and
// skeleton may use, template compilation, and locale-independent fixed-point numbers.
//
// A placeholder is '{' + a lowercase identifier + '}'; every other brace is KRL text (the
// aggregates "{E6POS: X ...}" and the fold markers ";%{PE}" contain no such token).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace redpost::krl {

enum class Ph : std::uint8_t {
  // skeletons
  name,
  program,
  base,
  tool,
  apo_mm,
  header_comment,
  date,
  body,
  decls,
  frames,  // a skeleton block: the base and tool statements (base_static or base_coupled, then
           // tool_select)
  // motions
  x,
  y,
  z,
  a,
  b,
  c,
  a1,
  a2,
  a3,
  a4,
  a5,
  a6,
  e1,
  e2,
  e3,
  e4,
  e5,
  e6,
  ext,
  s,
  t,
  s_bits,
  t_bits,
  // ext_axis
  n,
  value,
  // others
  vel,
  text,
  line,
  number,
  tool_name,
  rpm,
  direction,
  clockwise,
  mode,
  callee,
  // base, tools, dwell, circular motion
  machine,    // MACHINE_DEF index of a coupled kinematic
  base_data,  // BASE_DATA index of the base
  ex_axes,    // number of external axes ($ACT_EX_AX)
  tool_data,  // TOOL_DATA index of the tool
  routine,    // the cell's tool change routine
  seconds,    // a dwell
  ax,         // CIRC auxiliary point (mm, in $BASE)
  ay,
  az,
  load_data,   // LOAD_DATA index of the tool's load ($LOAD)
  ex_ax_data,  // EX_AX_DATA index of a coupled kinematic (KSS 5)
  count_
};

using PhMask = std::uint64_t;
static_assert(static_cast<int>(Ph::count_) <= 64, "placeholders must fit a 64-bit mask");

constexpr PhMask bit(Ph p) {
  return PhMask{1} << static_cast<int>(p);
}

// The name of a placeholder as written in templates, e.g. "a1".
std::string_view placeholder_name(Ph p);
// Ph::count_ if the name is not a placeholder at all.
Ph placeholder_from_name(std::string_view name);

// The statements a template set may hold. Each must be present (possibly empty), except that
// the spline ones belong only to a set with <spline> and "lin" only to one without (the
// writer would never use them: refused, so that a template edit is never silently ignored).
// `optional` statements (tools, base coupling, dwell, CIRC) may be left out of a set: the
// writer refuses, naming the statement, only when a program needs one the set lacks.
// `spline_optional` (SPL) may be left out of a spline set, and is refused in any other.
enum class StatementUse { always, spline_only, no_spline_only, optional, spline_optional };
struct StatementSpec {
  std::string_view name;
  PhMask allowed;
  StatementUse use;
  bool used_by(bool spline) const {
    if (use == StatementUse::spline_optional)
      return spline;
    return use == StatementUse::always || use == StatementUse::optional ||
           (use == StatementUse::spline_only) == spline;
  }
  bool required(bool spline) const {
    return use != StatementUse::optional && use != StatementUse::spline_optional && used_by(spline);
  }
};
const std::vector<StatementSpec>& statement_specs();
const StatementSpec* find_statement(std::string_view name);

enum class SkeletonKind { src, dat, main_src, main_dat, continued_src };
struct SkeletonSpec {
  std::string_view kind;  // as in <file kind="...">
  SkeletonKind id;
  PhMask allowed;
  bool needs_body;       // {body} must stand alone on one line, exactly once ({decls}, where
                         // allowed, at most once and alone on its line too)
  bool required = true;  // a set must have it (continued_src is optional)
};
const std::vector<SkeletonSpec>& skeleton_specs();
const SkeletonSpec* find_skeleton(std::string_view kind);

// A placeholder occurrence in a text: its kind (or count_ if unknown), its name, and the byte
// offset of its '{'.
struct PlaceholderUse {
  Ph ph;
  std::string_view name;
  std::size_t offset;
};
std::vector<PlaceholderUse> scan_placeholders(std::string_view text);

// A template text split into literal pieces and placeholders.
struct Piece {
  std::string literal;  // written before the placeholder
  Ph ph = Ph::count_;   // count_: no placeholder (the last piece)
};
struct Compiled {
  std::vector<Piece> pieces;
  PhMask used = 0;
  bool empty() const { return pieces.size() == 1 && pieces[0].literal.empty(); }
};
Compiled compile(std::string_view text);

// Fixed-point decimal with '.' whatever the locale; "-0.000" comes out as "0.000". Throws
// Error(internal) for NaN and infinities, naming `what`.
void append_fixed(std::string& out, double value, int decimals, std::string_view what);

// The KRL identifier rule (letter first, then letters, digits, '_'; at most 24 characters) and
// a few reserved words. Returns an empty string if `name` is fine, else why not.
std::string identifier_problem(std::string_view name);

// What a continued_src skeleton may not hold (it is called between two blended motions): a
// motion, a wait, a HALT, an interrupt declaration or BAS (#INITMOV). The 0-based line of the
// first such line and what it holds, or {-1, ""}.
std::pair<int, std::string> continued_problem(std::string_view text);
inline constexpr std::size_t kMaxIdentifierLength = 24;

}  // namespace redpost::krl
