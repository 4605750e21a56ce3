// Reading KRL programs: a line-based reader of the .src/.dat pairs redpost writes and of the
// usual hand-written forms (docs/krl-diff.md, "Reading KRL").
//
// The reader indexes each module (.src: its DEFs; .dat: the point DECLs), then walks the main
// DEF line by line, following subprogram calls into local DEFs or sibling .src files, and
// records every motion with the state in force. Control flow is not interpreted: the lines of
// IF/LOOP/FOR bodies are read once, in text order, and each skipped kind is warned about once.
#include "redpost/krl/reader.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <set>
#include <utility>

#include "io/text_util.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"

namespace redpost {

namespace {

namespace fs = std::filesystem;

std::string upper(std::string s) {
  for (char& c : s)
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

using detail::trim;

bool is_ident_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '$';
}

// Splits on LF, CRLF or CR.
std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::string cur;
  for (std::size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (c == '\r' || c == '\n') {
      lines.push_back(cur);
      cur.clear();
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n')
        ++i;
    } else {
      cur += c;
    }
  }
  if (!cur.empty())
    lines.push_back(cur);
  return lines;
}

// Splits a line into code and comment at the first ';' outside a "..." string.
void split_comment(const std::string& line, std::string& code, std::string& comment) {
  bool in_string = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == '"')
      in_string = !in_string;
    if (line[i] == ';' && !in_string) {
      code = trim(line.substr(0, i));
      comment = line.substr(i + 1);
      return;
    }
  }
  code = trim(line);
  comment.clear();
}

// The leading identifier of `s` (letters, digits, '_', '$'), upper case.
std::string leading_word(const std::string& s) {
  std::size_t i = 0;
  while (i < s.size() && is_ident_char(s[i]))
    ++i;
  return upper(s.substr(0, i));
}

[[noreturn]] void fail(const std::string& file, int line, const std::string& msg) {
  throw Error(ErrorCode::bad_input, msg, SourceLocation{file, line, 0});
}

// --- aggregates ------------------------------------------------------------------------------

const std::set<std::string>& point_types() {
  static const std::set<std::string> t{"E6POS", "E6AXIS", "POS", "AXIS", "FRAME"};
  return t;
}

bool is_value_field(const std::string& f) {
  static const std::set<std::string> names{"X",  "Y",  "Z",  "A",  "B",  "C",  "A1", "A2", "A3",
                                           "A4", "A5", "A6", "E1", "E2", "E3", "E4", "E5", "E6"};
  return names.count(f) != 0;
}

struct Cursor {
  const std::string& text;
  std::size_t pos;
  const std::string& file;
  int line;

  void skip_space() {
    while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos])))
      ++pos;
  }
  bool at_end() {
    skip_space();
    return pos >= text.size();
  }
  char peek() {
    skip_space();
    return pos < text.size() ? text[pos] : '\0';
  }
  std::string word() {
    skip_space();
    std::size_t b = pos;
    while (pos < text.size() && is_ident_char(text[pos]))
      ++pos;
    return text.substr(b, pos - b);
  }
};

int parse_integer_field(Cursor& c, const std::string& field) {
  c.skip_space();
  const std::string& t = c.text;
  if (c.pos < t.size() && t[c.pos] == '\'') {
    // 'B010' (binary) or 'H1F' (hex)
    std::size_t close = t.find('\'', c.pos + 1);
    if (close == std::string::npos)
      fail(c.file, c.line, "malformed aggregate: unterminated literal for " + field);
    std::string lit = upper(trim(t.substr(c.pos + 1, close - c.pos - 1)));
    c.pos = close + 1;
    int base = 0;
    if (!lit.empty() && lit[0] == 'B')
      base = 2;
    if (!lit.empty() && lit[0] == 'H')
      base = 16;
    std::string digits = base ? lit.substr(1) : std::string();
    if (digits.empty() || digits.size() > 30)
      fail(c.file, c.line, "malformed aggregate: bad literal '" + lit + "' for " + field);
    long v = 0;
    for (char d : digits) {
      int dv = std::isdigit(static_cast<unsigned char>(d)) ? d - '0'
               : (d >= 'A' && d <= 'F')                    ? d - 'A' + 10
                                                           : 99;
      if (dv >= base)
        fail(c.file, c.line, "malformed aggregate: bad literal '" + lit + "' for " + field);
      if (v > (INT_MAX - dv) / base)  // S and T are small; a longer literal would overflow
        fail(c.file, c.line, "malformed aggregate: literal '" + lit + "' too large for " + field);
      v = v * base + dv;
    }
    return static_cast<int>(v);
  }
  const char* start = t.c_str() + c.pos;
  char* end = nullptr;
  errno = 0;
  double v = std::strtod(start, &end);  // "6" or "6.0"
  // Range first: converting a double outside int's range (or NaN) is undefined behaviour.
  if (end == start || errno != 0 || !(v >= INT_MIN && v <= INT_MAX) ||
      v != static_cast<double>(static_cast<int>(v)))
    fail(c.file, c.line, "malformed aggregate: " + field + " needs an integer or 'B...' value");
  c.pos += static_cast<std::size_t>(end - start);
  return static_cast<int>(v);
}

double parse_real_field(Cursor& c, const std::string& field) {
  c.skip_space();
  const char* start = c.text.c_str() + c.pos;
  char* end = nullptr;
  errno = 0;
  double v = std::strtod(start, &end);
  if (end == start || errno != 0)
    fail(c.file, c.line, "malformed aggregate: " + field + " needs a number");
  // strtod also reads "nan", "inf" and hex floats, which are not KRL literals; a NaN would
  // compare as "within tolerance" in a diff. KRL's REAL is a 32-bit float.
  const bool decimal = std::all_of(start, static_cast<const char*>(end), [](char ch) {
    return std::isdigit(static_cast<unsigned char>(ch)) || ch == '.' || ch == '+' || ch == '-' ||
           ch == 'e' || ch == 'E';
  });
  if (!decimal || !(std::abs(v) <= 3.4e38)) {
    fail(c.file, c.line,
         "malformed aggregate: " + field + " = " +
             std::string(start, static_cast<const char*>(end)) +
             " is not a finite decimal number within the range of a KRL REAL");
  }
  c.pos += static_cast<std::size_t>(end - start);
  return v;
}

// Parses "{[TYPE:] F v, ...}" at c.pos; leaves c.pos after the '}'.
KrlAggregate parse_aggregate(Cursor& c) {
  KrlAggregate agg;
  if (c.peek() != '{')
    fail(c.file, c.line, "malformed aggregate: expected '{'");
  ++c.pos;
  // optional "TYPE:"
  {
    std::size_t save = c.pos;
    std::string w = c.word();
    if (!w.empty() && c.peek() == ':') {
      agg.type = upper(w);
      if (!point_types().count(agg.type))
        fail(c.file, c.line, "malformed aggregate: type " + agg.type + " is not a point type");
      ++c.pos;
    } else {
      c.pos = save;
    }
  }
  if (c.peek() == '}') {
    ++c.pos;
    return agg;
  }
  std::set<std::string> seen;
  for (;;) {
    std::string field = upper(c.word());
    if (field.empty()) {
      if (c.at_end())
        fail(c.file, c.line, "malformed aggregate: missing '}'");
      fail(c.file, c.line,
           std::string("malformed aggregate: expected a field name at '") + c.peek() + "'");
    }
    if (!seen.insert(field).second)
      fail(c.file, c.line, "malformed aggregate: field " + field + " given twice");
    if (field == "S") {
      agg.status = parse_integer_field(c, field);
    } else if (field == "T") {
      agg.turn = parse_integer_field(c, field);
    } else if (is_value_field(field)) {
      agg.values[field] = parse_real_field(c, field);
    } else {
      fail(c.file, c.line, "malformed aggregate: unknown field " + field);
    }
    char next = c.peek();
    if (next == ',') {
      ++c.pos;
      continue;
    }
    if (next == '}') {
      ++c.pos;
      return agg;
    }
    if (next == '\0')
      fail(c.file, c.line, "malformed aggregate: missing '}'");
    fail(c.file, c.line, std::string("malformed aggregate: expected ',' or '}' at '") + next + "'");
  }
}

// --- modules ---------------------------------------------------------------------------------

struct DefRange {
  std::string name;  // as written
  int begin = 0;     // index of the DEF line
  int end = 0;       // index of the END line
};

struct Module {
  std::string src_path;
  std::string dat_path;  // "" if none
  std::vector<std::string> lines;
  std::vector<DefRange> defs;                  // in file order; defs[0] is the module's main DEF
  std::map<std::string, KrlAggregate> points;  // upper-case name -> value
  std::map<std::string, std::string> array_types;  // upper-case array name -> point type
  int stray_line = 0;  // first line of code outside a DEF (0: none), warned about
};

bool is_motion_keyword(const std::string& w);

// Finds `stem.ext` in `dir` regardless of case; "" if absent.
std::string find_file_nocase(const fs::path& dir, const std::string& stem, const std::string& ext) {
  const std::string want = upper(stem + "." + ext);
  std::error_code ec;
  fs::path exact = dir / (stem + "." + ext);
  if (fs::is_regular_file(exact, ec))
    return exact.string();
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (upper(it->path().filename().string()) == want && it->is_regular_file(ec))
      return it->path().string();
  }
  return "";
}

// A DECL line (in the .dat or a DEF): "[DECL] [GLOBAL] TYPE NAME = {...}" or
// "NAME[i] = {...}" for an element of a declared point array. Other DECLs are skipped.
void read_decl(const std::string& code, const std::string& file, int line_no, Module& m) {
  std::string rest = code;
  std::string w = leading_word(rest);
  auto drop_word = [&](const std::string& word) { rest = trim(rest.substr(word.size())); };
  bool had_decl = false;
  if (w == "DECL") {
    drop_word(w);
    had_decl = true;
    w = leading_word(rest);
  }
  if (w == "GLOBAL") {
    drop_word(w);
    w = leading_word(rest);
  }
  if (w == "CONST") {
    drop_word(w);
    w = leading_word(rest);
  }
  std::string type;
  if (point_types().count(w)) {
    type = w;
    drop_word(w);
  } else if (!had_decl && m.array_types.count(w) && rest.size() > w.size() &&
             trim(rest.substr(w.size())).rfind('[', 0) == 0) {
    // NAME[i]={...}
    std::size_t eq = rest.find('=');
    if (eq == std::string::npos)
      return;
    std::string name = upper(trim(rest.substr(0, eq)));
    name.erase(std::remove_if(name.begin(), name.end(),
                              [](char ch) { return std::isspace(static_cast<unsigned char>(ch)); }),
               name.end());
    Cursor c{rest, eq + 1, file, line_no};
    KrlAggregate a = parse_aggregate(c);
    if (a.type.empty())
      a.type = m.array_types[w];
    m.points[name] = a;
    return;
  } else {
    return;  // not a point declaration
  }
  std::string name = leading_word(rest);
  if (name.empty())
    return;
  drop_word(name);
  if (!rest.empty() && rest[0] == '[') {  // an array declaration: DECL E6POS XP[10]
    m.array_types[name] = type;
    return;
  }
  if (rest.empty() || rest[0] != '=')
    return;  // declared without a value
  if (trim(rest.substr(1)).rfind('{', 0) != 0)
    return;  // "= P1" or an expression: not a literal
  Cursor c{rest, 1, file, line_no};
  KrlAggregate a = parse_aggregate(c);
  if (a.type.empty())
    a.type = type;
  m.points[name] = a;
}

Module load_module(const std::string& src_path) {
  Module m;
  m.src_path = src_path;
  m.lines = split_lines(read_text_file(src_path));
  const std::string& file = src_path;

  // DEFs and their ENDs
  int open = -1;
  std::string open_name;
  bool open_is_fct = false;
  for (int i = 0; i < static_cast<int>(m.lines.size()); ++i) {
    std::string code, comment;
    split_comment(m.lines[i], code, comment);
    std::string w = leading_word(code);
    if (w == "GLOBAL")
      w = leading_word(trim(code.substr(6)));
    if (w == "DEF" || w == "DEFFCT") {
      if (open >= 0)
        fail(file, open + 1,
             "missing END: " + std::string(open_is_fct ? "DEFFCT " : "DEF ") + open_name +
                 " is not closed before the " + w + " at line " + std::to_string(i + 1));
      open = i;
      open_is_fct = w == "DEFFCT";
      std::string after = trim(code.substr(code.find_first_of(" \t") == std::string::npos
                                               ? code.size()
                                               : code.find_first_of(" \t")));
      if (upper(leading_word(code)) == "GLOBAL")
        after = trim(after.substr(after.find(' ') + 1));
      if (open_is_fct)
        after = trim(after.substr(leading_word(after).size()));  // the type
      open_name = leading_word(after);
      if (open_name.empty())
        fail(file, i + 1, "DEF without a name");
    } else if (open < 0 && !code.empty() && code[0] != '&') {
      if (is_motion_keyword(w))
        fail(file, i + 1, "motion outside DEF");
      if (!m.stray_line)
        m.stray_line = i + 1;
    } else if (w == "END" || w == "ENDFCT") {
      if (open < 0)
        fail(file, i + 1, w + " without DEF");
      if ((w == "ENDFCT") != open_is_fct)
        fail(file, i + 1, w + " closes " + (open_is_fct ? "DEFFCT " : "DEF ") + open_name);
      if (!open_is_fct)
        m.defs.push_back(DefRange{open_name, open, i});
      open = -1;
    }
  }
  if (open >= 0)
    fail(file, open + 1,
         "missing END: " + std::string(open_is_fct ? "DEFFCT " : "DEF ") + open_name +
             " is not closed before the end of the file");
  if (m.defs.empty())
    fail(file, 0, "no DEF in the file");

  // local point DECLs in the DEFs
  for (int i = 0; i < static_cast<int>(m.lines.size()); ++i) {
    std::string code, comment;
    split_comment(m.lines[i], code, comment);
    if (leading_word(code) == "DECL")
      read_decl(code, file, i + 1, m);
  }

  // the .dat beside it
  fs::path p(src_path);
  m.dat_path = find_file_nocase(p.parent_path().empty() ? fs::path(".") : p.parent_path(),
                                p.stem().string(), "dat");
  if (!m.dat_path.empty()) {
    std::vector<std::string> dat = split_lines(read_text_file(m.dat_path));
    bool in_defdat = false;
    for (int i = 0; i < static_cast<int>(dat.size()); ++i) {
      std::string code, comment;
      split_comment(dat[i], code, comment);
      if (code.empty() || code[0] == '&')
        continue;
      std::string w = leading_word(code);
      if (w == "DEFDAT") {
        in_defdat = true;
        continue;
      }
      if (w == "ENDDAT") {
        in_defdat = false;
        continue;
      }
      if (in_defdat)
        read_decl(code, m.dat_path, i + 1, m);
    }
  }
  return m;
}

// --- execution -------------------------------------------------------------------------------

struct State {
  int cl_line = 0;
  double vel_cp = 0.0;
  std::string base, tool;
};

const std::set<std::string>& motion_keywords() {
  static const std::set<std::string> k{"PTP",      "LIN",      "CIRC",     "SPTP",    "SLIN",
                                       "SCIRC",    "SPL",      "LIN_REL",  "PTP_REL", "CIRC_REL",
                                       "SPTP_REL", "SLIN_REL", "SCIRC_REL"};
  return k;
}

bool is_motion_keyword(const std::string& w) {
  return motion_keywords().count(w) != 0;
}

const std::set<std::string>& approximations() {
  static const std::set<std::string> a{"C_DIS", "C_VEL", "C_PTP", "C_ORI", "C_SPL"};
  return a;
}

// Statements skipped without a word: set-up that redpost and the usual templates write.
const std::set<std::string>& quiet_keywords() {
  static const std::set<std::string> q{"INTERRUPT", "GLOBAL", "EXT",  "EXTFCT", "DECL",
                                       "CONTINUE",  "SIGNAL", "ENUM", "STRUC"};
  return q;
}

// Calls of built-ins that are not followed, silently.
const std::set<std::string>& builtin_calls() {
  static const std::set<std::string> b{"BAS", "IR_STOPM", "LOADDATA", "H50",
                                       "H70", "P00",      "TQM_INI",  "USER_GRP"};
  return b;
}

// System variables that only tune motion: set without a warning.
bool quiet_system_variable(const std::string& lhs) {
  static const std::set<std::string> q{
      "$ADVANCE",   "$APO",       "$VEL",       "$ACC",       "$VEL_AXIS",  "$ACC_AXIS",
      "$ORI_TYPE",  "$CIRC_TYPE", "$VEL_EXTAX", "$ACC_EXTAX", "$CIRC_MODE", "$SPL_ORI_JOINT_AUTO",
      "$GEAR_JERK", "$JERK"};
  std::string head = lhs.substr(0, lhs.find_first_of(".["));
  return q.count(head) != 0;
}

class Reader {
 public:
  explicit Reader(KrlProgram& out) : out_(out) {}

  void run(const std::string& src_path) {
    const Module& m = module(src_path);
    out_.main_file = m.src_path;
    const std::string stem = upper(fs::path(src_path).stem().string());
    int k = 0;
    for (int j = 0; j < static_cast<int>(m.defs.size()); ++j)
      if (upper(m.defs[j].name) == stem)
        k = j;
    execute(m, k);
  }

 private:
  KrlProgram& out_;
  std::map<std::string, std::unique_ptr<Module>> modules_;  // by canonical path
  std::vector<std::pair<const Module*, int>> stack_;        // DEFs being executed
  std::set<std::string> warned_;
  State state_;
  int spline_start_ = -1;  // index in out_.motions where the open SPLINE block started

  const Module& module(const std::string& path) {
    std::error_code ec;
    std::string key = fs::weakly_canonical(fs::path(path), ec).string();
    if (ec)
      key = path;
    auto it = modules_.find(key);
    if (it != modules_.end())
      return *it->second;
    auto m = std::make_unique<Module>(load_module(path));
    out_.files.push_back(path);
    if (m->stray_line)
      warn_once("outside-def:" + path, path, m->stray_line, "statement outside DEF skipped");
    return *(modules_[key] = std::move(m));
  }

  void warn_once(const std::string& kind, const std::string& file, int line,
                 const std::string& msg) {
    if (!warned_.insert(kind).second)
      return;
    out_.warnings.push_back(file + ":" + std::to_string(line) + ": " + msg);
  }

  void execute(const Module& m, int def_index) {
    for (const auto& frame : stack_) {
      if (frame.first == &m && frame.second == def_index) {
        std::string chain;
        for (const auto& f : stack_)
          chain += f.first->defs[f.second].name + " -> ";
        chain += m.defs[def_index].name;
        throw Error(ErrorCode::bad_input, "call cycle: " + chain, pending_call_);
      }
    }
    if (stack_.size() >= 64)
      throw Error(ErrorCode::bad_input, "subprogram calls nested more than 64 deep", pending_call_);
    stack_.emplace_back(&m, def_index);
    const DefRange& d = m.defs[def_index];
    for (int i = d.begin + 1; i < d.end; ++i)
      statement(m, i);
    stack_.pop_back();
  }

  SourceLocation pending_call_;

  void statement(const Module& m, int index) {
    const std::string& file = m.src_path;
    const int line = index + 1;
    std::string code, comment;
    split_comment(m.lines[index], code, comment);
    if (code.empty()) {
      cl_comment(comment);
      return;
    }
    std::string w = leading_word(code);
    if (w.empty()) {
      warn_once("syntax:" + code.substr(0, 1), file, line, "statement not understood, skipped");
      return;
    }
    if (motion_keywords().count(w)) {
      motion(m, line, w, trim(code.substr(w.size())));
      return;
    }
    std::string rest = trim(code.substr(w.size()));
    if (w == "SPLINE" || w == "PTP_SPLINE") {
      spline_start_ = static_cast<int>(out_.motions.size());
      return;
    }
    if (w == "ENDSPLINE" || w == "ENDPTP_SPLINE") {
      std::string a = upper(leading_word(rest));
      if (approximations().count(a) && spline_start_ >= 0 &&
          static_cast<int>(out_.motions.size()) > spline_start_)
        out_.motions.back().approximation = a;
      spline_start_ = -1;
      return;
    }
    if (!rest.empty() && rest[0] == '=' && (rest.size() < 2 || rest[1] != '=')) {
      assignment(file, line, w, trim(rest.substr(1)));
      return;
    }
    if (w[0] == '$') {  // $APO.CDIS = ..., $OUT[1] = ...
      std::size_t eq = code.find('=');
      std::string lhs = upper(trim(code.substr(0, eq)));
      lhs.erase(
          std::remove_if(lhs.begin(), lhs.end(),
                         [](char ch) { return std::isspace(static_cast<unsigned char>(ch)); }),
          lhs.end());
      if (eq == std::string::npos) {
        warn_once("statement:" + w, file, line, "statement " + w + " skipped");
        return;
      }
      assignment(file, line, lhs, trim(code.substr(eq + 1)));
      return;
    }
    static const std::set<std::string> flow{
        "IF",        "ELSE",     "ENDIF",  "LOOP",   "ENDLOOP", "FOR",  "ENDFOR",
        "WHILE",     "ENDWHILE", "REPEAT", "UNTIL",  "SWITCH",  "CASE", "DEFAULT",
        "ENDSWITCH", "GOTO",     "EXIT",   "RETURN", "HALT",    "WAIT", "TRIGGER",
        "PULSE",     "ANIN",     "ANOUT",  "BRAKE",  "RESUME"};
    if (flow.count(w)) {
      static const std::set<std::string> closers{"ELSE",      "ENDIF",    "ENDLOOP",
                                                 "ENDFOR",    "ENDWHILE", "UNTIL",
                                                 "ENDSWITCH", "CASE",     "DEFAULT"};
      if (closers.count(w))
        return;  // the opener was warned about
      warn_once("flow:" + w, file, line,
                w + " not interpreted (control flow and I/O are skipped; motions are read in "
                    "text order)");
      return;
    }
    if (!rest.empty() && rest[0] == '(' && code.back() == ')') {
      call(m, line, w);
      return;
    }
    if (quiet_keywords().count(w))
      return;
    if (rest.find('=') != std::string::npos) {  // "P[1].X = 3" and the like
      warn_once("assignment", file, line, "assignment to a variable skipped: " + code);
      return;
    }
    warn_once("statement:" + w, file, line, "statement " + w + " skipped");
  }

  void cl_comment(const std::string& comment) {
    std::string t = upper(trim(comment));
    if (t.rfind("CL LINE", 0) != 0)
      return;
    std::string num = trim(t.substr(7));
    char* end = nullptr;
    long v = std::strtol(num.c_str(), &end, 10);
    if (end != num.c_str() && v > 0)
      state_.cl_line = static_cast<int>(v);
  }

  void assignment(const std::string& file, int line, std::string lhs, const std::string& rhs) {
    lhs = upper(lhs);
    if (lhs == "$VEL.CP") {
      char* end = nullptr;
      double v = std::strtod(rhs.c_str(), &end);
      if (end == rhs.c_str() || !trim(std::string(end)).empty()) {
        warn_once("vel-expr", file, line, "$VEL.CP = " + rhs + " is not a number: not tracked");
        return;
      }
      state_.vel_cp = v;
      return;
    }
    if (lhs == "$BASE") {
      state_.base = rhs;
      return;
    }
    if (lhs == "$TOOL") {
      state_.tool = rhs;
      return;
    }
    if (lhs[0] == '$') {
      if (quiet_system_variable(lhs))
        return;
      std::string head = lhs.substr(0, lhs.find_first_of(".["));
      warn_once("sysvar:" + head, file, line, "assignment to " + head + " skipped");
      return;
    }
    warn_once("assignment", file, line, "assignment to a variable skipped: " + lhs);
  }

  void call(const Module& m, int line, const std::string& name) {
    const std::string& file = m.src_path;
    // a local DEF in the same file (not the module's main DEF unless named)
    for (int k = 0; k < static_cast<int>(m.defs.size()); ++k) {
      if (upper(m.defs[k].name) == name) {
        pending_call_ = SourceLocation{file, line, 0};
        execute(m, k);
        return;
      }
    }
    if (builtin_calls().count(name))
      return;
    fs::path dir = fs::path(file).parent_path();
    if (dir.empty())
      dir = ".";
    std::string path = find_file_nocase(dir, name, "src");
    if (!path.empty()) {
      pending_call_ = SourceLocation{file, line, 0};
      const Module& sub = module(path);
      int k = 0;
      for (int j = 0; j < static_cast<int>(sub.defs.size()); ++j)
        if (upper(sub.defs[j].name) == name)
          k = j;
      pending_call_ = SourceLocation{file, line, 0};
      execute(sub, k);
      return;
    }
    // Not found. A program part (the caller's module name followed by "_P<digits>", as
    // redpost's split programs name them) must be there; anything else may be a global
    // subprogram of the controller.
    std::string caller = upper(fs::path(stack_.front().first->src_path).stem().string());
    bool part = name.size() > caller.size() + 2 && name.compare(0, caller.size(), caller) == 0 &&
                name.compare(caller.size(), 2, "_P") == 0 &&
                name.find_first_not_of("0123456789", caller.size() + 2) == std::string::npos;
    if (part)
      fail(file, line,
           "program part " + name + " not found: no DEF " + name + " in this file and no " + name +
               ".src in " + dir.string());
    warn_once(
        "call:" + name, file, line,
        "call of " + name + " not followed: no DEF in this file and no " + name + ".src beside it");
  }

  KrlAggregate point(const Module& m, Cursor& c, std::size_t& taken) {
    c.skip_space();
    if (c.peek() == '{')
      return parse_aggregate(c);
    std::size_t b = c.pos;
    std::string name = c.word();
    if (name.empty())
      fail(c.file, c.line, "expected a point name or an aggregate");
    if (c.peek() == '[') {
      std::size_t close = c.text.find(']', c.pos);
      if (close == std::string::npos)
        fail(c.file, c.line, "missing ']' after " + name);
      c.pos = close + 1;
    }
    std::string key = upper(c.text.substr(b, c.pos - b));
    key.erase(std::remove_if(key.begin(), key.end(),
                             [](char ch) { return std::isspace(static_cast<unsigned char>(ch)); }),
              key.end());
    if (c.peek() == '.')
      fail(c.file, c.line, "point " + key + ": component access is not supported");
    if (key[0] == '$') {
      warn_once("sys-point:" + key, c.file, c.line,
                "target " + key + " is a system variable: recorded without coordinates");
      ++taken;
      return KrlAggregate{};
    }
    auto it = m.points.find(key);
    if (it == m.points.end())
      fail(c.file, c.line,
           "undeclared point " + key + " (not declared in " +
               (m.dat_path.empty() ? std::string("a .dat beside the .src (none found)")
                                   : m.dat_path) +
               " nor in the DEF; global points of $config.dat are not read)");
    return it->second;
  }

  void motion(const Module& m, int line, const std::string& kw, const std::string& args) {
    if (stack_.empty())
      fail(m.src_path, line, "motion outside DEF");
    KrlMotionRecord r;
    r.keyword = kw;
    r.relative = kw.size() > 4 && kw.compare(kw.size() - 4, 4, "_REL") == 0;
    r.file = m.src_path;
    r.line = line;
    r.cl_line = state_.cl_line;
    r.vel_cp_m_per_s = state_.vel_cp;
    r.base = state_.base;
    r.tool = state_.tool;
    Cursor c{args, 0, m.src_path, line};
    std::size_t unused = 0;
    if (c.at_end())
      fail(m.src_path, line, kw + " without a target");
    KrlAggregate first = point(m, c, unused);
    bool circ = kw == "CIRC" || kw == "SCIRC" || kw == "CIRC_REL" || kw == "SCIRC_REL";
    if (circ) {
      if (c.peek() != ',')
        fail(m.src_path, line, kw + " needs an auxiliary point and a target");
      ++c.pos;
      r.aux = first;
      r.target = point(m, c, unused);
    } else {
      r.target = first;
    }
    // the rest: [CA angle] [C_xxx] [WITH ...]
    while (!c.at_end()) {
      std::size_t b = c.pos;
      std::string w = upper(c.word());
      if (w.empty()) {
        fail(m.src_path, line,
             std::string("unexpected '") + c.text.substr(b, 1) + "' after the " + kw + " target");
      }
      if (approximations().count(w)) {
        r.approximation = w;
      } else if (w == "CA") {
        parse_real_field(c, "CA");
      } else if (w == "WITH") {
        break;  // SLIN ... WITH $VEL = ...: per-motion parameters are not tracked
      } else {
        fail(m.src_path, line, "unexpected '" + w + "' after the " + kw + " target");
      }
    }
    out_.motions.push_back(std::move(r));
  }
};

}  // namespace

KrlProgram read_krl_program(const std::string& src_path) {
  KrlProgram program;
  Reader reader(program);
  reader.run(src_path);
  return program;
}

}  // namespace redpost
