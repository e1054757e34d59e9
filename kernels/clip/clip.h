#pragma once
/// Kernel `clip`: per (stencil, triangle) pair, the fraction of the triangle covered by the
/// stencil, measured in the stencil's projected plane, and its exact derivatives w.r.t. the
/// stencil's parameters p = (q_x, q_y, q_z, s, φ).
///
/// Twins: clip_ref (plain loop, the reference), clip_tbb (TBB parallel_for over pairs); both
/// call the same per-pair function, so they agree bit for bit. A Vulkan twin (clip.comp,
/// clip_vk.cpp) mirrors kernels/common/stencil_geometry.h line by line.
///
/// What is computed per pair (s, t) — see kernels/common/stencil_geometry.h for the maps:
///  1. the three corners of triangle t are mapped into stencil s's reference frame by the
///     equidistant projection (paper §4.1), giving w_0, w_1, w_2 (reference units, = m / s);
///  2. the projected triangle's signed area A_T; a triangle that is back-facing or seen edge-on
///     (A_T ≤ 1e-12 · longest edge²) belongs to another sheet of the surface (the projection
///     is not injective there, paper §7) and contributes nothing;
///  3. early exits: triangle at distance ≥ 1 from the origin (outside the bounding circle): 0;
///     all corners inside the polygon's inscribed origin-centred disk: fully covered, 1; the
///     whole bounding circle inside the triangle: overlap = polygon area;
///  4. otherwise the stencil polygon (non-convex allowed) is clipped by the triangle's three
///     half-planes (Sutherland–Hodgman), area by the shoelace formula, gradient by the
///     transport theorem (stencil_geometry.h);
///  5. fraction = overlap / A_T (paper §5.2: "the ratio between the area of the overlap and the
///     area of the projected element"), both in the projected metric, so the ratio is
///     dimensionless and does not depend on s's units; its derivative by the quotient rule and
///     the chain rule through the projection (∂w/∂p).
///
/// Buffers (each maps 1:1 onto one GPU storage buffer; std430 layouts, static_asserted):
///   vertices  #V×3 double   mesh vertex positions (m), packed xyz
///   faces     #F×3 int32    triangle corner indices, CCW seen from the normal side
///   shapes    #K  ClipShape one record per stencil type
///   polygons  2·Σn double   all stencil polygons packed (x, y), reference frame, CCW
///   stencils  #S  ClipStencil frames and Jacobians (computed on the host)
///   pairs     #P  ClipPair  (stencil, face), sorted by face (the fill kernel needs that)
///   results   #P  ClipResult
#include <cstdint>
#include <memory>
#include <span>

#include "kernels/common/stencil_geometry.h"

namespace cutwork::kernels {

/// One stencil type. std430: {int offset; int count; double area; double inner_radius;}.
struct ClipShape {
  int32_t polygon_offset;  ///< first vertex of the polygon in `polygons` (in vertices, not doubles)
  int32_t polygon_count;   ///< number of vertices (≥ 3)
  double area;             ///< polygon area in reference units (bounding radius 1)
  double inner_radius;     ///< radius of the largest origin-centred disk inside the polygon
                           ///< (0 when the origin is outside it); drives the "fully inside" exit
};
static_assert(sizeof(ClipShape) == 24);

/// A stencil's placement and its Jacobians w.r.t. q. Doubles then two ints, so std430 arrays of
/// scalars give the same packing (stride 8) as C++; the struct is 8-aligned, 304 bytes.
struct ClipStencil {
  double origin[3];    ///< c: centre on the surface (m)
  double axis_x[3];    ///< e_x = cos φ t + sin φ b (unit)
  double axis_y[3];    ///< e_y = −sin φ t + cos φ b (unit)
  double d_origin[9];  ///< ∂c/∂q, row-major 3×3
  double d_axis_x[9];  ///< ∂e_x/∂q
  double d_axis_y[9];  ///< ∂e_y/∂q
  double scale;        ///< s > 0: bounding-circle radius (m)
  int32_t shape;       ///< index into `shapes`
  int32_t pad;
};
static_assert(sizeof(ClipStencil) == 304);

/// One candidate pair. std430: {int stencil; int face;}.
struct ClipPair {
  int32_t stencil;
  int32_t face;
};
static_assert(sizeof(ClipPair) == 8);

/// Per-pair output. std430: 8 doubles.
struct ClipResult {
  double fraction;       ///< overlap / projected triangle area, in [0, 1] up to round-off
  double d_fraction[5];  ///< ∂fraction/∂(q_x, q_y, q_z, s, φ); zeros when derivatives are off
  double overlap_area;   ///< overlap in the projected plane (m²)
  double triangle_area;  ///< signed projected triangle area (m²); ≤ 0: back-facing, skipped
};
static_assert(sizeof(ClipResult) == 64);

/// Switches (a GPU push-constant block). std430: two ints.
struct ClipOptions {
  int32_t derivatives = 1;  ///< 0: fraction only
  int32_t early_exits = 1;  ///< 0: always clip (tests check that the exits change nothing)
};

/// The kernel's inputs; spans are views, owned by the caller.
struct ClipInputs {
  std::span<const double> vertices;     ///< #V×3
  std::span<const int32_t> faces;       ///< #F×3
  std::span<const ClipShape> shapes;    ///< #K
  std::span<const double> polygons;     ///< 2 × total polygon vertices
  std::span<const ClipStencil> stencils;///< #S
  std::span<const ClipPair> pairs;      ///< #P, sorted by face
};

/// Reusable scratch for the twins (per-thread clip buffers); keep one per evaluator so repeated
/// calls do not allocate. Not thread-safe across concurrent calls.
class ClipWorkspace {
 public:
  ClipWorkspace();
  ~ClipWorkspace();
  ClipWorkspace(const ClipWorkspace&) = delete;
  ClipWorkspace& operator=(const ClipWorkspace&) = delete;
  struct Impl;
  Impl& impl() { return *m_impl; }

 private:
  std::unique_ptr<Impl> m_impl;
};

/// The result for pair index `pair`. `scratch` holds 2 · clip_scratch_capacity(n) vertices,
/// n ≥ the largest polygon count. Preconditions (checked by the host, not here): indices in
/// range, scale > 0, polygons simple and CCW with bounding radius 1.
ClipResult clip_pair(const ClipInputs& in, const ClipOptions& options, int32_t pair,
                     ClipVertex* scratch);

/// Largest polygon vertex count over `shapes` (sizes the scratch).
int32_t max_polygon_count(std::span<const ClipShape> shapes);

/// Reference twin: results[i] for every pair i, in order, single-threaded.
/// results.size() must equal in.pairs.size().
void clip_ref(const ClipInputs& in, const ClipOptions& options, std::span<ClipResult> results,
              ClipWorkspace& workspace);
/// TBB twin: same results, bit for bit (each pair is computed by clip_pair independently).
/// Uses the calling arena's threads (limit them with tbb::global_control).
void clip_tbb(const ClipInputs& in, const ClipOptions& options, std::span<ClipResult> results,
              ClipWorkspace& workspace);

}  // namespace cutwork::kernels
