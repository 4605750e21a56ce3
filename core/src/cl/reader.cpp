// The streaming APT/CLDATA and NX CLSF reader (docs/cl-format.md).
//
// One record at a time: ClLineSource gives physical lines, read_record() joins `$`
// continuations and strips `$$` comments, parse_record() finds the major word, and one handler
// per word turns the record into events. Records that stand for many moves (an arc, a NURBS, a
// drilling cycle at a hole) start a generator that refills the small event queue in batches of
// at most kBatch events, so memory does not depend on how many chords an arc needs.
//
// Nothing here allocates per record once the buffers have grown to the longest record: the
// record, its fields (string_views into it) and the event queue are reused, and numbers are
// read with std::from_chars.
#include "redpost/cl/reader.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <set>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "cl/arc_chords.hpp"
#include "cl/line_source.hpp"
#include "cl/nurbs_curve.hpp"
#include "redpost/io/error.hpp"

namespace redpost {

namespace {

using Eigen::Vector3d;

constexpr double kMmPerInch = 25.4;
// Largest magnitude of any number after conversion to mm (or mm/min, rpm): catches typos such
// as 1e30 before they poison the kinematics.
constexpr double kMaxMagnitude = 1e7;
constexpr double kMinAxisNorm = 1e-6;  // NX prints axes with 7 decimals
constexpr std::size_t kBatch = 64;     // events per refill from an arc, NURBS or cycle generator
constexpr double kMaxChords = 1e8;     // more chords than this is a tolerance typo

bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\v' || c == '\f';
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_blank(s.front()))
    s.remove_prefix(1);
  while (!s.empty() && is_blank(s.back()))
    s.remove_suffix(1);
  return s;
}

std::string_view trim_right(std::string_view s) {
  while (!s.empty() && is_blank(s.back()))
    s.remove_suffix(1);
  return s;
}

char upper(char c) {
  return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c;
}

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size())
    return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (upper(a[i]) != upper(b[i]))
      return false;
  }
  return true;
}

bool is_word_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-';
}

bool is_letter(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}

// Records whose argument is free text; classic APT also writes them without '/' ("PARTNO X").
bool is_text_word(std::string_view w) {
  return iequals(w, "PARTNO") || iequals(w, "PPRINT") || iequals(w, "INSERT");
}

// Major words that take values and so need a '/'.
bool needs_slash(std::string_view w) {
  for (std::string_view k :
       {"GOTO",   "GODLTA", "FROM",   "CIRCLE", "KNOT",   "CNTRL",  "CYCLE",  "FEDRAT",
        "SPINDL", "COOLNT", "LOADTL", "LOAD",   "SELECT", "CUTTER", "TLDATA", "UNITS",
        "UNIT",   "TLAXIS", "MSYS",   "CSYS",   "TRNTYP", "CUTCOM"}) {
    if (iequals(w, k))
      return true;
  }
  return false;
}

std::string fmt_mm(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 6);
  return std::string(buf, r.ptr);
}

struct Field {
  std::string_view text;  // trimmed
  std::size_t offset;     // of the text's first character in the record
};

// Record text from `offset` on came from physical line `line`, whose column 1 is at `offset`.
struct Segment {
  std::size_t offset;
  int line;
};

enum class Generator { none, arc, nurbs, hole };

// A drilling cycle as CYCLE/ defined it (lengths in mm, along the tool axis from the hole point).
struct DrillCycle {
  bool defined = false;
  bool active = false;
  // The tool changed (or a new NX operation began) while the cycle was on and no CYCLE/OFF came:
  // whether the GOTOs after it are holes or moves is not written, so motion is refused.
  bool interrupted = false;
  int interrupted_line = 0;
  bool deep = false;  // pecking: full retract to the clearance between pecks
  int line = 0;
  double depth_mm = 0.0;      // FEDTO: bottom of the hole below the GOTO point
  double clearance_mm = 0.0;  // RAPTO: rapids stop this far above the point (or a peck bottom)
  double retract_mm = 0.0;    // RTRCTO (or RAPTO): where the tool goes after the hole
  double feed_mm_per_min = 0.0;
  double first_peck_mm = 0.0;
  double next_peck_mm = 0.0;
};

enum class HolePhase { travel, approach, feed_on, reenter, cut, peck_out, feed_off, retract, done };

}  // namespace

struct ClReader::Impl {
  Impl(std::istream& in, std::string source_name, ClReaderOptions options)
      : source(std::move(source_name)),
        opt(options),
        lines(in, source, options.max_line_bytes),
        nx(options.dialect == ClDialect::nx_clsf) {
    if (!(opt.chordal_tolerance_mm > 0.0) || !std::isfinite(opt.chordal_tolerance_mm))
      throw Error(ErrorCode::bad_input, "chordal tolerance must be a positive number of mm");
    if (!(opt.point_match_tolerance_mm > 0.0) || !std::isfinite(opt.point_match_tolerance_mm))
      throw Error(ErrorCode::bad_input, "point match tolerance must be a positive number of mm");
    queue.reserve(kBatch + 8);
  }

  // ---- input ---------------------------------------------------------------------------------
  std::string source;
  ClReaderOptions opt;
  detail::ClLineSource lines;
  std::string line;
  std::string record;
  std::vector<Segment> segments;
  std::vector<std::string> comments;  // $$ comments of the record (keep_comments only)
  int record_line = 0;
  bool record_pending = false;  // parsed, to be handled once the NURBS before it is out

  // ---- the parsed record ---------------------------------------------------------------------
  std::string word;  // upper case, single spaces ("TOOL PATH"); empty for a comment-only line
  std::size_t word_offset = 0;
  std::size_t args_offset = 0;  // first character after '/'
  bool has_slash = false;
  std::vector<Field> fields;

  // ---- output --------------------------------------------------------------------------------
  std::vector<ClEvent> queue;
  std::size_t head = 0;
  bool finished = false;
  std::deque<std::string> warnings;
  std::set<std::string> warned;                      // keys of warnings already given
  std::set<std::string, std::less<>> unknown_words;  // unknown major words already reported

  // ---- machine state -------------------------------------------------------------------------
  bool nx;                   // NX CLSF conventions (see ClDialect)
  double unit_mm = 1.0;      // mm per unit of length in the file
  bool units_given = false;  // a UNITS record was read
  bool multax = false;
  bool axis_known = false;  // a TLAXIS or a GOTO with i,j,k was seen
  Vector3d axis = Vector3d::UnitZ();
  bool pos_known = false;
  Vector3d pos = Vector3d::Zero();
  bool rapid_next = false;
  bool feed_known = false;
  bool feed_per_rev = false;
  double feed_mm_per_rev = 0.0;
  double feed_mm_per_min = 0.0;
  double spindle_rpm = 0.0;       // 0 while stopped
  double last_spindle_rpm = 0.0;  // for SPINDL/ON
  SpindleDirection last_direction = SpindleDirection::clockwise;
  double tool_diameter_mm = 0.0;
  double tool_length_mm = 0.0;
  std::string tool_name;

  // ---- CIRCLE waiting for its GOTO -----------------------------------------------------------
  bool arc_pending = false;
  int arc_line = 0;
  Vector3d arc_centre = Vector3d::Zero();
  Vector3d arc_axis = Vector3d::UnitZ();  // travel by the right-hand rule (NX sign undone)
  bool arc_has_radius = false;
  double arc_radius_mm = 0.0;
  std::size_t arc_radius_offset = 0;

  // ---- NURBS being collected -----------------------------------------------------------------
  bool collecting_nurbs = false;
  int nurbs_line = 0;
  std::vector<double> nurbs_knots;                     // as written
  std::vector<detail::HomogeneousPoint> nurbs_points;  // as written

  // ---- generators ----------------------------------------------------------------------------
  Generator generator = Generator::none;
  int gen_line = 0;
  bool gen_rapid = false;
  Vector3d gen_axis = Vector3d::UnitZ();
  detail::ArcChords arc;
  long arc_done = 0;
  Vector3d arc_end_axis = Vector3d::UnitZ();
  detail::NurbsCurve curve;
  detail::NurbsChords curve_chords;
  DrillCycle cycle;
  HolePhase hole_phase = HolePhase::done;
  Vector3d hole_point = Vector3d::Zero();
  long hole_pecks = 1;
  long hole_peck = 0;

  // ===========================================================================================
  // Errors and warnings

  SourceLocation where(std::size_t offset) const {
    SourceLocation loc{source, record_line, 0};
    std::size_t base = 0;
    for (const Segment& s : segments) {
      if (s.offset > offset)
        break;
      loc.line = s.line;
      base = s.offset;
    }
    loc.column = static_cast<int>(offset - base) + 1;
    return loc;
  }

  [[noreturn]] void fail_at(std::size_t offset, const std::string& message) const {
    throw Error(ErrorCode::bad_input, message, where(offset));
  }
  [[noreturn]] void fail_word(const std::string& message) const { fail_at(word_offset, message); }
  [[noreturn]] void fail_line(int line_no, const std::string& message) const {
    throw Error(ErrorCode::bad_input, message, SourceLocation{source, line_no, 0});
  }

  void warn_once(const std::string& key, int line_no, const std::string& message) {
    if (warned.insert(key).second)
      warnings.push_back(format_error(SourceLocation{source, line_no, 0}, message));
  }

  // ===========================================================================================
  // Records

  // The position of the first "$$" (a comment to the end of the line), or npos.
  static std::size_t comment_start(std::string_view s) {
    std::size_t i = s.find('$');
    while (i != std::string_view::npos && i + 1 < s.size()) {
      if (s[i + 1] == '$')
        return i;
      i = s.find('$', i + 1);
    }
    return std::string_view::npos;
  }

  // Reads the next record (a comment-only line counts when comments are kept). False at the end.
  bool read_record() {
    if (record_pending) {
      record_pending = false;
      return true;
    }
    for (;;) {
      record.clear();
      segments.clear();
      comments.clear();
      bool continued = false;
      do {
        if (!lines.next(line)) {
          if (continued) {
            fail_line(lines.line_number(),
                      "the record ends with the continuation mark '$' but the file ends here");
          }
          return false;
        }
        std::string_view code(line);
        const std::size_t c = comment_start(code);
        if (c != std::string_view::npos) {
          if (opt.keep_comments && !trim(code.substr(c + 2)).empty())
            comments.emplace_back(trim(code.substr(c + 2)));
          code = code.substr(0, c);
        }
        code = trim_right(code);
        continued = !code.empty() && code.back() == '$';
        if (continued)
          code.remove_suffix(1);
        if (segments.empty())
          record_line = lines.line_number();
        segments.push_back({record.size(), lines.line_number()});
        record.append(code);
        if (record.size() > opt.max_line_bytes) {
          fail_line(record_line, "record longer than " + std::to_string(opt.max_line_bytes) +
                                     " bytes with its continuation lines");
        }
      } while (continued);
      if (!trim(record).empty() || !comments.empty())
        break;
    }
    parse_record();
    return true;
  }

  // Finds the major word and where the values start.
  void parse_record() {
    word.clear();
    fields.clear();
    const std::string_view rec(record);
    const std::size_t begin = rec.find_first_not_of(" \t\v\f");
    if (begin == std::string_view::npos)
      return;  // comment-only
    word_offset = begin;
    const std::size_t slash = rec.find('/', begin);
    std::size_t word_end = rec.size();
    has_slash = slash != std::string_view::npos;
    if (has_slash) {
      word_end = slash;
      args_offset = slash + 1;
    } else {
      args_offset = rec.size();
      const std::size_t gap = rec.find_first_of(" \t", begin);
      if (gap != std::string_view::npos) {
        const std::string_view first = rec.substr(begin, gap - begin);
        if (is_text_word(first)) {  // PARTNO text, PPRINT text, INSERT text
          word_end = gap;
          args_offset = gap + 1;
        } else if (needs_slash(first)) {
          fail_at(gap, std::string(first) + " needs '/' before its values");
        } else {
          fail_at(begin, "malformed record: expected a major word and '/' (such as GOTO/x,y,z)");
        }
      }
    }
    normalise_word(rec.substr(begin, word_end - begin));
  }

  // Upper case, runs of blanks to one space; a word is letters, digits, '_' and '-', starting
  // with a letter ("TOOL PATH" and "END-OF-PATH" are words).
  void normalise_word(std::string_view raw) {
    raw = trim(raw);
    if (raw.empty())
      fail_at(word_offset, "malformed record: no major word before '/'");
    bool blank = false;
    for (std::size_t i = 0; i < raw.size(); ++i) {
      const char c = raw[i];
      if (is_blank(c)) {
        blank = true;
        continue;
      }
      if (!is_word_char(c) || (word.empty() && !is_letter(c))) {
        // A byte that cannot be printed is shown in hex: it means binary data (a compressed
        // or executable file given by mistake).
        const auto u = static_cast<unsigned char>(c);
        if (u < 0x20 || u >= 0x7f) {
          const char* hex = "0123456789abcdef";
          fail_at(word_offset + i, std::string("malformed record: byte 0x") + hex[u >> 4] +
                                       hex[u & 15] +
                                       " in the major word: is this a CL text file (APT or CLSF)?");
        }
        fail_at(word_offset + i,
                std::string("malformed record: unexpected '") + c +
                    "' in the major word (expected a word such as GOTO, then '/')");
      }
      if (blank && !word.empty())
        word.push_back(' ');
      blank = false;
      word.push_back(upper(c));
    }
  }

  // Splits the values after '/' at commas; an empty value is an error.
  void split_fields() {
    fields.clear();
    const std::string_view rec(record);
    if (args_offset >= rec.size() || trim(rec.substr(args_offset)).empty())
      return;
    std::size_t start = args_offset;
    for (;;) {
      const std::size_t comma = rec.find(',', start);
      const std::size_t end = comma == std::string_view::npos ? rec.size() : comma;
      const std::string_view raw = rec.substr(start, end - start);
      const std::size_t lead = raw.find_first_not_of(" \t\v\f");
      if (lead == std::string_view::npos)
        fail_at(start, "empty value in " + word + "/ (two commas in a row, or a comma at the end)");
      fields.push_back({trim(raw), start + lead});
      if (comma == std::string_view::npos)
        break;
      start = comma + 1;
    }
  }

  std::string_view raw_args() const {
    const std::string_view rec(record);
    return args_offset >= rec.size() ? std::string_view() : rec.substr(args_offset);
  }

  // ===========================================================================================
  // Values

  double number(const Field& f, double scale = 1.0) const {
    const char* first = f.text.data();
    const char* last = first + f.text.size();
    // from_chars takes no '+'; take one, but not a second sign after it.
    if (first != last && *first == '+' && first + 1 != last && first[1] != '-' && first[1] != '+')
      ++first;
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
    if (ec == std::errc::result_out_of_range)
      fail_at(f.offset, "number out of range: '" + std::string(f.text) + "'");
    if (ec != std::errc() || ptr != last)
      fail_at(f.offset, "not a number: '" + std::string(f.text) + "'");
    // from_chars also reads "nan" and "inf"; neither is a position, a feed or a speed.
    if (!std::isfinite(v))
      fail_at(f.offset,
              "'" + std::string(f.text) + "' is not a finite number (NaN and inf are refused)");
    v *= scale;
    if (std::fabs(v) > kMaxMagnitude) {
      fail_at(f.offset, "number out of range: " + std::string(f.text) + " is beyond 1e7" +
                            (scale != 1.0 ? " mm after unit conversion" : ""));
    }
    return v;
  }

  double length(const Field& f) const { return number(f, unit_mm); }

  double non_negative_length(const Field& f, const char* what) const {
    const double v = length(f);
    if (v < 0.0)
      fail_at(f.offset, std::string(what) + " must be >= 0, got " + std::string(f.text));
    return v;
  }

  Vector3d point(std::size_t i) const {
    return Vector3d(length(fields[i]), length(fields[i + 1]), length(fields[i + 2]));
  }

  Vector3d unit_vector(std::size_t i, const char* what) const {
    const Vector3d v(number(fields[i]), number(fields[i + 1]), number(fields[i + 2]));
    const double n = v.norm();
    if (!(n >= kMinAxisNorm))
      fail_at(fields[i].offset, std::string(what) + " (i,j,k) has zero length");
    return v / n;
  }

  bool is(const Field& f, std::string_view w) const { return iequals(f.text, w); }

  // Whether the field reads as a number (a keyword such as 1STPECK does not).
  static bool looks_numeric(const Field& f) {
    const char* first = f.text.data();
    const char* last = first + f.text.size();
    if (first != last && *first == '+')
      ++first;
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
    return ptr == last && ptr != first &&
           (ec == std::errc() || ec == std::errc::result_out_of_range);
  }

  bool is_feed_unit(const Field& f) const {
    return is(f, "MMPM") || is(f, "IPM") || is(f, "MMPR") || is(f, "IPR");
  }

  int tool_number(const Field& f) const {
    const double v = number(f);
    if (v < 0.0 || v > 1e6 || v != std::floor(v))
      fail_at(f.offset,
              "tool number must be a whole number from 0 to 1000000, got " + std::string(f.text));
    return static_cast<int>(v);
  }

  void expect_count(std::size_t min_count, std::size_t max_count, const char* usage) const {
    const std::size_t n = fields.size();
    if (n >= min_count && n <= max_count)
      return;
    const std::string msg =
        word + " takes " + usage + ", got " + std::to_string(n) + (n == 1 ? " value" : " values");
    if (n > max_count)
      fail_at(fields[max_count].offset, msg);
    fail_word(msg);
  }

  // ===========================================================================================
  // Events

  ClEvent& push(ClEventKind kind, int line_no) {
    queue.emplace_back();
    ClEvent& e = queue.back();
    e.kind = kind;
    e.line = line_no;
    return e;
  }

  void push_move(const Vector3d& p, const Vector3d& tool_axis, MoveOrigin origin, bool rapid,
                 int line_no) {
    // Most CAM systems write no UNITS record (NX CLSF never does) and mean mm; a file in inches
    // without one would come out 25.4 times too small. Say so once, where it matters.
    if (!units_given)
      warn_once("UNITS", line_no,
                "no UNITS record before the first motion: coordinates are read as mm (add "
                "UNITS/INCHES at the top of the file if the CAM system wrote inches)");
    ClEvent& e = push(ClEventKind::move, line_no);
    e.p_mm = p;
    e.tool_axis = tool_axis;
    e.origin = origin;
    e.rapid = rapid;
  }

  void push_feed(double mm_per_min, int line_no) {
    push(ClEventKind::feed, line_no).value = mm_per_min;
  }

  void push_text(ClEventKind kind, std::string_view text) {
    push(kind, record_line).text.assign(text.data(), text.size());
  }

  bool take_rapid() {
    const bool r = rapid_next;
    rapid_next = false;
    return r;
  }

  // The tool axis for a motion that gives none.
  const Vector3d& current_axis() const {
    if (!axis_known && multax) {
      fail_word(word +
                " before any tool axis is known: with MULTAX/ON give TLAXIS/i,j,k or a GOTO "
                "with i,j,k first");
    }
    return axis;  // +Z until a TLAXIS or a GOTO with i,j,k says otherwise
  }

  // ===========================================================================================
  // Driving

  void step() {
    if (!read_record()) {
      finish_input();
      return;
    }
    handle_record();
  }

  void finish_input() {
    if (collecting_nurbs) {
      finish_nurbs();
      return;
    }
    if (arc_pending)
      fail_line(arc_line, "the file ends after CIRCLE without the GOTO that ends the arc");
    finished = true;
  }

  void handle_record() {
    if (word.empty()) {
      emit_comments();
      return;
    }
    if (collecting_nurbs) {
      if (word == "KNOT") {
        on_knot();
      } else if (word == "CNTRL") {
        on_cntrl();
      } else {
        finish_nurbs();
        record_pending = true;  // handled once the curve's moves are out
        return;
      }
      emit_comments();
      return;
    }
    if (opt.dialect == ClDialect::automatic && !nx) {
      nx = word == "TOOL PATH" || word == "TLDATA" || word == "MSYS" || word == "END-OF-PATH" ||
           word == "PAINT";
    }
    if (arc_pending)
      check_arc_not_interrupted();
    dispatch();
    emit_comments();
  }

  void emit_comments() {
    for (const std::string& c : comments)
      push(ClEventKind::comment, record_line).text = c;
  }

  void dispatch() {
    const std::string& w = word;
    if (w == "GOTO") {
      on_goto(MoveOrigin::goto_point);
    } else if (w == "FROM") {
      on_goto(MoveOrigin::from_point);
    } else if (w == "GODLTA") {
      on_godlta();
    } else if (w == "RAPID") {
      on_rapid();
    } else if (w == "CIRCLE") {
      on_circle();
    } else if (w == "NURBS") {
      on_nurbs();
    } else if (w == "KNOT" || w == "CNTRL") {
      fail_word(w + "/ outside a NURBS/ block (it must follow NURBS/ or another KNOT/ or CNTRL/)");
    } else if (w == "CYCLE") {
      on_cycle();
    } else if (w == "FEDRAT") {
      on_fedrat();
    } else if (w == "SPINDL") {
      on_spindl();
    } else if (w == "COOLNT") {
      on_coolnt();
    } else if (w == "LOADTL") {
      on_loadtl();
    } else if (w == "LOAD") {
      on_load_or_select(true);
    } else if (w == "SELECT") {
      on_load_or_select(false);
    } else if (w == "CUTTER") {
      on_cutter();
    } else if (w == "TLDATA") {
      on_tldata();
    } else if (w == "TOOL PATH") {
      on_tool_path();
    } else if (w == "END-OF-PATH") {
      push(ClEventKind::operation_end, record_line);
    } else if (w == "PARTNO") {
      push_text(ClEventKind::part_name, trim(raw_args()));
    } else if (w == "PPRINT") {
      push_text(ClEventKind::comment, trim(raw_args()));
    } else if (w == "INSERT") {
      push_text(ClEventKind::literal, trim_right(raw_args()));
    } else if (w == "UNITS" || w == "UNIT") {
      on_units();
    } else if (w == "MULTAX") {
      on_multax();
    } else if (w == "TLAXIS") {
      on_tlaxis();
    } else if (w == "MSYS") {
      on_msys();
    } else if (w == "CSYS") {
      on_csys();
    } else if (w == "TRNTYP") {
      on_trntyp();
    } else if (w == "CUTCOM") {
      on_cutcom();
    } else if (w == "PAINT") {
      // NX display colours and speeds for the toolpath replay: nothing for a robot.
    } else if (w == "END" || w == "FINI") {
      push(ClEventKind::end_of_program, record_line);
    } else if (w == "ORIGIN" || w == "TRANS" || w == "ROTABL" || w == "COPY" || w == "INDEX") {
      fail_word(w +
                " is not supported: it moves the coordinate system or repeats records, and "
                "ignoring it would put every following point in the wrong place");
    } else {
      on_unknown();
    }
  }

  void on_unknown() {
    if (unknown_words.find(word) != unknown_words.end())
      return;
    // A file of garbage words must not grow the warnings without bound.
    constexpr std::size_t kMaxUnknownWords = 1000;
    if (unknown_words.size() >= kMaxUnknownWords) {
      warn_once("many unknown words", record_line,
                "more than " + std::to_string(kMaxUnknownWords) +
                    " different unknown words; the others are ignored without a warning");
      return;
    }
    unknown_words.insert(word);
    warnings.push_back(
        format_error(SourceLocation{source, record_line, 0}, "unknown word " + word + " ignored"));
    push(ClEventKind::unknown_word, record_line).text = word;
  }

  // ===========================================================================================
  // Motion

  void on_goto(MoveOrigin origin) {
    check_cycle_not_interrupted();
    split_fields();
    expect_count(3, 6, "3 values (x,y,z) or 6 (x,y,z,i,j,k)");
    if (fields.size() != 3 && fields.size() != 6)
      fail_at(fields[3].offset, word + " takes 3 values (x,y,z) or 6 (x,y,z,i,j,k), got " +
                                    std::to_string(fields.size()) + " values");
    if (cycle.active && origin != MoveOrigin::goto_point)
      fail_word(word + " while a CYCLE is active: only GOTO (a hole) is allowed until CYCLE/OFF");
    const Vector3d p = point(0);
    const Vector3d before_axis = axis;
    if (fields.size() == 6) {
      axis = unit_vector(3, "the tool axis");
      axis_known = true;
    } else {
      current_axis();
    }
    if (arc_pending && origin == MoveOrigin::goto_point) {
      start_arc(p, before_axis);
      return;
    }
    if (cycle.active) {
      start_hole(p);
      return;
    }
    pos = p;
    pos_known = true;
    push_move(p, axis, origin, take_rapid(), record_line);
  }

  void on_godlta() {
    check_cycle_not_interrupted();
    split_fields();
    expect_count(1, 3, "1 value (a distance along the tool axis) or 3 (dx,dy,dz)");
    if (fields.size() == 2)
      fail_word("GODLTA takes 1 value (a distance along the tool axis) or 3 (dx,dy,dz), got 2");
    if (cycle.active)
      fail_word("GODLTA while a CYCLE is active: only GOTO (a hole) is allowed until CYCLE/OFF");
    if (!pos_known)
      fail_word("GODLTA needs a known position, but no GOTO or FROM came before it");
    const Vector3d delta =
        fields.size() == 1 ? Vector3d(length(fields[0]) * current_axis()) : Vector3d(point(0));
    if (fields.size() == 3)
      current_axis();
    pos += delta;
    push_move(pos, axis, MoveOrigin::goto_point, take_rapid(), record_line);
  }

  void on_rapid() {
    split_fields();
    if (!fields.empty())
      fail_at(fields[0].offset, "RAPID takes no values");
    rapid_next = true;
    push(ClEventKind::rapid, record_line);
  }

  void on_tlaxis() {
    split_fields();
    expect_count(3, 3, "3 values (i,j,k); other forms such as TLAXIS/NORMPS are not supported");
    axis = unit_vector(0, "the tool axis");
    axis_known = true;
  }

  // ===========================================================================================
  // Arcs

  void on_circle() {
    check_cycle_not_interrupted();
    split_fields();
    const std::size_t n = fields.size();
    if (n == 13 && is(fields[11], "TIMES"))
      fail_at(fields[11].offset,
              "CIRCLE/...,TIMES,n (a helix of several turns) is not supported; output the helix "
              "as GOTO points");
    if (n != 6 && n != 7 && n != 11) {
      fail_at(n > 6 ? fields[n - 1].offset : word_offset,
              "CIRCLE takes 6 values (xc,yc,zc,i,j,k), 7 (...,r) or 11 (...,r,t,f,d,e), got " +
                  std::to_string(n));
    }
    if (cycle.active)
      fail_word("CIRCLE while a CYCLE is active: give CYCLE/OFF first");
    arc_centre = point(0);
    Vector3d a = unit_vector(3, "the circle axis");
    // NX writes the axis "assuming a clockwise direction" (NX CLSF manual, CIRCLE); APT and
    // SolidWorks CAM by the right-hand rule. Keep the right-hand one.
    arc_axis = nx ? Vector3d(-a) : a;
    arc_has_radius = n >= 7;
    if (arc_has_radius) {
      arc_radius_mm = length(fields[6]);
      arc_radius_offset = fields[6].offset;
      if (!(arc_radius_mm > 0.0))
        fail_at(fields[6].offset,
                "the circle radius must be > 0, got " + std::string(fields[6].text));
      for (std::size_t i = 7; i < n; ++i)
        number(fields[i]);  // tolerances and tool size: checked, not needed
    }
    if (!pos_known)
      fail_word("CIRCLE needs a start point, but no position is known yet");
    current_axis();
    arc_pending = true;
    arc_line = record_line;
  }

  // Between CIRCLE and its GOTO only non-motion records may come (FEDRAT, PAINT, comments...).
  void check_arc_not_interrupted() const {
    static constexpr std::string_view kBreakers[] = {
        "GODLTA", "FROM",   "CIRCLE", "NURBS", "CYCLE", "END-OF-PATH", "TOOL PATH", "END",
        "FINI",   "LOADTL", "LOAD",   "UNITS", "UNIT",  "MULTAX",      "TLAXIS"};
    for (std::string_view b : kBreakers) {
      if (word == b) {
        fail_word("CIRCLE at line " + std::to_string(arc_line) +
                  " must be followed by the GOTO that ends the arc, not by " + word);
      }
    }
  }

  void start_arc(const Vector3d& end, const Vector3d& tool_axis) {
    arc_pending = false;
    detail::ArcWording wording;
    wording.circle = "the circle of the CIRCLE at line " + std::to_string(arc_line);
    detail::ArcBuild built = detail::make_arc_chords(
        pos, arc_centre, arc_axis, arc_has_radius ? arc_radius_mm : 0.0, end,
        opt.point_match_tolerance_mm, opt.chordal_tolerance_mm, wording);
    switch (built.problem) {
      case detail::ArcProblem::none:
        break;
      case detail::ArcProblem::end_off_circle:
        // The GOTO is the culprit: point at its values.
        fail_at(fields[0].offset, built.message);
      case detail::ArcProblem::start_on_axis:
      case detail::ArcProblem::start_off_radius:
      case detail::ArcProblem::too_many_chords:
        fail_line(arc_line, built.message);
    }
    arc = built.arc;
    arc_done = 0;
    gen_axis = tool_axis;
    arc_end_axis = axis;
    gen_rapid = take_rapid();
    gen_line = record_line;
    generator = Generator::arc;
    pos = end;
    pos_known = true;
  }

  void run_arc() {
    while (queue.size() < kBatch && arc_done < arc.chords) {
      ++arc_done;
      const bool last = arc_done == arc.chords;
      push_move(arc.point(arc_done), last ? arc_end_axis : gen_axis, MoveOrigin::arc, gen_rapid,
                gen_line);
    }
    if (arc_done >= arc.chords)
      generator = Generator::none;
  }

  // ===========================================================================================
  // NURBS

  void on_nurbs() {
    check_cycle_not_interrupted();
    split_fields();
    if (!fields.empty())
      fail_at(fields[0].offset, "NURBS/ takes no values (its data follow in KNOT/ and CNTRL/)");
    if (cycle.active)
      fail_word("NURBS while a CYCLE is active: give CYCLE/OFF first");
    if (!pos_known)
      fail_word("NURBS needs a start point, but no position is known yet");
    current_axis();
    collecting_nurbs = true;
    nurbs_line = record_line;
    nurbs_knots.clear();
    nurbs_points.clear();
  }

  void on_knot() {
    split_fields();
    if (fields.empty())
      fail_word("KNOT/ needs at least one value");
    if (!nurbs_points.empty())
      fail_word("KNOT/ after CNTRL/: all knots must come before the control points");
    for (const Field& f : fields) {
      const double k = number(f);
      if (!nurbs_knots.empty() && k < nurbs_knots.back()) {
        fail_at(f.offset, "knot " + std::string(f.text) + " is smaller than the one before it (" +
                              fmt_mm(nurbs_knots.back()) + "): knots must not decrease");
      }
      nurbs_knots.push_back(k);
    }
  }

  void on_cntrl() {
    split_fields();
    expect_count(3, 4, "3 values (x,y,z) or 4 (x,y,z,weight)");
    const Vector3d p = point(0);
    double w = 1.0;
    if (fields.size() == 4) {
      w = number(fields[3]);
      if (!(w > 0.0))
        fail_at(fields[3].offset, "a NURBS weight must be > 0, got " + std::string(fields[3].text));
    }
    nurbs_points.push_back({w * p.x(), w * p.y(), w * p.z(), w});
  }

  [[noreturn]] void fail_nurbs(const std::string& message) const {
    fail_line(nurbs_line, "NURBS: " + message);
  }

  // Builds the full clamped knot vector from what the file gives, checks it and starts the
  // curve's generator. Two forms (docs/cl-format.md, "NURBS"):
  // - complete: the list starts with `order` equal knots and ends with `order` equal knots;
  //   the control points are all written (the first must be the current position) or all but
  //   the first (which is the current position);
  // - NX: the `order` leading knots (0) and `order - 1` of the trailing ones are left out and
  //   the first control point is the current position, so K knots and C CNTRL records give
  //   order = C + 2 - K; the list must start above 0 and end at 1.
  void finish_nurbs() {
    collecting_nurbs = false;
    const std::size_t k_count = nurbs_knots.size();
    const std::size_t c_count = nurbs_points.size();
    if (k_count == 0 || c_count == 0)
      fail_nurbs("needs KNOT/ and CNTRL/ records, got " + std::to_string(k_count) + " knots and " +
                 std::to_string(c_count) + " control points");
    std::size_t lead = 1;
    while (lead < k_count && nurbs_knots[lead] == nurbs_knots[0])
      ++lead;
    curve.knots.clear();
    curve.points.clear();
    bool start_written = false;
    const std::string counts =
        std::to_string(k_count) + " knots and " + std::to_string(c_count) + " control points";
    if (lead >= 2) {
      curve.order = static_cast<int>(lead);
      if (k_count == c_count + lead) {
        start_written = true;
      } else if (k_count != c_count + 1 + lead) {
        fail_nurbs(counts + " do not fit a complete knot vector of order " + std::to_string(lead) +
                   " (it needs " + std::to_string(c_count + lead) +
                   " or, with the current position as first point, " +
                   std::to_string(c_count + 1 + lead) + " knots)");
      }
      curve.knots.assign(nurbs_knots.begin(), nurbs_knots.end());
    } else {
      const long order = static_cast<long>(c_count) + 2 - static_cast<long>(k_count);
      if (!(nurbs_knots.front() > 0.0) || std::fabs(nurbs_knots.back() - 1.0) > 1e-9) {
        fail_nurbs(
            "the knots neither start with a repeated value (a complete knot vector) nor "
            "run from above 0 to 1 (the NX form without the end knots): cannot tell the "
            "curve's order");
      }
      if (order < 2 || order > detail::kMaxNurbsOrder) {
        fail_nurbs(counts + " give order " + std::to_string(order) +
                   " in the NX form (order = " + "control points + 2 - knots); expected 2 to " +
                   std::to_string(detail::kMaxNurbsOrder));
      }
      curve.order = static_cast<int>(order);
      curve.knots.assign(static_cast<std::size_t>(order), 0.0);
      curve.knots.insert(curve.knots.end(), nurbs_knots.begin(), nurbs_knots.end() - 1);
      curve.knots.insert(curve.knots.end(), static_cast<std::size_t>(order), nurbs_knots.back());
    }
    if (curve.order > detail::kMaxNurbsOrder)
      fail_nurbs("order " + std::to_string(curve.order) + " is above the supported " +
                 std::to_string(detail::kMaxNurbsOrder));
    if (!start_written)
      curve.points.push_back({pos.x(), pos.y(), pos.z(), 1.0});
    curve.points.insert(curve.points.end(), nurbs_points.begin(), nurbs_points.end());
    check_knot_runs();
    if (start_written) {
      const double gap = (curve.cartesian(0) - pos).norm();
      if (gap > opt.point_match_tolerance_mm) {
        fail_nurbs("the curve starts " + fmt_mm(gap) +
                   " mm away from the current position (its first CNTRL/ must be the point "
                   "the tool is at; tolerance " +
                   fmt_mm(opt.point_match_tolerance_mm) + " mm)");
      }
    }
    gen_axis = axis;  // on_nurbs() made sure it is known
    gen_rapid = take_rapid();
    gen_line = nurbs_line;
    curve_chords.start(curve, opt.chordal_tolerance_mm);
    generator = Generator::nurbs;
    pos = curve.cartesian(curve.points.size() - 1);
  }

  // Clamped ends (order equal knots at each end) and interior knots repeated at most `degree`
  // times, so that the curve is continuous and every span formula is defined.
  void check_knot_runs() const {
    const std::vector<double>& u = curve.knots;
    const std::size_t order = static_cast<std::size_t>(curve.order);
    const std::size_t n = curve.points.size();
    if (n < order)
      fail_nurbs("order " + std::to_string(order) + " needs at least " + std::to_string(order) +
                 " control points, got " + std::to_string(n));
    std::size_t i = 0;
    while (i < u.size()) {
      std::size_t j = i;
      while (j < u.size() && u[j] == u[i])
        ++j;
      const std::size_t run = j - i;
      const bool at_start = i == 0;
      const bool at_end = j == u.size();
      if ((at_start || at_end) && run != order) {
        fail_nurbs(std::string("the knot vector must ") + (at_start ? "start" : "end") +
                   " with exactly " + std::to_string(order) + " equal knots (order " +
                   std::to_string(order) + "), got " + std::to_string(run));
      }
      if (!at_start && !at_end && run >= order) {
        fail_nurbs("the interior knot " + fmt_mm(u[i]) + " is repeated " + std::to_string(run) +
                   " times; at most " + std::to_string(order - 1) + " keeps the curve continuous");
      }
      i = j;
    }
  }

  void run_nurbs() {
    Vector3d p;
    while (queue.size() < kBatch) {
      if (!curve_chords.next(p)) {
        generator = Generator::none;
        return;
      }
      push_move(p, gen_axis, MoveOrigin::nurbs, gen_rapid, gen_line);
    }
  }

  // ===========================================================================================
  // Drilling cycles

  void on_cycle() {
    split_fields();
    if (fields.empty())
      fail_word("CYCLE/ needs a cycle type (DRILL, DEEP, OFF, ...)");
    const Field& type = fields[0];
    if (is(type, "OFF") || is(type, "INIT")) {
      // INIT: SolidWorks CAM opens a cycle block with it; the cycle itself follows.
      if (fields.size() > 1)
        fail_at(fields[1].offset, "CYCLE/" + std::string(type.text) + " takes no further values");
      if (is(type, "OFF")) {
        cycle.active = false;
        cycle.interrupted = false;
      }
      return;
    }
    if (is(type, "ON")) {
      if (!cycle.defined)
        fail_at(type.offset, "CYCLE/ON without a cycle defined before it");
      cycle.active = true;
      cycle.interrupted = false;
      return;
    }
    std::size_t i = 1;
    bool deep = false;
    if (is(type, "DRILL")) {
      if (fields.size() > 1 && (is(fields[1], "DEEP") || is(fields[1], "BRKCHP"))) {
        deep = true;
        i = 2;
      }
    } else if (type.text.size() >= 4 && iequals(type.text.substr(0, 4), "DEEP") &&
               std::all_of(type.text.begin() + 4, type.text.end(),
                           [](char c) { return c >= '0' && c <= '9'; })) {
      deep = true;  // DEEP, and SolidWorks CAM's DEEP2
    } else {
      fail_at(type.offset,
              "CYCLE/" + std::string(type.text) +
                  " is not supported; redpost expands only drilling cycles (CYCLE/DRILL, "
                  "CYCLE/DRILL,DEEP, CYCLE/DEEP) into moves: output this operation as GOTO "
                  "points instead");
    }
    read_cycle_parameters(i, deep);
  }

  void read_cycle_parameters(std::size_t i, bool deep) {
    DrillCycle c;
    c.deep = deep;
    c.line = record_line;
    bool has_depth = false, has_clearance = false, has_retract = false, has_feed = false;
    bool has_first = false, has_next = false;
    const std::string name = "CYCLE/" + std::string(fields[0].text);
    for (; i < fields.size(); i += 2) {
      const Field& key = fields[i];
      if (looks_numeric(key)) {
        fail_at(key.offset, name +
                                ": expected a keyword (FEDTO, RAPTO, RTRCTO, MMPM, ...) but "
                                "found the number " +
                                std::string(key.text) +
                                " (the positional ISO 4343:1978 form is not supported)");
      }
      if (i + 1 >= fields.size())
        fail_at(key.offset, name + ": " + std::string(key.text) + " needs a value after it");
      const Field& val = fields[i + 1];
      if (is(key, "FEDTO")) {
        c.depth_mm = non_negative_length(val, "FEDTO (the depth below the hole point)");
        has_depth = true;
      } else if (is(key, "RAPTO")) {
        c.clearance_mm = non_negative_length(val, "RAPTO (the clearance above the hole point)");
        has_clearance = true;
      } else if (is(key, "RTRCTO")) {
        c.retract_mm = non_negative_length(val, "RTRCTO (the retract height above the hole point)");
        has_retract = true;
      } else if (is_feed_unit(key)) {
        c.feed_mm_per_min = feed_value(val, key.text);
        has_feed = true;
      } else if (is(key, "DWELL")) {
        if (non_negative_length(val, "DWELL") > 0.0) {
          warn_once("DWELL", record_line,
                    name + ": DWELL ignored (a robot program gets no dwell at the hole bottom)");
        }
      } else if (is(key, "1STPECK")) {
        c.first_peck_mm = positive_length(val, "1STPECK");
        has_first = true;
      } else if (is(key, "SUBPECK")) {
        c.next_peck_mm = positive_length(val, "SUBPECK");
        has_next = true;
      } else {
        fail_at(key.offset, name + ": unknown parameter " + std::string(key.text) +
                                " (known: FEDTO, RAPTO, RTRCTO, MMPM, IPM, MMPR, IPR, DWELL, "
                                "1STPECK, SUBPECK); redpost will not guess what it means");
      }
    }
    if (!has_depth || !has_clearance)
      fail_word(name + " needs FEDTO (the depth) and RAPTO (the clearance) to be expanded safely");
    if (!has_feed) {
      if (!feed_known)
        fail_word(name + " gives no feed (MMPM, IPM, MMPR or IPR) and no FEDRAT came before it");
      c.feed_mm_per_min = feed_mm_per_min;
    }
    c.retract_mm = has_retract ? c.retract_mm : c.clearance_mm;
    if (deep) {
      if (!has_first && c.depth_mm > 0.0) {
        fail_word(name +
                  " gives no peck depth (1STPECK, SUBPECK): redpost will not guess one for a "
                  "pecking cycle");
      }
      c.next_peck_mm = has_next ? c.next_peck_mm : c.first_peck_mm;
      if (!has_first)  // FEDTO 0: a single touch, nothing to peck
        c.first_peck_mm = c.next_peck_mm = 1.0;
    }
    if (c.depth_mm == 0.0)
      warn_once("FEDTO0", record_line,
                name + " has FEDTO 0: its holes are only touched, not drilled");
    c.defined = true;
    c.active = true;
    cycle = c;
  }

  void interrupt_cycle() {
    if (cycle.active) {
      cycle.active = false;
      cycle.interrupted = true;
      cycle.interrupted_line = record_line;
    }
  }

  // Motion after an interrupted cycle (see DrillCycle::interrupted) is refused.
  void check_cycle_not_interrupted() const {
    if (!cycle.interrupted)
      return;
    fail_word("the CYCLE of line " + std::to_string(cycle.line) +
              " was still on when the tool changed at line " +
              std::to_string(cycle.interrupted_line) +
              " (no CYCLE/OFF): redpost cannot tell whether this " + word +
              " is a hole of that cycle or a plain move; add CYCLE/OFF before the tool change, "
              "or repeat the CYCLE after it");
  }

  double positive_length(const Field& f, const char* what) const {
    const double v = length(f);
    if (!(v > 0.0))
      fail_at(f.offset, std::string(what) + " must be > 0, got " + std::string(f.text));
    return v;
  }

  // A hole at `p` (the GOTO point, on the surface): travel at the retract height, rapid to the
  // clearance, feed down in one go or in pecks (rapid out to the clearance and back down to the
  // clearance above the last peck's bottom between them), rapid out to the retract height.
  void start_hole(const Vector3d& p) {
    take_rapid();  // the cycle decides which of its moves are rapid
    hole_point = p;
    hole_pecks = 1;
    if (cycle.deep && cycle.depth_mm > cycle.first_peck_mm) {
      const double more =
          std::ceil((cycle.depth_mm - cycle.first_peck_mm) / cycle.next_peck_mm - 1e-9);
      if (more + 1.0 > kMaxChords)
        fail_line(cycle.line, "this pecking cycle needs more than 1e8 pecks: check SUBPECK");
      hole_pecks = 1 + static_cast<long>(more);
    }
    hole_peck = 0;
    hole_phase = HolePhase::travel;
    gen_axis = axis;
    gen_line = record_line;
    generator = Generator::hole;
  }

  double peck_depth(long k) const {
    if (!cycle.deep)
      return cycle.depth_mm;
    return std::min(cycle.depth_mm,
                    cycle.first_peck_mm + static_cast<double>(k) * cycle.next_peck_mm);
  }

  // A move of the cycle, left out when it would not move.
  void hole_move(double above_mm, bool rapid) {
    const Vector3d q = hole_point + above_mm * gen_axis;
    if (pos_known && (q - pos).norm() <= 1e-9)
      return;
    push_move(q, gen_axis, MoveOrigin::cycle, rapid, gen_line);
    pos = q;
    pos_known = true;
  }

  void run_hole() {
    while (queue.size() < kBatch && hole_phase != HolePhase::done) {
      switch (hole_phase) {
        case HolePhase::travel:
          hole_move(cycle.retract_mm, true);
          hole_phase = HolePhase::approach;
          break;
        case HolePhase::approach:
          hole_move(cycle.clearance_mm, true);
          hole_phase = HolePhase::feed_on;
          break;
        case HolePhase::feed_on:
          push_feed(cycle.feed_mm_per_min, gen_line);
          hole_phase = HolePhase::cut;
          break;
        case HolePhase::reenter:
          hole_move(cycle.clearance_mm - peck_depth(hole_peck - 1), true);
          hole_phase = HolePhase::cut;
          break;
        case HolePhase::cut:
          hole_move(-peck_depth(hole_peck), false);
          hole_phase = hole_peck + 1 < hole_pecks ? HolePhase::peck_out : HolePhase::feed_off;
          break;
        case HolePhase::peck_out:
          hole_move(cycle.clearance_mm, true);
          ++hole_peck;
          hole_phase = HolePhase::reenter;
          break;
        case HolePhase::feed_off:
          if (feed_known)
            push_feed(feed_mm_per_min, gen_line);
          hole_phase = HolePhase::retract;
          break;
        case HolePhase::retract:
          hole_move(cycle.retract_mm, true);
          hole_phase = HolePhase::done;
          break;
        case HolePhase::done:
          break;
      }
    }
    if (hole_phase == HolePhase::done)
      generator = Generator::none;
  }

  void run_generator() {
    switch (generator) {
      case Generator::arc:
        run_arc();
        break;
      case Generator::nurbs:
        run_nurbs();
        break;
      case Generator::hole:
        run_hole();
        break;
      case Generator::none:
        break;
    }
  }

  // ===========================================================================================
  // Feed, spindle, coolant

  // A feed value with its unit word, in mm/min.
  double feed_value(const Field& value, std::string_view unit) const {
    double v = 0.0;
    if (iequals(unit, "MMPM")) {
      v = number(value);
    } else if (iequals(unit, "IPM")) {
      v = number(value, kMmPerInch);
    } else if (iequals(unit, "MMPR") || iequals(unit, "IPR")) {
      const double per_rev = number(value, iequals(unit, "IPR") ? kMmPerInch : 1.0);
      if (!(spindle_rpm > 0.0)) {
        fail_at(value.offset, word + "/..., " + std::string(unit) +
                                  " is a feed per revolution, but the spindle speed is not "
                                  "known (no SPINDL/n,RPM before it, or the spindle is off)");
      }
      v = per_rev * spindle_rpm;
    }
    if (!(v > 0.0))
      fail_at(value.offset, "the feed must be > 0, got " + std::string(value.text));
    if (v > kMaxMagnitude)
      fail_at(value.offset, "number out of range: the feed is beyond 1e7 mm/min");
    return v;
  }

  void on_fedrat() {
    split_fields();
    expect_count(1, 2, "f, f,MMPM or MMPM,f (also IPM, MMPR, IPR)");
    const Field* value = &fields[0];
    std::string_view unit = unit_mm == 1.0 ? "MMPM" : "IPM";  // FEDRAT/f: per minute
    if (fields.size() == 2) {
      const bool unit_first = is_feed_unit(fields[0]);
      value = &fields[unit_first ? 1 : 0];
      const Field& u = fields[unit_first ? 0 : 1];
      if (!is_feed_unit(u))
        fail_at(u.offset, "FEDRAT: unknown feed unit " + std::string(u.text) +
                              " (use MMPM, IPM, MMPR or IPR)");
      unit = u.text;
    }
    const double v = feed_value(*value, unit);
    feed_per_rev = iequals(unit, "MMPR") || iequals(unit, "IPR");
    feed_mm_per_rev = feed_per_rev ? v / spindle_rpm : 0.0;
    feed_mm_per_min = v;
    feed_known = true;
    push_feed(v, record_line);
  }

  void on_spindl() {
    split_fields();
    if (fields.empty())
      fail_word("SPINDL/ needs a speed (SPINDL/n,RPM,CLW) or OFF");
    bool has_rpm = false, off = false, on = false;
    double rpm = 0.0;
    SpindleDirection dir = SpindleDirection::clockwise;
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const Field& f = fields[i];
      if (is(f, "RPM")) {
      } else if (is(f, "CLW")) {
        dir = SpindleDirection::clockwise;
      } else if (is(f, "CCLW")) {
        dir = SpindleDirection::counter_clockwise;
      } else if (is(f, "OFF")) {
        off = true;
      } else if (is(f, "ON")) {
        on = true;
      } else if (is(f, "RANGE")) {
        ++i;  // the gearbox range: a robot spindle has none
        if (i >= fields.size())
          fail_at(f.offset, "SPINDL: RANGE needs a value after it");
        number(fields[i]);
      } else if (is(f, "SFM") || is(f, "SMM")) {
        fail_at(f.offset, "SPINDL: surface speed (" + std::string(f.text) +
                              ") is not supported; give the speed in RPM");
      } else if (is_letter(f.text.front())) {
        fail_at(f.offset, "SPINDL: unknown word " + std::string(f.text) +
                              " (known: RPM, CLW, CCLW, OFF, ON, RANGE)");
      } else {
        if (has_rpm)
          fail_at(f.offset, "SPINDL gives two speeds");
        rpm = number(f);
        if (rpm < 0.0)
          fail_at(f.offset, "the spindle speed must be >= 0 (CCLW gives the direction), got " +
                                std::string(f.text));
        has_rpm = true;
      }
    }
    if (off || (has_rpm && rpm == 0.0)) {
      spindle_rpm = 0.0;
      ClEvent& e = push(ClEventKind::spindle, record_line);
      e.value = 0.0;
      e.direction = SpindleDirection::off;
      return;
    }
    if (!has_rpm) {
      if (!on || !(last_spindle_rpm > 0.0))
        fail_word("SPINDL/ needs a speed in RPM (SPINDL/n,RPM,CLW)");
      rpm = last_spindle_rpm;
      dir = last_direction;
    }
    spindle_rpm = last_spindle_rpm = rpm;
    last_direction = dir;
    ClEvent& e = push(ClEventKind::spindle, record_line);
    e.value = rpm;
    e.direction = dir;
    if (feed_known && feed_per_rev) {  // a feed per revolution follows the spindle
      feed_mm_per_min = feed_mm_per_rev * rpm;
      push_feed(feed_mm_per_min, record_line);
    }
  }

  void on_coolnt() {
    split_fields();
    expect_count(1, 2, "a mode: ON, OFF, FLOOD, MIST, THRU or TAP");
    bool flag = true;
    std::string_view mode;
    for (const Field& f : fields) {
      if (is(f, "OFF")) {
        flag = false;
      } else if (is(f, "ON")) {
      } else if (is(f, "FLOOD") || is(f, "MIST") || is(f, "THRU") || is(f, "TAP")) {
        mode = f.text;
      } else {
        fail_at(f.offset, "COOLNT: unknown mode " + std::string(f.text) +
                              " (use ON, OFF, FLOOD, MIST, THRU or TAP)");
      }
    }
    ClEvent& e = push(ClEventKind::coolant, record_line);
    e.flag = flag;
    if (mode.empty())
      mode = flag ? "ON" : "OFF";
    e.text.resize(mode.size());
    std::transform(mode.begin(), mode.end(), e.text.begin(), upper);
  }

  // ===========================================================================================
  // Tools

  void push_tool_change(int number_) {
    interrupt_cycle();
    ClEvent& e = push(ClEventKind::tool_change, record_line);
    e.tool_number = number_;
    e.tool_diameter_mm = tool_diameter_mm;
    e.tool_length_mm = tool_length_mm;
    e.text = tool_name;
  }

  // Couplets after the tool number: ADJUST,m (length offset register) and LENGTH,l.
  void read_tool_couplets(std::size_t i) {
    for (; i < fields.size(); i += 2) {
      const Field& key = fields[i];
      if (i + 1 >= fields.size())
        fail_at(key.offset, word + ": " + std::string(key.text) + " needs a value after it");
      if (is(key, "ADJUST")) {
        tool_number(fields[i + 1]);
      } else if (is(key, "LENGTH")) {
        tool_length_mm = non_negative_length(fields[i + 1], "LENGTH");
      } else {
        fail_at(key.offset, word + ": unknown word " + std::string(key.text) +
                                " (known after the tool number: ADJUST, LENGTH)");
      }
    }
  }

  void on_loadtl() {
    split_fields();
    if (fields.empty())
      fail_word("LOADTL/ needs a tool number");
    const int n = tool_number(fields[0]);
    read_tool_couplets(1);
    push_tool_change(n);
  }

  void on_load_or_select(bool load) {
    split_fields();
    if (fields.size() < 2 || !is(fields[0], "TOOL")) {
      fail_at(fields.empty() ? word_offset : fields[0].offset,
              word + "/ is supported only as " + word + "/TOOL,n");
    }
    const int n = tool_number(fields[1]);
    read_tool_couplets(2);
    if (load || opt.select_tool_loads)
      push_tool_change(n);
    // Otherwise SELECT/TOOL is a preselect: the next tool to fetch, not a change (SolidWorks
    // CAM writes it right after LOAD/TOOL with the number of the following tool).
  }

  void on_cutter() {
    split_fields();
    expect_count(1, 7, "1 to 7 values (d, r, e, f, a, b, h)");
    tool_diameter_mm = non_negative_length(fields[0], "the cutter diameter");
    for (std::size_t i = 1; i < fields.size(); ++i)
      length(fields[i]);
    tool_length_mm = fields.size() == 7 ? non_negative_length(fields[6], "the cutter height") : 0.0;
  }

  void on_tldata() {
    split_fields();
    if (fields.empty())
      fail_word("TLDATA/ needs a tool type (TLDATA/MILL,d,r,length,...)");
    if (!is(fields[0], "MILL")) {
      warn_once("TLDATA " + std::string(fields[0].text), record_line,
                "TLDATA/" + std::string(fields[0].text) +
                    " not read: only TLDATA/MILL gives a diameter and length redpost knows");
      tool_diameter_mm = tool_length_mm = 0.0;
      return;
    }
    if (fields.size() < 4)
      fail_word("TLDATA/MILL takes at least 3 values (diameter, corner radius, length), got " +
                std::to_string(fields.size() - 1));
    tool_diameter_mm = non_negative_length(fields[1], "the tool diameter");
    non_negative_length(fields[2], "the corner radius");
    tool_length_mm = non_negative_length(fields[3], "the tool length");
    for (std::size_t i = 4; i < fields.size(); ++i)
      number(fields[i]);
  }

  void on_tool_path() {
    split_fields();
    if (fields.empty())
      fail_word("TOOL PATH/ needs the operation's name");
    if (fields.size() >= 3 && is(fields[1], "TOOL"))
      tool_name.assign(fields[2].text.data(), fields[2].text.size());
    interrupt_cycle();
    push_text(ClEventKind::operation_start, fields[0].text);
  }

  // ===========================================================================================
  // Programme and coordinate systems

  void on_units() {
    units_given = true;
    split_fields();
    expect_count(1, 1, "MM or INCHES");
    const Field& f = fields[0];
    if (is(f, "MM")) {
      unit_mm = 1.0;
    } else if (is(f, "INCHES") || is(f, "INCH")) {
      unit_mm = kMmPerInch;
    } else {
      fail_at(f.offset, word + ": unknown unit " + std::string(f.text) + " (use MM or INCHES)");
    }
  }

  void on_multax() {
    split_fields();
    expect_count(0, 1, "ON or OFF");
    if (fields.empty() || is(fields[0], "ON")) {
      multax = true;
    } else if (is(fields[0], "OFF")) {
      multax = false;
    } else {
      fail_at(fields[0].offset, "MULTAX: expected ON or OFF, got " + std::string(fields[0].text));
    }
  }

  // NX's machine coordinate system: origin and X, Y axes in NX's absolute frame. The CL points
  // are already in the MCS, which redpost takes as the workpiece frame; MSYS is only checked.
  void on_msys() {
    split_fields();
    expect_count(9, 9, "9 values (origin x,y,z, X axis i,j,k, Y axis i,j,k)");
    point(0);
    const Vector3d x(number(fields[3]), number(fields[4]), number(fields[5]));
    const Vector3d y(number(fields[6]), number(fields[7]), number(fields[8]));
    if (std::fabs(x.norm() - 1.0) > 1e-3 || std::fabs(y.norm() - 1.0) > 1e-3 ||
        std::fabs(x.dot(y)) > 1e-3) {
      fail_at(fields[3].offset, "MSYS: the X and Y axes must be orthogonal unit vectors");
    }
  }

  // A 3 x 4 matrix [R | t]. redpost reads only the identity (both layouts in use: rows of
  // [r r r t], or 9 rotation values then t); any other would put the points in another frame.
  void on_csys() {
    split_fields();
    expect_count(12, 12, "12 values (a 3 x 4 matrix)");
    static constexpr double kRows[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    static constexpr double kRotFirst[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    bool rows = true, rot_first = true;
    for (std::size_t i = 0; i < 12; ++i) {
      const double v = number(fields[i]);
      rows = rows && std::fabs(v - kRows[i]) <= 1e-9;
      rot_first = rot_first && std::fabs(v - kRotFirst[i]) <= 1e-9;
    }
    if (!rows && !rot_first) {
      fail_word(
          "CSYS/ with a matrix other than the identity is not supported: the points after "
          "it would be in another frame; output the CL data in the workpiece frame");
    }
  }

  void on_trntyp() {
    split_fields();
    if (fields.empty())
      fail_word("TRNTYP/ needs values (TRNTYP/WORLD,0,0,0)");
    bool identity = is(fields[0], "WORLD");
    for (std::size_t i = 1; i < fields.size(); ++i)
      identity = number(fields[i]) == 0.0 && identity;
    if (!identity) {
      fail_word(
          "TRNTYP/ other than TRNTYP/WORLD,0,0,0 is not supported: it would move the "
          "points after it into another frame");
    }
  }

  void on_cutcom() {
    split_fields();
    if (fields.empty())
      fail_word("CUTCOM/ needs LEFT, RIGHT or OFF");
    const Field& f = fields[0];
    if (is(f, "LEFT") || is(f, "RIGHT")) {
      warn_once("CUTCOM", record_line,
                "CUTCOM/" + std::string(f.text) +
                    " ignored: KRL has no cutter radius compensation; redpost takes the CL "
                    "points as the tool centre (NX: 'centerline data')");
    } else if (!is(f, "OFF")) {
      fail_at(f.offset, "CUTCOM: expected LEFT, RIGHT or OFF, got " + std::string(f.text));
    }
  }
};

ClReader::ClReader(std::istream& in, std::string source_name, ClReaderOptions options)
    : impl_(std::make_unique<Impl>(in, std::move(source_name), options)) {}

ClReader::~ClReader() = default;

bool ClReader::next(ClEvent& event) {
  Impl& m = *impl_;
  try {
    while (m.head == m.queue.size()) {
      if (m.finished)
        return false;
      m.queue.clear();
      m.head = 0;
      if (m.generator != Generator::none)
        m.run_generator();
      else
        m.step();
    }
  } catch (...) {
    // After an error the stream position is inside a broken record: stop for good.
    m.finished = true;
    m.generator = Generator::none;
    m.queue.clear();
    m.head = 0;
    throw;
  }
  event = std::move(m.queue[m.head++]);
  return true;
}

const std::deque<std::string>& ClReader::warnings() const {
  return impl_->warnings;
}

const std::string& ClReader::source_name() const {
  return impl_->source;
}

}  // namespace redpost
