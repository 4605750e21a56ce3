// Shared helpers of the fuzz targets: the input as text, the shipped definitions, a scratch
// directory per process, and the rule that redpost::Error is a normal outcome.
//
// A target returns normally when the input is accepted or refused with an Error; anything else
// that escapes (another exception, a sanitizer report, a hang) is a bug. In the libFuzzer build
// an escaping exception ends in std::terminate, which libFuzzer records as a crash; the replay
// driver (replay_main.cpp) catches it and names the input.
#pragma once

#include <unistd.h>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

#include "redpost/io/error.hpp"

namespace redpost::fuzz {

inline std::string as_text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

inline std::string source_path(const std::string& relative) {
  return std::string(REDPOST_SOURCE_DIR) + "/" + relative;
}

// An empty directory of this process's own (created on first use, emptied on every call), for
// targets that must write or read files. Removed at exit.
inline std::filesystem::path fresh_scratch_dir() {
  namespace fs = std::filesystem;
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("redpost_fuzz_" + std::to_string(::getpid()));
    fs::create_directories(d);
    std::atexit([] {
      std::error_code ec;
      fs::remove_all(fs::temp_directory_path() / ("redpost_fuzz_" + std::to_string(::getpid())),
                     ec);
    });
    return d;
  }();
  for (const auto& entry : fs::directory_iterator(dir))
    fs::remove_all(entry.path());
  return dir;
}

// Runs one input; Error (bad input, unreachable pose, ...) is the expected refusal. With
// REDPOST_FUZZ_VERBOSE set in the environment the refusals are printed (to see which seeds the
// readers accept).
template <class F>
int run_one(F&& body) {
  static const bool verbose = std::getenv("REDPOST_FUZZ_VERBOSE") != nullptr;
  try {
    body();
    if (verbose)
      std::fprintf(stderr, "accepted\n");
  } catch (const redpost::Error& e) {
    if (verbose)
      std::fprintf(stderr, "refused: %s\n", e.what());
  }
  return 0;
}

}  // namespace redpost::fuzz
