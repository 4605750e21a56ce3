// A static check of KRL programs (docs/krl-diff.md).
#include "redpost/krl/check.hpp"

#include "krl/check_motions.hpp"
#include "krl/reader_parse.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

#include <fmt/format.h>

#include "io/text_util.hpp"
#include "krl/text.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/krl/diff.hpp"
#include "redpost/krl/statement.hpp"

namespace redpost {

namespace fs = std::filesystem;

namespace {

using detail::trim;
using krl::ident_char;
using krl::ident_start;
using krl::upper;

// The code of a line: the comment (from ';' outside quotes) removed, and the contents of
// "strings" and 'B010' literals blanked so that they are not read as identifiers.
std::string code_of(const std::string& line) {
  std::string out;
  out.reserve(line.size());
  char quote = 0;
  for (char c : line) {
    if (quote) {
      if (c == quote) {
        quote = 0;
        out += c;
      } else {
        out += ' ';
      }
      continue;
    }
    if (c == ';')
      break;
    if (c == '"' || c == '\'')
      quote = c;
    out += c;
  }
  return out;
}

std::vector<std::string> words(const std::string& code) {
  std::vector<std::string> out;
  size_t i = 0;
  while (i < code.size()) {
    if (ident_start(code[i])) {
      size_t j = i;
      while (j < code.size() && ident_char(code[j]))
        ++j;
      out.push_back(upper(code.substr(i, j - i)));
      i = j;
    } else {
      ++i;
    }
  }
  return out;
}

const std::set<std::string>& builtin_types() {
  static const std::set<std::string> t = {"INT", "REAL",  "BOOL", "CHAR",  "FRAME",
                                          "POS", "E6POS", "AXIS", "E6AXIS"};
  return t;
}

const std::set<std::string>& motion_keywords() {
  static const std::set<std::string> k = {"PTP",     "LIN",      "CIRC",     "SPTP",
                                          "SLIN",    "SCIRC",    "SPL",      "PTP_REL",
                                          "LIN_REL", "CIRC_REL", "SPTP_REL", "SLIN_REL"};
  return k;
}

// Words after which a motion's arguments end.
const std::set<std::string>& motion_options() {
  static const std::set<std::string> k = {"C_DIS", "C_PTP", "C_VEL", "C_ORI", "C_SPL",
                                          "CA",    "CT",    "WITH",  "#BASE", "#TOOL"};
  return k;
}

// Names a motion may use without declaring them in its module ($config.dat globals).
const std::set<std::string>& global_points() {
  static const std::set<std::string> k = {"HOME", "XHOME"};
  return k;
}

// Is the line (code, upper-case words) a declaration? Sets `names` to the names it declares.
bool declaration(const std::string& code, const std::vector<std::string>& w,
                 std::vector<std::string>* names) {
  size_t i = 0;
  if (i < w.size() && w[i] == "GLOBAL")
    ++i;
  bool decl = false;
  if (i < w.size() && w[i] == "DECL") {
    decl = true;
    ++i;
  }
  while (i < w.size() && (w[i] == "GLOBAL" || w[i] == "CONST"))
    ++i;
  if (!decl) {
    if (i < w.size() && (w[i] == "STRUC" || w[i] == "ENUM" || w[i] == "SIGNAL" || w[i] == "EXT" ||
                         w[i] == "EXTFCT" || w[i] == "IMPORT"))
      return true;
    // Implicit DECL: a built-in type followed by a name ("INT I", "E6POS P1").
    if (!(i + 1 < w.size() && builtin_types().count(w[i])))
      return false;
    // "INT I" but not "INTERRUPT ..." (words() splits on identifiers, so INT is a whole word)
  }
  if (!names)
    return true;
  // After the type: NAME[dims] = value, NAME2, ...; split at top-level commas.
  const std::string type = i < w.size() ? w[i] : "";
  const std::string ucode = upper(code);
  size_t pos = ucode.find(type, ucode.find(decl ? "DECL" : type) + (decl ? 4 : 0));
  if (type.empty() || pos == std::string::npos)
    return true;
  pos += type.size();
  int depth = 0;
  bool expect_name = true;
  while (pos < ucode.size()) {
    const char c = ucode[pos];
    if (c == '{' || c == '[' || c == '(') {
      ++depth;
    } else if (c == '}' || c == ']' || c == ')') {
      --depth;
    } else if (c == ',' && depth == 0) {
      expect_name = true;
    } else if (c == '=' && depth == 0) {
      expect_name = false;
    } else if (expect_name && depth == 0 && ident_start(c)) {
      size_t j = pos;
      while (j < ucode.size() && ident_char(ucode[j]))
        ++j;
      names->push_back(ucode.substr(pos, j - pos));
      expect_name = false;
      pos = j;
      continue;
    }
    ++pos;
  }
  return true;
}

struct Block {
  std::string kind;  // DEF, DEFFCT, DEFDAT
  std::string name;
  int line = 0;
  int first_statement = 0;
};

// An assignment whose value is an expression the pass-through grammar (statement.hpp) does not
// have: an aggregate (`$BASE = {FRAME: X 0, ...}`), a function call (`$BASE = EK(...)`), an
// arithmetic or logical expression. The variable is checked as statement.hpp reads it; the
// value by its shape: brackets nested and closed, only the characters of KRL expressions.
bool expression_assignment(const std::string& code) {
  size_t eq = code.find('=');
  while (eq != std::string::npos && eq + 1 < code.size() && code[eq + 1] == '=')
    eq = code.find('=', eq + 2);
  if (eq == std::string::npos || eq == 0 ||
      std::string("<>=").find(code[eq - 1]) != std::string::npos)
    return false;
  const std::string value = trim(code.substr(eq + 1));
  if (value.empty() || std::string("+-*/=<>,:").find(value.back()) != std::string::npos ||
      !krl::statement_problem(code.substr(0, eq) + "= 0").empty())
    return false;
  std::string open;
  for (char c : value) {
    const bool word =
        std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '$' || c == '#' || c == '.';
    if (c == '(' || c == '[' || c == '{') {
      open += c;
    } else if (c == ')' || c == ']' || c == '}') {
      const char want = c == ')' ? '(' : c == ']' ? '[' : '{';
      if (open.empty() || open.back() != want)
        return false;
      open.pop_back();
    } else if (!word && std::string(" \t,:+-*/=<>\"'").find(c) == std::string::npos) {
      return false;
    }
  }
  return open.empty();
}

// Is the line a statement of KRL's flow, interrupts, splines or module declarations? Checked
// by their shape: the keyword, and the word that must follow it where there is one.
std::string flow_statement_problem(const std::vector<std::string>& w) {
  const auto has = [&](const char* word) { return std::find(w.begin(), w.end(), word) != w.end(); };
  static const std::set<std::string> alone = {
      "ELSE",   "ENDIF",     "ENDFOR",     "ENDWHILE", "LOOP",   "ENDLOOP",
      "REPEAT", "DEFAULT",   "ENDSWITCH",  "EXIT",     "RETURN", "CONTINUE",
      "SPLINE", "ENDSPLINE", "PTP_SPLINE", "BRAKE",    "RESUME"};
  const std::string& k = w[0];
  if (alone.count(k))
    return {};
  if (k == "IF")
    return has("THEN") ? "" : "IF without THEN";
  if (k == "FOR")
    return has("TO") ? "" : "FOR without TO";
  if (k == "WHILE" || k == "UNTIL" || k == "SWITCH" || k == "CASE" || k == "GOTO")
    return w.size() > 1 ? "" : k + " without its condition or value";
  if (k == "TRIGGER")
    return has("WHEN") && has("DO") ? "" : "TRIGGER needs WHEN ... DO ...";
  if (k == "INTERRUPT" || (k == "GLOBAL" && w.size() > 1 && w[1] == "INTERRUPT")) {
    const size_t i = k == "GLOBAL" ? 2 : 1;
    if (i < w.size() && (w[i] == "ON" || w[i] == "OFF" || w[i] == "ENABLE" || w[i] == "DISABLE"))
      return {};
    return i < w.size() && w[i] == "DECL" && has("WHEN") && has("DO")
               ? ""
               : "INTERRUPT needs ON, OFF, ENABLE, DISABLE or DECL ... WHEN ... DO ...";
  }
  static const std::set<std::string> module_decls = {"EXT",   "EXTFCT", "IMPORT", "ENUM",
                                                     "STRUC", "SIGNAL", "CONST"};
  const size_t d = k == "GLOBAL" && w.size() > 1 ? 1 : 0;
  if (module_decls.count(w[d]))
    return {};
  return "none";
}

std::string closing_of(const std::string& kind) {
  return kind == "DEFFCT" ? "ENDFCT" : kind == "DEFDAT" ? "ENDDAT" : "END";
}

template <typename F>
void for_each_line(const std::string& text, F f) {
  size_t pos = 0;
  int line = 0;
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    if (eol == std::string::npos)
      eol = text.size();
    std::string l = text.substr(pos, eol - pos);
    if (!l.empty() && l.back() == '\r')
      l.pop_back();
    f(++line, l);
    pos = eol + 1;
  }
}

std::string normal(const std::string& path) {
  return fs::path(path).lexically_normal().string();
}

// The .dat beside a .src (same stem, extension in any case), or "".
std::string dat_of(const fs::path& src) {
  return krl::find_file_nocase(src.has_parent_path() ? src.parent_path() : fs::path("."),
                               src.stem().string(), "dat");
}

// The text checks of one file, fed line by line: what is open (DEFs, FOLDs) and what was found.
struct TextCheck {
  explicit TextCheck(const std::string& checked_file) : file(checked_file) {}

  const std::string& file;
  std::set<std::string> declared;  // in the file and its .dat
  std::vector<int> folds;          // lines of the FOLDs open
  std::vector<Block> blocks;       // the DEF, DEFFCT or DEFDAT open
  std::set<std::string> long_reported;
  std::vector<KrlFinding> out;

  void find(int line, std::string message) { out.push_back({file, line, std::move(message)}); }

  // Lines that end in CR alone (classic Mac OS): the whole file would read as one line, and
  // every check after this would report a consequence ("no END") instead of the cause.
  void cr_alone(int line) {
    find(line,
         "a carriage return (CR) inside the line: the file's lines end in CR alone "
         "(classic Mac OS line endings), or a line holds a stray CR; a KRC reads "
         "CR LF: convert the line endings");
  }

  // What is still open at the end of the file.
  std::vector<KrlFinding> finish() {
    for (const Block& b : blocks)
      find(b.line, fmt::format("{} {} has no {}", b.kind, b.name, closing_of(b.kind)));
    for (int l : folds)
      find(l, "FOLD without a matching ENDFOLD");
    return std::move(out);
  }

  void check_line(int line_no, const std::string& line) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '&')
      return;
    if (t[0] == ';') {
      fold_comment(line_no, t);
      return;
    }
    const std::string code = code_of(line);
    const std::vector<std::string> w = words(code);
    if (w.empty())
      return;
    identifier_lengths(line_no, code);
    if (block_line(line_no, w))
      return;
    if (declaration_order(line_no, code, w))
      return;
    vel_cp(line_no, code);
    if (motion_keywords().count(w[0])) {
      motion_targets(line_no, code, w[0]);
      return;
    }
    statement(line_no, code, w);
  }

  // Every other line must be a statement a KRC accepts, of the kinds redpost reads: an
  // assignment (of an aggregate too), a routine call, WAIT, HALT, or KRL's flow, interrupt,
  // spline and module keywords. A line check cannot read is a finding, so that free text in a
  // program (or a line cut by a transfer) does not pass unseen.
  void statement(int line_no, const std::string& code, const std::vector<std::string>& w) {
    // A jump label, "NAME:" alone.
    const std::string t = trim(code);
    if (t.size() > 1 && t.back() == ':' && w.size() == 1 && upper(t) == w[0] + ":")
      return;
    const std::string flow = flow_statement_problem(w);
    if (flow.empty())
      return;
    if (flow != "none") {
      find(line_no, flow);
      return;
    }
    if (expression_assignment(code))
      return;
    const std::string why = krl::statement_problem(code);
    if (why.empty())
      return;
    const std::string shown = t.size() > 60 ? t.substr(0, 60) + "..." : t;
    find(line_no, "not a KRL statement that redpost check reads: '" + shown + "' (" + why + ")");
  }

  // FOLD/ENDFOLD pairs.
  void fold_comment(int line_no, const std::string& t) {
    const std::string u = upper(t);
    if (u.rfind(";FOLD", 0) == 0) {
      folds.push_back(line_no);
    } else if (u.rfind(";ENDFOLD", 0) == 0) {
      if (folds.empty())
        find(line_no, "ENDFOLD without a matching FOLD");
      else
        folds.pop_back();
    }
  }

  // Identifiers longer than 24 characters ($ system variables and #enum values excluded).
  void identifier_lengths(int line_no, const std::string& code) {
    size_t i = 0;
    while (i < code.size()) {
      if (ident_start(code[i]) && (i == 0 || !ident_char(code[i - 1]))) {
        size_t j = i;
        while (j < code.size() && ident_char(code[j]))
          ++j;
        const bool system = code[i] == '$' || (i > 0 && code[i - 1] == '#');
        const bool field = i > 0 && code[i - 1] == '.';
        const std::string name = code.substr(i, j - i);
        if (!system && !field && static_cast<int>(name.size()) > kKrlMaxIdentifierLength &&
            long_reported.insert(upper(name)).second)
          find(line_no, fmt::format("identifier '{}' has {} characters, more than {}", name,
                                    name.size(), kKrlMaxIdentifierLength));
        i = j;
      } else {
        ++i;
      }
    }
  }

  // DEF/END blocks. True for a line that opens or closes one.
  bool block_line(int line_no, const std::vector<std::string>& w) {
    size_t k = w[0] == "GLOBAL" ? 1 : 0;
    const std::string first = k < w.size() ? w[k] : "";
    if (first == "DEF" || first == "DEFFCT" || first == "DEFDAT") {
      if (!blocks.empty())
        find(line_no,
             fmt::format("{} inside {} {} (line {}): missing {}", first, blocks.back().kind,
                         blocks.back().name, blocks.back().line, closing_of(blocks.back().kind)));
      Block b;
      b.kind = first;
      size_t n = k + 1;
      if (first == "DEFFCT" && n < w.size())
        ++n;  // the return type
      b.name = n < w.size() ? w[n] : "";
      b.line = line_no;
      blocks.clear();
      blocks.push_back(b);
      return true;
    }
    if (first == "END" || first == "ENDFCT" || first == "ENDDAT") {
      if (blocks.empty()) {
        find(line_no, first + " without a matching DEF");
      } else {
        if (closing_of(blocks.back().kind) != first)
          find(line_no, fmt::format("{} closes {} {} (line {})", first, blocks.back().kind,
                                    blocks.back().name, blocks.back().line));
        blocks.pop_back();
      }
      return true;
    }
    return false;
  }

  // Declarations before statements. True for a declaration; notes the first statement.
  bool declaration_order(int line_no, const std::string& code, const std::vector<std::string>& w) {
    std::vector<std::string> names;
    if (declaration(code, w, &names)) {
      // Declared from here on (KRL declares before it uses: a file is read once, in order).
      declared.insert(names.begin(), names.end());
      if (!blocks.empty() && blocks.back().kind != "DEFDAT" && blocks.back().first_statement > 0)
        find(line_no, fmt::format("declaration after the first statement (line {}): KRL "
                                  "requires declarations before statements",
                                  blocks.back().first_statement));
      return true;
    }
    if (!blocks.empty() && blocks.back().first_statement == 0)
      blocks.back().first_statement = line_no;
    return false;
  }

  // $VEL.CP in (0, 2] m/s.
  void vel_cp(int line_no, const std::string& code) {
    const std::string ucode = upper(code);
    const size_t vel = ucode.find("$VEL.CP");
    if (vel == std::string::npos)
      return;
    size_t p = vel + 7;
    while (p < ucode.size() && ucode[p] == ' ')
      ++p;
    if (p < ucode.size() && ucode[p] == '=' && (p + 1 >= ucode.size() || ucode[p + 1] != '=')) {
      const char* begin = code.c_str() + p + 1;
      char* end = nullptr;
      const double v = std::strtod(begin, &end);
      if (end != begin && trim(std::string(end)).empty() && (v <= 0.0 || v > kKrlMaxVelCp))
        find(line_no, fmt::format("$VEL.CP = {} m/s is out of range (0, {}] m/s", trim(begin),
                                  kKrlMaxVelCp));
    }
  }

  // Named motion targets must be declared.
  void motion_targets(int line_no, const std::string& code, const std::string& keyword) {
    const std::string after = code.substr(upper(code).find(keyword) + keyword.size());
    size_t p = 0;
    int args = 0;
    while (p < after.size() && args < 2) {
      const char c = after[p];
      if (c == ' ' || c == '\t' || c == ',') {
        ++p;
      } else if (c == '{') {
        int depth = 0;
        while (p < after.size()) {
          if (after[p] == '{')
            ++depth;
          if (after[p] == '}' && --depth == 0)
            break;
          ++p;
        }
        ++p;
        ++args;
      } else if (ident_start(c)) {
        size_t j = p;
        while (j < after.size() && ident_char(after[j]))
          ++j;
        const std::string name = upper(after.substr(p, j - p));
        if (motion_options().count(name))
          break;
        ++args;
        if (name[0] != '$' && !global_points().count(name) && !declared.count(name))
          find(line_no,
               fmt::format("motion target '{}' is not declared (neither in this file nor in "
                           "its .dat)",
                           after.substr(p, j - p)));
        p = skip_index_or_component(after, j);
      } else {
        break;
      }
    }
  }

  // Skips an index or a component: P[1], XP1.X
  static size_t skip_index_or_component(const std::string& after, size_t p) {
    while (p < after.size() && (after[p] == '[' || after[p] == '.')) {
      if (after[p] == '[') {
        while (p < after.size() && after[p] != ']')
          ++p;
        ++p;
      } else {
        ++p;
        while (p < after.size() && ident_char(after[p]))
          ++p;
      }
    }
    return p;
  }
};

}  // namespace

std::vector<std::string> krl_declared_names(const std::string& text) {
  std::vector<std::string> names;
  for_each_line(text, [&](int, const std::string& line) {
    const std::string code = code_of(line);
    const std::vector<std::string> w = words(code);
    if (!w.empty())
      declaration(code, w, &names);
  });
  return names;
}

namespace {

// The text checks of one file's whole text. `declared`: the names declared in its .dat; on
// return, with the file's own.
std::vector<KrlFinding> check_text(const std::string& file, const std::string& text,
                                   std::set<std::string>& declared,
                                   const KrlCheckOptions& options) {
  TextCheck c(file);
  if (text.size() > options.max_bytes)
    c.find(1, fmt::format("file is {} bytes, more than the limit of {} (--max-bytes)", text.size(),
                          options.max_bytes));

  // Lines that end in CR alone (classic Mac OS): the whole file would read as one line, and
  // every check after this would report a consequence ("no END") instead of the cause.
  for (size_t cr = text.find('\r'); cr != std::string::npos; cr = text.find('\r', cr + 1)) {
    if (cr + 1 < text.size() && text[cr + 1] != '\n') {
      const int line = 1 + static_cast<int>(std::count(text.begin(),
                                                       text.begin() + static_cast<long>(cr), '\n'));
      c.cr_alone(line);
      return c.out;
    }
  }
  c.declared = std::move(declared);
  for_each_line(text, [&](int line_no, const std::string& line) { c.check_line(line_no, line); });
  declared = std::move(c.declared);
  return c.finish();
}

}  // namespace

std::vector<KrlFinding> check_krl_text(const std::string& file, const std::string& text,
                                       const std::vector<std::string>& dat_declared,
                                       const KrlCheckOptions& options) {
  std::set<std::string> declared(dat_declared.begin(), dat_declared.end());
  return check_text(file, text, declared, options);
}

namespace {

// The text checks of a file read a line at a time (memory: one line, the blocks open and the
// names declared). `declared`: the names declared in its .dat; on return, with the file's own.
std::vector<KrlFinding> check_krl_file(const std::string& file, std::set<std::string>& declared,
                                       const KrlCheckOptions& options) {
  TextCheck c(file);
  c.declared = std::move(declared);
  bool cr_alone = false;
  const std::size_t bytes =
      krl::for_each_krl_line(file, [&](int line, const std::string& text, std::string_view ending) {
        if (ending == "\r") {
          c.out.clear();
          c.cr_alone(line);
          cr_alone = true;
          return false;
        }
        c.check_line(line, text);
        return true;
      });
  declared = std::move(c.declared);
  if (cr_alone)
    return std::move(c.out);
  if (bytes > options.max_bytes)
    c.find(1, fmt::format("file is {} bytes, more than the limit of {} (--max-bytes)", bytes,
                          options.max_bytes));
  return c.finish();
}

}  // namespace

KrlFinding check_krl_statements(const std::string& lines) {
  const std::string text = "DEF REDPOST_CHECK( )\n" + lines + "\nEND\n";
  KrlCheckOptions options;
  std::vector<KrlFinding> found = check_krl_text("", text, {}, options);
  if (found.empty())
    return {};
  KrlFinding first =
      *std::min_element(found.begin(), found.end(),
                        [](const KrlFinding& a, const KrlFinding& b) { return a.line < b.line; });
  first.line = std::max(1, first.line - 1);
  return first;
}

namespace {

// The .src files of a folder and every folder under it (links not followed: a cell's programs
// are often kept one folder per part), and each folder's main programs among its own files.
void find_programs(const std::string& path, std::vector<std::string>& srcs,
                   std::vector<std::string>& mains) {
  std::error_code ec;
  std::vector<std::string> folders{path};
  for (fs::recursive_directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_directory() && !it->is_symlink())
      folders.push_back(it->path().string());
  std::sort(folders.begin() + 1, folders.end());
  for (const std::string& folder : folders) {
    const size_t first = srcs.size();
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
      if (it->is_regular_file() && upper(it->path().extension().string()) == ".SRC")
        srcs.push_back(it->path().string());
    if (srcs.size() == first)
      continue;
    std::sort(srcs.begin() + static_cast<long>(first), srcs.end());
    for (std::string& m : krl_main_programs(folder))
      mains.push_back(std::move(m));
  }
  if (srcs.empty()) {
    throw Error(ErrorCode::bad_input,
                "no KRL program (.src) in this folder or the folders under it: nothing to check",
                SourceLocation{path, 0, 0});
  }
}

}  // namespace

std::vector<KrlFinding> check_krl(const std::string& path, const KrlCheckOptions& options) {
  std::vector<KrlFinding> out;
  std::vector<std::string> srcs, mains;
  std::error_code ec;
  const bool directory = fs::is_directory(path, ec);
  if (!directory && !fs::exists(path, ec))
    throw Error(ErrorCode::io, "no such file or directory", SourceLocation{path, 0, 0});
  if (directory)
    find_programs(path, srcs, mains);
  else
    mains.push_back(path);

  // The program as read: motion checks, the text checks of each file as the reader loads it
  // (the .dat before its .src), and (for a file) the .src files it calls.
  std::set<std::string> seen;
  std::set<std::string> text_checked;                      // by normal path
  std::map<std::string, std::set<std::string>> dat_names;  // by normal path
  const auto check_loaded = [&](const std::string& file, const std::string& text) {
    if (!text_checked.insert(normal(file)).second)
      return;
    std::set<std::string> declared;
    if (upper(fs::path(file).extension().string()) == ".DAT") {
      for (KrlFinding& f : check_text(file, text, declared, options))
        out.push_back(std::move(f));
      dat_names[normal(file)] = std::move(declared);
      return;
    }
    const std::string dat = dat_of(fs::path(file));
    if (!dat.empty() && dat_names.count(normal(dat)))
      declared = dat_names[normal(dat)];
    for (KrlFinding& f : check_text(file, text, declared, options))
      out.push_back(std::move(f));
  };
  std::vector<KrlFinding> reader_stops;  // programs the reader rejected
  for (const std::string& m : mains) {
    try {
      // Streamed: a motion at a time, so that memory does not grow with the program.
      krl::MotionChecks checks(options, m);
      std::set<std::string> loaded;  // this program's files, each counted once
      size_t program_bytes = 0;
      const KrlProgram program = read_krl_program(
          m, [&](const KrlMotionRecord& r) { checks.add(r); },
          [&](const std::string& file, const std::string& text) {
            if (loaded.insert(normal(file)).second)
              program_bytes += text.size();
            check_loaded(file, text);
          });
      for (KrlFinding& f : checks.finish())
        out.push_back(std::move(f));
      if (options.max_program_bytes > 0 && program_bytes > options.max_program_bytes) {
        out.push_back({m, 1,
                       fmt::format("the program's {} files take {} bytes, more than the {} "
                                   "bytes of program memory (--program-memory): the controller "
                                   "cannot load it at once; run it a part at a time "
                                   "(docs/krl-templates.md, \"Splitting\")",
                                   loaded.size(), program_bytes, options.max_program_bytes)});
      }
      if (!directory)
        for (const std::string& f : program.files)
          if (seen.insert(normal(f)).second)
            srcs.push_back(f);
    } catch (const Error& e) {
      if (e.code() != ErrorCode::bad_input)
        throw;
      reader_stops.push_back(
          {e.where().file.empty() ? m : e.where().file, e.where().line, e.message()});
    }
  }
  if (!directory && seen.insert(normal(path)).second)
    srcs.insert(srcs.begin(), path);

  // Files the reader did not load (it stopped early, or no program calls them): read here, a
  // line at a time, the .dat first, whose names the .src may use.
  for (const std::string& src : srcs) {
    if (text_checked.count(normal(src)))
      continue;
    const std::string dat = dat_of(fs::path(src));
    std::set<std::string> declared;
    if (!dat.empty()) {
      const auto known = dat_names.find(normal(dat));
      if (known == dat_names.end()) {
        for (KrlFinding& f : check_krl_file(dat, declared, options))
          out.push_back(std::move(f));
        dat_names[normal(dat)] = declared;
        text_checked.insert(normal(dat));
      } else {
        declared = known->second;
      }
    }
    for (KrlFinding& f : check_krl_file(src, declared, options))
      out.push_back(std::move(f));
    text_checked.insert(normal(src));
  }

  for (KrlFinding& f : out)
    f.file = normal(f.file);
  // A program the reader rejects is a finding; where a text check already reports that line
  // (an undeclared point, say), only note that the motion checks were not done.
  for (KrlFinding& r : reader_stops) {
    r.file = normal(r.file);
    const bool known = std::any_of(out.begin(), out.end(), [&](const KrlFinding& f) {
      return f.file == r.file && f.line == r.line;
    });
    if (known)
      r.message = "the program cannot be read past this line: S/T and cell-limit checks not done";
    out.push_back(std::move(r));
  }
  std::sort(out.begin(), out.end(), [](const KrlFinding& a, const KrlFinding& b) {
    if (a.file != b.file)
      return a.file < b.file;
    if (a.line != b.line)
      return a.line < b.line;
    return a.message < b.message;
  });
  out.erase(std::unique(out.begin(), out.end(),
                        [](const KrlFinding& a, const KrlFinding& b) {
                          return a.file == b.file && a.line == b.line && a.message == b.message;
                        }),
            out.end());
  return out;
}

}  // namespace redpost
