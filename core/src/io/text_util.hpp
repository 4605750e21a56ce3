// Small text helpers shared by the readers of core (internal; not installed).
#pragma once

#include <cctype>
#include <string>

namespace redpost::detail {

// s without leading and trailing white space.
inline std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b])))
    ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1])))
    --e;
  return s.substr(b, e - b);
}

}  // namespace redpost::detail
