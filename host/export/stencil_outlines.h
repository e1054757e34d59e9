#pragma once
/// Stencil outlines in 3-D: each stencil's polygon placed in its tangent plane (the frame the
/// fill kernel and the cut use) and projected onto the surface, for stencils.vtp.
#include <span>
#include <vector>

#include "host/core/types.h"
#include "host/mesh/bvh.h"
#include "host/stencil/frame.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork {

/// One polyline per stencil (#polygon points × 3, metres, not closed): the polygon point (u, v)
/// at c + s (u e_x + v e_y) with the stencil's frame (compute_frame, make_clip_stencil's axes),
/// then moved to its closest point on the surface of `bvh`. Throws InputError for a stencil
/// type not in `shapes`.
std::vector<RowMatX3d> stencil_outlines(const FaceBvh& bvh, const StencilLibrary& shapes,
                                        const TangentField& field, std::span<const StencilParams> stencils);

}  // namespace cutwork
