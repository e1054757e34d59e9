#pragma once
/// Private to host/surfaces: near-equilateral triangulations of 2-D parameter domains (a
/// rectangle and a disk) and a tangential relaxation of such a triangulation once it is mapped
/// onto a surface. The built-in shapes (generators.cpp) map these domains to 3-D.
#include <functional>
#include <vector>

#include "host/core/types.h"

namespace cutwork::shapes_detail {

/// A triangulated parameter domain.
/// uv #V×2 parameter coordinates, faces #F×3 counter-clockwise in the (u, v) plane,
/// on_boundary #V flags (true on the domain's boundary).
struct DomainMesh {
  RowMatX2d uv;
  RowMatX3i faces;
  std::vector<bool> on_boundary;
};

/// Layout of the staggered lattice on a width × height rectangle at a target edge length:
/// `columns` spacings of `spacing` = width / columns along u, `rows` rows of `row_spacing` =
/// height / rows along v, with row_spacing ≤ (√3/2)·spacing (and as close to it as the height
/// allows) so that every triangle has all angles ≥ 30°.
struct RectangleLattice {
  double columns = 0;      ///< integral value, kept as double so huge requests cannot overflow
  double rows = 0;         ///< integral value
  double spacing = 0;      ///< metres along u
  double row_spacing = 0;  ///< metres along v (the largest, when row_positions are given)
  /// Optional (rows + 1 values, 0 first, the height last, increasing): where the rows are, when
  /// they are not evenly spaced (plan_rows).
  std::vector<double> row_positions;
  /// Exact counts of the mesh mesh_rectangle() builds from this layout.
  double num_faces() const { return rows * (2 * columns + 1); }
  double num_vertices() const;
};

/// Chooses the lattice for a width × height rectangle (metres) and target edge length h.
/// Pre: width, height, h finite and positive.
RectangleLattice plan_rectangle(double width, double height, double h);

/// The lattice of plan_rectangle(width, breaks.back(), h), but with a row on every break (the
/// first 0, the last the height, increasing): each stretch between breaks gets its own rows, as
/// many as keep their spacing ≤ (√3/2)·spacing, evenly spaced. A stretch shorter than half a row is
/// joined to the next (the last to the one before), so rows are at least half a row spacing
/// apart and every angle stays ≥ 30°. Extruded profiles use it so that the rows meet the
/// profile's corners and the ends of its fillets: a support that ends where a fillet begins (a
/// chair's runner) is then the same region on every mesh.
/// `max_row_spacing` (optional), of a stretch's ends: a closer spacing there (never below 0.3 of
/// the column spacing, so angles stay ≥ 30°), e.g. to resolve a fillet's curvature.
RectangleLattice plan_rows(double width, const std::vector<double>& breaks, double h,
                           const std::function<double(double, double)>& max_row_spacing = {});

/// Meshes [0, width] × [0, height] with the lattice `plan`: rows at v = j·row_spacing, even
/// rows (at plan.row_positions when given) with vertices at u = i·spacing, odd rows shifted by half a spacing plus one vertex on
/// each side, so that all four sides carry vertices. Consecutive rows are zipped by the
/// shorter diagonal. Faces are counter-clockwise in (u, v).
/// Every interior triangle is isosceles (base `spacing`, height `row_spacing`); the triangles at
/// u = 0 and u = width are right triangles with legs spacing/2 and row_spacing. With
/// row_spacing ≤ (√3/2)·spacing (plan_rectangle's choice) every angle is ≥ 30°.
DomainMesh mesh_rectangle(double width, double height, const RectangleLattice& plan);

/// The hexagonal-ring disk: a centre vertex and `rings` rings, ring k holding 6k vertices, whose
/// triangulation is the regular triangular lattice cut to a hexagon (6·rings² faces,
/// 1 + 3·rings·(rings+1) vertices, every interior vertex of valence 6). Ring k is placed on the
/// circle of radius k/rings (unit disk), vertex j at angle 2πj/(6k). Vertex 0 is the centre;
/// ring k starts at index 1 + 3k(k−1). Faces are counter-clockwise in (u, v).
/// The six boundary vertices at the hexagon's corners have only two faces spanning ~180°, so
/// their faces have an angle near 90° and a smallest angle near 44°; all others are within a
/// few degrees of equilateral.
DomainMesh mesh_hex_disk(int rings);

/// Map from the parameter domain to 3-D.
using SurfaceMap = std::function<Vec3(const Vec2&)>;

/// Improves triangle shapes on the mapped surface by moving vertices within the surface
/// ("smart" Laplacian smoothing): each sweep visits the vertices colour by colour (a greedy
/// colouring, so no two vertices of a colour are adjacent; TBB-parallel within a colour) and
/// moves an interior vertex half-way towards the centroid of its neighbours (in 3-D), pulled back to
/// the parameter domain through the map's Jacobian (least squares), and a boundary vertex
/// along the boundary towards the midpoint of its two boundary neighbours. A move is kept only
/// if it raises the smallest angle of the vertex's faces (in 3-D) and flips no face in the
/// domain, so the mesh's minimum angle never decreases. Within a colour every vertex reads
/// only other colours' positions, so the result is deterministic and independent of threads. Connectivity is unchanged; the cost is O(sweeps·#V).
/// keep_on_boundary projects a moved boundary vertex back onto the domain boundary;
/// boundary_tangent gives the boundary's direction at a boundary point; pinned (empty or #V)
/// marks vertices that must not move.
void relax_on_surface(DomainMesh& mesh, const SurfaceMap& map, int sweeps,
                      const std::function<Vec2(const Vec2&)>& keep_on_boundary,
                      const std::function<Vec2(const Vec2&)>& boundary_tangent,
                      const std::vector<bool>& pinned);

}  // namespace cutwork::shapes_detail
