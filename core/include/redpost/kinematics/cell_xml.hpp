// Loading cell definitions from XML (format: docs/cell-format.md).
//
// Every problem in the file is reported as an Error(ErrorCode::bad_input) whose location names
// the file and line, e.g. "kr15.xml:42: <limits> of joint 'theta_2': min 40 > max -155".
#pragma once

#include <string>

#include "redpost/kinematics/cell.hpp"

namespace redpost {

// Reads and validates a cell file. Throws Error (io or bad_input).
Cell load_cell(const std::string& path);

// Parses a cell from XML text; `source_name` is used in messages.
Cell parse_cell(const std::string& xml_text, const std::string& source_name);

}  // namespace redpost
