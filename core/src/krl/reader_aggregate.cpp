// The KRL reader's aggregates: {[TYPE:] F v, ...} with the fields of a point (X Y Z A B C,
// A1..A6, E1..E6) and S and T as integers or 'B010' / 'H1F' literals.
#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <set>

#include "io/text_util.hpp"
#include "krl/reader_parse.hpp"

namespace redpost::krl {

using detail::trim;

const std::set<std::string>& point_types() {
  static const std::set<std::string> t{"E6POS", "E6AXIS", "POS", "AXIS", "FRAME"};
  return t;
}

namespace {

bool is_value_field(const std::string& f) {
  static const std::set<std::string> names{"X",  "Y",  "Z",  "A",  "B",  "C",  "A1", "A2", "A3",
                                           "A4", "A5", "A6", "E1", "E2", "E3", "E4", "E5", "E6"};
  return names.count(f) != 0;
}

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

}  // namespace

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

}  // namespace redpost::krl
