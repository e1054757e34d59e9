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
#include <algorithm>
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

/// A ligament between two stencil holes: the narrowest material between two hole loops of a cut
/// surface, and the radius of curvature of each rim there (for the ligament peak estimate of
/// solvers/objective/ligament_peak.h). The radius is the least-squares circle through the rim's
/// vertices within 4 widths of the closest point (more, doubling, until six take part), in the
/// plane of the face there; +inf where the rim is straight or turns away from the ligament
/// (concave): the neck then does not narrow on that side.
struct Ligament {
  double width = 0;       ///< m
  Vec3 point_a = Vec3::Zero(), point_b = Vec3::Zero();  ///< the closest points on the two rims (m)
  double radius_a = std::numeric_limits<double>::infinity();  ///< m, rim a about point_a
  double radius_b = std::numeric_limits<double>::infinity();  ///< m, rim b about point_b
  double size_a = 0, size_b = 0;  ///< m: each hole's size, half the largest extent of its box
  int loop_a = -1, loop_b = -1;
  Vec3 midpoint() const { return 0.5 * (point_a + point_b); }
  /// The rims' radii as the estimate takes them: each capped at its hole's size (a rim that is
  /// straight or concave there would make it infinite).
  double capped_radius_a() const { return std::min(radius_a, size_a); }
  double capped_radius_b() const { return std::min(radius_b, size_b); }
  /// R_h: the neck's width about its narrowest point grows as w + s²/R_h with the distance s along
  /// it, 1/R_h = (1/ρ_a + 1/ρ_b)/2 (the harmonic mean of the capped radii; R for two holes of
  /// radius R).
  double neck_radius() const;
  /// S = (ρ_a² + ρ_b²)/(ρ_a + ρ_b), the pair's size (the contraharmonic mean of the capped radii; R
  /// for two holes of radius R): how much load the two holes turn aside towards the neck.
  double pair_radius() const;
};

/// Every ligament between two hole loops of `cut` (the border's loops left out) narrower than
/// `relative_width` × the smaller hole's size (half the largest extent of its bounding box: a
/// circle's radius), narrowest first. Loops as in check_min_feature. On symmetry planes
/// (`mirror_planes` as in check_min_feature) a hole's ligament to its own mirror image counts as
/// one (loop_a = loop_b; point_b the image of point_a, the hole's nearest vertex to the plane; both
/// rims' radii the one there).
std::vector<Ligament> find_ligaments(const CutSurface& cut, const SurfaceMesh& base, double relative_width,
                                     const Vec3& mirror_planes = Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));

/// Checks the cut surface `cut` of `base` against `minimum` (m, ≥ 0). The vertices of `cut`
/// that come from base vertices (CutSurface::source_vertex) tell which loops are the border.
/// `mirror_planes` (LoadCase::symmetry_planes: x = .x(), …; NaN where none): `base` is the half
/// (quarter) of a whole on those planes. The border's edges on a plane are then no border (the
/// material goes on across it), and each hole has a ligament to its own mirror image, twice its
/// distance to the plane ("stencils", the second point the image of the first). A hole and
/// another's image are never nearer than the two holes, so no other pair is added.
MinFeatureReport check_min_feature(const CutSurface& cut, const SurfaceMesh& base, double minimum,
                                   const Vec3& mirror_planes = Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));

/// Distance between segments [p0, p1] and [q0, q1], with the closest points (exact for
/// degenerate segments too).
double segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, Vec3* on_p, Vec3* on_q);

}  // namespace cutwork
