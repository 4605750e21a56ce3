#include "redpost/text_file.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

#include "redpost/error.hpp"

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
  if (static_cast<std::size_t>(st.st_size) > max_bytes) {
    throw Error(ErrorCode::io,
                "file is " + std::to_string(st.st_size) + " bytes, more than the " +
                    std::to_string(max_bytes) + " a definition may have",
                SourceLocation{path, 0, 0});
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw Error(ErrorCode::io, std::string("cannot open the file: ") + std::strerror(errno),
                SourceLocation{path, 0, 0});
  }
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad())
    throw Error(ErrorCode::io, "read error", SourceLocation{path, 0, 0});
  return text;
}

}  // namespace redpost
