#include "redpost/krl/writer.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <iterator>
#include <limits>
#include <string_view>

#include <fmt/format.h>

#include "krl/format.hpp"
#include "redpost/io/durable_write.hpp"
#include "redpost/io/error.hpp"

namespace redpost {

namespace {

namespace fs = std::filesystem;
using krl::Ph;

// KUKA controllers run on Windows and their own files use CRLF; so does RoboDK. Every line the
// writer emits ends with CRLF, whatever the template file used (docs/krl-templates.md).
constexpr std::string_view kEol = "\r\n";

// Parts are numbered NAME_P001 ... with a fixed width, so that they sort by name.
constexpr int kMaxParts = 999;
constexpr std::string_view kPartInfix = "_P";
constexpr size_t kPartSuffixLength = 5;  // "_P001"

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
  count_
};
constexpr std::string_view kStmtNames[] = {
    "ptp_axes", "rapid",       "lin",        "ext_axis",     "vel",        "comment",
    "cl_line",  "tool_change", "spindle_on", "spindle_off",  "coolant_on", "coolant_off",
    "literal",  "call",        "call_decl",  "spline_begin", "spline_lin", "spline_end"};
static_assert(std::size(kStmtNames) == static_cast<size_t>(Stmt::count_));

// A skeleton line: text with placeholders, or the place of a block ({body}, {decls}).
struct SkeletonLine {
  krl::Compiled text;
  Ph block = Ph::count_;
};
using Skeleton = std::vector<SkeletonLine>;

// Control characters would break a KRL line; a comment must stay one line. Trailing blanks
// (from a trailing line break) are dropped.
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

std::string errno_text() {
  return std::strerror(errno);
}

// A failed write of a program file (nothing gets a final name: see finish()).
std::string write_failure_text() {
  return "cannot write: " + errno_text() +
         "; check the free space and the file size limit (ulimit -f); no program was written";
}

}  // namespace

struct KrlWriter::Impl {
  KrlTemplateSet t;
  KrlProgramInfo info;
  std::array<krl::Compiled, static_cast<size_t>(Stmt::count_)> stmt;
  Skeleton src, dat, main_src, main_dat;
  std::string date;  // only if a skeleton asks for {date}

  // Every file made so far, in the order they are renamed: each program's .dat, then its .src;
  // the main program last.
  struct File {
    std::string temp, final_path;
    bool renamed = false;
  };
  std::vector<File> files;
  std::FILE* src_out = nullptr;  // the .src being written
  size_t out_index = 0;          // into files
  std::string module;            // its name
  std::vector<std::string> parts;

  long motion_count = 0;  // all motions so far
  int motions_in_module = 0;
  bool in_spline = false;
  int spline_points = 0;
  double vel_requested = std::numeric_limits<double>::quiet_NaN();
  std::string vel_written;  // the last $VEL.CP statement, to skip repeats
  bool have_last = false;
  AxisValues last_axes;
  int ext_mask = -1;  // external axes (bit n-1 for En) of the first motion
  // What a part restates so that it runs alone with the right tool, spindle and coolant.
  std::string tool_state, spindle_state, coolant_state;
  bool finished = false;

  // Rendering context.
  struct Values {
    const AxisValues* axes = nullptr;
    double xyz[3] = {0, 0, 0};
    KukaAbc abc;
    StatusTurn st;
    double number_value = 0.0;  // vel, rpm, or an external axis value
    long integer = 0;           // cl line, tool number, axis number
    std::string_view text, tool_name, direction, clockwise, mode, callee;
  };
  std::string_view current;  // the statement or file being rendered, for messages
  std::string line;          // reused buffer
  std::string converted;

  Impl(const KrlTemplateSet& templates, const KrlProgramInfo& program)
      : t(templates), info(program) {}

  // --- messages ------------------------------------------------------------------------------
  std::string context() const {
    return fmt::format("program '{}', motion {}: template set '{}' ({}), '{}'", info.name,
                       motion_count + 1, t.name, t.source_file, current);
  }

  // --- numbers and values --------------------------------------------------------------------
  void number(std::string& out, double v, int decimals, std::string_view what) {
    if (!std::isfinite(v)) {
      throw Error(ErrorCode::internal,
                  fmt::format("{}: {} is {}; the template needs it", context(), what,
                              std::isnan(v) ? "NaN (not given)" : "infinite"));
    }
    krl::append_fixed(out, v, decimals, what);
  }

  static void bits(std::string& out, int value, int width) {
    while (width < 31 && (value >> width) != 0)
      ++width;
    for (int i = width - 1; i >= 0; --i)
      out += (value >> i) & 1 ? '1' : '0';
  }

  void value(std::string& out, Ph ph, const Values& v) {
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
      case Ph::a1:
      case Ph::a2:
      case Ph::a3:
      case Ph::a4:
      case Ph::a5:
      case Ph::a6: {
        const int n = static_cast<int>(ph) - static_cast<int>(Ph::a1) + 1;
        static const char* const kArm[] = {"axis A1", "axis A2", "axis A3",
                                           "axis A4", "axis A5", "axis A6"};
        number(out, v.axes->arm(n), t.angle_decimals, kArm[n - 1]);
        break;
      }
      case Ph::e1:
      case Ph::e2:
      case Ph::e3:
      case Ph::e4:
      case Ph::e5:
      case Ph::e6: {
        const int n = static_cast<int>(ph) - static_cast<int>(Ph::e1) + 1;
        static const char* const kExt[] = {"axis E1", "axis E2", "axis E3",
                                           "axis E4", "axis E5", "axis E6"};
        number(out, v.axes->external(n), t.external_decimals, kExt[n - 1]);
        break;
      }
      case Ph::ext: {
        // Only the external axes the cell has: ", E1 500.0000, E2 90.0000" with ext_axis.
        const std::string_view outer = current;
        current = kStmtNames[static_cast<size_t>(Stmt::ext_axis)];
        for (int n = 1; n <= 6; ++n) {
          if (!(ext_mask & (1 << (n - 1))))
            continue;
          Values e;
          e.integer = n;
          e.number_value = v.axes->external(n);
          render_into(out, stmt[static_cast<size_t>(Stmt::ext_axis)], e);
        }
        current = outer;
        break;
      }
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
        out += info.tool;
        break;
      case Ph::apo_mm:
        number(out, info.apo_mm, t.position_decimals, "$APO.CDIS");
        break;
      case Ph::header_comment:
        out += one_line(info.header_comment);
        break;
      case Ph::date:
        out += date;
        break;
      case Ph::body:
      case Ph::decls:
      case Ph::count_:
        throw Error(ErrorCode::internal, context() + ": misplaced block placeholder");
    }
  }

  void render_into(std::string& out, const krl::Compiled& c, const Values& v) {
    for (const krl::Piece& p : c.pieces) {
      out += p.literal;
      if (p.ph != Ph::count_)
        value(out, p.ph, v);
    }
  }

  std::string render(Stmt s, const Values& v) {
    current = kStmtNames[static_cast<size_t>(s)];
    std::string out;
    render_into(out, stmt[static_cast<size_t>(s)], v);
    return out;
  }

  // --- output --------------------------------------------------------------------------------
  // One logical line; a multi-line statement has '\n' inside. Empty: nothing is written.
  void put(std::FILE* f, size_t file_index, std::string_view text) {
    if (text.empty())
      return;
    if (!f) {
      throw Error(ErrorCode::internal,
                  "KRL writer: no file open (an earlier error or finish() ended this program)");
    }
    converted.clear();
    for (char ch : text) {
      if (ch == '\n')
        converted += kEol;
      else
        converted += ch;
    }
    converted += kEol;
    if (std::fwrite(converted.data(), 1, converted.size(), f) != converted.size()) {
      throw Error(ErrorCode::io, write_failure_text(),
                  SourceLocation{files[file_index].final_path, 0, 0});
    }
  }

  void put(Stmt s, const Values& v) { put(src_out, out_index, render(s, v)); }

  size_t create(const std::string& file_name, std::FILE*& f) {
    File file;
    file.final_path = (fs::path(info.output_dir) / file_name).string();
    file.temp = (fs::path(info.output_dir) / ("." + file_name + ".part~")).string();
    f = std::fopen(file.temp.c_str(), "wb");
    if (!f) {
      throw Error(ErrorCode::io, "cannot create a file in the output directory: " + errno_text(),
                  SourceLocation{file.final_path, 0, 0});
    }
    std::setvbuf(f, nullptr, _IOFBF, 1 << 16);
    files.push_back(std::move(file));
    return files.size() - 1;
  }

  // Closes a finished file, flushed to the disk first (durable_write.hpp): its rename in
  // finish() must never give a final name to data still in the page cache.
  void close(std::FILE*& f, size_t file_index) {
    std::FILE* file = f;
    f = nullptr;
    const bool failed = std::ferror(file) != 0;
    if (!failed) {
      try {
        flush_to_disk(file, files[file_index].final_path);
      } catch (...) {
        std::fclose(file);
        throw;
      }
    }
    const int rc = std::fclose(file);
    if (failed || rc != 0) {
      throw Error(ErrorCode::io, write_failure_text(),
                  SourceLocation{files[file_index].final_path, 0, 0});
    }
  }

  // Writes skeleton lines [from, to) and returns the index of the block line that stopped it
  // (or to).
  template <class Block>
  size_t put_skeleton(std::FILE* f, size_t file_index, const Skeleton& sk, size_t from,
                      std::string_view file_kind, Block&& block) {
    for (size_t i = from; i < sk.size(); ++i) {
      if (sk[i].block == Ph::body)
        return i;
      if (sk[i].block == Ph::decls) {
        block(Ph::decls);
        continue;
      }
      current = file_kind;
      line.clear();
      render_into(line, sk[i].text, Values{});
      // A skeleton line is written even when empty: blank lines are part of the layout.
      converted.assign(line);
      converted += kEol;
      if (std::fwrite(converted.data(), 1, converted.size(), f) != converted.size()) {
        throw Error(ErrorCode::io, write_failure_text(),
                    SourceLocation{files[file_index].final_path, 0, 0});
      }
    }
    return sk.size();
  }

  void write_dat(const std::string& name, const Skeleton& sk, std::string_view kind) {
    module = name;
    std::FILE* f = nullptr;
    const size_t idx = create(name + ".dat", f);
    try {
      put_skeleton(f, idx, sk, 0, kind, [](Ph) {});
      close(f, idx);
    } catch (...) {
      if (f)
        std::fclose(f);
      throw;
    }
  }

  size_t body_line(const Skeleton& sk) const {
    for (size_t i = 0; i < sk.size(); ++i) {
      if (sk[i].block == Ph::body)
        return i;
    }
    return sk.size();
  }

  void open_module(const std::string& name) {
    write_dat(name, dat, "file dat");
    module = name;
    out_index = create(name + ".src", src_out);
    put_skeleton(src_out, out_index, src, 0, "file src", [](Ph) {});
    motions_in_module = 0;
  }

  void close_module() {
    end_spline();
    put_skeleton(src_out, out_index, src, body_line(src) + 1, "file src", [](Ph) {});
    close(src_out, out_index);
  }

  // --- statements ----------------------------------------------------------------------------
  void end_spline() {
    if (in_spline) {
      put(Stmt::spline_end, Values{});
      in_spline = false;
    }
  }

  void ptp_axes(const AxisValues& axes) {
    Values v;
    v.axes = &axes;
    put(Stmt::ptp_axes, v);
  }

  Values pose_values(const KrlMotion& m) {
    Values v;
    v.axes = &m.axes;
    const Eigen::Vector3d p = m.T_base_tcp.translation();
    for (int i = 0; i < 3; ++i)
      v.xyz[i] = p[i];
    v.abc = abc_from_rotation(m.T_base_tcp.linear());
    if (!m.T_base_tcp.linear().allFinite()) {
      v.abc.a_deg = v.abc.b_deg = v.abc.c_deg = std::numeric_limits<double>::quiet_NaN();
    }
    v.st = m.status_turn;
    return v;
  }

  void flush_velocity() {
    if (std::isnan(vel_requested)) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("program '{}', motion {}: a feed move before any feed rate "
                              "(velocity() was never called); refusing to write a LIN at the "
                              "controller's default speed",
                              info.name, motion_count + 1));
    }
    Values v;
    v.number_value = vel_requested;
    std::string text = render(Stmt::vel, v);
    if (text != vel_written) {
      end_spline();
      put(src_out, out_index, text);
      vel_written = std::move(text);
    }
  }

  // A part starts where the previous one ended, in the same state, so it can run alone.
  void restate() {
    put(src_out, out_index, tool_state);
    put(src_out, out_index, spindle_state);
    put(src_out, out_index, coolant_state);
    ptp_axes(last_axes);
    vel_written.clear();  // the part's INI reset $VEL.CP
  }

  void next_part() {
    if (static_cast<int>(parts.size()) == kMaxParts) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("program '{}' needs more than {} parts of {} motions; raise "
                              "motions_per_file",
                              info.name, kMaxParts, info.motions_per_file));
    }
    parts.push_back(fmt::format("{}{}{:03}", info.name, kPartInfix, parts.size() + 1));
    open_module(parts.back());
  }
};

KrlWriter::KrlWriter(const KrlTemplateSet& templates, const KrlProgramInfo& info)
    : impl_(std::make_unique<Impl>(templates, info)) {
  Impl& w = *impl_;
  if (const std::string why = krl::identifier_problem(info.name); !why.empty()) {
    throw Error(ErrorCode::bad_input, "program name '" + info.name + "' " + why);
  }
  if (info.motions_per_file > 0 &&
      info.name.size() + kPartSuffixLength > krl::kMaxIdentifierLength) {
    throw Error(
        ErrorCode::bad_input,
        fmt::format("program name '{}' has {} characters: too long to split, because "
                    "its parts are named {}{}001 and a KRL name has at most {}; use at "
                    "most {} characters",
                    info.name, info.name.size(), info.name, kPartInfix, krl::kMaxIdentifierLength,
                    krl::kMaxIdentifierLength - kPartSuffixLength));
  }
  if (info.motions_per_file < 0 || info.cl_line_every < 0) {
    throw Error(ErrorCode::bad_input, "motions_per_file and cl_line_every must be >= 0");
  }
  if (!std::isfinite(info.apo_mm) || info.apo_mm < 0.0) {
    throw Error(ErrorCode::bad_input, "$APO.CDIS must be a finite distance >= 0 mm");
  }
  for (const std::string* s : {&info.base, &info.tool}) {
    if (s->empty() || std::any_of(s->begin(), s->end(), [](char ch) {
          return static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f;
        })) {
      throw Error(ErrorCode::bad_input, "$BASE and $TOOL need a one-line, non-empty value");
    }
  }

  // The set may have been built by hand rather than loaded: check it as the loader does.
  const SourceLocation where{templates.source_file, 0, 0};
  const auto check_placeholders = [&](std::string_view text, krl::PhMask allowed,
                                      const std::string& what) {
    for (const krl::PlaceholderUse& u : krl::scan_placeholders(text)) {
      if (u.ph == Ph::count_ || !(allowed & krl::bit(u.ph))) {
        throw Error(ErrorCode::bad_input,
                    fmt::format("template set '{}': placeholder {{{}}} is {} in {}", templates.name,
                                u.name, u.ph == Ph::count_ ? "unknown" : "not allowed", what),
                    where);
      }
    }
  };
  for (size_t i = 0; i < static_cast<size_t>(Stmt::count_); ++i) {
    const krl::StatementSpec* spec = krl::find_statement(kStmtNames[i]);
    const auto it = templates.statements.find(std::string(kStmtNames[i]));
    if (it == templates.statements.end()) {
      if (!spec->used_by(templates.spline))
        continue;
      throw Error(
          ErrorCode::bad_input,
          fmt::format("template set '{}' has no statement '{}'", templates.name, kStmtNames[i]),
          where);
    }
    check_placeholders(it->second, spec->allowed, "statement '" + std::string(kStmtNames[i]) + "'");
    w.stmt[i] = krl::compile(it->second);
  }
  if (templates.max_spline_points < 1) {
    throw Error(ErrorCode::bad_input,
                "template set '" + templates.name + "': max_spline_points must be >= 1", where);
  }
  bool wants_date = false;
  const struct {
    const std::string* text;
    Skeleton* out;
    std::string_view kind;
  } skeletons[] = {{&templates.src_file, &w.src, "src"},
                   {&templates.dat_file, &w.dat, "dat"},
                   {&templates.main_src_file, &w.main_src, "main_src"},
                   {&templates.main_dat_file, &w.main_dat, "main_dat"}};
  for (const auto& s : skeletons) {
    const krl::SkeletonSpec* spec = krl::find_skeleton(s.kind);
    int bodies = 0;
    size_t pos = 0;
    const std::string& text = *s.text;
    while (true) {
      const size_t nl = text.find('\n', pos);
      const std::string_view l(text.data() + pos,
                               (nl == std::string::npos ? text.size() : nl) - pos);
      SkeletonLine sl;
      const size_t b = l.find_first_not_of(" \t"), e = l.find_last_not_of(" \t");
      const std::string_view core = b == l.npos ? l : l.substr(b, e - b + 1);
      if (core == "{body}" || core == "{decls}") {
        sl.block = core == "{body}" ? Ph::body : Ph::decls;
        bodies += sl.block == Ph::body;
      } else {
        // {body} and {decls} elsewhere than alone on their line are refused here too.
        check_placeholders(l, spec->allowed & ~(krl::bit(Ph::body) | krl::bit(Ph::decls)),
                           "file '" + std::string(s.kind) + "'");
        sl.text = krl::compile(l);
        wants_date = wants_date || (sl.text.used & krl::bit(Ph::date));
      }
      if (sl.block != Ph::count_ && !(spec->allowed & krl::bit(sl.block))) {
        throw Error(ErrorCode::bad_input,
                    fmt::format("template set '{}': {{{}}} is not allowed in file '{}'",
                                templates.name, krl::placeholder_name(sl.block), s.kind),
                    where);
      }
      s.out->push_back(std::move(sl));
      if (nl == std::string::npos)
        break;
      pos = nl + 1;
    }
    if (spec->needs_body && bodies != 1) {
      throw Error(ErrorCode::bad_input,
                  fmt::format("template set '{}': file '{}' needs exactly one line {{body}}",
                              templates.name, s.kind),
                  where);
    }
  }
  if (wants_date) {
    // Only on request: a date makes the output differ from run to run.
    const std::time_t now = std::time(nullptr);
    std::tm utc{};
    gmtime_r(&now, &utc);
    w.date = fmt::format("{:04}-{:02}-{:02} {:02}:{:02}:{:02} UTC", utc.tm_year + 1900,
                         utc.tm_mon + 1, utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec);
  }

  std::error_code ec;
  if (!fs::is_directory(info.output_dir, ec)) {
    throw Error(ErrorCode::io, "the output directory does not exist (or is not a directory)",
                SourceLocation{info.output_dir, 0, 0});
  }
  if (::access(info.output_dir.c_str(), W_OK | X_OK) != 0) {
    throw Error(ErrorCode::io, "the output directory is not writable: " + errno_text(),
                SourceLocation{info.output_dir, 0, 0});
  }

  // The first file now: an unwritable directory shows at once, not after the whole path.
  if (info.motions_per_file > 0)
    w.next_part();
  else
    w.open_module(info.name);
}

KrlWriter::~KrlWriter() {
  if (!impl_)
    return;
  Impl& w = *impl_;
  if (w.src_out)
    std::fclose(w.src_out);
  // A program that was not finished must not look finished: remove what is not renamed.
  for (const Impl::File& f : w.files) {
    if (!f.renamed)
      std::remove(f.temp.c_str());
  }
}

void KrlWriter::motion(const KrlMotion& m) {
  Impl& w = *impl_;
  if (w.finished)
    throw Error(ErrorCode::internal, "KRL writer: motion() after finish()");

  int mask = 0;
  for (int n = 1; n <= 6; ++n)
    mask |= std::isnan(m.axes.external(n)) ? 0 : 1 << (n - 1);
  if (w.ext_mask < 0)
    w.ext_mask = mask;
  if (mask != w.ext_mask) {
    throw Error(ErrorCode::internal,
                fmt::format("program '{}', motion {}: external axes (mask {:06b}) differ from "
                            "those of the first motion ({:06b})",
                            w.info.name, w.motion_count + 1, mask, w.ext_mask));
  }

  if (w.info.motions_per_file > 0 && w.motions_in_module == w.info.motions_per_file) {
    w.close_module();
    w.next_part();
    w.restate();
  }
  if (w.info.cl_line_every > 0 && m.cl_line > 0 && w.motion_count % w.info.cl_line_every == 0) {
    Impl::Values v;
    v.integer = m.cl_line;
    w.put(Stmt::cl_line, v);
  }

  if (!w.have_last) {
    // The first motion of a program is always a full-axis PTP: it fixes the posture, and the
    // controller's BCO run needs a PTP.
    w.ptp_axes(m.axes);
  } else {
    switch (m.kind) {
      case KrlMotionKind::ptp_axes:
        w.end_spline();
        w.ptp_axes(m.axes);
        break;
      case KrlMotionKind::rapid:
        w.end_spline();
        w.put(Stmt::rapid, w.pose_values(m));
        break;
      case KrlMotionKind::lin: {
        w.flush_velocity();
        const Impl::Values v = w.pose_values(m);
        if (w.t.spline) {
          if (w.in_spline && w.spline_points == w.t.max_spline_points)
            w.end_spline();
          if (!w.in_spline) {
            w.put(Stmt::spline_begin, Impl::Values{});
            w.in_spline = true;
            w.spline_points = 0;
          }
          w.put(Stmt::spline_lin, v);
          ++w.spline_points;
        } else {
          w.put(Stmt::lin, v);
        }
        break;
      }
    }
  }
  w.last_axes = m.axes;
  w.have_last = true;
  ++w.motion_count;
  ++w.motions_in_module;
}

void KrlWriter::velocity(double vel_m_per_s) {
  if (!std::isfinite(vel_m_per_s) || vel_m_per_s <= 0.0) {
    throw Error(ErrorCode::bad_input,
                fmt::format("program '{}': velocity {} m/s; a feed rate must be > 0",
                            impl_->info.name, vel_m_per_s));
  }
  impl_->vel_requested = vel_m_per_s;
}

void KrlWriter::tool_change(int number, const std::string& name) {
  Impl& w = *impl_;
  w.end_spline();
  Impl::Values v;
  v.integer = number;
  const std::string clean = one_line(name);
  v.tool_name = clean;
  w.tool_state = w.render(Stmt::tool_change, v);
  w.put(w.src_out, w.out_index, w.tool_state);
}

void KrlWriter::spindle(double rpm, bool clockwise) {
  Impl& w = *impl_;
  if (!std::isfinite(rpm) || rpm < 0.0) {
    throw Error(ErrorCode::bad_input,
                fmt::format("program '{}': spindle speed {} rpm; it must be >= 0 (0: off)",
                            w.info.name, rpm));
  }
  w.end_spline();
  Impl::Values v;
  if (rpm == 0.0) {
    w.spindle_state.clear();
    w.put(Stmt::spindle_off, v);
    return;
  }
  v.number_value = rpm;
  v.direction = clockwise ? "CW" : "CCW";
  v.clockwise = clockwise ? "TRUE" : "FALSE";
  w.spindle_state = w.render(Stmt::spindle_on, v);
  w.put(w.src_out, w.out_index, w.spindle_state);
}

void KrlWriter::coolant(bool on, const std::string& mode) {
  Impl& w = *impl_;
  w.end_spline();
  Impl::Values v;
  const std::string clean = one_line(mode);
  v.mode = clean;
  const std::string text = w.render(on ? Stmt::coolant_on : Stmt::coolant_off, v);
  w.coolant_state = on ? text : std::string();
  w.put(w.src_out, w.out_index, text);
}

void KrlWriter::comment(const std::string& text) {
  Impl& w = *impl_;
  Impl::Values v;
  const std::string clean = one_line(text);
  v.text = clean;
  w.put(Stmt::comment, v);  // a comment may stand inside a spline block
}

void KrlWriter::literal(const std::string& text) {
  Impl& w = *impl_;
  if (text.find_first_of("\r\n") != std::string::npos) {
    throw Error(ErrorCode::bad_input,
                "program '" + w.info.name + "': a literal KRL statement must be one line");
  }
  w.end_spline();
  Impl::Values v;
  v.text = text;
  w.put(Stmt::literal, v);
}

std::vector<std::string> KrlWriter::finish() {
  Impl& w = *impl_;
  if (w.finished)
    throw Error(ErrorCode::internal, "KRL writer: finish() called twice");
  w.close_module();

  std::vector<std::string> written;
  if (!w.parts.empty()) {
    // The main program: calls the parts in order.
    w.write_dat(w.info.name, w.main_dat, "file main_dat");
    w.module = w.info.name;
    std::FILE* f = nullptr;
    const size_t idx = w.create(w.info.name + ".src", f);
    try {
      const auto calls = [&](Stmt s) {
        for (const std::string& part : w.parts) {
          Impl::Values v;
          v.callee = part;
          w.put(f, idx, w.render(s, v));
        }
      };
      const size_t body = w.put_skeleton(f, idx, w.main_src, 0, "file main_src",
                                         [&](Ph) { calls(Stmt::call_decl); });
      calls(Stmt::call);
      w.module = w.info.name;
      w.put_skeleton(f, idx, w.main_src, body + 1, "file main_src",
                     [&](Ph) { calls(Stmt::call_decl); });
      w.close(f, idx);
    } catch (...) {
      if (f)
        std::fclose(f);
      throw;
    }
  }

  // Only now do the files get their names, the main .src last. An older program of the same
  // name loses its main .src first: a kill between two renames then leaves new parts or a new
  // .dat without any main .src, never an old main .src that would run beside (or call) new files.
  const std::string& main_src = w.files.back().final_path;
  if (std::remove(main_src.c_str()) != 0 && errno != ENOENT) {
    throw Error(ErrorCode::io, "cannot replace the existing program: " + errno_text(),
                SourceLocation{main_src, 0, 0});
  }
  for (Impl::File& f : w.files) {
    if (std::rename(f.temp.c_str(), f.final_path.c_str()) != 0) {
      throw Error(ErrorCode::io, "cannot rename " + f.temp + " to its final name: " + errno_text(),
                  SourceLocation{f.final_path, 0, 0});
    }
    f.renamed = true;
  }
  sync_directory(w.info.output_dir);
  w.finished = true;

  const auto src = [&](const std::string& name) {
    return (fs::path(w.info.output_dir) / (name + ".src")).string();
  };
  written.push_back(src(w.info.name));
  for (const std::string& part : w.parts)
    written.push_back(src(part));
  return written;
}

int KrlWriter::motions() const {
  return static_cast<int>(impl_->motion_count);
}

}  // namespace redpost
