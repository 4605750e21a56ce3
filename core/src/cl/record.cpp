// The record layer of the CL reader (cl/record.hpp): physical lines joined into records, the
// major word and the values of a record, and the errors that point into it.
#include "cl/record.hpp"

#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

#include "redpost/io/error.hpp"

namespace redpost::detail {

using Eigen::Vector3d;

namespace {

constexpr double kMinAxisNorm = 1e-6;  // NX prints axes with 7 decimals

bool is_word_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-';
}

// Records whose argument is free text; classic APT also writes them without '/' ("PARTNO X").
bool is_text_word(std::string_view w) {
  return ClRecordReader::iequals(w, "PARTNO") || ClRecordReader::iequals(w, "PPRINT") ||
         ClRecordReader::iequals(w, "INSERT");
}

// Major words that take values and so need a '/'.
bool needs_slash(std::string_view w) {
  for (std::string_view k :
       {"GOTO",   "GODLTA", "FROM",   "CIRCLE", "KNOT",   "CNTRL",  "CYCLE",  "FEDRAT",
        "SPINDL", "COOLNT", "LOADTL", "LOAD",   "SELECT", "CUTTER", "TLDATA", "UNITS",
        "UNIT",   "TLAXIS", "MSYS",   "CSYS",   "TRNTYP", "CUTCOM"}) {
    if (ClRecordReader::iequals(w, k))
      return true;
  }
  return false;
}

// The position of the first "$$" (a comment to the end of the line), or npos.
std::size_t comment_start(std::string_view s) {
  std::size_t i = s.find('$');
  while (i != std::string_view::npos && i + 1 < s.size()) {
    if (s[i + 1] == '$')
      return i;
    i = s.find('$', i + 1);
  }
  return std::string_view::npos;
}

}  // namespace

ClRecordReader::ClRecordReader(std::istream& in, std::string source_name,
                               std::size_t max_line_bytes, bool keep_comments)
    : source(std::move(source_name)),
      lines_(in, source, max_line_bytes),
      max_line_bytes_(max_line_bytes),
      keep_comments_(keep_comments) {}

// ===========================================================================================
// Records

// Reads the next record (a comment-only line counts when comments are kept). False at the end.
bool ClRecordReader::next_record() {
  for (;;) {
    record_.clear();
    segments_.clear();
    comments.clear();
    bool continued = false;
    do {
      if (!lines_.next(line_)) {
        if (continued) {
          fail_line(lines_.line_number(),
                    "the record ends with the continuation mark '$' but the file ends here");
        }
        return false;
      }
      std::string_view code(line_);
      const std::size_t c = comment_start(code);
      if (c != std::string_view::npos) {
        if (keep_comments_ && !trim(code.substr(c + 2)).empty())
          comments.emplace_back(trim(code.substr(c + 2)));
        code = code.substr(0, c);
      }
      code = trim_right(code);
      continued = !code.empty() && code.back() == '$';
      if (continued)
        code.remove_suffix(1);
      if (segments_.empty())
        record_line = lines_.line_number();
      segments_.push_back({record_.size(), lines_.line_number()});
      record_.append(code);
      if (record_.size() > max_line_bytes_) {
        fail_line(record_line, "record longer than " + std::to_string(max_line_bytes_) +
                                   " bytes with its continuation lines");
      }
    } while (continued);
    if (!trim(record_).empty() || !comments.empty())
      break;
  }
  parse_record();
  return true;
}

// Finds the major word and where the values start.
void ClRecordReader::parse_record() {
  word.clear();
  fields.clear();
  const std::string_view rec(record_);
  const std::size_t begin = rec.find_first_not_of(" \t\v\f");
  if (begin == std::string_view::npos)
    return;  // comment-only
  word_offset = begin;
  const std::size_t slash = rec.find('/', begin);
  std::size_t word_end = rec.size();
  const bool has_slash = slash != std::string_view::npos;
  if (has_slash) {
    word_end = slash;
    args_offset_ = slash + 1;
  } else {
    args_offset_ = rec.size();
    const std::size_t gap = rec.find_first_of(" \t", begin);
    if (gap != std::string_view::npos) {
      const std::string_view first = rec.substr(begin, gap - begin);
      if (is_text_word(first)) {  // PARTNO text, PPRINT text, INSERT text
        word_end = gap;
        args_offset_ = gap + 1;
      } else if (needs_slash(first)) {
        fail_at(gap, std::string(first) + " needs '/' before its values");
      } else {
        fail_at(begin, "malformed record: expected a major word and '/' (such as GOTO/x,y,z)");
      }
    }
  }
  normalise_word(rec.substr(begin, word_end - begin));
  // A NUL after a good word is binary data too, and would cut an INSERT's or a PPRINT's text
  // where it stands.
  if (const std::size_t nul = rec.find('\0'); nul != std::string_view::npos)
    fail_at(nul, "malformed record: byte 0x00: is this a CL text file (APT or CLSF)?");
}

// Upper case, runs of blanks to one space; a word is letters, digits, '_' and '-', starting
// with a letter ("TOOL PATH" and "END-OF-PATH" are words).
void ClRecordReader::normalise_word(std::string_view raw) {
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
      fail_at(word_offset + i, std::string("malformed record: unexpected '") + c +
                                   "' in the major word (expected a word such as GOTO, then '/')");
    }
    if (blank && !word.empty())
      word.push_back(' ');
    blank = false;
    word.push_back(upper(c));
  }
}

// Splits the values after '/' at commas; an empty value is an error.
void ClRecordReader::split_fields() {
  fields.clear();
  const std::string_view rec(record_);
  if (args_offset_ >= rec.size() || trim(rec.substr(args_offset_)).empty())
    return;
  std::size_t start = args_offset_;
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

std::string_view ClRecordReader::raw_args() const {
  const std::string_view rec(record_);
  return args_offset_ >= rec.size() ? std::string_view() : rec.substr(args_offset_);
}

// ===========================================================================================
// Values

double ClRecordReader::number(const Field& f, double scale) const {
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

double ClRecordReader::non_negative_length(const Field& f, const char* what) const {
  const double v = length(f);
  if (v < 0.0)
    fail_at(f.offset, std::string(what) + " must be >= 0, got " + std::string(f.text));
  return v;
}

double ClRecordReader::positive_length(const Field& f, const char* what) const {
  const double v = length(f);
  if (!(v > 0.0))
    fail_at(f.offset, std::string(what) + " must be > 0, got " + std::string(f.text));
  return v;
}

Vector3d ClRecordReader::point(std::size_t i) const {
  return Vector3d(length(fields[i]), length(fields[i + 1]), length(fields[i + 2]));
}

Vector3d ClRecordReader::unit_vector(std::size_t i, const char* what) const {
  const Vector3d v(number(fields[i]), number(fields[i + 1]), number(fields[i + 2]));
  const double n = v.norm();
  if (!(n >= kMinAxisNorm))
    fail_at(fields[i].offset, std::string(what) + " (i,j,k) has zero length");
  return v / n;
}

// Whether the field reads as a number (a keyword such as 1STPECK does not).
bool ClRecordReader::looks_numeric(const Field& f) {
  const char* first = f.text.data();
  const char* last = first + f.text.size();
  if (first != last && *first == '+')
    ++first;
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
  return ptr == last && ptr != first && (ec == std::errc() || ec == std::errc::result_out_of_range);
}

bool ClRecordReader::is_feed_unit(const Field& f) const {
  return is(f, "MMPM") || is(f, "IPM") || is(f, "MMPR") || is(f, "IPR");
}

int ClRecordReader::tool_number(const Field& f) const {
  const double v = number(f);
  if (v < 0.0 || v > 1e6 || v != std::floor(v))
    fail_at(f.offset,
            "tool number must be a whole number from 0 to 1000000, got " + std::string(f.text));
  return static_cast<int>(v);
}

void ClRecordReader::expect_count(std::size_t min_count, std::size_t max_count,
                                  const char* usage) const {
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
// Errors

SourceLocation ClRecordReader::where(std::size_t offset) const {
  SourceLocation loc{source, record_line, 0};
  std::size_t base = 0;
  for (const Segment& s : segments_) {
    if (s.offset > offset)
      break;
    loc.line = s.line;
    base = s.offset;
  }
  loc.column = static_cast<int>(offset - base) + 1;
  return loc;
}

void ClRecordReader::fail_at(std::size_t offset, const std::string& message) const {
  throw Error(ErrorCode::bad_input, message, where(offset));
}

void ClRecordReader::fail_word(const std::string& message) const {
  fail_at(word_offset, message);
}

void ClRecordReader::fail_line(int line_no, const std::string& message) const {
  throw Error(ErrorCode::bad_input, message, SourceLocation{source, line_no, 0});
}

}  // namespace redpost::detail
