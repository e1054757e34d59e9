#pragma once
/// The orientation field of §4.1/§4.4: a smooth N-RoSy tangent direction field on a surface
/// mesh, optionally aligned softly to sketch strokes.
///
/// Representation (Bommes, Zimmer, Kobbelt 2009 / libigl nrosy, in complex form): per face f a
/// complex number u_f in the face's local basis (e1 = first edge, e2 = n × e1) standing for
/// the N directions at angles arg(u_f)/N + 2πk/N. The field minimises
///   E(u) = Σ_interior edges (f,g) |u_g − r_fg u_f|²  +  Σ_stroke faces λ |u_f − c_f|²
/// where r_fg = exp(i N (θ_g − θ_f)) transports across the edge (θ_f, θ_g: the shared edge's
/// angle in each face's basis — parallel transport by unfolding the hinge), c_f is the stroke
/// direction's N-th power in face f's basis and λ = stroke_weight. The energy is a Hermitian
/// quadratic form; in real 2×2 blocks it is one sparse SPD system solved by CHOLMOD's supernodal
/// Cholesky (solvers/linear/cholmod_solver.h, the solvers' own, under the process's thread
/// policy). A connected component that no stroke touches gets one hard constraint (its
/// face nearest to the component's centroid is aligned with the mesh's longest bounding-box
/// axis), which makes the system definite and, on a flat plate, the field constant along
/// that axis.
///
/// Evaluation at a surface point: each vertex carries a representative direction (the
/// area-weighted N-th-power average of its faces, in the vertex tangent plane); inside a face
/// the three corner directions, each turned by a multiple of 2π/N to agree with the face's
/// direction, are blended barycentrically and projected into the Phong tangent plane. The
/// result is continuous across edges (up to the N-fold ambiguity, which N-fold symmetric
/// stencils do not see) and differentiable inside faces.
#include <vector>

#include <Eigen/Core>

#include "host/mesh/bvh.h"
#include "host/scene/scene.h"
#include "host/stencil/frame.h"

namespace cutwork {

struct OrientationFieldOptions {
  int symmetry = 1;                    ///< N ≥ 1
  std::vector<SketchStroke> strokes;   ///< polylines on or near the surface
  double stroke_weight = 10.0;         ///< λ, soft alignment weight (per constrained face)
  /// Faces within this distance (m) of a stroke are constrained; 0: the mean edge length.
  double stroke_band = 0.0;
  /// The symmetry planes the mesh is the half (quarter) of (LoadCase::symmetry_planes: x = .x(), …;
  /// NaN where none): the anchor's axis is the whole's longest (the half of a square plate keeps the
  /// whole's orientation), and across each boundary edge on a plane the smoothness sees the face's
  /// mirror image (the reflected field), so that the half's field is the symmetric whole's.
  Vec3 mirror_planes = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
};

/// The orientation field; as a TangentField it gives stencil frames their tangent t (paper
/// §4.1: "t_i is obtained by rotating a vector from an underlying orientation field").
class OrientationField final : public TangentField {
 public:
  OrientationField() = default;
  /// Solves the field on `mesh` (must outlive the field). `bvh` locates strokes on the surface.
  /// Throws InputError when a stroke point lies farther than 10% of the mesh's bounding-box
  /// diagonal from the surface, or when symmetry < 1.
  OrientationField(const SurfaceMesh& mesh, const FaceBvh& bvh,
                   const OrientationFieldOptions& options);

  int symmetry() const { return m_symmetry; }
  const SurfaceMesh& mesh() const { return *m_mesh; }

  /// #F×3: one unit representative direction per face (in the face plane).
  const RowMatX3d& face_directions() const { return m_face_dirs; }
  /// #F: the field's angle in each face's local basis (e1 = normalised edge v0→v1).
  const Eigen::VectorXd& face_angles() const { return m_face_angles; }
  /// #V×3: one unit representative direction per vertex (in the vertex tangent plane).
  const RowMatX3d& vertex_directions() const { return m_vertex_dirs; }
  /// Faces carrying a stroke constraint, ascending.
  const std::vector<int>& stroke_faces() const { return m_stroke_faces; }

  /// Unit direction at surface point p, tangent to the Phong normal there.
  /// `d_point` (nullable) receives ∂t/∂x (3×3), x the point moving within p's face (the
  /// in-plane barycentric map; motion along the face normal does not change p).
  Vec3 direction(const SurfacePoint& p, Eigen::Matrix3d* d_point = nullptr) const;

  /// The face's local basis (e1, e2), unit, e2 = n × e1.
  void face_basis(int face, Vec3& e1, Vec3& e2) const;

  /// TangentField: direction(where) and ∂t/∂q = (∂t/∂x) · d_point. The Phong normal is
  /// recomputed from `where` exactly as phong_normal_and_jacobian does, so `normal` and
  /// `d_normal` are not needed. `mesh` must be the mesh the field was solved on.
  Vec3 tangent(const SurfaceMesh& mesh, const SurfacePoint& where, const Vec3& point,
               const Vec3& normal, const Mat3& d_point, const Mat3& d_normal,
               Mat3* d_tangent) const override;

 private:
  const SurfaceMesh* m_mesh = nullptr;
  int m_symmetry = 1;
  RowMatX3d m_face_dirs;
  Eigen::VectorXd m_face_angles;
  RowMatX3d m_vertex_dirs;
  /// Per face, per corner: the corner's vertex direction turned to agree with the face (#F×9).
  Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor> m_corner_dirs;
  std::vector<int> m_stroke_faces;
};

/// Rotational symmetry order of a polygon about the origin: the largest k (a divisor of the
/// vertex count) such that rotating by 2π/k maps the vertex set onto itself (tolerance 1e-6 of
/// the polygon's radius). 1 for an asymmetric polygon; a regular n-gon gives n.
int polygon_symmetry_order(const std::vector<Vec2>& polygon);

/// The field symmetry N for a design: the stencil orientation is only defined modulo 2π/N, so N
/// must divide every shape's symmetry order, and for an exemplar with a rotational symmetry
/// (stripes: 2) N must divide that too, or the pattern could turn against the field.
/// N = gcd of the shapes' orders and the exemplar's symmetry, where a shape of order >
/// `isotropic_order` (a circle) and an exemplar symmetry of 0 (irregular) constrain nothing;
/// then the largest divisor ≤ 6 (more gives no visible benefit). When nothing constrains it
/// (only circles, irregular exemplar) N = 4: sketch strokes then act as unsigned lines.
int field_symmetry_for(const std::vector<int>& shape_orders, int exemplar_symmetry,
                       int isotropic_order = 12);

}  // namespace cutwork
