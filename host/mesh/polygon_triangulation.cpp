#include "host/mesh/polygon_triangulation.h"

#include <algorithm>
#include <cmath>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>

namespace cutwork {

namespace {

/// Distance of 2-D point p from segment [a, b].
double point_segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

/// Twice the signed area of (a, b, c).
double orient(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
}

/// Whether segments [a, b] and [c, d] cross or come closer than `tolerance`.
bool segments_meet(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                   const Eigen::Vector2d& d, double tolerance) {
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return true;
  return std::min({point_segment_distance(a, c, d), point_segment_distance(b, c, d), point_segment_distance(c, a, b),
                   point_segment_distance(d, a, b)}) <= tolerance;
}

/// The outline projected on its Newell plane is a simple polygon, with a margin of 1e-9 of its size:
/// a non-zero normal, no two corners at one place, no corner on a non-adjacent edge, no edges that
/// cross, no spike folding back along its neighbour. O(n²): outlines of more than 4096 corners are
/// refused.
bool simple_outline(std::span<const Vec3> corners) {
  const std::size_t n = corners.size();
  if (n < 3 || n > 4096) return false;
  Vec3 normal = Vec3::Zero(), lo = corners[0], hi = corners[0];
  for (std::size_t k = 0; k < n; ++k) {
    normal += corners[k].cross(corners[(k + 1) % n]);
    lo = lo.cwiseMin(corners[k]);
    hi = hi.cwiseMax(corners[k]);
  }
  const double size = (hi - lo).norm(), tolerance = 1e-9 * size;
  if (!(size > 0) || !(normal.norm() > 1e-9 * size * size)) return false;
  normal.normalize();
  const Vec3 u = normal.unitOrthogonal(), v = normal.cross(u);
  std::vector<Eigen::Vector2d> p(n);
  for (std::size_t k = 0; k < n; ++k) p[k] = {(corners[k] - lo).dot(u), (corners[k] - lo).dot(v)};
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d &a = p[i], &b = p[(i + 1) % n];
    if ((b - a).norm() <= tolerance) return false;
    // The next corner must not fold back onto this edge (or this edge's start onto the next).
    const Eigen::Vector2d& c = p[(i + 2) % n];
    if (n > 3 && (point_segment_distance(c, a, b) <= tolerance || point_segment_distance(a, b, c) <= tolerance))
      return false;
    for (std::size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
      if (segments_meet(a, b, p[j], p[(j + 1) % n], tolerance)) return false;
    }
  }
  return true;
}

}  // namespace

std::vector<std::array<int, 3>> triangulate_polygon(std::span<const Vec3> corners) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
  std::vector<std::array<int, 3>> out;
  if (corners.size() < 3) return out;
  // CGAL triangulates in the plane of the face's normal with inexact constructions: an outline that
  // is degenerate or crosses itself there makes it read freed memory or null references (fuzzing
  // findings in tests/data/fuzz-regressions/mesh_obj). Such outlines are refused here and the
  // caller reports the face.
  if (!simple_outline(corners)) return out;
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
