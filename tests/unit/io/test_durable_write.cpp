// Durable, all-or-nothing output (durable_write.hpp): checked on the file system itself.
#include "redpost/io/durable_write.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using redpost::Error;
using redpost::ErrorCode;
using redpost::TextOutput;
using redpost::test::TempDir;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every name in a folder, hidden ones included.
std::string listing(const fs::path& dir) {
  std::string names;
  for (const auto& e : fs::directory_iterator(dir))
    names += e.path().filename().string() + " ";
  return names;
}

}  // namespace

TEST_CASE("durable_write: the temporary is hidden beside the final name", "[durable_write]") {
  CHECK(redpost::temporary_path("/out/PROG.src") == "/out/.PROG.src.part~");
  CHECK(redpost::temporary_path("cal.xml") == ".cal.xml.part~");
}

TEST_CASE("durable_write: files are written whole, and replace older ones", "[durable_write]") {
  TempDir t;
  const fs::path a = t.path / "a.csv", b = t.path / "b.json";
  { std::ofstream(a) << "old contents, longer than the new ones\n"; }
  std::string big(3 << 20, 'x');  // larger than any stdio buffer
  big.back() = '\n';
  redpost::write_text_files({{a.string(), "x,y\n1,2\n"}, {b.string(), big}});
  CHECK(slurp(a) == "x,y\n1,2\n");
  CHECK(slurp(b) == big);
  CHECK(listing(t.path).find("part~") == std::string::npos);

  redpost::write_text_file((t.path / "empty.txt").string(), "");
  CHECK(fs::file_size(t.path / "empty.txt") == 0);
}

TEST_CASE("durable_write: a failure before the renames touches no final name", "[durable_write]") {
  TempDir t;
  const fs::path a = t.path / "a.csv";
  { std::ofstream(a) << "the old a\n"; }
  // The second file cannot be created: its folder is a regular file.
  { std::ofstream(t.path / "not_a_dir") << "x"; }
  const fs::path b = t.path / "not_a_dir" / "b.csv";
  try {
    redpost::write_text_files({{a.string(), "the new a\n"}, {b.string(), "b\n"}});
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::io);
    CHECK(e.where().file == b.string());
    CHECK(e.message().find("Not a directory") != std::string::npos);
  }
  CHECK(slurp(a) == "the old a\n");  // the first file was written, but never renamed
  CHECK(listing(t.path).find("part~") == std::string::npos);
}

TEST_CASE("durable_write: a folder that cannot be synced is an error", "[durable_write]") {
  CHECK_THROWS_AS(redpost::sync_directory("/no/such/folder"), Error);
  redpost::sync_directory("");  // the current folder
  TempDir t;
  redpost::sync_directory(t.path.string());
}
