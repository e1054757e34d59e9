#include "host/export/solid.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <ostream>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/stencil/frame.h"

namespace cutwork {
namespace {

/// Area-weighted vertex normals of a triangle soup (zero rows for unused vertices).
RowMatX3d vertex_normals(const RowMatX3d& V, const RowMatX3i& F) {
  RowMatX3d n = RowMatX3d::Zero(V.rows(), 3);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Vec3 a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Vec3 area_normal = (b - a).cross(c - a);  // twice the area times the unit normal
    for (int k = 0; k < 3; ++k) n.row(F(f, k)) += area_normal.transpose();
  }
  for (Eigen::Index v = 0; v < n.rows(); ++v) {
    const double len = n.row(v).norm();
    if (len > 0) n.row(v) /= len;
  }
  return n;
}

}  // namespace

RowMatX3d surface_normals_at(const FaceBvh& bvh, const RowMatX3d& points) {
  RowMatX3d n(points.rows(), 3);
  tbb::parallel_for(Eigen::Index(0), points.rows(), [&](Eigen::Index i) {
    const ClosestPoint c = bvh.closest_point(points.row(i).transpose());
    n.row(i) = phong_normal_and_jacobian(*bvh.mesh(), c.where, nullptr).transpose();
  });
  return n;
}

Solid thicken_surface(const RowMatX3d& vertices, const RowMatX3i& faces, double thickness, const RowMatX3d* normals) {
  if (!(thickness > 0) || !std::isfinite(thickness))
    throw InputError(fmt::format("solid: the thickness must be positive (got {})", thickness));
  if (faces.rows() == 0) throw InputError("solid: the surface has no faces");
  const Eigen::Index nv = vertices.rows(), nf = faces.rows();
  // Directed edges: a boundary edge is one whose reverse no face uses.
  std::unordered_map<uint64_t, int> directed;  // (a << 32 | b) -> uses
  auto key = [](int a, int b) { return (uint64_t(uint32_t(a)) << 32) | uint32_t(b); };
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      if (++directed[key(faces(f, k), faces(f, (k + 1) % 3))] > 1)
        throw InputError(fmt::format("solid: edge ({}, {}) is used twice in the same direction: the surface is "
                                     "not consistently oriented or not manifold",
                                     faces(f, k), faces(f, (k + 1) % 3)));
  std::vector<std::array<int, 2>> boundary;
  for (Eigen::Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      if (!directed.count(key(b, a))) boundary.push_back({a, b});
    }

  if (normals != nullptr && normals->rows() != nv)
    throw InternalError(fmt::format("solid: {} normals for {} vertices", normals->rows(), nv));
  const RowMatX3d n = normals != nullptr ? *normals : vertex_normals(vertices, faces);
  Solid s;
  s.vertices.resize(2 * nv, 3);
  s.vertices.topRows(nv) = vertices + 0.5 * thickness * n;
  s.vertices.bottomRows(nv) = vertices - 0.5 * thickness * n;
  s.faces.resize(2 * nf + 2 * Eigen::Index(boundary.size()), 3);
  s.faces.topRows(nf) = faces;
  for (Eigen::Index f = 0; f < nf; ++f) s.faces.row(nf + f) << faces(f, 0) + nv, faces(f, 2) + nv, faces(f, 1) + nv;
  Eigen::Index row = 2 * nf;
  for (const auto& [a, b] : boundary) {
    const int ta = a, tb = b, ba = a + int(nv), bb = b + int(nv);
    s.faces.row(row++) << ta, ba, bb;
    s.faces.row(row++) << ta, bb, tb;
  }
  s.wall_faces = int(2 * boundary.size());
  return s;
}

void write_stl(const std::filesystem::path& path, const Solid& solid) {
  const uint32_t n = uint32_t(solid.faces.rows());
  std::string data(84 + size_t(n) * 50, '\0');
  const std::string header = "cutwork cut_solid, millimetres";
  std::memcpy(data.data(), header.data(), header.size());
  std::memcpy(data.data() + 80, &n, 4);
  char* p = data.data() + 84;
  for (uint32_t f = 0; f < n; ++f, p += 50) {
    const Vec3 a = 1e3 * solid.vertices.row(solid.faces(f, 0)).transpose();
    const Vec3 b = 1e3 * solid.vertices.row(solid.faces(f, 1)).transpose();
    const Vec3 c = 1e3 * solid.vertices.row(solid.faces(f, 2)).transpose();
    const Vec3 normal = (b - a).cross(c - a).normalized();
    float values[12];
    for (int k = 0; k < 3; ++k) {
      values[k] = float(normal[k]);
      values[3 + k] = float(a[k]);
      values[6 + k] = float(b[k]);
      values[9 + k] = float(c[k]);
    }
    std::memcpy(p, values, sizeof values);  // little-endian IEEE floats, as STL wants on x86/ARM
  }
  write_file_atomic(path, data);
}

bool is_oriented_manifold_soup(const RowMatX3i& faces, Eigen::Index num_vertices) {
  const Eigen::Index F = faces.rows();
  // 1. Three distinct, valid corners per triangle.
  for (Eigen::Index f = 0; f < F; ++f) {
    const int a = faces(f, 0), b = faces(f, 1), c = faces(f, 2);
    if (std::min({a, b, c}) < 0 || std::max({a, b, c}) >= num_vertices) return false;
    if (a == b || b == c || a == c) return false;
  }
  // 2. No directed edge twice.
  std::vector<uint64_t> edges;
  edges.reserve(size_t(3 * F));
  for (Eigen::Index f = 0; f < F; ++f)
    for (int k = 0; k < 3; ++k)
      edges.push_back(uint64_t(uint32_t(faces(f, k))) << 32 | uint32_t(faces(f, (k + 1) % 3)));
  std::sort(edges.begin(), edges.end());
  if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return false;
  // 3. One fan per vertex. The corner of (v, b, c) at v contributes the link edge b → c; with
  // unique directed edges every link vertex starts and ends at most one link edge, so a vertex's
  // link is disjoint paths and cycles, and it is one fan when a walk from the only path start (or
  // from any edge when there is none) covers every link edge.
  const size_t V = size_t(num_vertices);
  std::vector<int> first(V + 1, 0);
  for (Eigen::Index f = 0; f < F; ++f)
    for (int k = 0; k < 3; ++k) ++first[size_t(faces(f, k)) + 1];
  for (size_t v = 0; v < V; ++v) first[v + 1] += first[v];
  std::vector<std::pair<int, int>> link(size_t(3 * F));
  std::vector<int> cursor(first.begin(), first.end() - 1);
  for (Eigen::Index f = 0; f < F; ++f)
    for (int k = 0; k < 3; ++k)
      link[size_t(cursor[size_t(faces(f, k))]++)] = {faces(f, (k + 1) % 3), faces(f, (k + 2) % 3)};
  std::vector<int> ends;
  for (size_t v = 0; v < V; ++v) {
    const auto begin = link.begin() + first[v], end = link.begin() + first[v + 1];
    const long degree = long(end - begin);
    if (degree == 0) continue;
    std::sort(begin, end);  // by start b (unique)
    ends.clear();
    for (auto it = begin; it != end; ++it) ends.push_back(it->second);
    std::sort(ends.begin(), ends.end());
    long starts = 0;
    auto walk_from = begin;
    for (auto it = begin; it != end; ++it)
      if (!std::binary_search(ends.begin(), ends.end(), it->first)) {
        ++starts;
        walk_from = it;
      }
    if (starts > 1) return false;
    long visited = 0;
    for (auto it = walk_from; visited <= degree;) {
      ++visited;
      const auto next = std::lower_bound(begin, end, std::make_pair(it->second, std::numeric_limits<int>::min()));
      if (next == end || next->first != it->second || next == walk_from) break;
      it = next;
    }
    if (visited != degree) return false;
  }
  return true;
}

}  // namespace cutwork
