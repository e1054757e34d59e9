#pragma once
/// The explicit map between a base mesh (what is cut and exported) and the coarser simulation
/// mesh: every base vertex and face is located on the simulation mesh by closest point.
#include <vector>

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

/// Transfers a per-face field from simulation faces to base faces.
Eigen::VectorXd sim_to_base_faces(const MeshMapping& map, const Eigen::VectorXd& sim_field);

}  // namespace cutwork
