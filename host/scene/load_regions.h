#pragma once
/// Exact integrals over the region a selector describes, so that loads do not depend on the mesh.
///
/// A selector's region R is the box of its axis bounds (x_k > above_k, x_k < below_k) intersected
/// with its ball |x − near.point| ≤ near.radius when it has one. A load per area f on a triangle T
/// gives its vertices the consistent nodal forces
///   F_i = f ∫_{T∩R} N_i dA = f · area(T∩R) · N_i(centroid of T∩R)        (N_i linear on T)
/// so only the area and the centroid of T∩R are needed: T is clipped by the box's half-spaces (a
/// convex polygon), and with a ball the polygon is intersected with the disc the ball cuts from
/// T's plane, exactly — straight pieces and circular arcs, summed edge by edge as signed
/// (origin, edge) triangles and sectors. A segment ∩ R is an interval, exact as well. Refining a
/// mesh of the same surface therefore leaves the integrated measure (and a load's total) unchanged
/// up to the geometric error of the mesh itself (none on flat parts).
#include <array>

#include "host/core/types.h"
#include "host/scene/scene.h"

namespace cutwork {

/// ∫_{X∩R} dA (or ds) and ∫_{X∩R} x dA: the measure of the part of X inside the region and its
/// first moment (measure × centroid).
struct RegionMoment {
  double measure = 0;
  Vec3 first_moment = Vec3::Zero();
};

/// Triangle (a, b, c) ∩ region of `sel` (the selector's entity and `nearest` are ignored here).
RegionMoment triangle_in_region(const Vec3& a, const Vec3& b, const Vec3& c, const Selector& sel);

/// Segment [a, b] ∩ region of `sel`.
RegionMoment segment_in_region(const Vec3& a, const Vec3& b, const Selector& sel);

/// The consistent nodal weights ∫_{T∩R} N_i dA of a triangle (a, b, c), from its region moment:
/// measure × the barycentric coordinates of the centroid. They sum to the measure.
Vec3 triangle_nodal_weights(const Vec3& a, const Vec3& b, const Vec3& c, const RegionMoment& m);

/// The same for a segment [a, b]: ∫_{S∩R} N_a ds, ∫_{S∩R} N_b ds.
std::array<double, 2> segment_nodal_weights(const Vec3& a, const Vec3& b, const RegionMoment& m);

}  // namespace cutwork
