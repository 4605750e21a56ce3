// A strict reader of STL meshes (ASCII and binary), for the bodies of the collision checks.
//
// Strict because a mesh that is silently wrong (a truncated download, the wrong units, a facet
// missing a vertex) would make a collision check pass that should fail: every malformed file
// is refused with where it went wrong (file:line for ASCII, the byte offset for binary) and what
// to do about it.
//
// ASCII or binary, decided from the size and the first 84 bytes (a binary file's header often
// starts with "solid" too, so that word alone decides nothing):
//   1. at least 84 bytes and 84 + 50 * n == the file's size, n the little-endian uint32 at
//      offset 80: binary. A text file cannot pass this by chance: below about 7 GB it would
//      need a NUL byte among bytes 80..83, and text has none;
//   2. otherwise, if the first word (after white space, within the first 84 bytes) is "solid" in
//      any case and those 84 bytes hold no NUL byte: ASCII;
//   3. otherwise binary, and the size mismatch is reported (truncated, or bytes after the last
//      triangle). A truncated binary file whose header starts with "solid" still lands here:
//      the triangle count's high byte is 0 below 16.7 million triangles.
//
// ASCII is read line by line, one statement a line, keywords in any case, any white space
// (CRLF too), numbers with std::from_chars (locale-independent, scientific notation):
//   solid [name]
//     facet normal nx ny nz      (three numbers, not used: nothing here needs the normal)
//       outer loop
//         vertex x y z           (exactly three, each line exactly three numbers)
//       endloop
//     endfacet
//   endsolid [name]              (then only blank lines, or another solid)
// Binary is the 80-byte header, a uint32 triangle count and 50 bytes a triangle: the normal and
// three vertices as little-endian float32, and a uint16 attribute (ignored, as is the normal).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace redpost {

struct TriangleMesh {
  // In mm. Vertices with exactly equal coordinates are one vertex (-0 and +0 are equal).
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;  // indices into vertices, in the file's order
  std::string source;                         // the file it came from, for messages
};

// The bounds a file must keep; the defaults are what load_stl and parse_stl use. They exist to
// turn a wrong file (or wrong units) into a clear message rather than exhausting memory or
// passing silently; tests lower them to reach the messages cheaply.
struct StlLimits {
  std::uint64_t max_file_bytes = std::uint64_t{512} << 20;  // 512 MiB
  std::int64_t max_triangles = 20'000'000;                  // facets, degenerate ones included
  double max_coordinate_mm = 1e7;  // |x|, |y|, |z| after scaling: 10 km is no robot cell
};

// Reads an STL file. Coordinates are multiplied by scale_to_mm (an STL file has no units; CAD
// systems write mm or m, so 1000 for metres). Triangles of zero area (a cross product of exactly
// zero, e.g. two equal vertices) are dropped: they bound nothing.
//
// Throws Error with ErrorCode::io (missing, a directory, not a regular file, unreadable, larger
// than max_file_bytes) or ErrorCode::bad_input: malformed content; NaN or infinite coordinates;
// coordinates beyond max_coordinate_mm; no facet at all, or only degenerate ones; more than
// max_triangles facets; scale_to_mm not finite and > 0. ASCII errors carry the line
// (SourceLocation{path, line, 0}), binary ones SourceLocation{path, 0, 0} and the byte offset in
// the message. A problem of the whole mesh (empty, all degenerate) has line 0.
//
// Binary files are streamed: memory is the mesh plus a small block, not the file.
TriangleMesh load_stl(const std::string& path, double scale_to_mm = 1.0,
                      const StlLimits& limits = {});

// The same from bytes in memory (tests, fuzzing); `source` names them in messages and in the
// mesh. More than max_file_bytes is ErrorCode::bad_input here.
TriangleMesh parse_stl(std::string_view bytes, const std::string& source, double scale_to_mm = 1.0,
                       const StlLimits& limits = {});

}  // namespace redpost
