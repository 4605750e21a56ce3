// Fuzz target: the KRL reader (krl/reader.hpp), which reads files: the input is written into a
// scratch directory as a small program and read back with read_krl_program.
//
// Input layout: the text up to the first section line is PROG.src; a line "@@ NAME.src" or
// "@@ NAME.dat" (NAME of letters, digits and '_', at most 24 characters) starts another file, so
// that the .dat, split programs and their calls are reached too. At most 8 files.
#include <fstream>
#include <map>

#include "fuzz_support.hpp"
#include "redpost/krl/reader.hpp"

namespace {

// "NAME.src" / "NAME.dat" if `line` is a section line, "" otherwise.
std::string section_file(const std::string& line) {
  if (line.rfind("@@ ", 0) != 0)
    return "";
  const std::string file = line.substr(3);
  const std::size_t dot = file.find('.');
  if (dot == std::string::npos || dot == 0 || dot > 24)
    return "";
  for (std::size_t i = 0; i < dot; ++i) {
    const char c = file[i];
    if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'))
      return "";
  }
  const std::string ext = file.substr(dot);
  return ext == ".src" || ext == ".dat" ? file : "";
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text = redpost::fuzz::as_text(data, size);
  std::map<std::string, std::string> files;
  std::string current = "PROG.src";
  for (std::size_t begin = 0; begin <= text.size();) {
    std::size_t end = text.find('\n', begin);
    const bool last = end == std::string::npos;
    if (last)
      end = text.size();
    const std::string line = text.substr(begin, end - begin);
    const std::string named = section_file(line);
    if (!named.empty() && files.size() < 8) {
      current = named;
      files[current];
    } else {
      files[current] += line;
      if (!last)
        files[current] += '\n';
    }
    begin = end + 1;
  }
  const std::filesystem::path dir = redpost::fuzz::fresh_scratch_dir();
  for (const auto& [name, content] : files) {
    std::ofstream out(dir / name, std::ios::binary);
    out << content;
  }
  return redpost::fuzz::run_one([&] { redpost::read_krl_program((dir / "PROG.src").string()); });
}
