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
///  1b. with `coarsen_straight_runs`: vertices of straight runs of the boundary and of the feature
///     lines (each on the segment between its two neighbours along the line, to 1e-9 of its
///     length) are removed while that segment is at most L long, corners and feature ends kept; no
///     line moves. A boundary much finer than L along a straight side (a level coarser than its
///     base mesh) otherwise leaves triangles of size L spanning two collinear boundary edges, which
///     no flip repairs: zero-area faces. (The removals are greedy: a run's last piece can stay
///     short.)
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
///
/// Feature lines (`feature_edges`): interior input edges kept as lines through every step — split
/// with the boundary in step 2 and by each grading pass that reaches them, protected like it in
/// steps 3 and 4 — so that a region the input's vertices outline (a clamped area) is the same
/// region on every output mesh.
///
/// Grading (`grading.depth` > 0, for the conforming verification: a ligament between two holes
/// one triangle wide is far too stiff). After step 3, up to `depth` passes j = 1, 2, … refine the
/// faces that need it to L/2^j:
///  - local width: the material's local width at a face is the diameter of the largest disc inside
///    the material that holds its centroid (the "local thickness" of image analysis), sampled with
///    discs centred at face centroids of radius their distance to the boundary. A face whose width
///    is below `elements_across` × the pass's threshold size s = feature_scale × L/2^(j−1) (so
///    fewer than that many triangles of the level-0 size s would span it) is refined;
///  - outline radius: faces at a boundary vertex where the material turns inwards (its angle there
///    exceeds π: a hole's rim, a notch) with a radius of curvature (mean edge / turn) below
///    elements_across × s / 2, so a hole gets at least `elements_across` triangles across;
///  - plus `rings` rings of faces around them, so the size changes by at most 2 per few rings.
/// Each pass splits the selected region's boundary edges to 4/3 of its size, remeshes the region
/// (CGAL's isotropic_remeshing on that face range: its border with the rest is kept as it is) and
/// projects the new interior vertices back onto the input surface. `feature_scale` keeps a family
/// of meshes self-similar: remeshing at L/2^k with feature_scale 2^k refines the same regions as
/// at L (the thresholds are in units of the level-0 size), so the sizes are everywhere 2^-k of the
/// level-0 mesh's and Richardson extrapolation over the family holds.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "host/core/types.h"

namespace cutwork {

struct GradingOptions {
  int depth = 0;                 ///< refinement passes (faces down to L/2^depth); 0: uniform, no grading
  double elements_across = 3;    ///< triangles across the narrowest ligament and a hole's diameter
  double feature_scale = 1;      ///< thresholds in units of feature_scale × L (see the file comment)
  int rings = 2;                 ///< rings of faces added around the selected ones
  /// Focus (the conforming verification's peak zoom): after the grading passes, halving passes
  /// k = 1 … depth + focus_depth refine the faces within radius_k of any centre to L/2^k, where
  /// radius_k = focus_radius (1 + (depth + focus_depth − k)/2) shrinks to focus_radius on the last
  /// pass. A pass takes the faces its remeshing would split (longest edge over 4/3 of the size)
  /// plus `rings` rings, less the faces already as fine (mean edge below the size), so nothing an
  /// earlier pass refined is coarsened. Outside the widest ball the mesh is the one without focus.
  std::vector<Vec3> focus;       ///< centres, m (empty: no focus)
  double focus_radius = 0;       ///< m
  int focus_depth = 0;           ///< halvings beyond `depth` within focus_radius
  /// The passes beyond `depth` refine only the faces within focus_band × their size of the outline
  /// (0: the whole ball). Refining the whole ball made each step 3–4× the last (a sheet's fourth
  /// step: 416k triangles about a hole whose finest level had 13k); along the rims, where the peak
  /// is read, each step about doubles.
  double focus_band = 8;
};

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
  GradingOptions grading{};        ///< off by default
  /// Interior lines to keep (pairs of input vertex indices, each an edge of the input): split like
  /// the boundary, never flipped, collapsed or moved, so the output has a polyline of edges along
  /// each (the conforming verification's support outlines, scene.h support_outline_edges). Their
  /// vertices are kept like corners; a pair that is not an input edge is an InputError.
  std::vector<std::array<int, 2>> feature_edges{};
  /// Step 1b: straight runs of the boundary and of the feature lines coarsened to edges of at most
  /// L. The conforming verification sets it on a level at least twice as coarse as its base mesh
  /// (solvers/conforming/conforming_verification.h kStraightRunCoarsening).
  bool coarsen_straight_runs = false;
};

struct RemeshedMesh {
  RowMatX3d vertices;   ///< #V×3 (m), only referenced vertices
  RowMatX3i faces;      ///< #F×3, oriented like the input
  int corner_vertices = 0;  ///< boundary vertices kept as corners
  int collapsed_boundary_edges = 0;  ///< step 1
  int merged_line_vertices = 0;      ///< step 1b: vertices of straight boundary or feature runs removed
  int repaired_faces = 0;            ///< step 4: flat faces fewer after the repair
  int feature_edges = 0;             ///< output edges along RemeshOptions::feature_edges
  std::vector<int> graded_faces;     ///< faces selected by each grading pass (before it remeshed them)
  std::vector<int> focused_faces;    ///< the same for each focus pass that selected any
};

/// Remeshes (V, F) (#V×3, #F×3 consistently oriented, edge-manifold; unreferenced vertices are
/// ignored). Throws InputError for a bad target length or a mesh CGAL cannot hold (non-manifold).
RemeshedMesh remesh_isotropic(const RowMatX3d& vertices, const RowMatX3i& faces, const RemeshOptions& options);

/// The focus passes of GradingOptions alone, on a mesh that is already remeshed (the peak zoom's
/// submodel, solvers/conforming): passes k = 1 … depth + focus_depth halve the faces about
/// `grading.focus` as remesh_isotropic's focus does (sizes L/2^k, L = target_edge_length), but never
/// select a `frozen` face (one flag per input face), so that frozen faces, their edges and their
/// vertices come out exactly as they went in (the cap-and-needle repair leaves them alone too).
/// New interior vertices are projected onto the surface (surface_vertices, surface_faces) and new
/// boundary vertices onto its outline, as in the grading. Throws InputError for bad options.
RemeshedMesh refine_about(const RowMatX3d& vertices, const RowMatX3i& faces, const std::vector<bool>& frozen,
                          const RowMatX3d& surface_vertices, const RowMatX3i& surface_faces,
                          const RemeshOptions& options);

}  // namespace cutwork
