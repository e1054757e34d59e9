#include "host/export/solid.h"

#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <unordered_map>

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

}  // namespace cutwork
