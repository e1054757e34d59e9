#pragma once
/// Axis-aligned bounding-box hierarchy over the faces of a SurfaceMesh: closest-point queries
/// (stencil projection, mesh-to-mesh mapping) and ball queries (broad phase). Each query has a
/// brute-force twin used by the tests.
#include <vector>

#include <Eigen/Geometry>

#include "host/mesh/surface_mesh.h"

namespace cutwork {

struct ClosestPoint {
  SurfacePoint where;            ///< face and barycentric coordinates of the closest point
  Vec3 point = Vec3::Zero();     ///< its position
  double squared_distance = 0;   ///< |query − point|²
};

/// Closest point on triangle (a, b, c) to p, with barycentrics (exact, Ericson's regions).
ClosestPoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

class FaceBvh {
 public:
  FaceBvh() = default;
  /// Builds the hierarchy; the mesh must outlive the BVH (it is referenced, not copied).
  explicit FaceBvh(const SurfaceMesh& mesh);

  /// Closest point on the surface to `p`. Ties resolved towards the lower face index.
  ClosestPoint closest_point(const Vec3& p) const;
  /// Appends the faces whose closest point to `center` is within `radius` (exact test per face),
  /// sorted ascending. `out` is cleared first.
  void faces_in_ball(const Vec3& center, double radius, std::vector<int>& out) const;

  const SurfaceMesh* mesh() const { return m_mesh; }

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int left = -1, right = -1;     ///< children (internal nodes)
    int first = 0, count = 0;      ///< range in m_order (leaves: count > 0)
  };
  int build_node(int first, int count, std::vector<Vec3>& centroids, int depth);

  const SurfaceMesh* m_mesh = nullptr;
  std::vector<Node> m_nodes;
  std::vector<int> m_order;
};

/// Brute-force twins (all faces), for tests and tiny meshes.
ClosestPoint closest_point_brute_force(const SurfaceMesh& mesh, const Vec3& p);
void faces_in_ball_brute_force(const SurfaceMesh& mesh, const Vec3& center, double radius,
                               std::vector<int>& out);

}  // namespace cutwork
