// A fresh directory under the system's temporary directory, removed with everything in it when
// the object goes out of scope.
#pragma once

#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace redpost::test {

struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& prefix = "redpost_test") {
    std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "_XXXXXX")).string();
    if (mkdtemp(pattern.data()) == nullptr)
      throw std::runtime_error("cannot create a temporary directory");
    path = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

// Registers a directory to be removed with everything in it when the test process ends (for
// scratch directories whose lifetime spans several test cases).
inline void remove_at_exit(const std::filesystem::path& dir) {
  struct Registry {
    std::vector<std::filesystem::path> dirs;
    ~Registry() {
      for (const auto& d : dirs) {
        std::error_code ec;
        std::filesystem::remove_all(d, ec);
      }
    }
  };
  static Registry registry;
  registry.dirs.push_back(dir);
}

// A fresh, empty directory "<prefix>_<pid>_<name>" in the temp area (per process: ctest -j runs
// the cases of one executable in parallel processes), removed when the process ends.
inline std::string fresh_temp_dir(const std::string& prefix, const std::string& name) {
  const std::filesystem::path d = std::filesystem::temp_directory_path() /
                                  (prefix + "_" + std::to_string(::getpid()) + "_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  remove_at_exit(d);
  return d.string();
}

}  // namespace redpost::test
