// Reading KRL programs: a line-based reader of the .src/.dat pairs redpost writes and of the
// usual hand-written forms (docs/krl-diff.md, "Reading KRL"). This file holds the walk through
// the program; lines, aggregates and the index of a module are parsed by krl/reader_parse.hpp.
//
// The reader indexes each module (.src: its DEFs; .dat: the point DECLs), then walks the main
// DEF line by line, following subprogram calls into local DEFs or sibling .src files, and
// records every motion with the state in force. Control flow is not interpreted: the lines of
// IF/LOOP/FOR bodies are read once, in text order, and each skipped kind is warned about once.
#include "redpost/krl/reader.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <utility>

#include "io/text_util.hpp"
#include "krl/reader_parse.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/text_file.hpp"

namespace redpost {

namespace {

namespace fs = std::filesystem;
using detail::trim;
using krl::Cursor;
using krl::DefRange;
using krl::fail;
using krl::find_file_nocase;
using krl::leading_word;
using krl::load_module;
using krl::Module;
using krl::motion_keywords;
using krl::parse_aggregate;
using krl::parse_real_field;
using krl::split_comment;
using krl::upper;

// --- execution -------------------------------------------------------------------------------

struct State {
  int cl_line = 0;
  double vel_cp = 0.0;
  double apo_cdis = -1.0;      // $APO.CDIS (mm); -1: never set
  double ptp_velocity = -1.0;  // BAS (#VEL_PTP, n) (%); -1: never set
  std::string base, tool;
};

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

// System variables that only tune motion, or tell the controller the payload ($LOAD) and the
// numbers of the frames in force (the pendant's): set without a warning; the path is the same.
bool quiet_system_variable(const std::string& lhs) {
  static const std::set<std::string> q{
      "$ADVANCE",   "$APO",       "$VEL",       "$ACC",       "$VEL_AXIS",  "$ACC_AXIS",
      "$ORI_TYPE",  "$CIRC_TYPE", "$VEL_EXTAX", "$ACC_EXTAX", "$CIRC_MODE", "$SPL_ORI_JOINT_AUTO",
      "$GEAR_JERK", "$JERK",      "$ACT_EX_AX", "$ACT_BASE",  "$ACT_TOOL",  "$LOAD"};
  std::string head = lhs.substr(0, lhs.find_first_of(".["));
  return q.count(head) != 0;
}

class Reader {
 public:
  // With `sink`, motions are handed over instead of kept, and modules are dropped when no
  // call in progress needs them (read_krl_program with a sink, reader.hpp).
  explicit Reader(KrlProgram& out, const KrlMotionSink* sink = nullptr,
                  const KrlTextSink* text = nullptr)
      : out_(out), sink_(sink), text_(text) {}

  // The motion held back for an ENDSPLINE's approximation goes out at the end.
  void finish() {
    if (sink_ && held_) {
      (*sink_)(*held_);
      held_.reset();
    }
  }

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
  const KrlMotionSink* sink_;
  const KrlTextSink* text_;              // each file's text, the first time it is loaded
  std::optional<KrlMotionRecord> held_;  // with a sink: the last motion, until the next statement
  long motions_ = 0;                     // motions read so far
  std::set<std::string> files_seen_;
  std::map<std::string, std::unique_ptr<Module>> modules_;  // by canonical path
  std::vector<std::pair<const Module*, int>> stack_;        // DEFs being executed
  std::set<std::string> warned_;
  State state_;
  long spline_start_ = -1;  // motions read when the open SPLINE block started
  int spline_blocks_ = 0;   // SPLINE blocks opened so far
  int spline_block_ = 0;    // the open one (0: none)

  static std::string module_key(const std::string& path) {
    std::error_code ec;
    std::string key = fs::weakly_canonical(fs::path(path), ec).string();
    return ec ? path : key;
  }

  const Module& module(const std::string& path) {
    const std::string key = module_key(path);
    auto it = modules_.find(key);
    if (it != modules_.end())
      return *it->second;
    // A part dropped after its call and called again is read again, but its text was seen.
    const bool first = files_seen_.insert(key).second;
    auto m = std::make_unique<Module>(load_module(path, first ? text_ : nullptr));
    if (first)
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
      spline_start_ = motions_;
      spline_block_ = ++spline_blocks_;
      return;
    }
    if (w == "ENDSPLINE" || w == "ENDPTP_SPLINE") {
      std::string a = upper(leading_word(rest));
      if (approximations().count(a) && spline_start_ >= 0 && motions_ > spline_start_)
        (sink_ ? *held_ : out_.motions.back()).approximation = a;
      spline_start_ = -1;
      spline_block_ = 0;
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
    static const std::set<std::string> flow{"IF",    "ELSE",   "ENDIF",  "LOOP",     "ENDLOOP",
                                            "FOR",   "ENDFOR", "WHILE",  "ENDWHILE", "REPEAT",
                                            "UNTIL", "SWITCH", "CASE",   "DEFAULT",  "ENDSWITCH",
                                            "GOTO",  "EXIT",   "RETURN", "WAIT",     "TRIGGER",
                                            "PULSE", "ANIN",   "ANOUT",  "BRAKE",    "RESUME"};
    // A stop for the operator (a tool change by hand) or a dwell: the path is unchanged.
    if (w == "HALT" || (w == "WAIT" && upper(leading_word(rest)) == "SEC"))
      return;
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
      if (w == "BAS")
        bas_frame(rest);
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

  // BAS (#BASE, n) and BAS (#TOOL, n) select a base or tool by number (KSS 5's way to a coupled
  // base): recorded as written, blanks removed.
  void bas_frame(const std::string& args) {
    std::string a = upper(args);
    a.erase(std::remove_if(a.begin(), a.end(),
                           [](char ch) { return std::isspace(static_cast<unsigned char>(ch)); }),
            a.end());
    if (a.rfind("(#BASE,", 0) == 0) {
      state_.base = "BAS" + a;
    } else if (a.rfind("(#TOOL,", 0) == 0) {
      state_.tool = "BAS" + a;
    } else if (a.rfind("(#VEL_PTP,", 0) == 0) {
      char* end = nullptr;
      const double v = std::strtod(a.c_str() + 10, &end);
      if (end != a.c_str() + 10 && *end == ')')
        state_.ptp_velocity = v;
    }
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

  // A motion's WITH list (SLIN ... WITH $VEL.CP = 0.2, $TOOL = ...): its own $VEL.CP is its
  // speed, for this motion only; the other parameters are not tracked.
  void with_parameters(const std::string& list, KrlMotionRecord& r, const std::string& file,
                       int line) {
    int depth = 0;
    std::size_t from = 0;
    for (std::size_t i = 0; i <= list.size(); ++i) {
      const char ch = i < list.size() ? list[i] : ',';
      depth += (ch == '{' || ch == '(') - (ch == '}' || ch == ')');
      if (ch != ',' || depth > 0)
        continue;
      const std::string item = list.substr(from, i - from);
      from = i + 1;
      const std::size_t eq = item.find('=');
      if (eq == std::string::npos || upper(trim(item.substr(0, eq))) != "$VEL.CP")
        continue;
      const std::string rhs = trim(item.substr(eq + 1));
      char* end = nullptr;
      const double v = std::strtod(rhs.c_str(), &end);
      if (end == rhs.c_str() || !trim(std::string(end)).empty() || !(v > 0.0)) {
        warn_once("with-vel-expr", file, line,
                  "WITH $VEL.CP = " + rhs + " is not a speed: the $VEL.CP in force is used");
        continue;
      }
      r.vel_cp_m_per_s = v;
    }
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
    if (lhs == "$APO.CDIS") {
      char* end = nullptr;
      const double v = std::strtod(rhs.c_str(), &end);
      if (end != rhs.c_str() && trim(std::string(end)).empty())
        state_.apo_cdis = v;
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
      // Streaming: a part is read once; its lines need not stay (a second call reads it again).
      const bool in_use = std::any_of(stack_.begin(), stack_.end(),
                                      [&](const auto& frame) { return frame.first == &sub; });
      if (sink_ && !in_use)
        modules_.erase(module_key(path));
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
    r.spline_block = spline_block_;
    r.apo_cdis_mm = state_.apo_cdis;
    r.ptp_velocity_percent = state_.ptp_velocity;
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
        with_parameters(c.text.substr(c.pos), r, m.src_path, line);
        break;
      } else {
        fail(m.src_path, line, "unexpected '" + w + "' after the " + kw + " target");
      }
    }
    ++motions_;
    if (!sink_) {
      out_.motions.push_back(std::move(r));
      return;
    }
    if (held_)
      (*sink_)(*held_);
    held_ = std::move(r);
  }
};

}  // namespace

KrlProgram read_krl_program(const std::string& src_path) {
  KrlProgram program;
  Reader reader(program);
  reader.run(src_path);
  return program;
}

KrlProgram read_krl_program(const std::string& src_path, const KrlMotionSink& motion) {
  KrlProgram program;
  Reader reader(program, &motion);
  reader.run(src_path);
  reader.finish();
  return program;
}

KrlProgram read_krl_program(const std::string& src_path, const KrlMotionSink& motion,
                            const KrlTextSink& text) {
  KrlProgram program;
  Reader reader(program, &motion, &text);
  reader.run(src_path);
  reader.finish();
  return program;
}

}  // namespace redpost
