#include "redpost/krl/template.hpp"

#include <tinyxml2.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <iterator>
#include <map>
#include <set>
#include <string_view>

#include <fmt/format.h>

#include "io/strict_xml.hpp"
#include "krl/format.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/krl/check.hpp"

namespace redpost {

// ---------------------------------------------------------------------------------------------
// krl/format.hpp: shared with the writer.
namespace krl {

namespace {
constexpr std::array<std::string_view, static_cast<size_t>(Ph::count_)> kPlaceholderNames = {
    "name",      "program",   "base",    "tool",      "apo_mm",    "header_comment",
    "date",      "body",      "decls",   "frames",    "x",         "y",
    "z",         "a",         "b",       "c",         "a1",        "a2",
    "a3",        "a4",        "a5",      "a6",        "e1",        "e2",
    "e3",        "e4",        "e5",      "e6",        "ext",       "s",
    "t",         "s_bits",    "t_bits",  "n",         "value",     "vel",
    "text",      "line",      "number",  "tool_name", "rpm",       "direction",
    "clockwise", "mode",      "callee",  "machine",   "base_data", "ex_axes",
    "tool_data", "routine",   "seconds", "ax",        "ay",        "az",
    "load_data", "ex_ax_data"};
static_assert(kPlaceholderNames.back() == "ex_ax_data",
              "one name per placeholder, in the enum's order");

constexpr PhMask kArmAxes =
    bit(Ph::a1) | bit(Ph::a2) | bit(Ph::a3) | bit(Ph::a4) | bit(Ph::a5) | bit(Ph::a6);
constexpr PhMask kExternal = bit(Ph::e1) | bit(Ph::e2) | bit(Ph::e3) | bit(Ph::e4) | bit(Ph::e5) |
                             bit(Ph::e6) | bit(Ph::ext);
constexpr PhMask kCartesian =
    bit(Ph::x) | bit(Ph::y) | bit(Ph::z) | bit(Ph::a) | bit(Ph::b) | bit(Ph::c) | kExternal;
constexpr PhMask kStatusTurn = bit(Ph::s) | bit(Ph::t) | bit(Ph::s_bits) | bit(Ph::t_bits);
constexpr PhMask kSkeleton =
    bit(Ph::name) | bit(Ph::program) | bit(Ph::header_comment) | bit(Ph::date);
constexpr PhMask kProgram = kSkeleton | bit(Ph::base) | bit(Ph::tool) | bit(Ph::apo_mm);
constexpr PhMask kTool =
    bit(Ph::number) | bit(Ph::tool_name) | bit(Ph::tool) | bit(Ph::tool_data) | bit(Ph::load_data);

bool is_ident_start(char ch) {
  return ch >= 'a' && ch <= 'z';
}
bool is_ident_char(char ch) {
  return is_ident_start(ch) || (ch >= '0' && ch <= '9') || ch == '_';
}
}  // namespace

std::string_view placeholder_name(Ph p) {
  return kPlaceholderNames[static_cast<size_t>(p)];
}

Ph placeholder_from_name(std::string_view name) {
  for (size_t i = 0; i < kPlaceholderNames.size(); ++i) {
    if (kPlaceholderNames[i] == name)
      return static_cast<Ph>(i);
  }
  return Ph::count_;
}

const std::vector<StatementSpec>& statement_specs() {
  static const std::vector<StatementSpec> specs = {
      {"ptp_axes", kArmAxes | kExternal, StatementUse::always},
      {"bco_ptp", kArmAxes | kExternal, StatementUse::optional},
      {"rapid", kArmAxes | kCartesian | kStatusTurn, StatementUse::always},
      {"lin", kCartesian, StatementUse::no_spline_only},
      {"ext_axis", bit(Ph::n) | bit(Ph::value), StatementUse::always},
      {"vel", bit(Ph::vel), StatementUse::always},
      {"comment", bit(Ph::text), StatementUse::always},
      {"cl_line", bit(Ph::line), StatementUse::always},
      {"tool_change", kTool | bit(Ph::routine), StatementUse::always},
      {"tool_change_manual", kTool, StatementUse::optional},
      {"tool_select", kTool, StatementUse::optional},
      {"base_static", bit(Ph::base) | bit(Ph::base_data), StatementUse::optional},
      {"base_coupled",
       bit(Ph::base) | bit(Ph::machine) | bit(Ph::ex_ax_data) | bit(Ph::ex_axes) |
           bit(Ph::base_data),
       StatementUse::optional},
      {"dwell", bit(Ph::seconds), StatementUse::optional},
      {"circ", kCartesian | bit(Ph::ax) | bit(Ph::ay) | bit(Ph::az), StatementUse::optional},
      {"spindle_on", bit(Ph::rpm) | bit(Ph::direction) | bit(Ph::clockwise), StatementUse::always},
      {"spindle_off", 0, StatementUse::always},
      {"coolant_on", bit(Ph::mode), StatementUse::always},
      {"coolant_off", bit(Ph::mode), StatementUse::always},
      {"literal", bit(Ph::text), StatementUse::always},
      {"call", bit(Ph::callee), StatementUse::always},
      {"call_decl", bit(Ph::callee), StatementUse::always},
      {"spline_begin", 0, StatementUse::spline_only},
      {"spline_lin", kCartesian, StatementUse::spline_only},
      {"spline_end", 0, StatementUse::spline_only},
      {"spline_spl", kCartesian, StatementUse::spline_optional},
      {"spline_lin_vel", kCartesian | bit(Ph::vel), StatementUse::spline_optional},
      {"spline_spl_vel", kCartesian | bit(Ph::vel), StatementUse::spline_optional},
  };
  return specs;
}

const StatementSpec* find_statement(std::string_view name) {
  for (const StatementSpec& s : statement_specs()) {
    if (s.name == name)
      return &s;
  }
  return nullptr;
}

const std::vector<SkeletonSpec>& skeleton_specs() {
  static const std::vector<SkeletonSpec> specs = {
      {"src", SkeletonKind::src, kProgram | bit(Ph::body) | bit(Ph::frames), true},
      {"dat", SkeletonKind::dat, kSkeleton, false},
      {"main_src", SkeletonKind::main_src, kProgram | bit(Ph::body) | bit(Ph::decls), true},
      {"main_dat", SkeletonKind::main_dat, kSkeleton, false},
      // A part that continues a cut the part before it ended in (docs/krl-templates.md,
      // "Splitting"): no INI fold and no BCO run, so that the controller blends across the call.
      {"continued_src", SkeletonKind::continued_src, kProgram | bit(Ph::body) | bit(Ph::frames),
       true, false},
  };
  return specs;
}

const SkeletonSpec* find_skeleton(std::string_view kind) {
  for (const SkeletonSpec& s : skeleton_specs()) {
    if (s.kind == kind)
      return &s;
  }
  return nullptr;
}

std::vector<PlaceholderUse> scan_placeholders(std::string_view text) {
  std::vector<PlaceholderUse> out;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '{' || i + 1 >= text.size() || !is_ident_start(text[i + 1]))
      continue;
    size_t j = i + 1;
    while (j < text.size() && is_ident_char(text[j]))
      ++j;
    if (j < text.size() && text[j] == '}') {
      const std::string_view name = text.substr(i + 1, j - i - 1);
      out.push_back({placeholder_from_name(name), name, i});
      i = j;
    }
  }
  return out;
}

Compiled compile(std::string_view text) {
  Compiled c;
  size_t pos = 0;
  for (const PlaceholderUse& u : scan_placeholders(text)) {
    if (u.ph == Ph::count_)
      continue;  // refused by the checks before; never silently dropped
    c.pieces.push_back({std::string(text.substr(pos, u.offset - pos)), u.ph});
    c.used |= bit(u.ph);
    pos = u.offset + u.name.size() + 2;
  }
  c.pieces.push_back({std::string(text.substr(pos)), Ph::count_});
  return c;
}

void append_fixed(std::string& out, double value, int decimals, std::string_view what) {
  if (!std::isfinite(value)) {
    throw Error(ErrorCode::internal,
                fmt::format("KRL output: {} is {}, not a number that can be written", what,
                            std::isnan(value) ? "NaN" : "infinite"));
  }
  // std::to_chars ignores every locale ('.' always), rounds exactly, and costs a fraction of a
  // formatted write (this runs a dozen times per motion).
  const size_t start = out.size();
  char buf[64];
  const auto [end, ec] =
      std::to_chars(buf, buf + sizeof buf, value, std::chars_format::fixed, decimals);
  if (ec != std::errc()) {
    fmt::format_to(std::back_inserter(out), "{:.{}f}", value, decimals);  // beyond 64 digits
  } else {
    out.append(buf, end);
  }
  // A value that rounds to zero keeps its sign in printf-style output ("-0.000"); KRL readers
  // and diff tools should see one zero.
  if (out[start] == '-' && out.find_first_not_of("0.", start + 1) == std::string::npos) {
    out.erase(start, 1);
  }
}

std::pair<int, std::string> continued_problem(std::string_view text) {
  // PTP_REL and LIN_REL show as PTP and LIN (the word stops at '_').
  static const std::set<std::string, std::less<>> refused{"PTP",    "LIN",       "CIRC",  "SCIRC",
                                                          "SPLINE", "SLIN",      "SPL",   "HALT",
                                                          "WAIT",   "INTERRUPT", "GLOBAL"};
  size_t pos = 0;
  for (int line = 0;; ++line) {
    const size_t nl = text.find('\n', pos);
    const std::string_view l = text.substr(pos, nl == std::string_view::npos ? nl : nl - pos);
    std::string word;
    for (size_t i = l.find_first_not_of(" \t"); i != std::string_view::npos && i < l.size() &&
                                                std::isalpha(static_cast<unsigned char>(l[i]));
         ++i)
      word += static_cast<char>(std::toupper(static_cast<unsigned char>(l[i])));
    if (l.find("#INITMOV") != std::string_view::npos)
      return {line, "BAS (#INITMOV)"};
    if (refused.count(word))
      return {line, word};
    if (nl == std::string_view::npos)
      return {-1, ""};
    pos = nl + 1;
  }
}

std::string identifier_problem(std::string_view name) {
  if (name.empty())
    return "is empty";
  const auto letter = [](char ch) { return (ch >= 'A' && ch <= 'Z') || (ch >= 'a' && ch <= 'z'); };
  if (!letter(name[0]))
    return "must start with a letter (A-Z)";
  for (char ch : name) {
    if (!letter(ch) && !(ch >= '0' && ch <= '9') && ch != '_')
      return "may contain only letters A-Z, digits and '_'";
  }
  if (name.size() > kMaxIdentifierLength) {
    return fmt::format("has {} characters; KRL allows at most {}", name.size(),
                       kMaxIdentifierLength);
  }
  // A program named like a KRL keyword would not compile on the controller.
  static const char* const kReserved[] = {
      "AND",     "ANIN",    "ANOUT",  "B_AND",  "B_EXOR",   "B_NOT",     "B_OR",      "BOOL",
      "BRAKE",   "CASE",    "CHAR",   "CIRC",   "CIRC_REL", "CONST",     "CONTINUE",  "DECL",
      "DEF",     "DEFAULT", "DEFDAT", "DEFFCT", "DELAY",    "DO",        "ELSE",      "END",
      "ENDDAT",  "ENDFCT",  "ENDFOR", "ENDIF",  "ENDLOOP",  "ENDSPLINE", "ENDSWITCH", "ENDWHILE",
      "ENUM",    "EXIT",    "EXOR",   "EXT",    "EXTFCT",   "FALSE",     "FOR",       "GLOBAL",
      "GOTO",    "HALT",    "IF",     "IMPORT", "INT",      "INTERRUPT", "IS",        "LIN",
      "LIN_REL", "LOOP",    "NOT",    "OR",     "PRIO",     "PTP",       "PTP_REL",   "PUBLIC",
      "REAL",    "REPEAT",  "RESUME", "RETURN", "SCIRC",    "SEC",       "SIGNAL",    "SLIN",
      "SPL",     "SPLINE",  "SPTP",   "STRUC",  "SWITCH",   "THEN",      "TO",        "TRIGGER",
      "TRUE",    "UNTIL",   "WAIT",   "WHEN",   "WHILE",    "WITH"};
  std::string upper(name);
  for (char& ch : upper)
    ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  for (const char* r : kReserved) {
    if (upper == r)
      return "is a KRL keyword";
  }
  return {};
}

}  // namespace krl

// ---------------------------------------------------------------------------------------------
// The XML loader.
namespace {

using tinyxml2::XMLElement;
using tinyxml2::XMLNode;

class Reader : public detail::StrictXml {
 public:
  using StrictXml::StrictXml;

  int integer(const XMLElement* e, const char* attr, int lo, int hi) const {
    const std::string text = required(e, attr);
    int v = 0;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || ptr != text.data() + text.size() || v < lo || v > hi) {
      fail(e, std::string("<") + e->Name() + "> attribute '" + attr + "' = \"" + text +
                  "\": expected a whole number in " + std::to_string(lo) + ".." +
                  std::to_string(hi));
    }
    return v;
  }

  // A number in [lo, hi], written plainly (no unit).
  double real(const XMLElement* e, const char* attr, double lo, double hi) const {
    const std::string text = required(e, attr);
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(v) || v < lo ||
        v > hi) {
      fail(e, std::string("<") + e->Name() + "> attribute '" + attr + "' = \"" + text +
                  "\": expected a number from " + fmt::format("{}", lo) + " to " +
                  fmt::format("{}", hi));
    }
    return v;
  }

  // The text content of an element that holds text only (plain or CDATA), and the line on
  // which that text starts.
  std::string text_of(const XMLElement* e, int& line) const {
    std::string out;
    line = e->GetLineNum();
    bool first = true;
    for (const XMLNode* n = e->FirstChild(); n; n = n->NextSibling()) {
      if (n->ToComment())
        continue;
      const tinyxml2::XMLText* t = n->ToText();
      if (!t) {
        fail(n->GetLineNum(),
             std::string("<") + e->Name() + "> holds text only (use CDATA for text with < or &)");
      }
      if (!first) {
        fail(n->GetLineNum(),
             std::string("<") + e->Name() + "> must hold one piece of text (no comments inside)");
      }
      first = false;
      line = t->GetLineNum();
      out = t->Value() ? t->Value() : "";
      // tinyxml2 numbers plain text by its first non-blank character (CDATA by its marker):
      // count back to the line the text starts on, as the offsets into it count.
      if (!t->CData()) {
        const size_t text_start = std::min(out.find_first_not_of(" \t\r\n"), out.size());
        line -= static_cast<int>(std::count(out.begin(), out.begin() + text_start, '\n'));
      }
    }
    return out;
  }
};

std::string join_names(krl::PhMask allowed) {
  std::string list;
  for (int i = 0; i < static_cast<int>(krl::Ph::count_); ++i) {
    if (allowed & (krl::PhMask{1} << i))
      list += (list.empty() ? "{" : ", {") + std::string(krl::placeholder_name(krl::Ph(i))) + "}";
  }
  return list.empty() ? "none" : list;
}

int line_at(std::string_view text, size_t offset, int first_line) {
  int line = first_line;
  for (size_t i = 0; i < offset && i < text.size(); ++i)
    line += text[i] == '\n';
  return line;
}

// Refuses a placeholder that is unknown or not allowed here, with the line it is on.
void check_placeholders(const Reader& r, std::string_view text, int first_line, krl::PhMask allowed,
                        const std::string& where) {
  for (const krl::PlaceholderUse& u : krl::scan_placeholders(text)) {
    if (u.ph != krl::Ph::count_ && (allowed & krl::bit(u.ph)))
      continue;
    r.fail(line_at(text, u.offset, first_line),
           std::string(u.ph == krl::Ph::count_ ? "unknown placeholder {" : "placeholder {") +
               std::string(u.name) + "} " +
               (u.ph == krl::Ph::count_ ? "in " : "is not allowed in ") + where +
               " (allowed: " + join_names(allowed) + ")");
  }
}

bool blank(std::string_view s) {
  return s.find_first_not_of(" \t\r") == std::string_view::npos;
}

// A skeleton as written between <file> and </file>: the line break after the opening tag (or
// CDATA marker) and trailing blank lines are layout, not content.
std::string clean_skeleton(std::string_view raw, int& first_line) {
  const size_t nl = raw.find('\n');
  if (nl != std::string_view::npos && blank(raw.substr(0, nl))) {
    raw.remove_prefix(nl + 1);
    ++first_line;
  }
  while (!raw.empty()) {
    const size_t last_nl = raw.rfind('\n');
    const std::string_view tail = last_nl == std::string_view::npos ? raw : raw.substr(last_nl + 1);
    if (!blank(tail))
      break;
    raw = last_nl == std::string_view::npos ? std::string_view() : raw.substr(0, last_nl);
  }
  std::string out(raw);
  // Windows line breaks in the template file must not double up with the writer's CRLF.
  out.erase(std::remove(out.begin(), out.end(), '\r'), out.end());
  return out;
}

// A statement: each line trimmed (the XML indentation is layout), blank lines at the ends
// dropped.
std::string clean_statement(std::string_view raw, int& first_line) {
  std::vector<std::string_view> lines;
  size_t pos = 0;
  while (true) {
    const size_t nl = raw.find('\n', pos);
    std::string_view l = raw.substr(pos, nl == std::string_view::npos ? raw.npos : nl - pos);
    const size_t b = l.find_first_not_of(" \t\r");
    l = b == l.npos ? std::string_view() : l.substr(b, l.find_last_not_of(" \t\r") - b + 1);
    lines.push_back(l);
    if (nl == std::string_view::npos)
      break;
    pos = nl + 1;
  }
  size_t first = 0, last = lines.size();
  while (first < last && lines[first].empty()) {
    ++first;
    ++first_line;
  }
  while (last > first && lines[last - 1].empty())
    --last;
  std::string out;
  for (size_t i = first; i < last; ++i) {
    if (i > first)
      out += '\n';
    out += lines[i];
  }
  return out;
}

// {body} (and {decls}, {frames}) stand alone on their line, because the writer streams the
// statements between the part before and the part after.
void check_block_placeholders(const Reader& r, const std::string& text, int first_line,
                              const krl::SkeletonSpec& spec) {
  int body = 0, decls = 0, frames = 0;
  for (const krl::PlaceholderUse& u : krl::scan_placeholders(text)) {
    if (u.ph != krl::Ph::body && u.ph != krl::Ph::decls && u.ph != krl::Ph::frames)
      continue;
    const int line = line_at(text, u.offset, first_line);
    const size_t bol =
        text.rfind('\n', u.offset) == std::string::npos ? 0 : text.rfind('\n', u.offset) + 1;
    size_t eol = text.find('\n', u.offset);
    eol = eol == std::string::npos ? text.size() : eol;
    const std::string_view whole(text.data() + bol, eol - bol);
    const size_t b = whole.find_first_not_of(" \t");
    const size_t e = whole.find_last_not_of(" \t");
    if (whole.substr(b, e - b + 1) != "{" + std::string(u.name) + "}") {
      r.fail(line, "{" + std::string(u.name) + "} must stand alone on its line in <file kind=\"" +
                       std::string(spec.kind) + "\">");
    }
    (u.ph == krl::Ph::body ? body : u.ph == krl::Ph::decls ? decls : frames)++;
    if (body > 1 || decls > 1 || frames > 1) {
      r.fail(line, "{" + std::string(u.name) + "} appears twice in <file kind=\"" +
                       std::string(spec.kind) + "\">");
    }
  }
  if (spec.needs_body && body == 0) {
    r.fail(first_line, "<file kind=\"" + std::string(spec.kind) +
                           "\"> needs a line {body} where the statements go");
  }
}

// A continued part is called between two blended motions (krl::continued_problem).
void check_continued(const Reader& r, const std::string& text, int first_line) {
  const auto [line, what] = krl::continued_problem(text);
  if (line >= 0) {
    r.fail(first_line + line,
           "<file kind=\"continued_src\"> is called between two blended motions: it may not "
           "hold " +
               what + " (an INI fold, a wait or a motion stops the advance run)");
  }
}

// <statement name="...">: a known statement, once, with the placeholders it may use.
void read_statement(const Reader& r, const XMLElement* e, KrlTemplateSet& set,
                    std::map<std::string, int>& statement_line,
                    std::map<std::string, int>& text_line) {
  r.only_attributes(e, {"name"});
  const std::string name = r.required(e, "name");
  const krl::StatementSpec* spec = krl::find_statement(name);
  if (!spec) {
    std::string list;
    for (const krl::StatementSpec& s : krl::statement_specs())
      list += (list.empty() ? "" : ", ") + std::string(s.name);
    r.fail(e, "unknown statement \"" + name + "\" (known: " + list + ")");
  }
  if (statement_line.count(name))
    r.fail(e, "<statement name=\"" + name + "\"> given twice");
  statement_line[name] = e->GetLineNum();
  int line = 0;
  const std::string raw = r.text_of(e, line);
  check_placeholders(r, raw, line, spec->allowed, "<statement name=\"" + name + "\">");
  set.statements[name] = clean_statement(raw, line);
  text_line[name] = line;
}

// A value for each placeholder, as the writer would put one there, to read a template's fixed
// text as `redpost check` reads the program (check_fixed_text).
std::string_view sample_value(krl::Ph p) {
  using krl::Ph;
  switch (p) {
    case Ph::name:
    case Ph::program:
      return "REDPOST_PROGRAM";
    case Ph::callee:
      return "REDPOST_PROGRAM_P001";
    case Ph::base:
      return "BASE_DATA[1]";
    case Ph::tool:
      return "TOOL_DATA[1]";
    case Ph::routine:
      return "TOOL_CHANGE";
    case Ph::header_comment:
      return "text";
    case Ph::tool_name:
      return "T1";
    case Ph::direction:
      return "CW";
    case Ph::clockwise:
      return "TRUE";
    case Ph::mode:
      return "FLOOD";
    case Ph::date:
      return "2026-12-05 00:00:00 UTC";
    case Ph::body:
    case Ph::decls:
    case Ph::frames:
      return "";
    case Ph::ext:
      return ", E1 0.0";
    case Ph::s_bits:
      return "010";
    case Ph::t_bits:
      return "000011";
    case Ph::vel:
      return "0.1";
    default:
      return "1";  // numbers: coordinates, axes, counts, speeds, indices
  }
}

// `text` with its placeholders replaced by sample values; {text} by `text_sample` (a literal's
// is a statement, a comment's words).
std::string with_samples(std::string_view text, std::string_view text_sample = "text") {
  std::string out;
  size_t done = 0;
  for (const krl::PlaceholderUse& u : krl::scan_placeholders(text)) {
    out.append(text.substr(done, u.offset - done));
    out.append(u.ph == krl::Ph::text ? text_sample : sample_value(u.ph));
    done = u.offset + u.name.size() + 2;
  }
  out.append(text.substr(done));
  return out;
}

// The set's text of a file kind: the one place that maps the kinds to the fields.
std::string& skeleton_text(KrlTemplateSet& set, krl::SkeletonKind kind) {
  switch (kind) {
    case krl::SkeletonKind::dat:
      return set.dat_file;
    case krl::SkeletonKind::main_src:
      return set.main_src_file;
    case krl::SkeletonKind::main_dat:
      return set.main_dat_file;
    case krl::SkeletonKind::continued_src:
      return set.continued_src_file;
    case krl::SkeletonKind::src:
      break;
  }
  return set.src_file;
}
const std::string& skeleton_text(const KrlTemplateSet& set, krl::SkeletonKind kind) {
  return skeleton_text(const_cast<KrlTemplateSet&>(set), kind);
}

// The fixed text of every skeleton and statement, with a sample value for each placeholder,
// must pass the text checks of `redpost check` (identifiers of at most 24 characters, statements
// it reads, DEF/END and FOLD pairs, declarations first): a program the set writes must not be
// one check rejects. Refused at the template's line. (The literal statement's {text} is the
// host's statement, checked when it is given: HALT here; ext_axis is a fragment of an
// aggregate.)
void check_fixed_text(const Reader& r, const KrlTemplateSet& set,
                      const std::map<std::string, int>& skeleton_line,
                      const std::map<std::string, int>& statement_line) {
  for (const krl::SkeletonSpec& spec : krl::skeleton_specs()) {
    const auto at = skeleton_line.find(std::string(spec.kind));
    if (at == skeleton_line.end())
      continue;  // an optional file the set does not have
    const std::vector<KrlFinding> found = check_krl_text(
        set.source_file, with_samples(skeleton_text(set, spec.id)), {}, KrlCheckOptions{});
    if (!found.empty())
      r.fail(at->second + found.front().line - 1,
             "<file kind=\"" + std::string(spec.kind) + "\">: " + found.front().message +
                 " (redpost check would reject every program of this set)");
  }
  for (const auto& [name, text] : set.statements) {
    if (name == "ext_axis" || text.empty())
      continue;
    const std::string shown = with_samples(text, name == "literal" ? "HALT" : "text");
    const KrlFinding f = check_krl_statements(shown);
    if (f.line > 0)
      r.fail(statement_line.at(name) + f.line - 1,
             "<statement name=\"" + name + "\">: " + f.message +
                 " (redpost check would reject the programs that use it)");
  }
}

// Every statement the set needs is there, and none it would never use.
void check_statements(const Reader& r, const XMLElement* root, const KrlTemplateSet& set,
                      const std::map<std::string, int>& statement_line) {
  for (const krl::StatementSpec& s : krl::statement_specs()) {
    const auto it = statement_line.find(std::string(s.name));
    if (!s.used_by(set.spline) && it != statement_line.end()) {
      r.fail(it->second, "statement \"" + std::string(s.name) + "\" " +
                             (set.spline ? "is not used by a set with <spline> (feed moves go "
                                           "into spline blocks: spline_lin)"
                                         : "is for spline blocks, but the set has no <spline> "
                                           "element"));
    }
    if (s.required(set.spline) && it == statement_line.end()) {
      r.fail(root, "<krl-templates> needs a <statement name=\"" + std::string(s.name) +
                       "\"> (it may be empty to write nothing)");
    }
  }
  // A segment's own speed is written only with both forms, and only with SPL (the writer
  // would otherwise ignore them: refused, as a statement never used is).
  const auto line_of = [&](const char* name) {
    const auto it = statement_line.find(name);
    return it == statement_line.end() ? 0 : it->second;
  };
  const int lin_vel = line_of("spline_lin_vel"), spl_vel = line_of("spline_spl_vel");
  if ((lin_vel > 0) != (spl_vel > 0)) {
    r.fail(std::max(lin_vel, spl_vel),
           "spline_lin_vel and spline_spl_vel go together: give both, or neither");
  }
  if (lin_vel > 0 && line_of("spline_spl") == 0) {
    r.fail(std::min(lin_vel, spl_vel),
           "spline_lin_vel and spline_spl_vel are used only with spline_spl: add it, or leave "
           "them out");
  }
}

// <timing>: what the program's skeleton sets up for the controller's motion, for the time
// model (docs/timing.md). Every attribute is optional; the defaults are documented there.
void read_timing(const Reader& r, const XMLElement* e, KrlTemplateSet& set) {
  r.only_attributes(e, {"ptp-velocity", "ptp-acceleration", "path-acceleration",
                        "orientation-velocity", "interpolation-cycle", "advance"});
  if (e->Attribute("ptp-velocity"))
    set.timing.ptp_velocity_percent = r.real(e, "ptp-velocity", 1.0, 100.0);
  if (e->Attribute("ptp-acceleration"))
    set.timing.ptp_acceleration_percent = r.real(e, "ptp-acceleration", 1.0, 100.0);
  if (e->Attribute("path-acceleration"))
    set.timing.path_acceleration_m_s2 = r.real(e, "path-acceleration", 0.01, 100.0);
  if (e->Attribute("orientation-velocity"))
    set.timing.orientation_velocity_deg_s = r.real(e, "orientation-velocity", 1.0, 10000.0);
  if (e->Attribute("interpolation-cycle"))
    set.timing.interpolation_cycle_ms = r.real(e, "interpolation-cycle", 1.0, 100.0);
  if (e->Attribute("advance"))
    set.timing.advance = r.integer(e, "advance", 0, 5);
}

// The $ADVANCE a skeleton sets (the last "$ADVANCE = n" of its text), -1 if none: the time
// model must plan with the look-ahead the program really sets.
int skeleton_advance(const std::string& text) {
  int found = -1;
  std::size_t at = 0;
  while ((at = text.find("$ADVANCE", at)) != std::string::npos) {
    std::size_t k = at + 8;
    at = k;
    while (k < text.size() && (text[k] == ' ' || text[k] == '\t'))
      ++k;
    if (k >= text.size() || text[k] != '=')
      continue;
    ++k;
    while (k < text.size() && (text[k] == ' ' || text[k] == '\t'))
      ++k;
    if (k < text.size() && text[k] >= '0' && text[k] <= '9')
      found = text[k] - '0';
  }
  return found;
}

// <file kind="...">: a skeleton, once per kind, with the placeholders its kind may use.
void read_file_element(const Reader& r, const XMLElement* e, KrlTemplateSet& set,
                       std::set<std::string>& files_seen,
                       std::map<std::string, int>& skeleton_line) {
  r.only_attributes(e, {"kind"});
  const std::string kind = r.required(e, "kind");
  const krl::SkeletonSpec* spec = krl::find_skeleton(kind);
  if (!spec) {
    r.fail(e, "unknown file kind \"" + kind +
                  "\" (known: src, dat, main_src, main_dat, continued_src)");
  }
  if (!files_seen.insert(kind).second)
    r.fail(e, "<file kind=\"" + kind + "\"> given twice");
  int line = 0;
  const std::string raw = r.text_of(e, line);
  check_placeholders(r, raw, line, spec->allowed, "<file kind=\"" + kind + "\">");
  std::string text = clean_skeleton(raw, line);
  check_block_placeholders(r, text, line, *spec);
  if (spec->id == krl::SkeletonKind::continued_src)
    check_continued(r, text, line);
  skeleton_line[kind] = line;
  skeleton_text(set, spec->id) = std::move(text);
}

}  // namespace

KrlTemplateSet parse_krl_templates(const std::string& xml_text, const std::string& source_name) {
  Reader r(source_name);
  tinyxml2::XMLDocument doc;
  const XMLElement* root = r.parse(doc, xml_text, "krl-templates");
  r.only_attributes(root, {"name", "format"});
  const std::string format = r.required(root, "format");
  if (format != "1") {
    r.fail(root, "unsupported template format \"" + format + "\" (this redpost reads 1)");
  }

  KrlTemplateSet set;
  set.source_file = source_name;
  set.name = r.required(root, "name");
  if (set.name.empty())
    r.fail(root, "<krl-templates> needs a non-empty name");

  const XMLElement* numbers = nullptr;
  const XMLElement* spline = nullptr;
  const XMLElement* limits = nullptr;
  const XMLElement* timing = nullptr;
  std::set<std::string> files_seen;
  std::map<std::string, int> statement_line, statement_text_line, skeleton_line;

  for (const XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string n = e->Name();
    if (n == "description") {
      r.only_attributes(e, {});
    } else if (n == "numbers") {
      if (numbers)
        r.fail(e, "<numbers> given twice");
      numbers = e;
      r.only_attributes(e, {"position", "angle", "external", "velocity", "rpm"});
      set.position_decimals = r.integer(e, "position", 0, 9);
      set.angle_decimals = r.integer(e, "angle", 0, 9);
      set.external_decimals = r.integer(e, "external", 0, 9);
      set.velocity_decimals = r.integer(e, "velocity", 0, 9);
      set.rpm_decimals = r.integer(e, "rpm", 0, 9);
    } else if (n == "spline") {
      if (spline)
        r.fail(e, "<spline> given twice");
      spline = e;
      r.only_attributes(e, {"max-points"});
      set.spline = true;
      set.max_spline_points = r.integer(e, "max-points", 1, 100000);
    } else if (n == "limits") {
      if (limits)
        r.fail(e, "<limits> given twice");
      limits = e;
      r.only_attributes(e, {"max-bytes", "program-memory"});
      // At least 16 KiB: a program file's skeleton and one motion fit many times over.
      if (e->Attribute("max-bytes") || !e->Attribute("program-memory"))
        set.max_file_bytes = r.integer(e, "max-bytes", 16 * 1024, 1 << 30);
      if (e->Attribute("program-memory"))
        set.program_memory_bytes = r.integer(e, "program-memory", 64 * 1024, 1 << 30);
    } else if (n == "timing") {
      if (timing)
        r.fail(e, "<timing> given twice");
      timing = e;
      read_timing(r, e, set);
    } else if (n == "file") {
      read_file_element(r, e, set, files_seen, skeleton_line);
    } else if (n == "statement") {
      read_statement(r, e, set, statement_line, statement_text_line);
    } else {
      r.fail(e, "unknown element <" + n +
                    "> in <krl-templates> (known: description, numbers, spline, limits, timing, "
                    "file, statement)");
    }
  }

  if (!numbers)
    r.fail(root, "<krl-templates> needs a <numbers> element");
  for (const krl::SkeletonSpec& s : krl::skeleton_specs()) {
    if (s.required && !files_seen.count(std::string(s.kind)))
      r.fail(root, "<krl-templates> needs a <file kind=\"" + std::string(s.kind) + "\">");
  }
  check_statements(r, root, set, statement_line);
  check_fixed_text(r, set, skeleton_line, statement_text_line);
  // The look-ahead the time model plans with is the one the program sets.
  const int set_advance = skeleton_advance(set.src_file);
  if (set_advance >= 0) {
    if (timing && timing->Attribute("advance") && set_advance != set.timing.advance) {
      r.fail(timing, "<timing advance=\"" + std::to_string(set.timing.advance) +
                         "\"> but the src skeleton sets $ADVANCE = " + std::to_string(set_advance) +
                         ": give one value (docs/timing.md)");
    }
    set.timing.advance = set_advance;
  }
  return set;
}

KrlTemplateSet load_krl_templates(const std::string& path) {
  return parse_krl_templates(read_text_file(path), path);
}

}  // namespace redpost
