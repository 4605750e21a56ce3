// Durable, all-or-nothing output (durable_write.hpp): checked on the file system itself.
#include "redpost/io/durable_write.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/io/output_target.hpp"
#include "redpost/io/temporaries.hpp"
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

TEST_CASE("durable_write: each temporary is new, hidden and unique", "[durable_write]") {
  TempDir t;
  const std::string final_path = (t.path / "PROG.src").string();
  const redpost::Temporary a = redpost::create_temporary(final_path);
  const redpost::Temporary b = redpost::create_temporary(final_path);
  std::fclose(a.file);
  std::fclose(b.file);
  CHECK(a.path != b.path);  // two writers of one name never share a temporary
  for (const std::string& p : {a.path, b.path}) {
    const std::string name = fs::path(p).filename().string();
    CHECK(name.rfind(".PROG.src.", 0) == 0);
    CHECK(name.size() == std::string(".PROG.src.").size() + 8 + std::string(".part~").size());
    CHECK(name.substr(name.size() - 6) == ".part~");
  }
  redpost::remove_temporary(a.path);
  redpost::remove_temporary(b.path);
  CHECK(listing(t.path).empty());
}

TEST_CASE("durable_write: remove_all_temporaries removes what was not renamed", "[durable_write]") {
  TempDir t;
  const redpost::Temporary a = redpost::create_temporary((t.path / "A.src").string());
  std::fclose(a.file);
  redpost::write_text_file((t.path / "B.txt").string(), "kept\n");
  redpost::remove_all_temporaries();  // what a signal handler calls
  CHECK(listing(t.path) == "B.txt ");
  redpost::forget_temporary(a.path);
}

TEST_CASE("durable_write: outputs that are not regular files are refused", "[durable_write]") {
  TempDir t;
  const fs::path victim = t.path / "victim";
  { std::ofstream(victim) << "precious\n"; }
  const fs::path link = t.path / "report.html";
  fs::create_symlink(victim, link);
  fs::create_directory(t.path / "dir.csv");
  for (const fs::path& p : {link, t.path / "dir.csv", fs::path("/dev/null")}) {
    try {
      redpost::write_text_file(p.string(), "new\n");
      FAIL("no error for " << p);
    } catch (const Error& e) {
      CHECK(e.code() == ErrorCode::io);
      CHECK(e.where().file == p.string());
      CHECK(e.message().find("name a regular file") != std::string::npos);
    }
  }
  CHECK(slurp(victim) == "precious\n");
  CHECK(fs::is_symlink(link));
  CHECK(listing(t.path).find("part~") == std::string::npos);
}

TEST_CASE("durable_write: outputs that name an input or each other are refused",
          "[durable_write]") {
  TempDir t;
  const fs::path in = t.path / "part.apt";
  { std::ofstream(in) << "FEDRAT/100\n"; }
  fs::create_symlink(in, t.path / "alias.apt");
  using redpost::NamedPath;
  const auto clash = [&](const std::vector<NamedPath>& outputs) {
    try {
      redpost::check_distinct_files({{"the CL input", in.string()}, {"--cell", ""}}, outputs);
      return std::string();
    } catch (const Error& e) {
      return e.message();
    }
  };
  CHECK(clash({{"--report", (t.path / "r.html").string()}}).empty());
  CHECK(clash({{"--joints-csv", in.string()}}).find("the same file as the CL input") !=
        std::string::npos);
  // The same file by another path: a link, and a path with "." and "..".
  CHECK(!clash({{"--joints-csv", (t.path / "alias.apt").string()}}).empty());
  CHECK(!clash({{"--joints-csv", (t.path / "." / ".." / t.path.filename() / "part.apt").string()}})
             .empty());
  // Two outputs that do not exist yet, named alike.
  const std::string r = (t.path / "out.html").string();
  CHECK(clash({{"--report", r}, {"--joints-csv", (t.path / "." / "out.html").string()}})
            .find("--joints-csv names the same file as --report") != std::string::npos);
}

TEST_CASE("durable_write: a failed swap keeps the old set whole", "[durable_write]") {
  TempDir t;
  const fs::path a = t.path / "P_1.src", b = t.path / "P_2.src", main = t.path / "P.src";
  { std::ofstream(a) << "old 1\n"; }
  { std::ofstream(b) << "old 2\n"; }
  { std::ofstream(main) << "old main\n"; }
  std::vector<redpost::Replacement> swap;
  for (const fs::path& p : {a, b, main}) {
    const redpost::Temporary tmp = redpost::create_temporary(p.string());
    std::fputs("new\n", tmp.file);
    std::fclose(tmp.file);
    swap.push_back({tmp.path, p.string()});
  }
  // The second rename fails after the first succeeded: its temporary is gone.
  fs::remove(swap[1].temp);
  try {
    redpost::replace_files(swap);
    FAIL("no error");
  } catch (const Error& e) {
    CHECK(e.where().file == b.string());
    CHECK(e.message().find("the old files are kept") != std::string::npos);
  }
  CHECK(slurp(a) == "old 1\n");
  CHECK(slurp(b) == "old 2\n");
  CHECK(slurp(main) == "old main\n");
  CHECK(listing(t.path).find('~') == std::string::npos);  // no temporary, no .old~ left

  // A folder under one of the names: refused before anything moves.
  fs::remove(b);
  fs::create_directory(b);
  swap.clear();
  for (const fs::path& p : {a, b, main}) {
    const redpost::Temporary tmp = redpost::create_temporary(p.string());
    std::fclose(tmp.file);
    swap.push_back({tmp.path, p.string()});
  }
  CHECK_THROWS_AS(redpost::replace_files(swap), Error);
  CHECK(slurp(a) == "old 1\n");
  CHECK(slurp(main) == "old main\n");
  CHECK(listing(t.path).find('~') == std::string::npos);
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
