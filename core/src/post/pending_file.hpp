// A file written under a temporary name and renamed into place on commit(), removed otherwise:
// the post session's joints log appears only complete (docs/reliability.md).
//
// Internal to redpost::core; not installed.
#pragma once

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "redpost/io/durable_write.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/output_target.hpp"
#include "redpost/io/temporaries.hpp"

namespace redpost {

class PendingFile {
 public:
  PendingFile() = default;
  explicit PendingFile(std::string path) : path_(std::move(path)) {
    check_output_target(path_, "the joints CSV");
    Temporary t = create_temporary(path_);
    temp_ = std::move(t.path);
    file_ = t.file;
  }
  ~PendingFile() {
    if (file_) {
      std::fclose(file_);
      remove_temporary(temp_);
    }
  }
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  bool open() const { return file_ != nullptr; }
  void write(const fmt::memory_buffer& b) {
    if (std::fwrite(b.data(), 1, b.size(), file_) != b.size()) {
      throw Error(ErrorCode::io, std::string("write failed: ") + std::strerror(errno),
                  SourceLocation{path_, 0, 0});
    }
  }
  // Written and flushed to the disk, not yet renamed: a full disk shows here.
  void prepare() {
    if (prepared_)
      return;
    try {
      flush_to_disk(file_, path_);
    } catch (...) {
      std::fclose(file_);
      file_ = nullptr;
      remove_temporary(temp_);
      throw;
    }
    prepared_ = true;
  }
  void commit() {
    prepare();
    std::FILE* file = file_;
    file_ = nullptr;
    if (std::fclose(file) != 0) {
      const int err = errno;
      remove_temporary(temp_);
      throw Error(ErrorCode::io, std::string("cannot complete the file: ") + std::strerror(err),
                  SourceLocation{path_, 0, 0});
    }
    replace_files({Replacement{temp_, path_}});
  }

 private:
  std::string path_, temp_;
  std::FILE* file_ = nullptr;
  bool prepared_ = false;
};

}  // namespace redpost
