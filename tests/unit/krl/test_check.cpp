// redpost check as a library: each finding at its line, clean programs clean.
#include <filesystem>
#include <fstream>
#include <string>

#include <algorithm>

#include <fmt/format.h>

#include "catch_compat.hpp"
#include "redpost/io/error.hpp"
#include "redpost/kinematics/cell_xml.hpp"
#include "redpost/kinematics/controller_axes.hpp"
#include "redpost/krl/check.hpp"

using namespace redpost;

namespace {

// Findings of check_krl_text whose message contains `what`, as line numbers.
std::vector<int> lines_with(const std::vector<KrlFinding>& findings, const std::string& what) {
  std::vector<int> out;
  for (const KrlFinding& f : findings)
    if (f.message.find(what) != std::string::npos)
      out.push_back(f.line);
  return out;
}

const char* const kClean =
    "&ACCESS RVP\r\n"                                                             // 1
    "DEF PROG( )\r\n"                                                             // 2
    "DECL E6POS P_LOCAL={X 1,Y 2,Z 3,A 0,B 0,C 0}\r\n"                            // 3
    "INT I\r\n"                                                                   // 4
    ";FOLD INI\r\n"                                                               // 5
    "  GLOBAL INTERRUPT DECL 3 WHEN $STOPMESS==TRUE DO IR_STOPM ( )\r\n"          // 6
    "  INTERRUPT ON 3\r\n"                                                        // 7
    ";ENDFOLD (INI)\r\n"                                                          // 8
    ";;FOLD a commented-out fold is no fold\r\n"                                  // 9
    "$VEL.CP = 0.2\r\n"                                                           // 10
    "PTP XP1\r\n"                                                                 // 11
    "LIN P_LOCAL C_DIS\r\n"                                                       // 12
    "PTP HOME\r\n"                                                                // 13
    "LIN {X 1, Y 2, Z 3} ; comment with an_identifier_that_is_much_too_long\r\n"  // 14
    "END\r\n";                                                                    // 15

}  // namespace

TEST_CASE("check: a clean text has no findings") {
  const auto f = check_krl_text("PROG.src", kClean, {"XP1"}, KrlCheckOptions{});
  for (const KrlFinding& x : f)
    UNSCOPED_INFO(x.line << ": " << x.message);
  CHECK(f.empty());
}

TEST_CASE("check: declared names") {
  const auto names = krl_declared_names(
      "DEFDAT P PUBLIC\nDECL E6POS XP1={X 1,Y 2},XP2\nDECL GLOBAL FDAT FP1={TOOL_NO 1}\n"
      "DECL INT COUNTER=0\nE6POS P9\nENDDAT\n");
  for (const char* n : {"XP1", "XP2", "FP1", "COUNTER", "P9"})
    CHECK(std::find(names.begin(), names.end(), n) != names.end());
}

TEST_CASE("check: each text finding at its line") {
  const std::string text =
      "DEF PROG( )\n"                    // 1
      "DECL INT I\n"                     // 2
      "$VEL.CP = 5\n"                    // 3
      ";FOLD never closed\n"             // 4
      "DECL REAL LATE\n"                 // 5
      "ABCDEFGHIJKLMNOPQRSTUVWXY = 1\n"  // 6 (25 characters)
      "ABCDEFGHIJKLMNOPQRSTUVWX = 1\n"   // 7 (24: fine)
      "PTP XP9\n"                        // 8
      "$VEL.CP = 0\n"                    // 9
      "$VEL.CP = 2\n"                    // 10 (fine)
      "CIRC XP1, XP7 C_DIS\n"            // 11
      "END\n"                            // 12
      "END\n"                            // 13
      "DEF SUB( )\n";                    // 14
  const auto f = check_krl_text("PROG.src", text, {"XP1"}, KrlCheckOptions{});
  for (const KrlFinding& x : f)
    UNSCOPED_INFO(x.line << ": " << x.message);
  CHECK(lines_with(f, "$VEL.CP") == std::vector<int>{3, 9});
  CHECK(lines_with(f, "FOLD without") == std::vector<int>{4});
  CHECK(lines_with(f, "declaration after") == std::vector<int>{5});
  CHECK(lines_with(f, "25 characters") == std::vector<int>{6});
  CHECK(lines_with(f, "'XP9' is not declared") == std::vector<int>{8});
  CHECK(lines_with(f, "'XP7' is not declared") == std::vector<int>{11});
  CHECK(lines_with(f, "END without") == std::vector<int>{13});
  CHECK(lines_with(f, "has no END") == std::vector<int>{14});
  CHECK(f.size() == 9);
}

TEST_CASE("check: every statement is read, and a line that is none is a finding at its line") {
  const std::string text =
      "DEF PROG( )\n"                                                              // 1
      "EXT BAS (BAS_COMMAND :IN,REAL :IN )\n"                                      // 2
      "INTERRUPT OFF 3\n"                                                          // 3
      "BAS (#VEL_PTP,20)\n"                                                        // 4
      "$BASE = EK(MACHINE_DEF[2].ROOT, MACHINE_DEF[2].MECH_TYPE, BASE_DATA[1])\n"  // 5
      "$BASE = {FRAME: X 0.000,Y 0.000,Z 0.000,A 0.000,B 0.000,C 0.000}\n"         // 6
      "$OUT[1] = ($IN[2] AND NOT $IN[3])\n"                                        // 7
      "IF $IN[1] == TRUE THEN\n"                                                   // 8
      "  WAIT SEC 0.5\n"                                                           // 9
      "ELSE\n"                                                                     // 10
      "  HALT\n"                                                                   // 11
      "ENDIF\n"                                                                    // 12
      "FOR I = 1 TO 3\n"                                                           // 13
      "ENDFOR\n"                                                                   // 14
      "SPLINE\n"                                                                   // 15
      "ENDSPLINE\n"                                                                // 16
      "this is not KRL at all !!\n"                                                // 17
      "X = 1 +\n"                                                                  // 18
      "IF $IN[1]\n"                                                                // 19
      "INTERRUPT 3\n"                                                              // 20
      "$VEL.CP = {\n"                                                              // 21
      "CALL_IT(1, 2\n"                                                             // 22
      "END\n";                                                                     // 23
  const auto f = check_krl_text("PROG.src", text, {}, KrlCheckOptions{});
  for (const KrlFinding& x : f)
    UNSCOPED_INFO(x.line << ": " << x.message);
  CHECK(lines_with(f, "not a KRL statement that redpost check reads") ==
        std::vector<int>{17, 18, 21, 22});
  CHECK(lines_with(f, "IF without THEN") == std::vector<int>{19});
  CHECK(lines_with(f, "INTERRUPT needs") == std::vector<int>{20});
  CHECK(f.size() == 6);
}

TEST_CASE("check: CR-only line endings are named, not reported as a missing END") {
  const auto f = check_krl_text("MAC.src", "DEF MAC( )\rPTP HOME\rEND\r", {}, KrlCheckOptions{});
  REQUIRE(f.size() == 1);
  CHECK(f[0].line == 1);
  CHECK(f[0].message.find("the file's lines end in CR alone") != std::string::npos);
  // CR LF is a KRC's own line ending: clean.
  CHECK(check_krl_text("DOS.src", "DEF DOS( )\r\nPTP HOME\r\nEND\r\n", {}, {}).empty());
}

TEST_CASE("check: a folder is checked with its subfolders, and one with no program is an error") {
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / "redpost_check_tree";
  fs::remove_all(root);
  fs::create_directories(root / "part_a");
  fs::create_directories(root / "empty" / "deeper");
  const auto write = [](const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
  };
  write(root / "TOP.src", "DEF TOP( )\nWAIT SEC 1\nEND\n");
  write(root / "part_a" / "A.src", "DEF A( )\nnot a statement\nEND\n");
  const auto f = check_krl(root.string(), KrlCheckOptions{});
  for (const KrlFinding& x : f)
    UNSCOPED_INFO(x.file << ":" << x.line << ": " << x.message);
  REQUIRE(f.size() == 1);
  CHECK(f[0].file == (root / "part_a" / "A.src").lexically_normal().string());
  CHECK(f[0].line == 2);
  try {
    check_krl((root / "empty").string(), KrlCheckOptions{});
    FAIL("no error for a folder without programs");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::bad_input);
    CHECK(e.message().find("no KRL program (.src)") != std::string::npos);
  }
  fs::remove_all(root);
}

TEST_CASE("check: a split program's files checked as the reader loads them") {
  // MAIN calls P1, P2 and P1 again. P1 uses a point of its .dat; P2 has a line that is no
  // statement and its END missing, so the reader stops there. Each finding once, at its line:
  // the text checks run on the text the reader loaded, the .dat's names reaching its .src.
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / "redpost_check_split";
  fs::remove_all(root);
  fs::create_directories(root);
  const auto write = [](const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
  };
  write(root / "MAIN.src", "DEF MAIN( )\nP1( )\nP2( )\nP1( )\nEND\n");
  write(root / "P1.dat", "DEFDAT P1\nDECL E6POS XP1={X 1,Y 2,Z 3,A 0,B 0,C 0}\nENDDAT\n");
  write(root / "P1.src", "DEF P1( )\nLIN XP1\nnot a statement either\nEND\n");
  write(root / "P2.src", "DEF P2( )\nnot a statement\nWAIT SEC 1\n");
  const auto f = check_krl((root / "MAIN.src").string(), KrlCheckOptions{});
  std::vector<std::string> where;
  for (const KrlFinding& x : f) {
    UNSCOPED_INFO(x.file << ":" << x.line << ": " << x.message);
    where.push_back(fs::path(x.file).filename().string() + ":" + std::to_string(x.line));
  }
  CHECK(std::count(where.begin(), where.end(), "P1.src:2") == 0);  // XP1 is declared in P1.dat
  CHECK(std::count(where.begin(), where.end(), "P1.src:3") == 1);
  CHECK(std::count(where.begin(), where.end(), "P2.src:2") == 1);
  // The text check's "no END" and the reader's stop, though the reader never got past it.
  CHECK(std::count(where.begin(), where.end(), "P2.src:1") == 2);
  CHECK(std::count(where.begin(), where.end(), "MAIN.src:2") == 0);
  fs::remove_all(root);
}

TEST_CASE("check: ENDFOLD without FOLD, file size") {
  KrlCheckOptions o;
  o.max_bytes = 10;
  const auto f = check_krl_text("P.src", "DEF P( )\n;ENDFOLD\nEND\n", {}, o);
  CHECK(lines_with(f, "ENDFOLD without") == std::vector<int>{2});
  CHECK(lines_with(f, "bytes, more than the limit of 10") == std::vector<int>{1});
}

TEST_CASE("check: S/T on the first Cartesian PTP, cell limits") {
  KrlProgram p;
  KrlMotionRecord axis;
  axis.keyword = "PTP";
  axis.target.values = {{"A1", 0}, {"A2", -90}, {"A3", 90}, {"A4", 0},
                        {"A5", 0}, {"A6", 0},   {"E1", 0},  {"E2", 0}};
  axis.file = "P.src";
  axis.line = 5;
  KrlMotionRecord cart;
  cart.keyword = "PTP";
  cart.target.values = {{"X", 1}, {"Y", 2}, {"Z", 3}, {"A", 0}, {"B", 0}, {"C", 0}};
  cart.file = "P.src";
  cart.line = 6;
  KrlMotionRecord cart2 = cart;
  cart2.line = 7;
  p.motions = {axis, cart, cart2};
  auto f = check_krl_motions(p, KrlCheckOptions{});
  REQUIRE(f.size() == 1);
  CHECK(f[0].line == 6);
  CHECK(f[0].message.find("no S and T") != std::string::npos);
  p.motions[1].target.status = 2;
  p.motions[1].target.turn = 35;
  CHECK(check_krl_motions(p, KrlCheckOptions{}).empty());

  const Cell cell = load_cell(std::string(REDPOST_SOURCE_DIR) +
                              "/definitions/cells/andres2011_kr15_track_table.xml");
  const Joint* a2 = nullptr;
  for (int j = 0; j < cell.size(); ++j)
    if (cell.joint(j).axis.kind == AxisKind::arm && cell.joint(j).axis.number == 2)
      a2 = &cell.joint(j);
  REQUIRE(a2 != nullptr);
  const double lo = to_axis_value(*a2, a2->lower), hi = to_axis_value(*a2, a2->upper);
  KrlCheckOptions o;
  o.cell = &cell;
  p.motions[0].target.values["A2"] = (lo + hi) / 2;
  CHECK(check_krl_motions(p, o).empty());
  p.motions[0].target.values["A2"] = std::max(lo, hi) + 5.0;
  f = check_krl_motions(p, o);
  REQUIRE(f.size() == 1);
  CHECK(f[0].line == 5);
  CHECK(f[0].message.find("A2") == 0);

  // An axis the cell does not have (the Andres cell maps E1 and E2): 0 is what posts write for
  // absent axes; any other value is reported, once per axis and file.
  p.motions[0].target.values["A2"] = (lo + hi) / 2;
  p.motions[0].target.values["E3"] = 0.0;
  CHECK(check_krl_motions(p, o).empty());
  p.motions[0].target.values["E3"] = 250.0;
  p.motions[1].target.values["E3"] = 260.0;
  f = check_krl_motions(p, o);
  REQUIRE(f.size() == 1);
  CHECK(f[0].line == 5);
  CHECK(f[0].message.find("E3 is 250, but the cell") == 0);
}

TEST_CASE("check: the first motion must be a PTP to a full E6AXIS (the BCO run)") {
  const Cell cell = load_cell(std::string(REDPOST_SOURCE_DIR) +
                              "/definitions/cells/andres2011_kr15_track_table.xml");
  KrlCheckOptions with_cell;
  with_cell.cell = &cell;
  KrlMotionRecord full;
  full.keyword = "PTP";
  full.target.type = "E6AXIS";
  full.target.values = {{"A1", 0}, {"A2", -90}, {"A3", 90}, {"A4", 0},
                        {"A5", 0}, {"A6", 0},   {"E1", 0},  {"E2", 0}};
  full.file = "P.src";
  full.line = 4;
  KrlMotionRecord lin;
  lin.keyword = "LIN";
  lin.target.values = {{"X", 1}, {"Y", 2}, {"Z", 3}, {"A", 0}, {"B", 0}, {"C", 0}};
  lin.file = "P.src";
  lin.line = 5;
  const auto findings = [&](std::vector<KrlMotionRecord> motions, const KrlCheckOptions& o) {
    KrlProgram p;
    p.motions = std::move(motions);
    return lines_with(check_krl_motions(p, o), "the program's first motion is");
  };
  // A full E6AXIS first, with or without the cell; what follows is not the BCO run.
  CHECK(findings({full, lin}, with_cell).empty());
  CHECK(findings({full, lin}, KrlCheckOptions{}).empty());
  // A CP motion first: at its line, whatever comes after.
  CHECK(findings({lin, full}, KrlCheckOptions{}) == std::vector<int>{5});
  KrlMotionRecord slin = lin;
  slin.keyword = "SLIN";
  CHECK(findings({slin}, KrlCheckOptions{}) == std::vector<int>{5});
  // A relative PTP, a Cartesian PTP (even with S and T), a PTP without A4.
  KrlMotionRecord rel = full;
  rel.keyword = "PTP_REL";
  rel.relative = true;
  CHECK(findings({rel}, KrlCheckOptions{}) == std::vector<int>{4});
  KrlMotionRecord cart = lin;
  cart.keyword = "PTP";
  cart.target.status = 2;
  cart.target.turn = 35;
  CHECK(findings({cart}, KrlCheckOptions{}) == std::vector<int>{5});
  KrlMotionRecord no_a4 = full;
  no_a4.target.values.erase("A4");
  auto f = check_krl_motions(KrlProgram{"", {}, {no_a4}, {}}, KrlCheckOptions{});
  REQUIRE(f.size() == 1);
  CHECK(f[0].message.find("a PTP without A4") != std::string::npos);
  // An external axis of the cell left out: only the cell knows it is there.
  KrlMotionRecord no_e2 = full;
  no_e2.target.values.erase("E2");
  CHECK(findings({no_e2}, KrlCheckOptions{}).empty());
  f = check_krl_motions(KrlProgram{"", {}, {no_e2}, {}}, with_cell);
  REQUIRE(f.size() == 1);
  CHECK(f[0].message.find("a PTP without E2") != std::string::npos);
  // Through the reader: a main program whose first motion is in its first part.
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / "redpost_check_bco";
  fs::remove_all(root);
  fs::create_directories(root);
  const auto write = [](const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
  };
  write(root / "MAIN.src", "DEF MAIN( )\nP1( )\nEND\n");
  write(root / "P1.src",
        "DEF P1( )\nPTP {E6AXIS: A1 0, A2 -90, A3 90, A4 0, A5 30, A6 0, E1 0, E2 0}\n"
        "LIN {E6POS: X 1, Y 2, Z 3, A 0, B 0, C 0, E1 0, E2 0} C_DIS\nEND\n");
  CHECK(lines_with(check_krl((root / "MAIN.src").string(), with_cell),
                   "the program's first motion is")
            .empty());
  write(root / "P1.src",
        "DEF P1( )\nLIN {E6POS: X 1, Y 2, Z 3, A 0, B 0, C 0, E1 0, E2 0} C_DIS\n"
        "PTP {E6AXIS: A1 0, A2 -90, A3 90, A4 0, A5 30, A6 0, E1 0, E2 0}\nEND\n");
  CHECK(lines_with(check_krl((root / "MAIN.src").string(), with_cell),
                   "the program's first motion is a LIN") == std::vector<int>{2});
  fs::remove_all(root);
}

TEST_CASE("check: a program whose files together pass the program memory") {
  namespace fs = std::filesystem;
  const fs::path root = fs::temp_directory_path() / "redpost_check_memory";
  fs::remove_all(root);
  fs::create_directories(root);
  const auto write = [](const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
  };
  const std::string ptp = "PTP {E6AXIS: A1 0, A2 -90, A3 90, A4 0, A5 30, A6 0}\n";
  write(root / "MAIN.src", "DEF MAIN( )\nP1( )\nP2( )\nP1( )\nEND\n");
  write(root / "MAIN.dat", "DEFDAT MAIN\nENDDAT\n");
  write(root / "P1.src", "DEF P1( )\n" + ptp + "END\n");
  write(root / "P2.src", "DEF P2( )\n" + ptp + ptp + "END\n");
  write(root / "OTHER.src", "DEF OTHER( )\n" + ptp + "END\n");  // not called: not counted
  std::size_t total = 0;
  for (const char* f : {"MAIN.src", "MAIN.dat", "P1.src", "P2.src"})
    total += fs::file_size(root / f);
  KrlCheckOptions o;
  o.max_program_bytes = total;
  CHECK(lines_with(check_krl((root / "MAIN.src").string(), o), "bytes of program memory").empty());
  o.max_program_bytes = total - 1;
  const auto f = check_krl((root / "MAIN.src").string(), o);
  REQUIRE(lines_with(f, "bytes of program memory") == std::vector<int>{1});
  for (const KrlFinding& x : f) {
    if (x.message.find("bytes of program memory") != std::string::npos) {
      CHECK(fs::path(x.file).filename() == "MAIN.src");
      CHECK(x.message.find(fmt::format("the program's 4 files take {} bytes, more than the {} "
                                       "bytes",
                                       total, total - 1)) == 0);
    }
  }
  fs::remove_all(root);
}

TEST_CASE("check: golden programs are clean (through the reader)") {
  namespace fs = std::filesystem;
  const Cell cell = load_cell(std::string(REDPOST_SOURCE_DIR) +
                              "/definitions/cells/andres2011_kr15_track_table.xml");
  KrlCheckOptions o;
  o.cell = &cell;
  for (const auto& e : fs::directory_iterator(std::string(REDPOST_SOURCE_DIR) + "/tests/golden")) {
    if (!e.is_directory())
      continue;
    const auto f = check_krl(e.path().string(), o);
    for (const KrlFinding& x : f)
      UNSCOPED_INFO(x.file << ":" << x.line << ": " << x.message);
    CHECK(f.empty());
  }
}

TEST_CASE("check: evaluation KRL files are checked without a crash") {
  namespace fs = std::filesystem;
  const std::string dir = "/work/shared/evaldata/krl";
  if (!fs::is_directory(dir)) {
    WARN("no " << dir << ": skipped");
    return;
  }
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".src")
      continue;
    try {
      const auto f = check_krl(e.path().string(), KrlCheckOptions{});
      for (const KrlFinding& x : f)
        UNSCOPED_INFO(x.file << ":" << x.line << ": " << x.message);
      SUCCEED();
    } catch (const Error& err) {
      FAIL(e.path().string() << ": " << err.what());
    }
  }
  CHECK_NOTHROW(check_krl(dir, KrlCheckOptions{}));
}
