#pragma once
/// Isotropic remeshing of a triangle mesh with boundaries, for the conforming verification: a cut
/// surface (host/cut) carries needles and slivers along every stencil outline; this turns it into
/// near-equilateral triangles of one target edge length while keeping every boundary where it is.
///
/// Method (the outline is kept exactly, so the conforming surface has the area the fill ratios
/// measured):
///  1. boundary edges shorter than `min_boundary_edge` × L are collapsed onto one of their ends (a
///     corner when there is one; never when a face around would flip). The cut leaves such edges
///     where an outline crosses a mesh edge next to a polygon vertex; kept, each would leave a
///     needle beside it. The outline moves by less than that length there.
///  2. boundary edges longer than 4/3 L are split at equal intervals (points on the edge);
///  3. CGAL's Polygon_mesh_processing::isotropic_remeshing (split long edges, collapse short
///     ones, flip towards valence 6, tangential relaxation, projection onto the input surface)
///     with every boundary edge protected: not split, collapsed, flipped or moved.
///  4. caps (an angle above 160°) flipped away and needles' short interior edges collapsed
///     (CGAL's experimental remove_almost_degenerate_faces) with the boundary constrained, when
///     any face is flatter than `repair_flatness`: a valence flip across two collinear boundary
///     edges leaves a flat cap beside the outline (a zero-area face failed verify on the chair).
/// So every boundary vertex of the output is a boundary vertex of the input or lies on an input
/// boundary edge. Where the outline's own segments are shorter than L (a polygon of 64 sides on a
/// small stencil), the triangles next to it are as small as those segments and grow to L away from
/// it. Boundary vertices where the boundary turns by more than `corner_angle` (the sheet's
/// corners, a star's tips) are never collapsed away in step 1.
#include <Eigen/Core>

#include "host/core/types.h"

namespace cutwork {

struct RemeshOptions {
  double target_edge_length = 0;   ///< m, > 0
  int iterations = 5;              ///< CGAL's split/collapse/flip/relax rounds
  double corner_angle = 30.0;      ///< degrees: boundary turns above this are kept as corners
  double min_boundary_edge = 0.1;  ///< boundary edges shorter than this × L are collapsed (step 1)
  /// Step 4: faces flatter than this (twice the area over the longest edge squared; √3/2 for an
  /// equilateral face) start a cap-and-needle repair, where angles above `cap_angle` (degrees) are
  /// flipped away and interior edges shorter than 1/`needle_ratio` of their face's longest,
  /// collapsed.
  double repair_flatness = 0.1;
  double cap_angle = 160.0;
  double needle_ratio = 4.0;
};

struct RemeshedMesh {
  RowMatX3d vertices;   ///< #V×3 (m), only referenced vertices
  RowMatX3i faces;      ///< #F×3, oriented like the input
  int corner_vertices = 0;  ///< boundary vertices kept as corners
  int collapsed_boundary_edges = 0;  ///< step 1
  int repaired_faces = 0;            ///< step 4: flat faces fewer after the repair
};

/// Remeshes (V, F) (#V×3, #F×3 consistently oriented, edge-manifold; unreferenced vertices are
/// ignored). Throws InputError for a bad target length or a mesh CGAL cannot hold (non-manifold).
RemeshedMesh remesh_isotropic(const RowMatX3d& vertices, const RowMatX3i& faces, const RemeshOptions& options);

}  // namespace cutwork
