#include "redpost/io/text_file.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include "redpost/io/error.hpp"

namespace redpost {

namespace {
struct stat checked_stat(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    throw Error(ErrorCode::io,
                err == ENOENT ? "no such file; check the path"
                              : std::string("cannot access the file: ") + std::strerror(err),
                SourceLocation{path, 0, 0});
  }
  if (S_ISDIR(st.st_mode)) {
    throw Error(ErrorCode::io, "is a directory, expected a file", SourceLocation{path, 0, 0});
  }
  return st;
}
}  // namespace

std::ifstream open_text_stream(const std::string& path) {
  checked_stat(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw Error(ErrorCode::io, std::string("cannot open the file: ") + std::strerror(errno),
                SourceLocation{path, 0, 0});
  }
  return in;
}

std::string read_text_file(const std::string& path, std::size_t max_bytes) {
  const struct stat st = checked_stat(path);
  const auto too_large = [&] {
    return Error(ErrorCode::io,
                 "file has more than " + std::to_string(max_bytes) +
                     " bytes, the most a definition, readings or KRL file may have: is it the "
                     "right file?",
                 SourceLocation{path, 0, 0});
  };
  if (static_cast<std::size_t>(st.st_size) > max_bytes)
    throw too_large();
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw Error(ErrorCode::io, std::string("cannot open the file: ") + std::strerror(errno),
                SourceLocation{path, 0, 0});
  }
  // Read by blocks up to the limit, whatever stat said: a pipe or a device (/dev/zero) has
  // st_size 0 and must not be read without bound. libstdc++ reports a failed read() by
  // throwing from sgetn.
  std::string text;
  char block[1 << 16];
  try {
    for (std::streamsize got; (got = in.rdbuf()->sgetn(block, sizeof block)) > 0;) {
      if (text.size() + static_cast<std::size_t>(got) > max_bytes)
        throw too_large();
      text.append(block, static_cast<std::size_t>(got));
    }
  } catch (const std::ios_base::failure&) {
    throw Error(ErrorCode::io, "read error: is it a readable regular file?",
                SourceLocation{path, 0, 0});
  }
  return text;
}

}  // namespace redpost
