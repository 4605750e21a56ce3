#include "redpost/io/durable_write.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "redpost/io/error.hpp"

namespace redpost {
namespace fs = std::filesystem;

namespace {

std::string errno_text(int err) {
  return std::strerror(err);
}

// The folder a path lies in, "." for a bare file name.
std::string folder_of(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

}  // namespace

std::string temporary_path(const std::string& final_path) {
  const fs::path p(final_path);
  return (p.parent_path() / ("." + p.filename().string() + ".part~")).string();
}

void flush_to_disk(std::FILE* file, const std::string& path_for_message) {
  if (std::fflush(file) != 0 || ::fsync(::fileno(file)) != 0) {
    throw Error(ErrorCode::io,
                "cannot write: " + errno_text(errno) +
                    "; check the free space and that the output folder is on a working disk",
                SourceLocation{path_for_message, 0, 0});
  }
}

void sync_directory(const std::string& dir_or_empty) {
  const std::string dir = dir_or_empty.empty() ? std::string(".") : dir_or_empty;
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) {
    throw Error(ErrorCode::io, "cannot open the output folder to sync it: " + errno_text(errno),
                SourceLocation{dir, 0, 0});
  }
  const int rc = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (rc != 0 && err != EINVAL && err != EROFS) {
    throw Error(ErrorCode::io, "cannot sync the output folder: " + errno_text(err),
                SourceLocation{dir, 0, 0});
  }
}

void write_text_files(const std::vector<TextOutput>& files) {
  std::vector<std::string> temps;
  const auto remove_temps = [&temps] {
    for (const std::string& t : temps)
      std::remove(t.c_str());
  };
  try {
    for (const TextOutput& f : files) {
      temps.push_back(temporary_path(f.path));
      std::FILE* fp = std::fopen(temps.back().c_str(), "wb");
      if (fp == nullptr) {
        temps.pop_back();
        throw Error(ErrorCode::io,
                    "cannot create a file: " + errno_text(errno) +
                        "; check that the folder exists and is writable",
                    SourceLocation{f.path, 0, 0});
      }
      const bool written = std::fwrite(f.text.data(), 1, f.text.size(), fp) == f.text.size();
      const int write_err = errno;
      try {
        if (!written) {
          throw Error(ErrorCode::io,
                      "cannot write: " + errno_text(write_err) + "; check the free space",
                      SourceLocation{f.path, 0, 0});
        }
        flush_to_disk(fp, f.path);
      } catch (...) {
        std::fclose(fp);
        throw;
      }
      if (std::fclose(fp) != 0) {
        throw Error(ErrorCode::io, "cannot write: " + errno_text(errno),
                    SourceLocation{f.path, 0, 0});
      }
    }
  } catch (...) {
    remove_temps();
    throw;
  }
  for (size_t k = 0; k < files.size(); ++k) {
    if (std::rename(temps[k].c_str(), files[k].path.c_str()) != 0) {
      const int err = errno;
      for (size_t j = k; j < temps.size(); ++j)
        std::remove(temps[j].c_str());
      throw Error(ErrorCode::io, "cannot rename the finished file into place: " + errno_text(err),
                  SourceLocation{files[k].path, 0, 0});
    }
  }
  std::vector<std::string> synced;
  for (const TextOutput& f : files) {
    const std::string dir = folder_of(f.path);
    if (std::find(synced.begin(), synced.end(), dir) == synced.end()) {
      sync_directory(dir);
      synced.push_back(dir);
    }
  }
}

}  // namespace redpost
