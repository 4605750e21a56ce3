// The STL reader (redpost/collision/stl.hpp): meshes written here in both forms, byte by byte
// from the format's definition, read back through memory and through a file; every refusal with
// its code, its line (ASCII) or byte offset (binary), and advice at the end of its message.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "catch_compat.hpp"
#include "redpost/collision/stl.hpp"
#include "redpost/io/error.hpp"
#include "temp_dir.hpp"

using namespace redpost;

namespace {

using Corner = std::array<float, 3>;
using Tri = std::array<Corner, 3>;

// The unit cube, two triangles a face, outward normals by the right-hand rule.
std::vector<Tri> cube() {
  const Corner c[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                       {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int faces[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                            {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  std::vector<Tri> out;
  for (const auto& f : faces)
    out.push_back({c[f[0]], c[f[1]], c[f[2]]});
  return out;
}

// Triangles on a pool of random points (so that corners are shared), seeded.
std::vector<Tri> random_mesh(std::mt19937& rng, int pool_size, int triangles) {
  std::uniform_real_distribution<float> coord(-1000.0f, 1000.0f);
  std::vector<Corner> pool(static_cast<std::size_t>(pool_size));
  for (Corner& p : pool)
    p = {coord(rng), coord(rng), coord(rng)};
  std::uniform_int_distribution<int> pick(0, pool_size - 1);
  std::vector<Tri> out;
  while (static_cast<int>(out.size()) < triangles) {
    const int a = pick(rng), b = pick(rng), c = pick(rng);
    if (a != b && b != c && a != c)
      out.push_back({pool[a], pool[b], pool[c]});
  }
  return out;
}

std::size_t distinct_corners(const std::vector<Tri>& tris) {
  std::set<Corner> seen;
  for (const Tri& t : tris)
    seen.insert(t.begin(), t.end());
  return seen.size();
}

std::string number(float v, const char* format) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, static_cast<double>(v));
  return buf;
}

std::string ascii_stl(const std::vector<Tri>& tris, const char* format = "%.17g",
                      const char* eol = "\n") {
  std::string s = std::string("solid test") + eol;
  for (const Tri& t : tris) {
    s += std::string("  facet normal 0 0 0") + eol + "    outer loop" + eol;
    for (const Corner& p : t) {
      s += "      vertex " + number(p[0], format) + " " + number(p[1], format) + " " +
           number(p[2], format) + eol;
    }
    s += std::string("    endloop") + eol + "  endfacet" + eol;
  }
  return s + "endsolid test" + eol;
}

void put_u32(std::string& s, std::uint32_t u) {
  for (int i = 0; i < 4; ++i)
    s += static_cast<char>((u >> (8 * i)) & 0xff);
}

void put_float(std::string& s, float f) {
  std::uint32_t u = 0;
  std::memcpy(&u, &f, sizeof u);
  put_u32(s, u);
}

// Overwrites the float at byte `offset` (little-endian).
void patch_float(std::string& s, std::size_t offset, float f) {
  std::string bytes;
  put_float(bytes, f);
  s.replace(offset, 4, bytes);
}

std::string binary_stl(const std::vector<Tri>& tris, const std::string& header = "test mesh") {
  std::string s = header;
  s.resize(80, '\0');
  put_u32(s, static_cast<std::uint32_t>(tris.size()));
  for (const Tri& t : tris) {
    for (int k = 0; k < 3; ++k)
      put_float(s, 0.0f);  // normal
    for (const Corner& p : t) {
      for (float c : p)
        put_float(s, c);
    }
    s += std::string(2, '\0');  // attribute byte count
  }
  return s;
}

// Where the binary format puts coordinate c of vertex v of triangle k (all 0-based).
std::size_t coordinate_offset(int k, int v, int c) {
  return 84 + 50 * static_cast<std::size_t>(k) + 12 + 12 * v + 4 * c;
}

std::string write_file(const test::TempDir& dir, const std::string& name,
                       const std::string& bytes) {
  const std::string path = (dir.path / name).string();
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// The mesh holds exactly `expected` (degenerate ones left out by the caller), in order, scaled.
void check_mesh(const TriangleMesh& mesh, const std::vector<Tri>& expected, double scale,
                std::size_t vertex_count) {
  REQUIRE(mesh.triangles.size() == expected.size());
  CHECK(mesh.vertices.size() == vertex_count);
  for (std::size_t t = 0; t < expected.size(); ++t) {
    for (int v = 0; v < 3; ++v) {
      const int i = mesh.triangles[t][static_cast<std::size_t>(v)];
      REQUIRE(i >= 0);
      REQUIRE(static_cast<std::size_t>(i) < mesh.vertices.size());
      for (int c = 0; c < 3; ++c) {
        INFO("triangle " << t << " vertex " << v << " coordinate " << c);
        CHECK(mesh.vertices[static_cast<std::size_t>(i)][c] ==
              static_cast<double>(expected[t][static_cast<std::size_t>(v)][c]) * scale);
      }
    }
  }
}

// Every message ends with what to do.
void check_advice(const Error& e) {
  const std::string& m = e.message();
  const std::size_t semi = m.rfind("; ");
  REQUIRE(semi != std::string::npos);
  const std::string advice = m.substr(semi + 2);
  bool known = false;
  for (const char* verb : {"re-export", "check", "copy", "export", "repair", "give"})
    known = known || advice.rfind(verb, 0) == 0;
  CHECK(known);
}

// The error of reading `bytes` from memory and, the same, from a file.
void expect_error(const std::string& bytes, ErrorCode code, int line, const std::string& words,
                  double scale = 1.0, const StlLimits& limits = {}) {
  test::TempDir dir("redpost_test_stl");
  const std::string path = write_file(dir, "bad.stl", bytes);
  for (const bool from_file : {false, true}) {
    const std::string source = from_file ? path : std::string("mem.stl");
    try {
      if (from_file)
        load_stl(path, scale, limits);
      else
        parse_stl(bytes, source, scale, limits);
      FAIL("accepted (from_file " << from_file << "): " << bytes.substr(0, 200));
    } catch (const Error& e) {
      INFO(e.what());
      CHECK(e.code() == code);
      CHECK(e.where().file == source);
      CHECK(e.where().line == line);
      CHECK(e.where().column == 0);
      CHECK(e.message().find(words) != std::string::npos);
      check_advice(e);
    }
  }
}

const std::string kFacetStart = "solid s\nfacet normal 0 0 1\nouter loop\n";
const std::string kFacetEnd = "endloop\nendfacet\nendsolid s\n";

}  // namespace

TEST_CASE("stl: a unit cube round-trips in ASCII and binary, 8 shared vertices", "[stl]") {
  const std::vector<Tri> tris = cube();
  test::TempDir dir("redpost_test_stl");
  const std::string ascii = ascii_stl(tris), binary = binary_stl(tris);
  REQUIRE(binary.size() == 84 + 50 * 12);
  check_mesh(parse_stl(ascii, "cube.stl"), tris, 1.0, 8);
  check_mesh(parse_stl(binary, "cube.stl"), tris, 1.0, 8);
  check_mesh(load_stl(write_file(dir, "a.stl", ascii)), tris, 1.0, 8);
  const TriangleMesh from_file = load_stl(write_file(dir, "b.stl", binary));
  check_mesh(from_file, tris, 1.0, 8);
  CHECK(from_file.source == (dir.path / "b.stl").string());
  // Scientific notation, and -0 for every other zero written: -0 and +0 are the same vertex.
  std::string sci = ascii_stl(tris, "%.6e");
  int zeros = 0;
  for (std::size_t at = 0; (at = sci.find(" 0.000000e+00", at)) != std::string::npos; at += 4) {
    if (zeros++ % 2 == 0)
      sci.replace(at, 1, " -");
  }
  REQUIRE(sci.find(" -0.000000e+00") != std::string::npos);
  REQUIRE(sci.find(" 0.000000e+00") != std::string::npos);
  check_mesh(parse_stl(sci, "cube.stl"), tris, 1.0, 8);
  // Metres to mm.
  check_mesh(parse_stl(binary, "cube.stl", 1000.0), tris, 1000.0, 8);
}

TEST_CASE("stl: a seeded random mesh round-trips in both forms", "[stl]") {
  std::mt19937 rng(20240611);
  for (int round = 0; round < 5; ++round) {
    const std::vector<Tri> tris = random_mesh(rng, 40, 300);
    const std::size_t corners = distinct_corners(tris);
    INFO("round " << round << ", " << corners << " distinct corners");
    REQUIRE(corners < 3 * tris.size());  // shared corners, or dedup is not tested
    check_mesh(parse_stl(ascii_stl(tris), "r.stl"), tris, 1.0, corners);
    check_mesh(parse_stl(binary_stl(tris), "r.stl"), tris, 1.0, corners);
    check_mesh(parse_stl(binary_stl(tris), "r.stl", 25.4), tris, 25.4, corners);
  }
  // Through files, large enough for the binary reader's several blocks (64 KiB each).
  const std::vector<Tri> tris = random_mesh(rng, 2000, 4000);
  test::TempDir dir("redpost_test_stl");
  check_mesh(load_stl(write_file(dir, "r.stl", binary_stl(tris))), tris, 1.0,
             distinct_corners(tris));
  check_mesh(load_stl(write_file(dir, "a.stl", ascii_stl(tris))), tris, 1.0,
             distinct_corners(tris));
}

TEST_CASE("stl: a binary file whose header starts with 'solid' is read as binary", "[stl]") {
  const std::vector<Tri> tris = cube();
  std::string spaces = "solid cube exported by a CAD system";
  spaces.resize(80, ' ');  // no NUL in the header at all
  for (const std::string& header : {spaces, std::string("solid cube"), std::string("SOLID x")}) {
    check_mesh(parse_stl(binary_stl(tris, header), "b.stl"), tris, 1.0, 8);
    test::TempDir dir("redpost_test_stl");
    check_mesh(load_stl(write_file(dir, "b.stl", binary_stl(tris, header))), tris, 1.0, 8);
  }
  // Truncated, it is still binary (the triangle count's high bytes are NUL).
  const std::string cut = binary_stl(tris, spaces).substr(0, 84 + 50 * 3 + 7);
  expect_error(cut, ErrorCode::bad_input, 0, "binary STL truncated at byte offset 241:");
}

TEST_CASE("stl: ASCII in any case and spacing, CRLF, signs, exponents, two solids", "[stl]") {
  const std::string text =
      "\r\n  SOLID  odd name \r\n"
      "\r\n"
      "\tFacet\tNORMAL +0 -0.0 -1E0\r\n"
      "  outer   LOOP\r\n"
      "   VERTEX 1.5e+1 -2E-1 +3\r\n"
      "   vertex\t0.0  0 \t 0\r\n"
      "   Vertex 1 1 1   \r\n"
      "  ENDLOOP\r\n"
      " endfacet \r\n"
      "EndSolid odd name\r\n"
      "\r\n"
      "solid second\r\n"
      "facet normal nan nan nan\r\n"  // the normal is not used
      "outer loop\r\nvertex 2 0 0\r\nvertex 0 0 0\r\nvertex 0 2 0\r\nendloop\r\nendfacet\r\n"
      "endsolid\r\n";
  const TriangleMesh mesh = parse_stl(text, "odd.stl");
  REQUIRE(mesh.triangles.size() == 2);
  CHECK(mesh.vertices.size() == 5);
  CHECK(mesh.vertices[0] == Eigen::Vector3d(15.0, -0.2, 3.0));  // as parsed, not as a float
  CHECK(mesh.vertices[1] == Eigen::Vector3d(0, 0, 0));
  CHECK(mesh.triangles[1] == std::array<int, 3>{3, 1, 4});
  test::TempDir dir("redpost_test_stl");
  const TriangleMesh from_file = load_stl(write_file(dir, "odd.stl", text));
  CHECK(from_file.vertices == mesh.vertices);
  CHECK(from_file.triangles == mesh.triangles);
  check_mesh(parse_stl(ascii_stl(cube(), "%.17g", "\r\n"), "crlf.stl"), cube(), 1.0, 8);
}

TEST_CASE("stl: malformed ASCII is refused at its line", "[stl]") {
  const ErrorCode bad = ErrorCode::bad_input;
  const std::string v3 = "vertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n";
  expect_error(kFacetStart + "vertex 1 2\n", bad, 4, "expected 'vertex x y z', found 'vertex 1 2'");
  expect_error(kFacetStart + "vertex 0 0 0\nvertex 1 0 0\n" + kFacetEnd, bad, 6,
               "facet has 2 vertices, expected 3");
  expect_error(kFacetStart + v3 + "vertex 1 1 0\n" + kFacetEnd, bad, 7,
               "facet has more than 3 vertices, expected 3");
  expect_error(kFacetStart + "vertex 1 abc 3\n", bad, 4, "not a number: 'abc'");
  expect_error(kFacetStart + "vertex 1 2 3x\n", bad, 4, "not a number: '3x'");
  expect_error(kFacetStart + "vertex 1 2 1e400\n", bad, 4, "number out of range: '1e400'");
  expect_error(kFacetStart + v3, bad, 6,
               "file ends inside a facet (no 'endloop'/'endfacet'/'endsolid')");
  expect_error(kFacetStart + v3 + "endloop\n\n\n", bad, 9, "file ends inside a facet");
  expect_error(kFacetStart + v3 + "endloop\nendfacet\n", bad, 8, "file ends without 'endsolid'");
  expect_error("solid s\nfacet normal 0 0 1\nouter lop\n", bad, 3,
               "expected 'outer loop', found 'outer lop'");
  expect_error(kFacetStart + v3 + "endloop\nendsolid\n", bad, 8, "expected 'endfacet'");
  expect_error(kFacetStart + v3 + "vertex\n", bad, 7, "facet has more than 3 vertices");
  expect_error(kFacetStart + v3 + kFacetEnd + "garbage\n", bad, 10,
               "expected 'solid name' or the end of the file, found 'garbage'");
  expect_error("solid s\nfacet normal 0 0\n", bad, 2,
               "expected 'facet normal nx ny nz', found 'facet normal 0 0'");
  expect_error("solid s\nfacet 0 0 1\n", bad, 2, "expected 'facet normal nx ny nz'");
  expect_error("solid s\nloop\n", bad, 2, "expected 'facet normal nx ny nz' or 'endsolid'");
  // CRLF counts one line; a tab inside the shown line is escaped.
  expect_error("solid s\r\nfacet normal 0 0 1\r\nouter loop\r\nvertex 1\t2\r\n", bad, 4,
               "found 'vertex 1\\x092'");
}

TEST_CASE("stl: NaN, infinite and huge coordinates are refused in ASCII", "[stl]") {
  const ErrorCode bad = ErrorCode::bad_input;
  expect_error(kFacetStart + "vertex 0 0 0\nvertex nan 0 0\n", bad, 5,
               "vertex coordinate is NaN: 'nan'");
  expect_error(kFacetStart + "vertex 0 0 -inf\n", bad, 4, "vertex coordinate is infinite: '-inf'");
  expect_error(kFacetStart + "vertex 0 2e7 0\n", bad, 4,
               "coordinate 2e+07 mm is beyond +-1e+07 mm");
  // The bound is in mm, after scaling: 10.001 km given in metres.
  expect_error(kFacetStart + "vertex 0 0 -10001\n", bad, 4, "is beyond +-1e+07 mm", 1000.0);
  // At the bound exactly, and in metres just under it: accepted.
  const std::string edge = kFacetStart + "vertex 0 1e7 0\nvertex 0 0 0\nvertex 1 0 0\n" + kFacetEnd;
  CHECK(parse_stl(edge, "e.stl").vertices[0].y() == 1e7);
  CHECK(parse_stl(edge, "e.stl", 1.0 / 1000).vertices[0].y() == 1e7 / 1000);
}

TEST_CASE("stl: binary coordinates: NaN, inf and huge ones at their byte offset", "[stl]") {
  const ErrorCode bad = ErrorCode::bad_input;
  const std::string good = binary_stl(cube());
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> k_of(0, 11), v_of(0, 2);
  for (int round = 0; round < 10; ++round) {
    const int k = k_of(rng), v = v_of(rng), c = v_of(rng);
    const std::size_t at = coordinate_offset(k, v, c);
    const std::string where = "at byte offset " + std::to_string(at) + " (triangle " +
                              std::to_string(k + 1) + ", vertex " + std::to_string(v + 1) + ")";
    INFO(where);
    std::string s = good;
    patch_float(s, at, std::numeric_limits<float>::quiet_NaN());
    expect_error(s, bad, 0, "binary STL coordinate is NaN " + where);
    patch_float(s, at, -std::numeric_limits<float>::infinity());
    expect_error(s, bad, 0, "binary STL coordinate is infinite " + where);
    patch_float(s, at, 2e7f);
    expect_error(s, bad, 0, "binary STL coordinate 2e+07 mm is beyond +-1e+07 mm " + where);
    patch_float(s, at, 20000.0f);  // 20 km in metres
    expect_error(s, bad, 0, "coordinate 2e+07 mm is beyond +-1e+07 mm " + where, 1000.0);
  }
  // The normal is not read: NaN there is fine.
  std::string s = good;
  patch_float(s, 84 + 50 * 3 + 4, std::numeric_limits<float>::quiet_NaN());
  check_mesh(parse_stl(s, "n.stl"), cube(), 1.0, 8);
}

TEST_CASE("stl: binary size and count mismatches", "[stl]") {
  const ErrorCode bad = ErrorCode::bad_input;
  const std::string good = binary_stl(cube());
  expect_error(good + "abc", bad, 0,
               "binary STL has 687 bytes, but the header promises 12 triangles (684 bytes): 3 "
               "bytes from byte offset 684 are too many");
  StlLimits eleven;
  eleven.max_triangles = 11;
  expect_error(good, bad, 0, "header promises 12 triangles, more than the 11 redpost reads", 1.0,
               eleven);
  expect_error(std::string(50, 'x'), bad, 0,
               "file has 50 bytes, too short for a binary STL (84 bytes of header and triangle "
               "count) (and not ASCII either: it does not start with 'solid')");
  expect_error("", bad, 0, "empty file, not an STL");
  // An ASCII file with a NUL byte in its first 84 bytes is not taken as text.
  expect_error(std::string("solid a\0b\n", 10) + kFacetEnd, bad, 0, "too short for a binary STL");
}

TEST_CASE("stl: truncated binary files, at seeded random offsets", "[stl]") {
  const std::string full = binary_stl(cube(), "cube from a CAD system");
  std::mt19937 rng(42);
  std::uniform_int_distribution<std::size_t> cut_at(1, full.size() - 1);
  std::vector<std::size_t> cuts = {1, 83, 84, 85, 133, 134, full.size() - 1};
  for (int i = 0; i < 25; ++i)
    cuts.push_back(cut_at(rng));
  for (const std::size_t n : cuts) {
    INFO("cut at " << n);
    const std::string cut = full.substr(0, n);
    if (n < 84) {
      expect_error(cut, ErrorCode::bad_input, 0,
                   "file has " + std::to_string(n) + " bytes, too short for a binary STL");
    } else {
      expect_error(cut, ErrorCode::bad_input, 0,
                   "binary STL truncated at byte offset " + std::to_string(n) +
                       ": the header promises 12 triangles (684 bytes), the file has " +
                       std::to_string(n) + " bytes");
    }
  }
}

TEST_CASE("stl: empty and degenerate meshes", "[stl]") {
  const ErrorCode bad = ErrorCode::bad_input;
  expect_error("solid empty\nendsolid empty\n", bad, 0, "no facet in the STL");
  expect_error(binary_stl({}), bad, 0, "no facet in the STL");
  // Zero area: two equal corners; three corners on a line.
  const Tri twice = {Corner{0, 0, 0}, Corner{5, 5, 5}, Corner{0, 0, 0}};
  const Tri line = {Corner{0, 0, 0}, Corner{1, 2, 3}, Corner{2, 4, 6}};
  expect_error(ascii_stl({twice, line}), bad, 0, "all 2 facets are degenerate (zero area)");
  expect_error(binary_stl({line, line, twice}), bad, 0, "all 3 facets are degenerate");
  // Among good ones they are dropped silently, and their corners are no vertices.
  std::vector<Tri> mixed = cube();
  mixed.insert(mixed.begin() + 3, line);
  mixed.push_back(twice);
  for (const std::string& bytes : {ascii_stl(mixed), binary_stl(mixed)})
    check_mesh(parse_stl(bytes, "m.stl"), cube(), 1.0, 8);
}

TEST_CASE("stl: the facet and size limits", "[stl]") {
  StlLimits two;
  two.max_triangles = 2;
  const std::string three = ascii_stl({cube()[0], cube()[1], cube()[2]});
  // Line 16 is the third "facet normal" (1 + 7 lines a facet).
  expect_error(three, ErrorCode::bad_input, 16, "more than 2 facets, the most redpost reads", 1.0,
               two);
  CHECK(parse_stl(ascii_stl({cube()[0], cube()[1]}), "two.stl", 1.0, two).triangles.size() == 2);
  StlLimits small;
  small.max_file_bytes = 683;
  const std::string binary = binary_stl(cube());
  try {
    parse_stl(binary, "big.stl", 1.0, small);
    FAIL("accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::bad_input);
    CHECK(e.message().find("684 bytes, more than the 683") != std::string::npos);
  }
  test::TempDir dir("redpost_test_stl");
  const std::string path = write_file(dir, "big.stl", binary);
  try {
    load_stl(path, 1.0, small);
    FAIL("accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ErrorCode::io);
    CHECK(e.where().file == path);
    CHECK(e.message().find("684 bytes, more than the 683") != std::string::npos);
    check_advice(e);
  }
  small.max_file_bytes = 684;
  CHECK(load_stl(path, 1.0, small).triangles.size() == 12);
}

TEST_CASE("stl: missing files, directories and bad scales", "[stl]") {
  test::TempDir dir("redpost_test_stl");
  const auto io_error = [](const std::string& path, const std::string& words) {
    try {
      load_stl(path);
      FAIL("accepted: " << path);
    } catch (const Error& e) {
      INFO(e.what());
      CHECK(e.code() == ErrorCode::io);
      CHECK(e.where().file == path);
      CHECK(e.where().line == 0);
      CHECK(e.message().find(words) != std::string::npos);
      check_advice(e);
    }
  };
  io_error((dir.path / "nothing.stl").string(), "no such file; check the path");
  io_error(dir.path.string(), "is a directory, expected a file");
  io_error("/dev/null", "is not a regular file");
  expect_error("", ErrorCode::bad_input, 0, "empty file");
  for (const double scale : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    INFO("scale " << scale);
    expect_error(binary_stl(cube()), ErrorCode::bad_input, 0,
                 "scale_to_mm must be a finite number > 0", scale);
  }
}
