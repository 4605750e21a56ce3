// Small text helpers for KRL source, shared by the reader, the check and the diff: KRL is case
// insensitive (names are compared upper case) and its identifiers include '$' (system
// variables).
#pragma once

#include <cctype>
#include <string>

namespace redpost::krl {

inline std::string upper(std::string s) {
  for (char& c : s)
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

inline bool ident_start(char c) {
  return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == '$';
}

inline bool ident_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '$';
}

}  // namespace redpost::krl
