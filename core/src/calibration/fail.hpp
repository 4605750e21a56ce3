// The refusal every check of the calibration ends in: Error(bad_input) with the message
// (internal to core; not installed).
#pragma once

#include <string>

#include "redpost/io/error.hpp"

namespace redpost::detail {

[[noreturn]] inline void fail_bad_input(const std::string& message) {
  throw Error(ErrorCode::bad_input, message);
}

}  // namespace redpost::detail
