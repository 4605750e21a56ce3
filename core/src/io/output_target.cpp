#include "redpost/io/output_target.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "redpost/io/error.hpp"

namespace redpost {
namespace fs = std::filesystem;

namespace {

const char* kind_of(mode_t mode) {
  if (S_ISLNK(mode))
    return "a symbolic link";
  if (S_ISDIR(mode))
    return "a folder";
  if (S_ISCHR(mode))
    return "a character device";
  if (S_ISBLK(mode))
    return "a block device";
  if (S_ISFIFO(mode))
    return "a FIFO";
  if (S_ISSOCK(mode))
    return "a socket";
  return "not a regular file";
}

}  // namespace

void check_output_target(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode))
    return;
  throw Error(ErrorCode::io,
              what + " is " + kind_of(st.st_mode) +
                  ": redpost writes a new file and renames it into place, which would replace "
                  "it; name a regular file, or remove it first",
              SourceLocation{path, 0, 0});
}

void check_output_folder(const std::string& path, const std::string& what) {
  const fs::path p(path), folder = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  if (fs::is_directory(folder, ec) && ::access(folder.c_str(), W_OK) == 0)
    return;
  throw Error(ErrorCode::io,
              what + ": the folder '" + folder.string() +
                  "' does not exist or is not writable; create it or choose another path",
              SourceLocation{path, 0, 0});
}

bool same_file(const std::string& a, const std::string& b) {
  struct stat sa {
  }, sb{};
  if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0)
    return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
  std::error_code ea, eb;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a), ea);
  const fs::path cb = fs::weakly_canonical(fs::absolute(b), eb);
  return !ea && !eb && ca == cb;
}

void check_distinct_files(const std::vector<NamedPath>& inputs,
                          const std::vector<NamedPath>& outputs) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    const NamedPath& out = outputs[i];
    if (out.path.empty())
      continue;
    for (const NamedPath& in : inputs) {
      if (!in.path.empty() && same_file(out.path, in.path)) {
        throw Error(ErrorCode::io,
                    out.role + " names the same file as " + in.role +
                        ": writing it would destroy that input; choose another path",
                    SourceLocation{out.path, 0, 0});
      }
    }
    for (size_t j = 0; j < i; ++j) {
      if (!outputs[j].path.empty() && same_file(out.path, outputs[j].path)) {
        throw Error(ErrorCode::io,
                    out.role + " names the same file as " + outputs[j].role +
                        ": one would overwrite the other; choose another path",
                    SourceLocation{out.path, 0, 0});
      }
    }
  }
}

}  // namespace redpost
