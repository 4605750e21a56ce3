#include "redpost/collision/stl.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <unordered_map>
#include <utility>

#include <Eigen/Geometry>

#include "redpost/io/error.hpp"

namespace redpost {

namespace {

constexpr std::uint64_t kHeaderBytes = 84;  // 80 bytes of text, a uint32 triangle count
constexpr std::uint64_t kRecordBytes = 50;  // normal, three vertices (float32 x 12), attribute
constexpr const char* kReexport = "; re-export the STL from the CAD system";
constexpr const char* kSimplify =
    "; export a coarser tessellation (a larger chord tolerance) or split the body";

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// A piece of the file as it can be printed in a message: quoted, control bytes as \xNN, long
// text cut (a binary file read as text must not flood the terminal).
std::string quoted(std::string_view text) {
  constexpr std::size_t kMaxShown = 60;
  std::string out = "'";
  for (std::size_t i = 0; i < text.size() && i < kMaxShown; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    }
  }
  if (text.size() > kMaxShown)
    out += "...";
  return out + "'";
}

[[noreturn]] void fail(const std::string& source, int line, const std::string& message) {
  throw Error(ErrorCode::bad_input, message, SourceLocation{source, line, 0});
}

void check_scale(double scale_to_mm, const std::string& source) {
  if (!(std::isfinite(scale_to_mm) && scale_to_mm > 0.0)) {
    fail(source, 0,
         "scale_to_mm must be a finite number > 0, got " + num(scale_to_mm) +
             "; give the STL's unit in mm (1 for mm, 1000 for m)");
  }
}

// What is wrong with a coordinate (raw: as in the file, scaled: in mm), or "" if nothing.
std::string coordinate_problem(double raw, double scaled_mm, const StlLimits& limits) {
  if (std::isnan(raw))
    return "coordinate is NaN";
  if (!std::isfinite(raw))
    return "coordinate is infinite";
  if (std::fabs(scaled_mm) > limits.max_coordinate_mm) {
    return "coordinate " + num(scaled_mm) + " mm is beyond +-" + num(limits.max_coordinate_mm) +
           " mm";
  }
  return {};
}

std::string coordinate_advice(double raw) {
  return std::isfinite(raw) ? "; check the units (scale_to_mm) or re-export the STL"
                            : "; repair the mesh or re-export the STL from the CAD system";
}

// ===========================================================================================
// The mesh: exactly-equal vertices shared, zero-area triangles dropped.

class MeshBuilder {
 public:
  explicit MeshBuilder(std::string source) { mesh_.source = std::move(source); }

  void reserve(std::size_t triangles) { mesh_.triangles.reserve(triangles); }
  std::int64_t facets() const { return facets_; }

  void add(const std::array<Eigen::Vector3d, 3>& p_mm) {
    ++facets_;
    // Exactly zero: two equal corners, or three on a line in exact arithmetic of the doubles.
    if ((p_mm[1] - p_mm[0]).cross(p_mm[2] - p_mm[0]).isZero(0.0))
      return;
    mesh_.triangles.push_back({index_of(p_mm[0]), index_of(p_mm[1]), index_of(p_mm[2])});
  }

  TriangleMesh finish() {
    if (facets_ == 0) {
      fail(mesh_.source, 0,
           "no facet in the STL: the mesh is empty; re-export the STL with the body selected");
    }
    if (mesh_.triangles.empty()) {
      fail(mesh_.source, 0,
           "all " + std::to_string(facets_) +
               " facets are degenerate (zero area), so the mesh bounds nothing; check the units "
               "(scale_to_mm) or re-export the STL from the CAD system");
    }
    return std::move(mesh_);
  }

 private:
  struct Key {
    std::uint64_t x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct KeyHash {
    static std::uint64_t mix(std::uint64_t h) {  // splitmix64's finaliser
      h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ULL;
      h = (h ^ (h >> 27)) * 0x94d049bb133111ebULL;
      return h ^ (h >> 31);
    }
    std::size_t operator()(const Key& k) const {
      return static_cast<std::size_t>(mix(k.x ^ mix(k.y ^ mix(k.z))));
    }
  };
  static std::uint64_t bits(double v) {
    v += 0.0;  // -0 becomes +0: equal coordinates must have equal keys
    std::uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
  }

  int index_of(const Eigen::Vector3d& p) {
    const Key key{bits(p.x()), bits(p.y()), bits(p.z())};
    const auto found = index_.find(key);
    if (found != index_.end())
      return found->second;
    if (mesh_.vertices.size() >= static_cast<std::size_t>(INT_MAX))
      fail(mesh_.source, 0, std::string("too many vertices for one mesh") + kSimplify);
    const int i = static_cast<int>(mesh_.vertices.size());
    mesh_.vertices.push_back(p);
    index_.emplace(key, i);
    return i;
  }

  TriangleMesh mesh_;
  std::int64_t facets_ = 0;
  std::unordered_map<Key, int, KeyHash> index_;
};

// ===========================================================================================
// Telling the forms apart (the rule is in the header).

bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

bool same_word(std::string_view a, std::string_view b) {  // ASCII, any case
  if (a.size() != b.size())
    return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; };
    if (lower(a[i]) != lower(b[i]))
      return false;
  }
  return true;
}

bool starts_with_solid(std::string_view head) {
  std::size_t i = 0;
  while (i < head.size() && is_blank(head[i]))
    ++i;
  std::size_t e = i;
  while (e < head.size() && !is_blank(head[e]))
    ++e;
  return same_word(head.substr(i, e - i), "solid");
}

std::uint32_t le_u32(const char* p) {
  const auto b = [p](int i) { return std::uint32_t{static_cast<unsigned char>(p[i])}; };
  return b(0) | (b(1) << 8) | (b(2) << 16) | (b(3) << 24);
}

float le_float(const char* p) {
  const std::uint32_t u = le_u32(p);
  float f = 0.0f;
  std::memcpy(&f, &u, sizeof f);
  return f;
}

// head: the file's first min(size, 84) bytes.
bool is_ascii(std::string_view head, std::uint64_t size_bytes) {
  if (head.size() >= kHeaderBytes && size_bytes >= kHeaderBytes &&
      kHeaderBytes + kRecordBytes * le_u32(head.data() + 80) == size_bytes)
    return false;
  return starts_with_solid(head) && head.find('\0') == std::string_view::npos;
}

// ===========================================================================================
// ASCII

class AsciiStl {
 public:
  AsciiStl(const std::string& source, double scale_to_mm, const StlLimits& limits)
      : source_(source), scale_(scale_to_mm), limits_(limits), mesh_(source) {}

  // The next line, without its '\n'.
  void line(std::string_view text) {
    ++line_;
    split(text);
    if (tokens_.empty())
      return;
    const std::string_view key = tokens_[0];
    switch (state_) {
      case State::before_solid:
      case State::after_solid:
        if (!same_word(key, "solid")) {
          expected(state_ == State::before_solid ? "'solid name'"
                                                 : "'solid name' or the end of the file");
        }
        state_ = State::in_solid;
        return;
      case State::in_solid:
        if (same_word(key, "endsolid")) {
          state_ = State::after_solid;
          return;
        }
        facet_normal();
        return;
      case State::in_facet:
        if (tokens_.size() != 2 || !same_word(key, "outer") || !same_word(tokens_[1], "loop"))
          expected("'outer loop'");
        state_ = State::in_loop;
        corners_seen_ = 0;
        return;
      case State::in_loop:
        in_loop();
        return;
      case State::after_loop:
        if (tokens_.size() != 1 || !same_word(key, "endfacet"))
          expected("'endfacet'");
        mesh_.add(corners_mm_);
        state_ = State::in_solid;
        return;
    }
  }

  TriangleMesh finish() {
    switch (state_) {
      case State::before_solid:
        fail(source_, line_, std::string("no 'solid' line: the file is blank") + kReexport);
      case State::in_solid:
        fail(source_, line_, std::string("file ends without 'endsolid' (truncated?)") + kReexport);
      case State::in_facet:
      case State::in_loop:
      case State::after_loop:
        fail(source_, line_,
             std::string("file ends inside a facet (no 'endloop'/'endfacet'/'endsolid')") +
                 kReexport);
      case State::after_solid:
        break;
    }
    return mesh_.finish();
  }

 private:
  enum class State { before_solid, in_solid, in_facet, in_loop, after_loop, after_solid };

  void split(std::string_view text) {
    tokens_.clear();
    std::size_t i = 0;
    while (i < text.size() && is_blank(text[i]))
      ++i;
    std::size_t end = text.size();
    while (end > i && is_blank(text[end - 1]))
      --end;
    text_ = text.substr(i, end - i);
    while (i < end) {
      std::size_t e = i;
      while (e < end && !is_blank(text[e]))
        ++e;
      tokens_.push_back(text.substr(i, e - i));
      for (i = e; i < end && is_blank(text[i]);)
        ++i;
    }
  }

  [[noreturn]] void expected(const std::string& what) const {
    fail(source_, line_, "expected " + what + ", found " + quoted(text_) + kReexport);
  }

  void facet_normal() {
    if (tokens_.size() != 5 || !same_word(tokens_[0], "facet") ||
        !same_word(tokens_[1], "normal")) {
      expected(same_word(tokens_[0], "facet") ? "'facet normal nx ny nz'"
                                              : "'facet normal nx ny nz' or 'endsolid'");
    }
    if (mesh_.facets() >= limits_.max_triangles) {
      fail(source_, line_,
           "more than " + std::to_string(limits_.max_triangles) +
               " facets, the most redpost reads" + kSimplify);
    }
    for (std::size_t k = 2; k < 5; ++k)
      number(tokens_[k]);  // checked, not used: the normal may be NaN for a degenerate facet
    state_ = State::in_facet;
  }

  void in_loop() {
    if (same_word(tokens_[0], "endloop") && tokens_.size() == 1) {
      if (corners_seen_ != 3) {
        fail(source_, line_,
             "facet has " + std::to_string(corners_seen_) + " vertices, expected 3" + kReexport);
      }
      state_ = State::after_loop;
      return;
    }
    if (!same_word(tokens_[0], "vertex"))
      expected(corners_seen_ < 3 ? "'vertex x y z'" : "'endloop'");
    if (corners_seen_ == 3)
      fail(source_, line_, std::string("facet has more than 3 vertices, expected 3") + kReexport);
    if (tokens_.size() != 4)
      expected("'vertex x y z'");
    Eigen::Vector3d& p = corners_mm_[static_cast<std::size_t>(corners_seen_++)];
    for (int k = 0; k < 3; ++k) {
      const double raw = number(tokens_[static_cast<std::size_t>(k + 1)]);
      p[k] = raw * scale_;
      const std::string problem = coordinate_problem(raw, p[k], limits_);
      if (!problem.empty()) {
        fail(source_, line_,
             "vertex " + problem + ": " + quoted(tokens_[static_cast<std::size_t>(k + 1)]) +
                 coordinate_advice(raw));
      }
    }
  }

  double number(std::string_view token) const {
    const char* first = token.data();
    const char* last = first + token.size();
    // from_chars takes no '+'; take one, but not a second sign after it.
    if (last - first > 1 && *first == '+' && first[1] != '-' && first[1] != '+')
      ++first;
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
    if (ec == std::errc::result_out_of_range) {
      fail(source_, line_, "number out of range: " + quoted(token) + coordinate_advice(1.0));
    }
    if (ec != std::errc() || ptr != last) {
      fail(source_, line_, "not a number: " + quoted(token) + " in " + quoted(text_) + kReexport);
    }
    return v;
  }

  const std::string& source_;
  double scale_;
  const StlLimits& limits_;
  MeshBuilder mesh_;
  State state_ = State::before_solid;
  int line_ = 0;
  std::string_view text_;  // the current line without the white space around it
  std::vector<std::string_view> tokens_;
  int corners_seen_ = 0;
  std::array<Eigen::Vector3d, 3> corners_mm_;
};

// ===========================================================================================
// Binary

[[noreturn]] void throw_truncated(const std::string& source, std::uint64_t size_bytes,
                                  std::uint32_t count) {
  fail(source, 0,
       "binary STL truncated at byte offset " + std::to_string(size_bytes) +
           ": the header promises " + std::to_string(count) + " triangles (" +
           std::to_string(kHeaderBytes + kRecordBytes * count) + " bytes), the file has " +
           std::to_string(size_bytes) +
           " bytes; copy the file again or re-export the STL from "
           "the CAD system");
}

class BinaryStl {
 public:
  // head: the file's first min(size, 84) bytes. Checks the count against the size.
  BinaryStl(std::string_view head, std::uint64_t size_bytes, const std::string& source,
            double scale_to_mm, const StlLimits& limits)
      : source_(source), scale_(scale_to_mm), limits_(limits), mesh_(source) {
    const std::string not_ascii =
        starts_with_solid(head) ? "" : " (and not ASCII either: it does not start with 'solid')";
    if (size_bytes == 0)
      fail(source_, 0, std::string("empty file, not an STL") + kReexport);
    if (size_bytes < kHeaderBytes) {
      fail(source_, 0,
           "file has " + std::to_string(size_bytes) +
               " bytes, too short for a binary STL (84 bytes of header and triangle count)" +
               not_ascii + kReexport);
    }
    count_ = le_u32(head.data() + 80);
    if (count_ > limits_.max_triangles) {
      fail(source_, 0,
           "binary STL header promises " + std::to_string(count_) + " triangles, more than the " +
               std::to_string(limits_.max_triangles) + " redpost reads (is it an STL file?)" +
               kSimplify);
    }
    const std::uint64_t expected_bytes = kHeaderBytes + kRecordBytes * count_;
    if (size_bytes < expected_bytes)
      throw_truncated(source_, size_bytes, count_);
    if (size_bytes > expected_bytes) {
      fail(source_, 0,
           "binary STL has " + std::to_string(size_bytes) + " bytes, but the header promises " +
               std::to_string(count_) + " triangles (" + std::to_string(expected_bytes) +
               " bytes): " + std::to_string(size_bytes - expected_bytes) +
               " bytes from byte offset " + std::to_string(expected_bytes) + " are too many" +
               not_ascii + kReexport);
    }
    mesh_.reserve(count_);
  }

  std::uint32_t count() const { return count_; }

  // The next whole records, in order.
  void records(std::string_view bytes) {
    for (std::size_t at = 0; at + kRecordBytes <= bytes.size(); at += kRecordBytes) {
      record(bytes.data() + at);
      offset_ += kRecordBytes;
      ++done_;
    }
  }

  TriangleMesh finish() { return mesh_.finish(); }

 private:
  void record(const char* p) {
    std::array<Eigen::Vector3d, 3> corners_mm;
    for (int v = 0; v < 3; ++v) {
      for (int c = 0; c < 3; ++c) {
        const std::size_t at = static_cast<std::size_t>(12 + 12 * v + 4 * c);  // after the normal
        const double raw = le_float(p + at);
        corners_mm[static_cast<std::size_t>(v)][c] = raw * scale_;
        const std::string problem =
            coordinate_problem(raw, corners_mm[static_cast<std::size_t>(v)][c], limits_);
        if (!problem.empty()) {
          fail(source_, 0,
               "binary STL " + problem + " at byte offset " + std::to_string(offset_ + at) +
                   " (triangle " + std::to_string(done_ + 1) + ", vertex " + std::to_string(v + 1) +
                   ")" + coordinate_advice(raw));
        }
      }
    }
    mesh_.add(corners_mm);
  }

  const std::string& source_;
  double scale_;
  const StlLimits& limits_;
  MeshBuilder mesh_;
  std::uint32_t count_ = 0;
  std::uint32_t done_ = 0;
  std::uint64_t offset_ = kHeaderBytes;  // of the next record
};

// ===========================================================================================
// Files

[[noreturn]] void io_error(const std::string& path, const std::string& message) {
  throw Error(ErrorCode::io, message, SourceLocation{path, 0, 0});
}

// The size of a regular file, with the messages of read_text_file (io/text_file.cpp).
std::uint64_t regular_file_size(const std::string& path, const StlLimits& limits) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    const int err = errno;
    io_error(path, err == ENOENT ? "no such file; check the path"
                                 : std::string("cannot access the file: ") + std::strerror(err));
  }
  if (S_ISDIR(st.st_mode))
    io_error(path, "is a directory, expected a file; give the STL file's path");
  if (!S_ISREG(st.st_mode))
    io_error(path, "is not a regular file (a device or a pipe?); give the STL file's path");
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > limits.max_file_bytes) {
    io_error(path, "file has " + std::to_string(size) + " bytes, more than the " +
                       std::to_string(limits.max_file_bytes) +
                       " an STL file may have: is it the right file?" + kSimplify);
  }
  return size;
}

// Reads up to `count` bytes; returns how many came (fewer only at the end of the file).
std::size_t read_some(std::ifstream& in, char* data, std::size_t count, const std::string& path) {
  in.read(data, static_cast<std::streamsize>(count));
  if (in.bad())
    io_error(path, "read error: is it a readable regular file?");
  return static_cast<std::size_t>(in.gcount());
}

TriangleMesh stream_binary(std::ifstream& in, std::string_view head, std::uint64_t size_bytes,
                           const std::string& path, double scale_to_mm, const StlLimits& limits) {
  BinaryStl stl(head, size_bytes, path, scale_to_mm, limits);
  constexpr std::size_t kBlockRecords = 1310;  // 64 KiB a read
  std::vector<char> block(kBlockRecords * kRecordBytes);
  for (std::uint64_t left = stl.count(); left > 0;) {
    const std::size_t records =
        static_cast<std::size_t>(std::min<std::uint64_t>(left, kBlockRecords));
    const std::size_t want = records * kRecordBytes;
    const std::size_t got = read_some(in, block.data(), want, path);
    if (got < want) {  // shorter than stat said: changed while being read
      const std::uint64_t done = stl.count() - left;
      throw_truncated(path, kHeaderBytes + kRecordBytes * done + got, stl.count());
    }
    stl.records(std::string_view(block.data(), got));
    left -= records;
  }
  return stl.finish();
}

}  // namespace

TriangleMesh load_stl(const std::string& path, double scale_to_mm, const StlLimits& limits) {
  check_scale(scale_to_mm, path);
  std::uint64_t size_bytes = regular_file_size(path, limits);
  std::ifstream in(path, std::ios::binary);
  if (!in)
    io_error(path, std::string("cannot open the file: ") + std::strerror(errno));
  std::string head(static_cast<std::size_t>(std::min(size_bytes, kHeaderBytes)), '\0');
  const std::size_t got = read_some(in, head.data(), head.size(), path);
  if (got < head.size()) {  // shorter than stat said: changed since; take what is there
    head.resize(got);
    size_bytes = got;
  }
  if (!is_ascii(head, size_bytes))
    return stream_binary(in, head, size_bytes, path, scale_to_mm, limits);
  in.clear();
  in.seekg(0);
  AsciiStl stl(path, scale_to_mm, limits);
  for (std::string line; std::getline(in, line);)
    stl.line(line);
  if (in.bad())
    io_error(path, "read error: is it a readable regular file?");
  return stl.finish();
}

TriangleMesh parse_stl(std::string_view bytes, const std::string& source, double scale_to_mm,
                       const StlLimits& limits) {
  check_scale(scale_to_mm, source);
  if (bytes.size() > limits.max_file_bytes) {
    fail(source, 0,
         "STL has " + std::to_string(bytes.size()) + " bytes, more than the " +
             std::to_string(limits.max_file_bytes) + " an STL file may have" + kSimplify);
  }
  const std::string_view head = bytes.substr(0, kHeaderBytes);
  if (!is_ascii(head, bytes.size())) {
    BinaryStl stl(head, bytes.size(), source, scale_to_mm, limits);
    stl.records(bytes.substr(head.size()));
    return stl.finish();
  }
  AsciiStl stl(source, scale_to_mm, limits);
  for (std::size_t at = 0; at < bytes.size();) {
    const std::size_t nl = std::min(bytes.find('\n', at), bytes.size());
    stl.line(bytes.substr(at, nl - at));
    at = nl + 1;
  }
  return stl.finish();
}

}  // namespace redpost
