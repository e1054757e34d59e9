#pragma once
/// Constant-strain-triangle (CST) membrane with a St. Venant–Kirchhoff plane-stress material (§5.1),
/// scaled by the triangle's fill ratio α as in (9).
///
/// Energy of one triangle:  W = α A Ψ(E),   Ψ = μ tr(E²) + (λ/2) tr(E)²,   E = ½(FᵀF − I),
/// with F = Ds Dm⁻¹ (3×2) the deformation gradient, Ds = [x1−x0, x2−x0] the deformed edge matrix and
/// Dm the rest edge matrix in an orthonormal 2D frame of the rest triangle, A the rest area.
///
/// Why this form and not (7): the paper prints Ψ = (μ/2) tr(EᵗE) + λ tr(E)². With the μ and λ of
/// ShellStiffness (thickness-integrated plane-stress Lamé parameters), only the standard form
/// μ tr(E²) + (λ/2) tr(E)² reproduces linear plane-stress elasticity: a uniaxial stress state then has
/// lateral strain −ν ε and energy ½ E h ε² per area (the patch test checks it). (7)'s factors would
/// halve the μ term and double the λ term, i.e. silently change the effective E and ν.
///
/// DOF order of every vector/matrix here: x = (x0, y0, z0, x1, y1, z1, x2, y2, z2) — the triangle's
/// vertices in face order, metres. Energies in J, gradients in N (J/m), Hessians in N/m.
#include <Eigen/Core>

#include "host/core/types.h"

namespace cutwork::solvers {

using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;

/// Rest-state data of one triangle.
struct MembraneRest {
  Eigen::Matrix2d dm_inverse = Eigen::Matrix2d::Identity();  ///< Dm⁻¹ (1/m)
  double area = 0;                                           ///< rest area A (m²)
};

/// Rest data of the triangle (X0, X1, X2) (m). The 2D frame has its first axis along X1 − X0.
/// Precondition: a non-degenerate triangle (SurfaceMesh guarantees it).
MembraneRest membrane_rest(const Vec3& X0, const Vec3& X1, const Vec3& X2);

/// Deformation gradient F = Ds Dm⁻¹ (3×2, dimensionless) of the deformed triangle x.
Eigen::Matrix<double, 3, 2> membrane_deformation_gradient(const Vec9& x, const MembraneRest& rest);

/// Ψ(F) (J/m², per rest area) for thickness-integrated Lamé parameters mu, lambda (N/m).
double membrane_energy_density(const Eigen::Matrix<double, 3, 2>& F, double mu, double lambda);

/// W = α A Ψ (J).
double membrane_energy(const Vec9& x, const MembraneRest& rest, double mu, double lambda, double alpha);
/// ∂W/∂x (9, N).
Vec9 membrane_gradient(const Vec9& x, const MembraneRest& rest, double mu, double lambda, double alpha);
/// ∂²W/∂x² (9×9, N/m); symmetric, indefinite under compression (not projected).
Mat9 membrane_hessian(const Vec9& x, const MembraneRest& rest, double mu, double lambda, double alpha);

/// Energy, gradient and (when hessian != nullptr) Hessian in one pass, for assembly.
/// The fill-ratio partials follow from linearity in α: ∂W/∂α = W/α, ∂(∂W/∂x)/∂α = (∂W/∂x)/α.
void membrane_energy_gradient_hessian(const Vec9& x, const MembraneRest& rest, double mu,
                                      double lambda, double alpha, double* energy, Vec9* gradient,
                                      Mat9* hessian);

/// The same with a general constitutive matrix: Ψ = ½ εᵀ C ε, ε = (E₁₁, E₂₂, 2E₁₂) in the rest
/// frame of membrane_rest (first axis along X1 − X0), C symmetric (N/m), energy times `scale` A.
/// What an anisotropic (square-lattice) part needs (fill_stiffness_map.h); for C =
/// membrane_constitutive(μ, λ) it is the Lamé form above. Hessian blocks:
///     H_ab = scale A [ (β_aᵀ S β_b) I + F G_aᵀ C G_b Fᵀ ],   G_b = [β_b1 0; 0 β_b2; β_b2 β_b1],
/// with S the 2×2 stress of σ = C ε and β_a the shape rows (∂F/∂x_a,c = e_c β_aᵀ).
void membrane_energy_gradient_hessian(const Vec9& x, const MembraneRest& rest, const Eigen::Matrix3d& C,
                                      double scale, double* energy, Vec9* gradient, Mat9* hessian);

/// The Voigt matrix of Ψ = μ tr(E²) + (λ/2) tr(E)²: [2μ+λ λ 0; λ 2μ+λ 0; 0 0 μ] (N/m).
Eigen::Matrix3d membrane_constitutive(double mu, double lambda);

}  // namespace cutwork::solvers
