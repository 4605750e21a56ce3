// The pass-through KRL statements (redpost/krl/statement.hpp): a small recursive-descent
// reader of exactly the forms listed there.
#include "redpost/krl/statement.hpp"

#include <cctype>
#include <charconv>
#include <cmath>

namespace redpost::krl {

namespace {

bool name_start(char c) {
  return std::isalpha(static_cast<unsigned char>(c)) || c == '_';
}
bool name_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}
char upper(char c) {
  return static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
}

class Parser {
 public:
  explicit Parser(std::string_view s) : s_(s) {}

  std::string parse() {
    skip();
    if (at_end())
      return "it is empty";
    const size_t start = i_;
    std::string_view word = ident();
    if (word.empty() && peek() == '$') {
      ++i_;
      word = ident();
      if (word.empty())
        return "'$' must start a system variable's name";
      i_ = start;
      return assignment();
    }
    if (word.empty())
      return "expected a statement (HALT, WAIT, an assignment or a routine call)";
    if (iequal(word, "HALT"))
      return end();
    if (iequal(word, "WAIT"))
      return wait();
    if (is_reserved(word))
      return "'" + std::string(word) + "' is not one of the statements redpost passes through " +
             kAccepted;
    skip();
    if (peek() == '(') {
      ++i_;
      return call_arguments();
    }
    i_ = start;
    return assignment();
  }

 private:
  static constexpr const char* kAccepted =
      "(HALT, WAIT SEC, WAIT FOR, an assignment, or a routine call)";

  std::string_view s_;
  size_t i_ = 0;

  bool at_end() const { return i_ >= s_.size(); }
  char peek() const { return at_end() ? '\0' : s_[i_]; }
  void skip() {
    while (!at_end() && (s_[i_] == ' ' || s_[i_] == '\t'))
      ++i_;
  }
  std::string_view ident() {
    const size_t b = i_;
    if (at_end() || !name_start(s_[i_]))
      return {};
    while (!at_end() && name_char(s_[i_]))
      ++i_;
    return s_.substr(b, i_ - b);
  }
  static bool iequal(std::string_view a, std::string_view b) {
    if (a.size() != b.size())
      return false;
    for (size_t k = 0; k < a.size(); ++k) {
      if (upper(a[k]) != upper(b[k]))
        return false;
    }
    return true;
  }
  static bool is_reserved(std::string_view w) {
    for (std::string_view k :
         {"PTP",     "LIN",       "CIRC",      "SPTP",      "SLIN",    "SCIRC",    "PTP_REL",
          "LIN_REL", "SPLINE",    "ENDSPLINE", "IF",        "ELSE",    "ENDIF",    "FOR",
          "ENDFOR",  "WHILE",     "ENDWHILE",  "LOOP",      "ENDLOOP", "REPEAT",   "UNTIL",
          "SWITCH",  "CASE",      "DEFAULT",   "ENDSWITCH", "GOTO",    "EXIT",     "RETURN",
          "DECL",    "DEF",       "DEFFCT",    "END",       "ENDFCT",  "DEFDAT",   "ENDDAT",
          "GLOBAL",  "INTERRUPT", "TRIGGER",   "BRAKE",     "RESUME",  "CONTINUE", "SIGNAL",
          "STRUC",   "ENUM",      "EXT",       "EXTFCT",    "CONST",   "PUBLIC"}) {
      if (iequal(w, k))
        return true;
    }
    return false;
  }

  // The rest of the line: blanks, then nothing or a comment.
  std::string end() {
    skip();
    if (at_end() || peek() == ';')
      return {};
    return "unexpected '" + std::string(s_.substr(i_)) + "' after the statement";
  }

  std::string number() {
    const char* first = s_.data() + i_;
    const char* last = s_.data() + s_.size();
    if (first != last && (*first == '-' || *first == '+'))
      ++first;
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
    if (ec != std::errc() || !std::isfinite(v) || std::fabs(v) > 1e9)
      return "expected a number of at most 1e9";
    i_ = static_cast<size_t>(ptr - s_.data());
    return {};
  }

  // NAME or $NAME, then [i] / [i, j] and .FIELD parts.
  std::string variable() {
    if (peek() == '$')
      ++i_;
    if (ident().empty())
      return "expected a variable's name";
    for (;;) {
      if (peek() == '[') {
        ++i_;
        for (;;) {
          skip();
          if (!std::isdigit(static_cast<unsigned char>(peek())))
            return "expected a whole number as an index";
          while (std::isdigit(static_cast<unsigned char>(peek())))
            ++i_;
          skip();
          if (peek() == ',') {
            ++i_;
            continue;
          }
          if (peek() != ']')
            return "expected ']' after an index";
          ++i_;
          break;
        }
      } else if (peek() == '.') {
        ++i_;
        if (ident().empty())
          return "expected a field name after '.'";
      } else {
        return {};
      }
    }
  }

  std::string value() {
    skip();
    const char c = peek();
    if (c == '#') {
      ++i_;
      return ident().empty() ? "expected an enumeration value after '#'" : std::string();
    }
    if (c == '"') {
      const size_t close = s_.find('"', i_ + 1);
      if (close == std::string_view::npos)
        return "a text in \" \" is not closed";
      i_ = close + 1;
      return {};
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.')
      return number();
    const size_t b = i_;
    const std::string_view w = ident();
    if (iequal(w, "TRUE") || iequal(w, "FALSE"))
      return {};
    i_ = b;
    if (c == '$' || name_start(c))
      return variable();
    return "expected a value (a number, TRUE, FALSE, #VALUE, \"text\" or a variable)";
  }

  std::string assignment() {
    if (std::string why = variable(); !why.empty())
      return why;
    skip();
    if (peek() != '=' || (i_ + 1 < s_.size() && s_[i_ + 1] == '='))
      return std::string("expected '=' of an assignment ") + kAccepted;
    ++i_;
    if (std::string why = value(); !why.empty())
      return why;
    return end();
  }

  std::string call_arguments() {
    skip();
    if (peek() == ')') {
      ++i_;
      return end();
    }
    for (;;) {
      if (std::string why = value(); !why.empty())
        return why;
      skip();
      if (peek() == ',') {
        ++i_;
        continue;
      }
      if (peek() != ')')
        return "expected ',' or ')' in the routine's arguments";
      ++i_;
      return end();
    }
  }

  std::string wait() {
    skip();
    const std::string_view kind = ident();
    if (iequal(kind, "SEC")) {
      skip();
      if (std::string why = number(); !why.empty())
        return "WAIT SEC: " + why;
      return end();
    }
    if (!iequal(kind, "FOR"))
      return "WAIT needs SEC or FOR";
    skip();
    const size_t b = i_;
    if (!iequal(ident(), "NOT"))
      i_ = b;
    skip();
    if (std::string why = variable(); !why.empty())
      return "WAIT FOR: " + why;
    skip();
    if (peek() == '=' && i_ + 1 < s_.size() && s_[i_ + 1] == '=') {
      i_ += 2;
      skip();
      const std::string_view v = ident();
      if (!iequal(v, "TRUE") && !iequal(v, "FALSE"))
        return "WAIT FOR: expected TRUE or FALSE after '=='";
    }
    return end();
  }
};

}  // namespace

std::string statement_problem(std::string_view text) {
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if ((u < 0x20 && c != '\t') || u == 0x7f)
      return "it holds a control character";
  }
  if (text.size() > 2000)
    return "it is longer than 2000 characters";
  return Parser(text).parse();
}

}  // namespace redpost::krl
