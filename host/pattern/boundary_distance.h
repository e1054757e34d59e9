#pragma once
/// Distance from a point to the open boundary of a surface (the boundary-collision term (2)
/// and the initialisations): the boundary loops are precomputed as polylines of segments,
/// bucketed in a uniform grid so that a query within a radius touches only nearby segments.
/// A brute-force twin scans every segment.
///
/// Signed distance: a query point may leave the surface during a line search (the optimiser's
/// variables are unprojected positions), and must then be pushed back rather than stuck with a
/// zero distance. The nearest boundary point b carries the inward direction m (the surface
/// lies on the left of each loop seen from the normal side, so m = n_face × edge direction);
/// the signed distance is +|p − b| when (p − b)·m ≥ 0 and −|p − b| otherwise. On the surface
/// it equals the ordinary distance.
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "host/mesh/surface_mesh.h"
#include "host/pattern/pattern_mirror.h"

namespace cutwork {

/// Nearest point on the boundary polylines.
struct BoundaryPoint {
  int segment = -1;             ///< index into BoundaryPolylines::segments()
  Vec3 point = Vec3::Zero();    ///< closest point b (m)
  Vec3 inward = Vec3::Zero();   ///< unit inward direction m at b (tangent to the surface)
  double distance = 0;          ///< |p − b| (m)
  double signed_distance = 0;   ///< ±distance, negative outside the surface
  /// ∂signed_distance/∂p (unit vector, or zero when p = b).
  Vec3 gradient = Vec3::Zero();
};

class BoundaryPolylines {
 public:
  struct Segment {
    Vec3 a, b;       ///< end points, in loop order (m)
    Vec3 inward;     ///< unit inward direction of the segment (n_face × (b − a), normalised)
    int loop = -1;
    int prev = -1;   ///< the previous and next segment of the same loop
    int next = -1;
  };

  BoundaryPolylines() = default;
  /// Collects the boundary loops of `mesh`; `cell_size` (m, > 0) sets the bucket size, best
  /// about the largest query radius. Segments with both ends on a symmetry plane of `mirror`
  /// (nullable; within 1e-6 of the mesh's bounding-box diagonal) are left out: the plane is no edge
  /// of the whole the mesh is a part of (pattern_mirror.h). A segment whose neighbour in the loop
  /// was left out takes its own inward direction at that end.
  BoundaryPolylines(const SurfaceMesh& mesh, double cell_size, const PatternMirror* mirror = nullptr);

  const std::vector<Segment>& segments() const { return m_segments; }
  bool empty() const { return m_segments.empty(); }

  /// Nearest boundary point to `p` if it is within `max_distance` (m); nullopt otherwise or
  /// when the surface is closed. Ties go to the lowest segment index.
  std::optional<BoundaryPoint> nearest(const Vec3& p, double max_distance) const;

  /// Brute-force twin (every segment, no radius limit unless finite).
  std::optional<BoundaryPoint> nearest_brute_force(const Vec3& p, double max_distance) const;

 private:
  static uint64_t key(int64_t x, int64_t y, int64_t z);
  BoundaryPoint evaluate(int segment, const Vec3& p) const;

  std::vector<Segment> m_segments;
  double m_cell = 1;
  std::unordered_map<uint64_t, std::vector<int>> m_buckets;
};

}  // namespace cutwork
