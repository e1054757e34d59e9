#pragma once
/// Kirchhoff bending of a triangle from a discrete shape operator over its edge-neighbour patch — the
/// default bending element (`"mechanics": {"bending": "shape_operator"}`).
///
/// The patch of face f is f's three vertices and the three vertices opposite them across f's edges
/// (the rotation-free "basic shell triangle" patch of Oñate & Zárate 2000). At rest the patch is
/// laid out in f's tangent plane — f's own vertices in an orthonormal frame of f, each neighbour
/// triangle unfolded about the shared edge (edge lengths and the neighbour's shape kept) — and the
/// quadratic interpolant through the six nodes gives constant second derivatives
///     x_,αβ = Σ_a Q_αβ,a x_a            (α, β ∈ {1, 2}: f's rest frame; a = 0…5: patch nodes),
/// a fixed linear map of the node positions. The second fundamental form is b_αβ = n · x_,αβ with n
/// the unit normal of the deformed face f, and the bending strain is its change from rest,
/// k = b − b̄ (1/m). In Voigt order k = (k11, k22, k12) the energy is Kirchhoff's (Koiter's bending
/// term with f's rest metric, which is the identity in f's rest frame):
///     W = s · D · A/2 · [ν (k11 + k22)² + (1−ν)(k11² + k22² + 2 k12²)] = s · D · A/2 · kᵀ Ĉ k,
///     Ĉ = [[1, ν, 0], [ν, 1, 0], [0, 0, 2(1−ν)]],   D = E h³/(12(1−ν²)),  A = rest area of f,
/// with the material's ν, and s the fill-ratio factor (α_f, or the homogenised bending factor).
/// The quadratic patch reproduces every quadratic surface exactly on any non-degenerate patch, so
/// the element is isotropic and consistent on irregular meshes (unlike the hinge model, whose
/// coupling is that of ν = −1/3 whatever the material and which is 3× too stiff about the diagonal
/// of a right-triangle grid).
///
/// Boundaries. Across a free (or simply supported) edge there is no neighbour; the patch then
/// leaves one quadratic mode undetermined (two or three at corners). Those modes are condensed out
/// by minimising the element's energy over them — the discrete form of the natural boundary
/// condition M_nn = 0 of a free edge: k ← P k with P = I − H (Hᵀ Ĉ H)⁻¹ Hᵀ Ĉ, H the Voigt curvatures
/// of the undetermined modes. Since P is linear it folds into Q at rest (the element stays a fixed
/// linear map, now depending on ν). A nearly degenerate patch (six nodes close to one conic) is
/// treated the same way: modes with a singular value below kShapeOperatorModeCutoff = 1e-3 of the
/// largest (of the Vandermonde matrix over the nodes in f's rest frame, centred at f's centroid and
/// scaled by √A) are condensed. Such a mode is one the nodes do not determine: on a hole rim four
/// patch nodes lie nearly on one line (f's rim edge and the rim vertices of both neighbours), and
/// the across-rim curvature would be read off the rim's in-plane wiggle, its weights amplified by
/// 1/σ and the element's stiffness by 1/σ². Measured on the chair's default design cut and remeshed
/// at 0.0109 m (tests/solvers/conforming/conforming_verification_test.cpp): one rim patch at
/// σ = 3e-7 σ_max had max|Q|·A = 4.5e5 (typical: 0.1–10) and put 3.4e19 N/m on a diagonal of the
/// stiffness (typical: 1e8), which then factorised as singular; 1.1% of the mesh's patches lie
/// below 1e-3 (none of any built-in scene's base or simulation mesh), and condensing them changes
/// the conforming compliance by 0.15% at that edge length and by < 2e-5 at half and a quarter of it.
/// Across a clamped edge the missing neighbour is a ghost point that continues the surface evenly
/// across the edge, as a clamp (w_n = 0 along the edge) demands: the current position of f's opposite
/// vertex x_i reflected in the plane through the (fixed) edge normal to the edge's rest conormal m̄,
///     g = R x_i + (I − R) X_a,   R = I − 2 m̄ m̄ᵀ   (X_a: a rest edge vertex).
/// A smooth clamped deflection w = ½κn² is then seen with its full curvature κ, and a face rotated
/// rigidly about the clamped edge bends the patch into a V, which the clamp resists. The ghost is a
/// linear function of x_i, so its derivatives fold into node i's.
///
/// DOF order: x = (x0, x1, x2, x3, x4, x5), each (x, y, z), metres: x0…x2 the vertices of f in face
/// order; x(3+i) the vertex opposite vertex i across f's edge (x(i+1), x(i+2)); across a clamped or
/// free edge slot 3+i is not a DOF (its entries are ignored, its gradient and Hessian rows are zero).
/// Energies in J, gradients in N, Hessians in N/m.
#include <array>

#include <Eigen/Core>

#include "host/core/types.h"

namespace cutwork::solvers {

using Vec18 = Eigen::Matrix<double, 18, 1>;
using Mat18 = Eigen::Matrix<double, 18, 18>;
using Mat3x6 = Eigen::Matrix<double, 3, 6>;

/// Relative singular value below which a quadratic mode of the patch counts as undetermined and is
/// condensed (see the header comment).
inline constexpr double kShapeOperatorModeCutoff = 1e-3;

/// What lies across edge i of a face (the edge opposite vertex i).
enum class PatchNode {
  Vertex,  ///< the neighbour face's opposite vertex
  Ghost,   ///< a clamped edge (or one on a symmetry plane): a ghost point mirroring the opposite vertex
  Free,    ///< a free or simply supported edge: the mode is condensed
};

/// Rest-state data of one face's bending element.
struct ShapeOperatorRest {
  /// What lies across each edge.
  std::array<PatchNode, 3> across = {PatchNode::Free, PatchNode::Free, PatchNode::Free};
  /// Per clamped edge i: the rest conormal m̄ (unit, in f's rest plane, perpendicular to the edge)
  /// and a rest point X_a of the edge, defining the ghost g = R x_i + (I − R) X_a, R = I − 2 m̄ m̄ᵀ.
  std::array<Vec3, 3> ghost_conormal = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  std::array<Vec3, 3> ghost_anchor = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  /// Q (1/m²): rows k11, k22, k12 — the curvature of the patch is b_r = n · Σ_a Q(r, a) x_a.
  /// Columns of unused nodes are zero.
  Mat3x6 weights = Mat3x6::Zero();
  /// b̄ (1/m): the rest second fundamental form in f's rest frame (zero for a flat rest patch).
  Vec3 rest_curvature = Vec3::Zero();
  /// A (m²): rest area of the face.
  double area = 0;
};

/// Builds the rest data from the rest positions of the six patch nodes (`X[3+i]` is ignored unless
/// `across[i]` is Vertex) and Poisson's ratio ν ∈ [0, 0.5). Throws SolveError for a degenerate face.
/// `mirror` (optional): per edge i whose ghost is a symmetry plane's rather than a clamp's, the
/// plane's unit normal (zero elsewhere). The ghost is then f's opposite vertex reflected in that
/// plane, through the edge's rest vertices (which must lie on it), g = R x_i + (I − R) X_a with
/// R = I − 2 n nᵀ: the mirror image of the surface beyond the plane, whatever angle f meets it at (a
/// clamp's ghost is the special case n = m̄, f meeting the plane square). The edge's vertices slide
/// in the plane (held along n) while the ghost follows x_i.
ShapeOperatorRest shape_operator_rest(const std::array<Vec3, 6>& X, const std::array<PatchNode, 3>& across,
                                      double poisson_ratio, const std::array<Vec3, 3>* mirror = nullptr);

/// The mirror image of `opposite` across the line (a, b) in the plane of (a, b, opposite): the ghost
/// point of a clamped edge (a, b) at rest (the hinge model's fixed clamp ghost).
Vec3 ghost_point(const Vec3& a, const Vec3& b, const Vec3& opposite);

/// Ĉ of the header comment (dimensionless).
Eigen::Matrix3d bending_constitutive(double poisson_ratio);

/// Bending strain k = b − b̄ (Voigt k11, k22, k12; 1/m) of the patch positions x.
Vec3 shape_operator_strain(const Vec18& x, const ShapeOperatorRest& rest);

/// W (J) for scale = s · D (N·m), with Ĉ = bending_constitutive(ν).
double shape_operator_energy(const Vec18& x, const ShapeOperatorRest& rest, const Eigen::Matrix3d& C, double scale);
/// Energy, gradient (18, N) and Hessian (18×18, N/m; exact, indefinite away from rest, not
/// projected) in one pass; null outputs are skipped. Closed form — no automatic differentiation.
void shape_operator_energy_gradient_hessian(const Vec18& x, const ShapeOperatorRest& rest,
                                            const Eigen::Matrix3d& C, double scale, double* energy,
                                            Vec18* gradient, Mat18* hessian);

}  // namespace cutwork::solvers
