// Escaping text for HTML and SVG (both XML-like): the one function both writers use.
#pragma once

#include <string>
#include <string_view>

namespace redpost::report {

// &, <, > and " as entities; everything else as is (UTF-8 passes through).
inline std::string esc(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace redpost::report
