// The one exception type of redpost::core.
//
// Every failure that a user can cause (bad input, an unreachable pose, a joint-limit breach)
// is reported as an Error carrying a code and, for input, the place it came from, so that a
// message always reads "file:line: what is wrong". The C ABI turns these into status codes.
#pragma once

#include <stdexcept>
#include <string>

namespace redpost {

enum class ErrorCode {
  bad_input,    // malformed or out-of-range input data (file contents, stdin, arguments)
  io,           // a file that cannot be opened, read or written
  unreachable,  // a pose the cell cannot reach
  joint_limit,  // a posture outside the joint limits
  internal,     // a broken invariant inside redpost: a bug
};

// Where an input error was found. line/column are 1-based; 0 means "not known".
struct SourceLocation {
  std::string file;
  int line = 0;
  int column = 0;
};

class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, std::string message, SourceLocation where = {});

  ErrorCode code() const noexcept { return code_; }
  const std::string& message() const noexcept { return message_; }
  const SourceLocation& where() const noexcept { return where_; }

 private:
  ErrorCode code_;
  std::string message_;
  SourceLocation where_;
};

// "file:line:column: message", leaving out the parts that are not known.
std::string format_error(const SourceLocation& where, const std::string& message);

}  // namespace redpost
