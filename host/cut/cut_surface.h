#pragma once
/// The cut surface: the base mesh with every stencil outline cut out (what `cutwork design`
/// writes as cut.obj, ready to view or thicken).
///
/// The cut agrees with the fill ratios by construction. The fill kernel measures, per pair
/// (stencil s, triangle t), the covered fraction of t in s's projected plane, where t is the
/// straight triangle through its projected corners w_0, w_1, w_2 (kernels/clip/clip.h). That
/// triangle is the image of t under one affine map M_s (corner k ↦ w_k), and affine maps keep
/// area ratios, so cutting t by M_s⁻¹(polygon of s) removes exactly the fraction the kernel
/// reported: the area of the cut surface is Σ_t α_t A_t for non-overlapping stencils (without
/// the min_fill clamp), and overlapping stencils remove their union.
///
/// Per base triangle t (all triangles in parallel, merged in face order):
///  - no stencil covers any of it (fraction 0, or a back-facing pair): t is kept as it is;
///  - a stencil covers all of it (fraction ≥ 1): t is removed;
///  - otherwise t is re-triangulated by a constrained Delaunay triangulation (CGAL) in an
///    isometric 2-D frame of t, constrained by t's boundary and the pieces of the polygon edges
///    inside t; each sub-triangle is removed when M_s of its centroid lies inside some polygon.
/// Where a polygon edge crosses a mesh edge (u, v), u < v, the crossing is computed from the
/// edge's point of view only (orientation tests of w_u, w_v against the polygon edge's line and
/// of the polygon edge's ends against the edge's line), so both faces of the edge make the same
/// decisions and the same vertex X_u + τ (X_v − X_u), bit for bit; the stencils of both faces
/// split a shared edge, so the output is watertight across it even where only one face is cut
/// (a polygon touching the edge, a fold the other face sees from behind).
/// Exact and near contacts happen (lattice meshes, stencils centred on vertices, outlines an
/// optimiser pushed against the border or against each other) and are snapped, with one
/// distance δ = 1e-9 × the mesh's longest edge, the same way on both sides: a polygon vertex
/// within 2δ of a mesh vertex is that vertex, within δ of an edge (in the stencil's frame, δ/s)
/// lies on the edge; points of one edge within δ of each other are one vertex, and within δ of
/// an end they are that mesh vertex; inside a face, a polygon vertex within δ of another
/// stencil's polygon vertex is that vertex and within δ of another stencil's polygon edge lies
/// on it. So no output face is a needle or a sliver (twice its area > 1e-10 × its longest edge²
/// wherever one stencil meets the mesh or another stencil in a point; the mesh loader asks for
/// 1e-12), and the area moves by at most δ × the polygon's local edge lengths per snap. Sub-
/// triangles below 1e-14 of their face's area (round-off slivers outside the face) are dropped.
/// Where round-off still makes a face's tests inconsistent (not seen in the tests) the cut
/// keeps the polygon pieces whose midpoint lies inside the face and classification by
/// centroids keeps the area right; the output may then have a T-junction.
/// Coordinates are not made robust to single precision: a face may be thinner than float
/// round-off of its coordinates (e.g. an outline 1e-8 × the edge length from the border).
#include <span>

#include <Eigen/Core>

#include "host/core/types.h"
#include "host/mesh/bvh.h"
#include "host/stencil/frame.h"
#include "host/stencil/stencil_opening.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork {

/// A base mesh with its stencils cut out. Vertex order: the referenced base vertices in base
/// order, then the vertices on base edges (sorted by (edge, stencil, polygon edge)), then the
/// vertices inside base faces (in face order). Face order: by source face, so without stencils
/// the output equals the input (when every base vertex is referenced).
struct CutSurface {
  RowMatX3d vertices;            ///< #V'×3 positions (m)
  RowMatX3i faces;               ///< #F'×3, counter-clockwise like their source faces
  Eigen::VectorXi source_vertex; ///< #V': base vertex index, or −1 for a vertex the cut made
  Eigen::VectorXi source_face;   ///< #F': the base face each output face lies in
  int kept_faces = 0;            ///< base faces copied unchanged
  int split_faces = 0;           ///< base faces re-triangulated (partly covered, or sharing an
                                 ///< edge with a cut face whose outline touches that edge)
  int removed_faces = 0;         ///< base faces cut away entirely
  double area = 0;               ///< total area of the output (m²)
};

/// Cuts `stencils` (#S) out of the surface of `surface_bvh`. Frames come from `field` exactly
/// as in FillRatioEvaluator (which the cut runs on the base mesh), so the cut and the fill
/// ratios see the same projection. Parallel (TBB) over base faces; the result does not depend
/// on the number of threads.
/// Throws InputError for an invalid stencil (non-finite position or angle, scale not finite
/// and positive, type not in `shapes`) or stencils with an empty library.
CutSurface cut_stencils(const FaceBvh& surface_bvh, const StencilLibrary& shapes,
                        const TangentField& field, std::span<const StencilParams> stencils);

/// The stencils as a tool of radius `tool_radius` (m) cuts them (host/stencil/stencil_opening.h:
/// each stencil the union of the discs of that radius inside it), cut out: what a part cut with
/// that tool is (fabrication.tool_radius). 0: cut_stencils of the drawn outlines. With `tool`, what
/// the tool did (its shapes and counts; left empty for 0). Throws InputError as cut_stencils and
/// tool_cut_stencils do, and for a tool radius that is not finite and at least 0.
CutSurface cut_with_tool(const FaceBvh& surface_bvh, const StencilLibrary& shapes, const TangentField& field,
                         std::span<const StencilParams> stencils, double tool_radius, ToolCutStencils* tool = nullptr);

}  // namespace cutwork
