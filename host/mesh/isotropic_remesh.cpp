#include "host/mesh/isotropic_remesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "host/core/error.h"

namespace cutwork {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using VertexIndex = Mesh::Vertex_index;

Mesh to_cgal(const RowMatX3d& V, const RowMatX3i& F) {
  Mesh m;
  std::vector<VertexIndex> index(size_t(V.rows()), Mesh::null_vertex());
  std::vector<bool> used(size_t(V.rows()), false);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) used[size_t(F(f, k))] = true;
  for (int v = 0; v < V.rows(); ++v)
    if (used[size_t(v)]) index[size_t(v)] = m.add_vertex(Point(V(v, 0), V(v, 1), V(v, 2)));
  for (int f = 0; f < F.rows(); ++f) {
    const auto face = m.add_face(index[size_t(F(f, 0))], index[size_t(F(f, 1))], index[size_t(F(f, 2))]);
    if (face == Mesh::null_face())
      throw InputError(fmt::format("remeshing: face {} makes the surface non-manifold", f));
  }
  return m;
}

/// Marks boundary vertices whose boundary turns by more than `angle` (radians) as constrained.
int mark_corners(const Mesh& m, double angle, Mesh::Property_map<VertexIndex, bool>& corner) {
  int count = 0;
  for (const auto h : m.halfedges()) {
    if (!m.is_border(h)) continue;
    // Border halfedges run along the boundary: prev → h, turning at target(prev) = source(h).
    const auto prev = m.prev(h);
    const Point& a = m.point(m.source(prev));
    const Point& b = m.point(m.source(h));
    const Point& c = m.point(m.target(h));
    const Kernel::Vector_3 d0 = b - a, d1 = c - b;
    const double n0 = std::sqrt(d0.squared_length()), n1 = std::sqrt(d1.squared_length());
    if (n0 == 0 || n1 == 0) continue;
    const double cosine = std::clamp(double(d0 * d1) / (n0 * n1), -1.0, 1.0);
    if (std::acos(cosine) > angle) {
      corner[m.source(h)] = true;
      ++count;
    }
  }
  return count;
}

}  // namespace

RemeshedMesh remesh_isotropic(const RowMatX3d& vertices, const RowMatX3i& faces, const RemeshOptions& options) {
  if (!(options.target_edge_length > 0) || !std::isfinite(options.target_edge_length))
    throw InputError(fmt::format("remeshing: target edge length {} is not a positive length (m)",
                                 options.target_edge_length));
  if (options.iterations < 1) throw InputError("remeshing: at least one iteration is needed");
  Mesh m = to_cgal(vertices, faces);
  auto corner = m.add_property_map<VertexIndex, bool>("v:corner", false).first;
  RemeshedMesh out;
  out.corner_vertices = mark_corners(m, options.corner_angle * std::numbers::pi / 180.0, corner);
  namespace PMP = CGAL::Polygon_mesh_processing;
  // Border edges count as constrained (split and collapsed along the outline, never flipped,
  // their vertices never relaxed); corners are constrained vertices (never touched).
  PMP::isotropic_remeshing(m.faces(), options.target_edge_length, m,
                           CGAL::parameters::number_of_iterations(unsigned(options.iterations))
                               .vertex_is_constrained_map(corner)
                               .protect_constraints(false)
                               .relax_constraints(false));
  m.collect_garbage();
  std::vector<int> index(m.number_of_vertices(), -1);
  out.vertices.resize(Eigen::Index(m.number_of_vertices()), 3);
  int n = 0;
  for (const auto v : m.vertices()) {
    if (m.is_isolated(v)) continue;
    const Point& p = m.point(v);
    out.vertices.row(n) << p.x(), p.y(), p.z();
    index[size_t(v.idx())] = n++;
  }
  out.vertices.conservativeResize(n, 3);
  out.faces.resize(Eigen::Index(m.number_of_faces()), 3);
  int f = 0;
  for (const auto face : m.faces()) {
    int k = 0;
    for (const auto v : m.vertices_around_face(m.halfedge(face))) out.faces(f, k++) = index[size_t(v.idx())];
    ++f;
  }
  return out;
}

}  // namespace cutwork
