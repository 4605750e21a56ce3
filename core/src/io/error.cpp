#include "redpost/io/error.hpp"

#include <utility>

namespace redpost {

std::string format_error(const SourceLocation& where, const std::string& message) {
  std::string out;
  if (!where.file.empty()) {
    out += where.file;
    if (where.line > 0) {
      out += ':' + std::to_string(where.line);
      if (where.column > 0)
        out += ':' + std::to_string(where.column);
    }
    out += ": ";
  }
  out += message;
  return out;
}

Error::Error(ErrorCode code, std::string message, SourceLocation where)
    : std::runtime_error(format_error(where, message)),
      code_(code),
      message_(std::move(message)),
      where_(std::move(where)) {}

}  // namespace redpost
