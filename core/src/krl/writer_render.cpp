// Rendering for the KRL writer: a compiled statement or skeleton line with the value of each
// placeholder substituted (numbers with fixed decimals, names and texts of the program).
#include <cmath>
#include <iterator>

#include <fmt/format.h>

#include "krl/format.hpp"
#include "krl/writer_impl.hpp"
#include "redpost/io/error.hpp"

namespace redpost {

using krl::Ph;
using krl::Stmt;

namespace krl {

std::string one_line(std::string_view text) {
  std::string out(text);
  for (char& ch : out) {
    if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f)
      ch = ' ';
  }
  while (!out.empty() && out.back() == ' ')
    out.pop_back();
  return out;
}

}  // namespace krl

namespace {

void bits(std::string& out, int value, int width) {
  while (width < 31 && (value >> width) != 0)
    ++width;
  for (int i = width - 1; i >= 0; --i)
    out += (value >> i) & 1 ? '1' : '0';
}

}  // namespace

// --- messages --------------------------------------------------------------------------------
std::string KrlWriter::Impl::context() const {
  return fmt::format("program '{}', motion {}: template set '{}' ({}), '{}'", info.name,
                     motion_count + 1, t.name, t.source_file, current);
}

// --- numbers and values ----------------------------------------------------------------------
void KrlWriter::Impl::number(std::string& out, double v, int decimals, std::string_view what) {
  if (!std::isfinite(v)) {
    throw Error(ErrorCode::internal,
                fmt::format("{}: {} is {}; the template needs it", context(), what,
                            std::isnan(v) ? "NaN (not given)" : "infinite"));
  }
  krl::append_fixed(out, v, decimals, what);
}

// A tool, load or base number: where $TOOL or $BASE is an expression of the user's (--tool,
// --base) rather than a TOOL_DATA or BASE_DATA entry, there is no number to write, and a wrong
// one would make the pendant jog in another frame, or the controller model another payload.
void KrlWriter::Impl::data_index(std::string& out, long index, std::string_view what) {
  if (index < 1) {
    const std::string_view option = what == "base" ? "--base" : "--tool";
    const std::string_view entry = what == "base" ? "BASE_DATA" : "TOOL_DATA";
    throw Error(ErrorCode::bad_input,
                fmt::format("{}: the set writes the {} number, but the {} is not a {}[n] entry: "
                            "give {} {}[n], or take the number out of the set's statement "
                            "(docs/krl-templates.md, \"Base and tool\")",
                            context(), what, what == "load" ? "tool" : what, entry, option, entry));
  }
  fmt::format_to(std::back_inserter(out), "{}", index);
}

void KrlWriter::Impl::value(std::string& out, Ph ph, const Values& v) {
  switch (ph) {
    case Ph::x:
    case Ph::y:
    case Ph::z:
    case Ph::a:
    case Ph::b:
    case Ph::c:
      pose_value(out, ph, v);
      break;
    case Ph::a1:
    case Ph::a2:
    case Ph::a3:
    case Ph::a4:
    case Ph::a5:
    case Ph::a6:
    case Ph::e1:
    case Ph::e2:
    case Ph::e3:
    case Ph::e4:
    case Ph::e5:
    case Ph::e6:
      axis_value(out, ph, v);
      break;
    case Ph::ext:
      external_axes(out, v);
      break;
    case Ph::s:
    case Ph::t:
    case Ph::s_bits:
    case Ph::t_bits:
    case Ph::n:
    case Ph::line:
    case Ph::number:
    case Ph::value:
    case Ph::vel:
    case Ph::rpm:
    case Ph::text:
    case Ph::tool_name:
    case Ph::direction:
    case Ph::clockwise:
    case Ph::mode:
    case Ph::callee:
    case Ph::tool_data:
    case Ph::load_data:
    case Ph::routine:
    case Ph::seconds:
    case Ph::ax:
    case Ph::ay:
    case Ph::az:
      statement_value(out, ph, v);
      break;
    case Ph::tool:
      // A tool statement names its tool; a skeleton line the one its module's header sets.
      if (!v.tool.empty())
        out += v.tool;
      else
        program_value(out, ph);
      break;
    case Ph::name:
    case Ph::program:
    case Ph::base:
    case Ph::machine:
    case Ph::ex_ax_data:
    case Ph::base_data:
    case Ph::ex_axes:
    case Ph::apo_mm:
    case Ph::header_comment:
    case Ph::date:
      program_value(out, ph);
      break;
    case Ph::body:
    case Ph::decls:
    case Ph::frames:
    case Ph::count_:
      throw Error(ErrorCode::internal, context() + ": misplaced block placeholder");
  }
}

// X, Y, Z (mm) and A, B, C (deg) of a Cartesian target.
void KrlWriter::Impl::pose_value(std::string& out, Ph ph, const Values& v) {
  static const char* const kXyz[] = {"X", "Y", "Z"};
  switch (ph) {
    case Ph::x:
    case Ph::y:
    case Ph::z: {
      const int i = static_cast<int>(ph) - static_cast<int>(Ph::x);
      number(out, v.xyz[i], t.position_decimals, kXyz[i]);
      break;
    }
    case Ph::a:
      number(out, v.abc.a_deg, t.angle_decimals, "A");
      break;
    case Ph::b:
      number(out, v.abc.b_deg, t.angle_decimals, "B");
      break;
    case Ph::c:
      number(out, v.abc.c_deg, t.angle_decimals, "C");
      break;
    default:
      break;
  }
}

// A1..A6 and E1..E6 of an axis target.
void KrlWriter::Impl::axis_value(std::string& out, Ph ph, const Values& v) {
  if (ph >= Ph::a1 && ph <= Ph::a6) {
    const int n = static_cast<int>(ph) - static_cast<int>(Ph::a1) + 1;
    static const char* const kArm[] = {"axis A1", "axis A2", "axis A3",
                                       "axis A4", "axis A5", "axis A6"};
    number(out, v.axes->arm(n), t.angle_decimals, kArm[n - 1]);
  } else if (ph >= Ph::e1 && ph <= Ph::e6) {
    const int n = static_cast<int>(ph) - static_cast<int>(Ph::e1) + 1;
    static const char* const kExt[] = {"axis E1", "axis E2", "axis E3",
                                       "axis E4", "axis E5", "axis E6"};
    number(out, v.axes->external(n), t.external_decimals, kExt[n - 1]);
  }
}

// Only the external axes the cell has: ", E1 500.0000, E2 90.0000" with ext_axis.
void KrlWriter::Impl::external_axes(std::string& out, const Values& v) {
  const std::string_view outer = current;
  current = krl::stmt_name(Stmt::ext_axis);
  for (int n = 1; n <= 6; ++n) {
    if (!(ext_mask & (1 << (n - 1))))
      continue;
    Values e;
    e.integer = n;
    e.number_value = v.axes->external(n);
    render_into(out, tpl[Stmt::ext_axis], e);
  }
  current = outer;
}

// The values a statement is given: Status and Turn, counts, speeds, texts and names.
void KrlWriter::Impl::statement_value(std::string& out, Ph ph, const Values& v) {
  switch (ph) {
    case Ph::s:
      fmt::format_to(std::back_inserter(out), "{}", v.st.status);
      break;
    case Ph::t:
      fmt::format_to(std::back_inserter(out), "{}", v.st.turn);
      break;
    case Ph::s_bits:
      bits(out, v.st.status, 3);
      break;
    case Ph::t_bits:
      bits(out, v.st.turn, 6);
      break;
    case Ph::n:
    case Ph::line:
    case Ph::number:
      fmt::format_to(std::back_inserter(out), "{}", v.integer);
      break;
    case Ph::value:
      number(out, v.number_value, t.external_decimals, "an external axis value");
      break;
    case Ph::vel:
      number(out, v.number_value, t.velocity_decimals, "the velocity");
      break;
    case Ph::rpm:
      number(out, v.number_value, t.rpm_decimals, "the spindle speed");
      break;
    case Ph::text:
      out += v.text;
      break;
    case Ph::tool_name:
      out += v.tool_name;
      break;
    case Ph::direction:
      out += v.direction;
      break;
    case Ph::clockwise:
      out += v.clockwise;
      break;
    case Ph::mode:
      out += v.mode;
      break;
    case Ph::callee:
      out += v.callee;
      break;
    case Ph::tool_data:
      data_index(out, v.tool_data, "tool");
      break;
    case Ph::load_data:
      data_index(out, v.load_data, "load");
      break;
    case Ph::routine:
      out += v.routine;
      break;
    case Ph::seconds:
      // Dwell times to the millisecond (the controller's clock is finer; CAM writes less).
      number(out, v.number_value, 3, "the dwell time");
      break;
    case Ph::ax:
    case Ph::ay:
    case Ph::az:
      number(out, v.aux[static_cast<int>(ph) - static_cast<int>(Ph::ax)], t.position_decimals,
             "the auxiliary point of a CIRC");
      break;
    default:
      break;
  }
}

// The values a skeleton line takes from the program and the module being written.
void KrlWriter::Impl::program_value(std::string& out, Ph ph) {
  switch (ph) {
    case Ph::name:
      out += module;
      break;
    case Ph::program:
      out += info.name;
      break;
    case Ph::base:
      out += info.base;
      break;
    case Ph::tool:
      out += header_tool.tool;
      break;
    case Ph::machine:
      fmt::format_to(std::back_inserter(out), "{}", info.machine_def);
      break;
    case Ph::ex_axes:
      fmt::format_to(std::back_inserter(out), "{}", info.ex_axes);
      break;
    case Ph::ex_ax_data:
      fmt::format_to(std::back_inserter(out), "{}", info.ex_ax_data);
      break;
    case Ph::base_data:
      data_index(out, info.base_data, "base");
      break;
    case Ph::apo_mm:
      number(out, info.apo_mm, t.position_decimals, "$APO.CDIS");
      break;
    case Ph::header_comment:
      out += krl::one_line(info.header_comment);
      break;
    case Ph::date:
      out += date;
      break;
    default:
      break;
  }
}

void KrlWriter::Impl::render_into(std::string& out, const krl::Compiled& c, const Values& v) {
  for (const krl::Piece& p : c.pieces) {
    out += p.literal;
    if (p.ph != Ph::count_)
      value(out, p.ph, v);
  }
}

std::string KrlWriter::Impl::render(Stmt s, const Values& v) {
  current = krl::stmt_name(s);
  std::string out;
  render_into(out, tpl[s], v);
  return out;
}

}  // namespace redpost
