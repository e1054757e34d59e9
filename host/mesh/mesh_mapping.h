#pragma once
/// The explicit map between a base mesh (what is cut and exported) and the coarser simulation
/// mesh: every base vertex and face is located on the simulation mesh by closest point.
#include <vector>

#include "host/mesh/bvh.h"
#include "host/mesh/surface_mesh.h"

namespace cutwork {

struct MeshMapping {
  /// #V_base: location of each base vertex on the simulation mesh.
  std::vector<SurfacePoint> vertex_on_sim;
  /// #F_base: the simulation face containing (closest to) each base face's centroid.
  std::vector<int> face_to_sim_face;
  /// Largest distance between a base vertex and its image (m); a sanity measure.
  double max_distance = 0;
};

/// Maps `base` onto `sim`. When the two are the same mesh the map is the identity.
MeshMapping map_meshes(const SurfaceMesh& base, const SurfaceMesh& sim);

/// #V of `mesh`: true for the boundary vertices of `mesh` that lie within `tolerance` (m) of a
/// boundary edge of `reference` — for a mesh cut from `reference` (stencils cut out, remeshed),
/// the vertices on the uncut surface's boundary as opposed to the rims of the holes.
std::vector<bool> boundary_vertices_on_boundary_of(const SurfaceMesh& mesh, const SurfaceMesh& reference,
                                                   double tolerance);

/// A per-vertex field (#V_from×3) of the mesh `from` indexes, at `points` (#P×3, m): each
/// point's closest point on that mesh, the field interpolated linearly over the face it lies in.
/// What carries one mesh's solution to another mesh of the same surface (a conforming level's
/// displacements to the next level, the peak zoom's submodel). Pre: `from` has faces.
RowMatX3d interpolate_vertex_field(const FaceBvh& from, const RowMatX3d& field, const RowMatX3d& points);

/// Transfers a per-face field from simulation faces to base faces.
Eigen::VectorXd sim_to_base_faces(const MeshMapping& map, const Eigen::VectorXd& sim_field);

}  // namespace cutwork
