#pragma once
/// Isotropic remeshing of a triangle mesh with boundaries, for the conforming verification: a cut
/// surface (host/cut) carries needles and slivers along every stencil outline; this turns it into
/// near-equilateral triangles of one target edge length while keeping every boundary where it is.
///
/// Method: CGAL's Polygon_mesh_processing::isotropic_remeshing (split long edges, collapse short
/// ones, flip towards valence 6, tangential relaxation, projection onto the input surface).
/// Boundary edges are constrained: they are split (at their midpoints, which lie on the straight
/// outline segment) and collapsed (onto one of their end vertices), never flipped, and their
/// vertices are never moved by relaxation — so every boundary vertex of the output is a boundary
/// vertex of the input or lies on an input boundary edge: the outlines stay where the cut put them,
/// resampled at the target length. Boundary vertices where the boundary turns by more than
/// `corner_angle` (the sheet's corners, a star's tips) are kept as they are (never collapsed away).
#include <Eigen/Core>

#include "host/core/types.h"

namespace cutwork {

struct RemeshOptions {
  double target_edge_length = 0;   ///< m, > 0
  int iterations = 5;              ///< CGAL's split/collapse/flip/relax rounds
  double corner_angle = 30.0;      ///< degrees: boundary turns above this are kept as corners
};

struct RemeshedMesh {
  RowMatX3d vertices;   ///< #V×3 (m), only referenced vertices
  RowMatX3i faces;      ///< #F×3, oriented like the input
  int corner_vertices = 0;  ///< boundary vertices kept as corners
};

/// Remeshes (V, F) (#V×3, #F×3 consistently oriented, edge-manifold; unreferenced vertices are
/// ignored). Throws InputError for a bad target length or a mesh CGAL cannot hold (non-manifold).
RemeshedMesh remesh_isotropic(const RowMatX3d& vertices, const RowMatX3i& faces, const RemeshOptions& options);

}  // namespace cutwork
