// Reading a whole small text file (definitions, templates), with messages that say what is
// wrong: missing, a directory, unreadable, or too large to be a definition.
//
// CL files are never read whole; they are streamed (see the CL reader).
#pragma once

#include <cstddef>
#include <fstream>
#include <string>

namespace redpost {

inline constexpr std::size_t kMaxDefinitionBytes = 16u << 20;  // 16 MiB

// Throws Error(ErrorCode::io) with the path in the message.
std::string read_text_file(const std::string& path, std::size_t max_bytes = kMaxDefinitionBytes);

// Opens a file to be streamed (a CL file), with the same checks and messages: missing, a
// directory, unreadable.
std::ifstream open_text_stream(const std::string& path);

}  // namespace redpost
