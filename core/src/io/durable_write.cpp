#include "redpost/io/durable_write.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "redpost/io/error.hpp"
#include "redpost/io/output_target.hpp"
#include "redpost/io/temporaries.hpp"

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

// The swap of replace_files(), with what it has done so far, so that it can be undone.
struct Swap {
  const std::vector<Replacement>& files;
  std::vector<std::string> aside;  // per file: where its old file was moved, empty: none
  size_t renamed_in = 0;           // files[0, renamed_in) carry their new content

  // Moves the existing final files aside, the last first (the file that makes the set usable
  // disappears before any of the others changes).
  void move_old_aside() {
    aside.assign(files.size(), std::string());
    for (size_t n = files.size(); n-- > 0;) {
      const std::string& final_path = files[n].final_path;
      if (::access(final_path.c_str(), F_OK) != 0 && errno == ENOENT)
        continue;
      std::string backup;
      try {
        backup = create_unique_beside(final_path, ".old~");
      } catch (const Error& e) {
        fail(final_path, e.message());
      }
      if (::rename(final_path.c_str(), backup.c_str()) != 0) {
        const int err = errno;
        ::unlink(backup.c_str());
        fail(final_path, "cannot move the existing file aside to replace it: " + errno_text(err) +
                             " (is it immutable or on a read-only mount?)");
      }
      aside[n] = backup;
    }
  }

  void rename_new_in() {
    for (; renamed_in < files.size(); ++renamed_in) {
      const Replacement& f = files[renamed_in];
      if (::rename(f.temp.c_str(), f.final_path.c_str()) != 0) {
        fail(f.final_path, "cannot rename the finished file into place: " + errno_text(errno));
      }
      forget_temporary(f.temp);
    }
  }

  // Undoes what was done, then throws. The old files go back under their names; the new ones
  // and every temporary are removed.
  [[noreturn]] void fail(const std::string& where, const std::string& why) {
    bool restored = true;
    for (size_t n = 0; n < files.size(); ++n) {
      if (n < renamed_in)
        ::unlink(files[n].final_path.c_str());
      else
        remove_temporary(files[n].temp);
      if (!aside.empty() && !aside[n].empty() &&
          ::rename(aside[n].c_str(), files[n].final_path.c_str()) != 0) {
        restored = false;
      }
    }
    throw Error(ErrorCode::io,
                why + (restored ? "; nothing was replaced: the old files are kept"
                                : "; the old files could not all be put back: they are in the "
                                  "hidden '.old~' files of the folder"),
                SourceLocation{where, 0, 0});
  }
};

}  // namespace

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

void replace_files(const std::vector<Replacement>& files) {
  try {
    for (const Replacement& f : files)
      check_output_target(f.final_path, "the output file");
  } catch (...) {
    for (const Replacement& f : files)
      remove_temporary(f.temp);
    throw;
  }
  {
    const FileSection section;
    Swap swap{files, {}, 0};
    swap.move_old_aside();
    swap.rename_new_in();
    for (const std::string& old : swap.aside) {
      if (!old.empty())
        ::unlink(old.c_str());
    }
  }
  std::vector<std::string> synced;
  for (const Replacement& f : files) {
    const std::string dir = folder_of(f.final_path);
    if (std::find(synced.begin(), synced.end(), dir) == synced.end()) {
      sync_directory(dir);
      synced.push_back(dir);
    }
  }
}

PreparedTexts::PreparedTexts(const std::vector<TextOutput>& files) {
  try {
    for (const TextOutput& f : files) {
      check_output_target(f.path, "the output file");
      const Temporary t = create_temporary(f.path);
      files_.push_back(Replacement{t.path, f.path});
      const bool written = std::fwrite(f.text.data(), 1, f.text.size(), t.file) == f.text.size();
      const int write_err = errno;
      try {
        if (!written) {
          throw Error(ErrorCode::io,
                      "cannot write: " + errno_text(write_err) + "; check the free space",
                      SourceLocation{f.path, 0, 0});
        }
        flush_to_disk(t.file, f.path);
      } catch (...) {
        std::fclose(t.file);
        throw;
      }
      if (std::fclose(t.file) != 0) {
        throw Error(ErrorCode::io, "cannot write: " + errno_text(errno),
                    SourceLocation{f.path, 0, 0});
      }
    }
  } catch (...) {
    for (const Replacement& r : files_)
      remove_temporary(r.temp);
    throw;
  }
}

PreparedTexts::~PreparedTexts() {
  for (const Replacement& r : files_)
    remove_temporary(r.temp);
}

void PreparedTexts::commit() {
  std::vector<Replacement> files;
  files.swap(files_);
  replace_files(files);
}

void write_text_files(const std::vector<TextOutput>& files) {
  PreparedTexts(files).commit();
}

}  // namespace redpost
