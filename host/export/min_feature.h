#pragma once
/// The minimum-feature check of a cut surface: how narrow the material gets between two stencil
/// holes (a ligament) and between a hole and the surface's border, against a printable minimum.
///
/// The holes and the border are the boundary loops of the cut surface (the connected components
/// of its boundary edges): a loop that passes through a boundary vertex of the base mesh is the
/// border, every other loop is a hole (one stencil, or several that overlap and cut one hole).
/// The width of the material between two loops is the smallest Euclidean distance between their
/// edges (exact segment–segment distances). On a thin curved shell this is never more than the
/// width measured along the surface, so the check errs on the safe side. A narrow neck within
/// one loop (a thin stencil, or two overlapping stencils) is not a ligament and is not checked.
#include <limits>
#include <string>
#include <vector>

#include "host/core/types.h"
#include "host/cut/cut_surface.h"
#include "host/mesh/surface_mesh.h"

namespace cutwork {

/// One pair of loops closer than the minimum.
struct LigamentViolation {
  std::string kind;       ///< "stencils" (hole to hole) or "boundary" (hole to border)
  double width = 0;       ///< the distance between the loops (m)
  Vec3 point_a, point_b;  ///< the closest points, on the first and the second loop (m)
  int loop_a = -1, loop_b = -1;
};

struct MinFeatureReport {
  double minimum = 0;  ///< the printable minimum checked against (m)
  int holes = 0;       ///< boundary loops that are holes
  int borders = 0;     ///< boundary loops that are the border
  /// Narrowest ligaments (m); +inf when there is no such pair (fewer than two holes, no border).
  double narrowest_between_stencils = std::numeric_limits<double>::infinity();
  double narrowest_to_boundary = std::numeric_limits<double>::infinity();
  std::vector<LigamentViolation> violations;  ///< every loop pair closer than `minimum`, narrowest first
};

/// Checks the cut surface `cut` of `base` against `minimum` (m, ≥ 0). The vertices of `cut`
/// that come from base vertices (CutSurface::source_vertex) tell which loops are the border.
MinFeatureReport check_min_feature(const CutSurface& cut, const SurfaceMesh& base, double minimum);

/// Distance between segments [p0, p1] and [q0, q1], with the closest points (exact for
/// degenerate segments too).
double segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, Vec3* on_p, Vec3* on_q);

}  // namespace cutwork
