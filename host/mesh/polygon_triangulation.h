#pragma once
/// Triangulation of one simple polygon in space (an OBJ face with more than three corners), for
/// the mesh readers when their own library's triangulation is wrong (concave polygons).
#include <array>
#include <span>
#include <vector>

#include "host/core/types.h"

namespace cutwork {

/// The polygon with corners `corners` (in order, 3D, roughly planar) split into corners.size() − 2
/// triangles of its own corners (local indices into `corners`), each oriented like the polygon.
/// Convex and concave simple polygons alike (CGAL's constrained Delaunay triangulation in the
/// polygon's plane). Empty when the outline is not a simple polygon in its (Newell) plane, within
/// 1e-9 of its size — fewer than 3 corners, a repeated corner or two at one position, edges that
/// cross or touch, a spike — since CGAL's inexact triangulation misbehaves on those.
std::vector<std::array<int, 3>> triangulate_polygon(std::span<const Vec3> corners);

}  // namespace cutwork
