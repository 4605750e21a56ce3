// The convex hull through qhull's reentrant C library (convex_hull.hpp).
#include "redpost/collision/convex_hull.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include "redpost/io/error.hpp"

namespace redpost {

namespace {

// How far the points stand off their best plane, against their extent: zero volume, which
// qhull would refuse with its own words ("initial simplex is flat"), said here in ours.
bool spans_volume(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points)
    centre += p;
  centre /= static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  double extent = 0.0;
  for (const Eigen::Vector3d& p : points) {
    scatter += (p - centre) * (p - centre).transpose();
    extent = std::max(extent, (p - centre).norm());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  const Eigen::Vector3d normal = eig.eigenvectors().col(0);  // the smallest eigenvalue's
  double thickness = 0.0;
  for (const Eigen::Vector3d& p : points)
    thickness = std::max(thickness, std::abs(normal.dot(p - centre)));
  return extent > 0.0 && thickness > 1e-9 * extent;
}

// qhull's error text goes to a FILE*: a memory stream keeps it for the message, off stderr.
struct MemoryStream {
  char* text = nullptr;
  std::size_t size = 0;
  FILE* file = open_memstream(&text, &size);
  ~MemoryStream() {
    if (file)
      std::fclose(file);
    std::free(text);
  }
  std::string first_line() {
    if (!file || std::fflush(file) != 0 || !text)
      return {};
    std::string s(text, size);
    return s.substr(0, s.find('\n'));
  }
};

}  // namespace

TriangleMesh convex_hull(const std::vector<Eigen::Vector3d>& points, const std::string& source) {
  for (const Eigen::Vector3d& p : points) {
    if (!p.allFinite())
      throw Error(ErrorCode::bad_input, source + ": a point of the convex hull is not finite");
  }
  if (points.size() < 4 || !spans_volume(points)) {
    throw Error(ErrorCode::bad_input,
                source + ": the " + std::to_string(points.size()) +
                    " point(s) span no volume (a convex hull needs at least 4 points not on "
                    "one plane): give the points around the whole body, or use a <box> or a "
                    "<cylinder> for a thin one");
  }
  std::vector<coordT> coords;
  coords.reserve(3 * points.size());
  for (const Eigen::Vector3d& p : points)
    coords.insert(coords.end(), {p.x(), p.y(), p.z()});

  qhT qh_storage;
  qhT* qh = &qh_storage;
  MemoryStream errors;
  qh_zero(qh, errors.file);
  // Qt: every facet as triangles (a box's square sides as two), each with the facet's normal.
  char command[] = "qhull Qt";
  const int status = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coords.data(), False,
                                  command, nullptr, errors.file);
  TriangleMesh hull;
  hull.source = source;
  if (status == 0) {
    std::map<int, int> index;  // input point -> hull vertex
    facetT* facet;
    FORALLfacets {
      std::array<int, 3> t{};
      int k = 0;
      vertexT *vertex, **vertexp;
      FOREACHvertex_(facet->vertices) {
        const int id = qh_pointid(qh, vertex->point);
        auto [it, added] = index.emplace(id, static_cast<int>(hull.vertices.size()));
        if (added)
          hull.vertices.push_back(points[static_cast<std::size_t>(id)]);
        if (k < 3)
          t[static_cast<std::size_t>(k)] = it->second;
        ++k;
      }
      if (k != 3)
        continue;  // (Qt makes simplicial facets only)
      // qhull keeps a facet's vertices in index order, not wound: turn it to face out.
      const Eigen::Vector3d& a = hull.vertices[static_cast<std::size_t>(t[0])];
      const Eigen::Vector3d n = (hull.vertices[static_cast<std::size_t>(t[1])] - a)
                                    .cross(hull.vertices[static_cast<std::size_t>(t[2])] - a);
      if (n.dot(Eigen::Vector3d(facet->normal[0], facet->normal[1], facet->normal[2])) < 0.0)
        std::swap(t[1], t[2]);
      hull.triangles.push_back(t);
    }
  }
  const std::string why = errors.first_line();
  qh_freeqhull(qh, !qh_ALL);
  int still_long = 0, total_long = 0;
  qh_memfreeshort(qh, &still_long, &total_long);
  if (status != 0 || hull.triangles.size() < 4) {
    throw Error(ErrorCode::bad_input,
                source + ": no convex hull of these points (qhull: " +
                    (why.empty() ? "status " + std::to_string(status) : why) +
                    "): check that they are in mm and spread around the body");
  }
  return hull;
}

}  // namespace redpost
