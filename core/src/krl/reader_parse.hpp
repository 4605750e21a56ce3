// The parsing level of the KRL reader, with which reader.cpp walks a program: lines, comments
// and the index of a module, i.e. its DEFs and the points declared in it and in its .dat
// (reader_module.cpp), and aggregates such as {X 1, Y 2, S 6} (reader_aggregate.cpp).
#pragma once

#include <cctype>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "krl/text.hpp"
#include "redpost/krl/reader.hpp"

namespace redpost::krl {

// --- lines -------------------------------------------------------------------------------------

// The whole of a .src or .dat as it is, with the limits of for_each_krl_line.
inline constexpr std::size_t kMaxKrlLineBytes = 64 * 1024;
std::string read_krl_text(const std::string& path);

// Reads a .src or .dat a line at a time: `visit` gets each line without its ending, and the
// ending as it is ("\n", "\r\n", "\r" alone, "" at the end of the file); it returns false to
// stop. A line longer than kMaxKrlLineBytes is refused at once (Error(bad_input) with its line),
// the file beyond kMaxKrlFileBytes (Error(io)). Returns the bytes read. Memory: one line.
using KrlLineVisitor =
    std::function<bool(int line, const std::string& text, std::string_view ending)>;
std::size_t for_each_krl_line(const std::string& path, const KrlLineVisitor& visit);

// Splits on LF, CRLF or CR: views into `text`, which must outlive them.
std::vector<std::string_view> split_lines(const std::string& text);

// Splits a line into code and comment at the first ';' outside a "..." string.
void split_comment(std::string_view line, std::string& code, std::string& comment);

// The leading identifier of `s` (letters, digits, '_', '$'), upper case.
std::string leading_word(const std::string& s);

[[noreturn]] void fail(const std::string& file, int line, const std::string& msg);

bool is_motion_keyword(const std::string& w);
const std::set<std::string>& motion_keywords();

// --- aggregates --------------------------------------------------------------------------------

const std::set<std::string>& point_types();

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
    while (pos < text.size() && ident_char(text[pos]))
      ++pos;
    return text.substr(b, pos - b);
  }
};

double parse_real_field(Cursor& c, const std::string& field);

// Parses "{[TYPE:] F v, ...}" at c.pos; leaves c.pos after the '}'.
KrlAggregate parse_aggregate(Cursor& c);

// --- modules -----------------------------------------------------------------------------------

struct DefRange {
  std::string name;  // as written
  int begin = 0;     // index of the DEF line
  int end = 0;       // index of the END line
};

struct Module {
  std::string src_path;
  std::string dat_path;                        // "" if none
  std::unique_ptr<const std::string> text;     // the .src as read (its bytes stay put when moved)
  std::vector<std::string_view> lines;         // into *text
  std::vector<DefRange> defs;                  // in file order; defs[0] is the module's main DEF
  std::map<std::string, KrlAggregate> points;  // upper-case name -> value
  std::map<std::string, std::string> array_types;  // upper-case array name -> point type
  int stray_line = 0;  // first line of code outside a DEF (0: none), warned about
};

// Finds `stem.ext` in `dir` regardless of case; "" if absent.
std::string find_file_nocase(const std::filesystem::path& dir, const std::string& stem,
                             const std::string& ext);

// Reads a .src, indexes its DEFs and reads the point DECLs in it and in the .dat beside it.
// Throws Error(bad_input) with file:line for unmatched DEF/END and malformed aggregates.
// `text`, when given, gets the .dat's text and then the .src's as they are read, before either
// is parsed.
Module load_module(const std::string& src_path, const KrlTextSink* text = nullptr);

}  // namespace redpost::krl
