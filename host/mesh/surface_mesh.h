#pragma once
/// Triangle surface mesh stored as arrays, with the connectivity every later stage needs
/// (edges, hinges, boundary loops) and per-element geometry (areas, normals).
///
/// Vocabulary (used across cutwork): `vertices` #V×3 rest positions (metres), `faces` #F×3
/// vertex indices, counter-clockwise when seen from the side the face normal points to.
#include <string>
#include <vector>

#include "host/core/types.h"

namespace cutwork {

/// A bending hinge: two faces sharing the edge (v[0], v[1]).
/// Vertex order (the DOF order of every hinge energy in cutwork):
///   v[0], v[1]  the shared edge, oriented as it appears in face[0] = (v[0], v[1], v[2]) (CCW);
///   v[2]        the vertex of face[0] opposite the edge;
///   v[3]        the vertex of face[1] opposite the edge (face[1] contains v[1] -> v[0]).
struct Hinge {
  int edge = -1;
  int face[2] = {-1, -1};
  int v[4] = {-1, -1, -1, -1};
};

/// A point on the surface: face index plus barycentric coordinates w.r.t. that face's vertices.
struct SurfacePoint {
  int face = -1;
  Vec3 bary = Vec3::Zero();
};

class SurfaceMesh {
 public:
  SurfaceMesh() = default;

  /// Builds a mesh from arrays and derives its connectivity and geometry.
  /// Input: vertices #V×3 (finite), faces #F×3 (indices in [0,#V)).
  /// Throws InputError("<what>: <problem>") where `what` names the source (file name or shape)
  /// for: no faces, non-finite coordinates, indices out of range, repeated-index or zero-area
  /// faces, duplicate faces (same vertex set), non-manifold edges (> 2 faces), inconsistent
  /// orientation of two faces sharing an edge (the same directed edge used twice).
  /// A face counts as zero-area when twice its area is ≤ 1e-12 × its longest edge² (collinear up
  /// to round-off; the test is scale-free, so millimetre and kilometre meshes are treated alike).
  /// Only the first problem found is reported, in the order listed above.
  /// Unreferenced vertices are kept (they carry no stiffness and are reported by `check`).
  SurfaceMesh(RowMatX3d vertices, RowMatX3i faces, const std::string& what = "mesh");

  int num_vertices() const { return int(m_vertices.rows()); }
  int num_faces() const { return int(m_faces.rows()); }
  int num_edges() const { return int(m_edges.rows()); }

  const RowMatX3d& vertices() const { return m_vertices; }
  const RowMatX3i& faces() const { return m_faces; }

  /// #E×2 unique undirected edges, stored with edges(e,0) < edges(e,1).
  const RowMatX2i& edges() const { return m_edges; }
  /// #F×3: face_edges(f,k) is the edge from faces(f,k) to faces(f,(k+1)%3).
  const RowMatX3i& face_edges() const { return m_face_edges; }
  /// #E×2 adjacent faces of each edge; column 1 is -1 on boundary edges.
  const RowMatX2i& edge_faces() const { return m_edge_faces; }
  /// One hinge per interior edge.
  const std::vector<Hinge>& hinges() const { return m_hinges; }
  /// Boundary loops as vertex cycles, each oriented like the faces it bounds (the surface on
  /// the left of the walking direction, seen from the normal side). Empty for closed meshes.
  const std::vector<std::vector<int>>& boundary_loops() const { return m_boundary_loops; }
  /// Per vertex: true where the vertex lies on a boundary loop.
  const std::vector<bool>& is_boundary_vertex() const { return m_is_boundary_vertex; }

  /// #F rest areas (m²), #F×3 unit face normals, #V×3 unit area-weighted vertex normals
  /// (zero rows for unreferenced vertices).
  const Eigen::VectorXd& face_areas() const { return m_face_areas; }
  const RowMatX3d& face_normals() const { return m_face_normals; }
  const RowMatX3d& vertex_normals() const { return m_vertex_normals; }

  /// Number of connected components of the faces (through shared edges; faces touching at a
  /// single vertex are separate components, unreferenced vertices are not counted).
  int num_components() const { return m_num_components; }
  /// V − E + F.
  int euler_characteristic() const { return num_vertices() - num_edges() + num_faces(); }
  /// Mean edge length (m).
  double mean_edge_length() const;
  Vec3 bbox_min() const;
  Vec3 bbox_max() const;

  /// Position of a surface point.
  Vec3 point(const SurfacePoint& p) const;
  /// Phong normal: the normalised barycentric interpolation of the vertex normals.
  Vec3 phong_normal(const SurfacePoint& p) const;

 private:
  void build(const std::string& what);

  RowMatX3d m_vertices;
  RowMatX3i m_faces;
  RowMatX2i m_edges;
  RowMatX3i m_face_edges;
  RowMatX2i m_edge_faces;
  std::vector<Hinge> m_hinges;
  std::vector<std::vector<int>> m_boundary_loops;
  std::vector<bool> m_is_boundary_vertex;
  Eigen::VectorXd m_face_areas;
  RowMatX3d m_face_normals;
  RowMatX3d m_vertex_normals;
  int m_num_components = 0;
};

/// #F: the connected component (through shared edges, as num_components counts them) of each
/// face, numbered 0, 1, … in order of their first face.
std::vector<int> face_components(const SurfaceMesh& mesh);

/// The 1 → 4 midpoint subdivision of `mesh`: the vertices (same indices) followed by one vertex at
/// the middle of each edge (index #V + e), and four faces per face (corner triangles, then the
/// middle one), oriented like their parent. The surface is the same set of flat facets, at half
/// the edge length.
SurfaceMesh midpoint_subdivision(const SurfaceMesh& mesh);

/// Triangle quality: the smallest interior angle (radians) over all faces.
double min_angle(const SurfaceMesh& mesh);
/// The fraction of faces (0 for an empty mesh) whose smallest interior angle is below `angle`
/// (radians): slivers and needles.
double fraction_of_faces_below_angle(const SurfaceMesh& mesh, double angle);
/// Largest ratio longest-edge / shortest-altitude-normalised aspect (1 for equilateral, ≥ 1).
double max_aspect_ratio(const SurfaceMesh& mesh);

}  // namespace cutwork
