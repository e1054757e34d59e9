#pragma once
/// Discrete-shell hinge bending (8) [GHDS03, GGWZ07], scaled by fill ratios as in (10).
///
/// A hinge is a pair of edge-adjacent triangles; its energy is
///     W = s · k · (θ − θ̄)²,     k = (D/6) |ē|² / Ā,     Ā = (A_i + A_j)/3,
/// with θ, θ̄ the deformed and rest dihedral angles, |ē| the rest edge length, A_i, A_j the rest areas
/// of the two triangles, D = E h³/(12(1−ν²)) and s the fill-ratio factor √(α_i α_j) of (10).
/// (8)'s A_ij/h_ij "geometry factor" is this |ē|²/Ā: with h̄ = (h_i + h_j)/6 a third of the mean
/// height, |ē|/h̄ = 3|ē|²/(A_i + A_j) = |ē|²/Ā.
///
/// Calibration of D/6 (checked against plate theory in tests/solvers/equilibrium): bend a flat,
/// regular mesh isometrically onto a cylinder of curvature κ. Then Σ_hinges θ² |ē|²/Ā = 3 κ² · area
/// (exactly, up to the boundary, for a right-triangle grid bent about either grid axis; within 1% in
/// every direction for a near-equilateral mesh), while Kirchhoff's cylindrical-bending energy is
/// D/2 · κ² · area; hence k = D/6 · |ē|²/Ā. Limits a user should know: the hinge model is isotropic
/// only on near-equilateral meshes (a right-triangle grid bent about its diagonal is 3× too stiff),
/// and its coupling of the two curvatures is that of ν = −1/3 whatever the material's ν: on the
/// near-equilateral lattice the hinge sum gives ½Dκ² for a cylinder (as calibrated), ⅔Dκ² for a
/// sphere and (4/3)Dτ² for a twist, where Kirchhoff gives (1+ν)Dκ² and (1−ν)Dτ²
/// (tests/solvers/shell/shape_operator_test.cpp measures it). It matters wherever the
/// Gaussian-curvature term does not integrate to zero — free edges and holes: a free strip bends
/// anticlastically the wrong way — and vanishes for clamped plates without holes. This is why the
/// default bending element is the shape operator (shape_operator_energy.h); hinges stay available
/// (`"mechanics": {"bending": "hinge"}`) to reproduce the paper. The membrane uses the material's ν.
///
/// Clamped supports use one-sided "clamp hinges" (see shell_model.h): the same energy with the
/// fourth vertex a fixed ghost point in the rest tangent plane and Ā = A_f/3.
///
/// DOF order: x = (x0, x1, x2, x3), each (x, y, z), metres, following cutwork::Hinge::v:
///   x0, x1  the shared edge, oriented as in face 0 = (x0, x1, x2);
///   x2      the vertex of face 0 opposite the edge;
///   x3      the vertex of face 1 = (x1, x0, x3) opposite the edge.
/// Angles in radians, energies in J, gradients in N, Hessians in N/m.
///
/// Sign of θ: θ = atan2(((n0 × n1)·e)/|e|, n0·n1) with n0 = (x1−x0)×(x2−x0), n1 = (x0−x1)×(x3−x1),
/// e = x1 − x0; θ = 0 for a flat hinge and θ > 0 where the surface is convex as seen from its
/// normals (the wings fold away from the normal side), θ ∈ (−π, π].
#include <Eigen/Core>

#include "host/core/types.h"

namespace cutwork::solvers {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;

/// Rest-state data of one hinge.
struct HingeRest {
  double rest_angle = 0;  ///< θ̄ (rad)
  double stiffness = 0;   ///< k = (D/6)|ē|²/Ā (J/rad²)
};

/// Stiffness coefficient k = (D/6) |ē|²/Ā for bending stiffness D (N·m), rest edge length (m) and
/// hinge area Ā (m²: (A_i + A_j)/3 for a hinge, A_f/3 for a clamp hinge).
double hinge_stiffness(double bending_stiffness, double rest_edge_length, double hinge_area);

/// θ (rad) of the hinge x.
double dihedral_angle(const Vec12& x);
/// ∂θ/∂x (12, 1/m). Closed form: ∂θ/∂x2 = −|e| n0/|n0|², ∂θ/∂x3 = −|e| n1/|n1|², and the edge
/// vertices take −(1−t)·, −t· of those, t the projection parameter of the opposite vertex on e.
Vec12 dihedral_angle_gradient(const Vec12& x);
/// ∂²θ/∂x² (12×12, 1/m²): the exact Jacobian of the closed-form gradient (forward-mode dual
/// numbers through the gradient formula; no finite differences).
Mat12 dihedral_angle_hessian(const Vec12& x);

/// W = s k (θ − θ̄)² (J) for the fill-ratio factor s (√(α_i α_j) for a hinge, α_f for a clamp).
double hinge_energy(const Vec12& x, const HingeRest& rest, double s);
/// ∂W/∂x (12, N).
Vec12 hinge_gradient(const Vec12& x, const HingeRest& rest, double s);
/// ∂²W/∂x² (12×12, N/m) = 2 s k (∇θ ∇θᵀ + (θ − θ̄) ∇²θ); indefinite when θ ≠ θ̄ (not projected).
Mat12 hinge_hessian(const Vec12& x, const HingeRest& rest, double s);
/// Energy, gradient and (when hessian != nullptr) Hessian in one pass, for assembly. The energy is
/// linear in s, so its fill-ratio partials are the s = 1 quantities times ∂s/∂α.
void hinge_energy_gradient_hessian(const Vec12& x, const HingeRest& rest, double s, double* energy,
                                   Vec12* gradient, Mat12* hessian);

}  // namespace cutwork::solvers
