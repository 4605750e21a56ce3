// Fuzz target: the APT/CLDATA and NX CLSF reader (cl_reader.hpp), every event of the input.
#include <sstream>

#include "fuzz_support.hpp"
#include "redpost/cl/reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return redpost::fuzz::run_one([&] {
    std::istringstream in(redpost::fuzz::as_text(data, size));
    redpost::ClReaderOptions options;
    options.keep_comments = true;
    redpost::ClReader reader(in, "fuzz.apt", options);
    redpost::ClEvent event;
    while (reader.next(event)) {
    }
  });
}
