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

namespace redpost {

class PendingFile {
 public:
  PendingFile() = default;
  explicit PendingFile(std::string path) : path_(std::move(path)), temp_(temporary_path(path_)) {
    file_ = std::fopen(temp_.c_str(), "wb");
    if (!file_) {
      throw Error(ErrorCode::io, std::string("cannot create the file: ") + std::strerror(errno),
                  SourceLocation{path_, 0, 0});
    }
  }
  ~PendingFile() {
    if (file_) {
      std::fclose(file_);
      std::remove(temp_.c_str());
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
  void commit() {
    std::FILE* file = file_;
    file_ = nullptr;
    try {
      flush_to_disk(file, path_);
    } catch (...) {
      std::fclose(file);
      std::remove(temp_.c_str());
      throw;
    }
    const bool closed = std::fclose(file) == 0;
    if (!closed || std::rename(temp_.c_str(), path_.c_str()) != 0) {
      const int err = errno;
      std::remove(temp_.c_str());
      throw Error(ErrorCode::io, std::string("cannot complete the file: ") + std::strerror(err),
                  SourceLocation{path_, 0, 0});
    }
    sync_directory(std::filesystem::path(path_).parent_path().string());
  }

 private:
  std::string path_, temp_;
  std::FILE* file_ = nullptr;
};

}  // namespace redpost
