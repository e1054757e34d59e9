#pragma once
/// Admissibility of a layout (§4.2: "no pair of stencils may overlap"): bounding circles
/// enlarged by the safety factor must keep apart, (1+s)(r_i + r_j) + g ≤ |c_i − c_j|, and off the
/// open boundary, (1+s) r_i + g ≤ distance(c_i, boundary). The gap g (m, default 0) is an absolute
/// width of material the structural phase keeps between any two bounding circles and between one
/// and the border: the fabrication minimum feature as a hard constraint (outlines lie inside their
/// bounding circles, so the ligament between two holes is at least g wherever the chord between
/// the centres measures the distance). The penalties of the objectives leave a residue of order
/// 1/w_collision; resolve_overlaps removes it exactly. On symmetry planes (PatternSurface::mirror) the
/// pair condition holds between every stencil and every mirror image, its own included — so a
/// stencil keeps (1+s) r + g/2 from a plane — and the planes are no boundary.
#include "host/pattern/pattern_surface.h"

namespace cutwork {

struct OverlapReport {
  int pairs = 0;            ///< stencil pairs violating the pair condition
  int boundary = 0;         ///< stencils violating the boundary condition
  int images = 0;           ///< pairs of a stencil and an image across symmetry planes (its own
                            ///< included) violating the pair condition (pattern_mirror.h)
  double worst = 0;         ///< largest violation relative to the required distance (0: none)
  bool any() const { return pairs > 0 || boundary > 0 || images > 0; }
};

/// Checks a layout (uniform grid for the pairs).
OverlapReport find_overlaps(const PatternSurface& surface, const StencilLayout& layout,
                            double safety, double gap = 0);
/// Brute-force twin (all pairs, all boundary segments).
OverlapReport find_overlaps_brute_force(const PatternSurface& surface, const StencilLayout& layout,
                                        double safety, double gap = 0);

/// Makes the layout admissible by shrinking scales: each stencil takes the smallest factor
/// f_ij = (d_ij − g) / ((1+s)(r_i + r_j)) over its violating pairs and (d_i − g) / ((1+s) r_i) for
/// the boundary (both ends of a pair shrink by at most its factor, so every pair is admissible
/// after one pass), times (1 − 1e-9) against round-off. A stencil that would shrink below
/// min_scales[i] (#S) is removed instead. Returns the number of stencils removed.
int resolve_overlaps(const PatternSurface& surface, StencilLayout& layout, double safety,
                     const Eigen::VectorXd& min_scales, double gap = 0);

}  // namespace cutwork
