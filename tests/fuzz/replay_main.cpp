// Replays the fuzz targets over their corpora in the normal (gcc) build, without libFuzzer:
//
//   redpost_fuzz_replay TARGET DIR...
//
// runs target TARGET on every regular file under each DIR (recursively, in sorted order; a
// missing DIR is skipped). The targets are compiled with LLVMFuzzerTestOneInput renamed to
// redpost_fuzz_<target> (tests/fuzz/CMakeLists.txt). A target refuses bad input with
// redpost::Error, which it catches; any other exception is a bug: the input is named and the
// exit status is 1. Sanitizer builds of the suite catch memory errors on the same inputs.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using TargetFn = int (*)(const std::uint8_t*, std::size_t);

extern "C" {
int redpost_fuzz_cl_reader(const std::uint8_t*, std::size_t);
int redpost_fuzz_cell_xml(const std::uint8_t*, std::size_t);
int redpost_fuzz_krl_template(const std::uint8_t*, std::size_t);
int redpost_fuzz_krl_reader(const std::uint8_t*, std::size_t);
int redpost_fuzz_calibration_csv(const std::uint8_t*, std::size_t);
int redpost_fuzz_convert(const std::uint8_t*, std::size_t);
int redpost_fuzz_abi_calls(const std::uint8_t*, std::size_t);
}

namespace {

struct Target {
  const char* name;
  TargetFn fn;
};

const Target kTargets[] = {
    {"cl_reader", redpost_fuzz_cl_reader},
    {"cell_xml", redpost_fuzz_cell_xml},
    {"krl_template", redpost_fuzz_krl_template},
    {"krl_reader", redpost_fuzz_krl_reader},
    {"calibration_csv", redpost_fuzz_calibration_csv},
    {"convert", redpost_fuzz_convert},
    {"abi_calls", redpost_fuzz_abi_calls},
};

}  // namespace

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s TARGET DIR...\n", argv[0]);
    return 2;
  }
  const Target* target = nullptr;
  for (const Target& t : kTargets)
    if (std::strcmp(t.name, argv[1]) == 0)
      target = &t;
  if (!target) {
    std::fprintf(stderr, "unknown target '%s'\n", argv[1]);
    return 2;
  }
  std::vector<fs::path> inputs;
  for (int i = 2; i < argc; ++i) {
    if (!fs::is_directory(argv[i]))
      continue;
    for (const auto& entry : fs::recursive_directory_iterator(argv[i]))
      if (entry.is_regular_file())
        inputs.push_back(entry.path());
  }
  std::sort(inputs.begin(), inputs.end());
  if (inputs.empty()) {
    std::fprintf(stderr, "no inputs for target '%s'\n", target->name);
    return 1;
  }
  int failed = 0;
  for (const fs::path& path : inputs) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    try {
      target->fn(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "FAIL %s: %s escaped: %s\n", path.c_str(), target->name, e.what());
      ++failed;
    } catch (...) {
      std::fprintf(stderr, "FAIL %s: %s: a non-standard exception escaped\n", path.c_str(),
                   target->name);
      ++failed;
    }
  }
  std::printf("%s: %zu inputs, %d failed\n", target->name, inputs.size(), failed);
  return failed ? 1 : 0;
}
