#pragma once
/// Poisson-disk initialisation for the packing objective (§4.3: "we simply use a Poisson disk
/// sampling strategy"): dart throwing on the surface with area-weighted sampling.
///
/// A dart is a uniformly distributed surface point c with the local scale r = unit·sizing(c);
/// it is kept when it respects the collision safety factor against every stencil already placed
/// (|c − c_j| ≥ (1+s)(r + r_j)) and against the open boundary (distance ≥ (1+s) r), and
/// rejected otherwise. Sampling stops after `count` stencils or after max_misses consecutive
/// rejections (then the uncovered area that could still take a stencil is below about
/// 1/max_misses of the surface: a maximal sampling). Existing stencils in the layout are kept,
/// so the same routine fills holes in a packing (§6.3).
/// Deterministic for a seed (PatternRng).
#include "host/pattern/pattern_surface.h"

namespace cutwork {

struct PoissonDiskOptions {
  double unit = 0.01;      ///< nominal scale ℓ (m); a stencil's scale is unit·sizing(c)
  double safety = 0.2;     ///< s
  int count = 0;           ///< stop at this many stencils in the layout (0: until saturated)
  int max_misses = 0;      ///< consecutive rejections before stopping; 0: max(3000, 30·#placed)
  int num_types = 1;       ///< types drawn uniformly from [0, num_types)
};

/// Adds darts to `layout`; returns how many were added.
int poisson_disk_sample(const PatternSurface& surface, StencilLayout& layout, PatternRng& rng,
                        const PoissonDiskOptions& options);

}  // namespace cutwork
