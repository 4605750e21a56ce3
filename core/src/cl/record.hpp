// The record layer of the CL reader: a CL file read record by record, the major word and the
// values of the current record, read as numbers, lengths in mm (with the file's unit), points
// and unit vectors, and the errors that name the file, line and column of a value. It knows
// nothing of motion: ClReader::Impl (cl/reader_impl.hpp) derives from it and handles the records.
//
// A record is one or more physical lines joined at a `$` continuation mark, without its `$$`
// comments; its fields are string_views into it, so reading a record allocates nothing once the
// buffers have grown to the longest record.
//
// Internal to the CL reader (core/src/cl/); not installed.
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "cl/line_source.hpp"
#include "redpost/io/error.hpp"

namespace redpost::detail {

class ClRecordReader {
 public:
  using Vector3d = Eigen::Vector3d;

  struct Field {
    std::string_view text;  // trimmed
    std::size_t offset;     // of the text's first character in the record
  };

  static constexpr double kMmPerInch = 25.4;
  // Largest magnitude of any number after conversion to mm (or mm/min, rpm): catches typos such
  // as 1e30 before they poison the kinematics.
  static constexpr double kMaxMagnitude = 1e7;

  ClRecordReader(std::istream& in, std::string source_name, std::size_t max_line_bytes,
                 bool keep_comments);

  // ---- records -------------------------------------------------------------------------------
  // Reads the next record and finds its major word (a comment-only line counts when comments are
  // kept). False at the end.
  bool next_record();
  void split_fields();
  std::string_view raw_args() const;

  // ---- values --------------------------------------------------------------------------------
  double number(const Field& f, double scale = 1.0) const;
  double length(const Field& f) const { return number(f, unit_mm); }
  double non_negative_length(const Field& f, const char* what) const;
  double positive_length(const Field& f, const char* what) const;
  Vector3d point(std::size_t i) const;  // fields i, i+1, i+2 as a length in mm
  Vector3d unit_vector(std::size_t i, const char* what) const;
  bool is(const Field& f, std::string_view w) const { return iequals(f.text, w); }
  static bool looks_numeric(const Field& f);
  bool is_feed_unit(const Field& f) const;
  int tool_number(const Field& f) const;
  void expect_count(std::size_t min_count, std::size_t max_count, const char* usage) const;

  // ---- errors --------------------------------------------------------------------------------
  SourceLocation where(std::size_t offset) const;
  [[noreturn]] void fail_at(std::size_t offset, const std::string& message) const;
  [[noreturn]] void fail_word(const std::string& message) const;
  [[noreturn]] void fail_line(int line_no, const std::string& message) const;

  // ---- text ----------------------------------------------------------------------------------
  static bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }

  static std::string_view trim(std::string_view s) {
    while (!s.empty() && is_blank(s.front()))
      s.remove_prefix(1);
    while (!s.empty() && is_blank(s.back()))
      s.remove_suffix(1);
    return s;
  }

  static std::string_view trim_right(std::string_view s) {
    while (!s.empty() && is_blank(s.back()))
      s.remove_suffix(1);
    return s;
  }

  static char upper(char c) {
    return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 'a' + 'A') : c;
  }

  static bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size())
      return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (upper(a[i]) != upper(b[i]))
        return false;
    }
    return true;
  }

  static bool is_letter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }

  // ---- the file ------------------------------------------------------------------------------
  std::string source;
  double unit_mm = 1.0;  // mm per unit of length in the file (set by UNITS)

  // ---- the current record --------------------------------------------------------------------
  int record_line = 0;
  std::vector<std::string> comments;  // $$ comments of the record (keep_comments only)
  std::string word;  // upper case, single spaces ("TOOL PATH"); empty for a comment-only line
  std::size_t word_offset = 0;
  std::vector<Field> fields;  // by split_fields()

 private:
  // Record text from `offset` on came from physical line `line`, whose column 1 is at `offset`.
  struct Segment {
    std::size_t offset;
    int line;
  };

  void parse_record();
  void normalise_word(std::string_view raw);

  ClLineSource lines_;
  std::size_t max_line_bytes_;
  bool keep_comments_;
  std::string line_;
  std::string record_;
  std::vector<Segment> segments_;
  std::size_t args_offset_ = 0;  // first character after '/'
};

}  // namespace redpost::detail
