// What the XML standard refuses and tinyxml2 lets through (issue 48): tinyxml2 reads a comment
// that holds "--", a bare '&' or an undefined entity as text, and a '<' inside an attribute
// value. xmllint, Python's parser and every XML editor refuse such a file, so a definition a
// user copies and edits there would break; redpost refuses it too, at its line.
#include <cctype>
#include <string>
#include <string_view>

#include "io/strict_xml.hpp"

namespace redpost::detail {

namespace {

struct Scan {
  std::string_view text;
  std::size_t i = 0;
  int line = 1;

  // Moves to position `to`, counting the lines passed.
  void advance(std::size_t to) {
    for (; i < to && i < text.size(); ++i)
      line += text[i] == '\n' ? 1 : 0;
  }
  // The line of position `at` (at >= i).
  int line_at(std::size_t at) const {
    int n = line;
    for (std::size_t k = i; k < at && k < text.size(); ++k)
      n += text[k] == '\n' ? 1 : 0;
    return n;
  }
};

bool is_hex(char c) {
  return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
}

// The reference that starts at text[at] == '&': empty if it is one XML knows without a DTD (the
// five predefined entities, a character reference), else what is wrong with it.
std::string check_reference(std::string_view text, std::size_t at) {
  const std::size_t semi = text.find(';', at);
  const std::string_view ref = semi == std::string_view::npos || semi - at > 12
                                   ? std::string_view()
                                   : text.substr(at + 1, semi - at - 1);
  if (ref == "amp" || ref == "lt" || ref == "gt" || ref == "quot" || ref == "apos")
    return {};
  if (ref.size() >= 2 && ref[0] == '#') {
    const bool hex = ref[1] == 'x';
    std::size_t k = hex ? 2 : 1;
    bool digits = k < ref.size();
    for (; k < ref.size(); ++k)
      digits = digits && (hex ? is_hex(ref[k]) : (ref[k] >= '0' && ref[k] <= '9'));
    if (digits)
      return {};
  }
  bool name = !ref.empty();
  for (char c : ref) {
    const auto u = static_cast<unsigned char>(c);
    name = name && (std::isalnum(u) || c == '_' || c == '-' || c == '.' || c == ':' || u >= 0x80);
  }
  if (name) {
    return "the entity '&" + std::string(ref) +
           ";' is not defined (XML knows &amp; &lt; &gt; &quot; &apos; and &#N;)";
  }
  return "a bare '&', which XML does not allow: write it as &amp;";
}

}  // namespace

std::optional<XmlProblem> find_xml_lexical_problem(std::string_view text) {
  Scan s{text};
  while (s.i < text.size()) {
    const std::size_t lt = text.find_first_of("<&", s.i);
    if (lt == std::string_view::npos)
      break;
    s.advance(lt);
    if (text[lt] == '&') {
      if (std::string what = check_reference(text, lt); !what.empty())
        return XmlProblem{s.line, "not well-formed XML: " + what};
      s.advance(lt + 1);
      continue;
    }
    const std::string_view rest = text.substr(lt);
    // A comment: no "--" inside it, and it may not end in "--->".
    if (rest.rfind("<!--", 0) == 0) {
      const std::size_t end = text.find("-->", lt + 4);
      if (end == std::string_view::npos)
        break;  // unterminated: tinyxml2 has said so already
      const std::size_t dd = text.find("--", lt + 4);
      if (dd < end || (end > lt + 4 && text[end - 1] == '-')) {
        const std::size_t at = dd < end ? dd : end - 1;
        return XmlProblem{s.line_at(at),
                          "not well-formed XML: a comment holds '--' (two hyphens in a row), "
                          "which XML forbids and XML editors refuse: write them apart or "
                          "reword"};
      }
      s.advance(end + 3);
      continue;
    }
    // CDATA, a processing instruction, a declaration: passed over.
    const auto skip_to = [&](std::string_view close) {
      const std::size_t end = text.find(close, lt);
      s.advance(end == std::string_view::npos ? text.size() : end + close.size());
    };
    if (rest.rfind("<![CDATA[", 0) == 0) {
      skip_to("]]>");
      continue;
    }
    if (rest.rfind("<?", 0) == 0) {
      skip_to("?>");
      continue;
    }
    if (rest.rfind("<!", 0) == 0) {
      skip_to(">");
      continue;
    }
    // A tag: its attribute values may hold neither '<' nor a bare '&'.
    std::size_t k = lt + 1;
    char quote = 0;
    for (; k < text.size(); ++k) {
      const char c = text[k];
      if (quote) {
        if (c == quote) {
          quote = 0;
        } else if (c == '<') {
          return XmlProblem{s.line_at(k),
                            "not well-formed XML: an attribute value holds '<', which XML "
                            "does not allow: write it as &lt;"};
        } else if (c == '&') {
          if (std::string what = check_reference(text, k); !what.empty())
            return XmlProblem{s.line_at(k), "not well-formed XML: " + what};
        }
      } else if (c == '"' || c == '\'') {
        quote = c;
      } else if (c == '>') {
        break;
      }
    }
    s.advance(k + 1);
  }
  return std::nullopt;
}

}  // namespace redpost::detail
