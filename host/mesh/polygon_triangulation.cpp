#include "host/mesh/polygon_triangulation.h"

#include <algorithm>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>

namespace cutwork {

std::vector<std::array<int, 3>> triangulate_polygon(std::span<const Vec3> corners) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
  std::vector<std::array<int, 3>> out;
  if (corners.size() < 3) return out;
  // Two corners at one position (distinct OBJ vertices with equal coordinates) make a degenerate
  // outline on which CGAL's face triangulation reads freed memory (fuzzing finding, see
  // tests/data/fuzz-regressions/mesh_obj): refused here, the caller reports the face.
  {
    std::vector<Vec3> sorted(corners.begin(), corners.end());
    std::sort(sorted.begin(), sorted.end(), [](const Vec3& a, const Vec3& b) {
      return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    });
    Vec3 lo = sorted.front(), hi = sorted.front();
    for (const Vec3& p : sorted) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const double tolerance = 1e-12 * (hi - lo).norm();
    for (std::size_t i = 0; i < sorted.size(); ++i)
      for (std::size_t j = i + 1; j < sorted.size() && sorted[j].x() - sorted[i].x() <= tolerance; ++j)
        if ((sorted[j] - sorted[i]).norm() <= tolerance) return out;
  }
  Mesh mesh;
  std::vector<Mesh::Vertex_index> vertices;
  vertices.reserve(corners.size());
  for (const Vec3& p : corners) vertices.push_back(mesh.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z())));
  if (mesh.add_face(vertices) == Mesh::null_face()) return out;  // e.g. a repeated corner
  // One face: CGAL projects it on its plane (Newell normal) and keeps the constrained Delaunay
  // triangles inside the outline, which handles concave outlines; it adds no vertices.
  if (!CGAL::Polygon_mesh_processing::triangulate_faces(mesh)) return out;
  for (const Mesh::Face_index f : mesh.faces()) {
    std::array<int, 3> tri{};
    int k = 0;
    for (const Mesh::Vertex_index v : mesh.vertices_around_face(mesh.halfedge(f))) {
      if (k == 3) return {};
      tri[std::size_t(k++)] = int(v.idx());
    }
    if (k != 3) return {};
    out.push_back(tri);
  }
  return out;
}

}  // namespace cutwork
