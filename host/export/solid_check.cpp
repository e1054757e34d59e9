// check_solid: CGAL's Polygon Mesh Processing on the thickened surface (kept in its own file:
// these headers are slow to compile).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <array>
#include <vector>

#include "host/export/solid.h"

namespace cutwork {

SolidCheck check_solid(const Solid& solid) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Point = Kernel::Point_3;
  using Mesh = CGAL::Surface_mesh<Point>;
  namespace PMP = CGAL::Polygon_mesh_processing;

  SolidCheck c;
  std::vector<Point> points;
  points.reserve(size_t(solid.vertices.rows()));
  for (Eigen::Index v = 0; v < solid.vertices.rows(); ++v)
    points.emplace_back(solid.vertices(v, 0), solid.vertices(v, 1), solid.vertices(v, 2));
  std::vector<std::array<int, 3>> polygons(size_t(solid.faces.rows()));
  for (Eigen::Index f = 0; f < solid.faces.rows(); ++f)
    polygons[size_t(f)] = {solid.faces(f, 0), solid.faces(f, 1), solid.faces(f, 2)};

  c.manifold = is_oriented_manifold_soup(solid.faces, solid.vertices.rows());
  if (!c.manifold) {
    c.problem = "not manifold (an edge with more than two faces, or faces meeting only at a vertex)";
    return c;
  }
  Mesh mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  c.area = PMP::area(mesh);
  c.closed = CGAL::is_closed(mesh);
  if (!c.closed) {
    c.problem = "not closed (it has border edges)";
    return c;
  }
  c.volume = PMP::volume(mesh);
  c.self_intersecting = PMP::does_self_intersect<CGAL::Parallel_if_available_tag>(mesh);
  if (c.self_intersecting) {
    c.problem = "self-intersecting (the surface curves more sharply than half the thickness, or two outlines touch)";
    return c;
  }
  c.outward = PMP::is_outward_oriented(mesh);
  c.bounds_volume = PMP::does_bound_a_volume(mesh);
  if (!c.outward)
    c.problem = "oriented inwards";
  else if (!c.bounds_volume)
    c.problem = "does not bound a volume";
  return c;
}

}  // namespace cutwork
