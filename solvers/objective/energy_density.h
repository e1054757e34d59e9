#pragma once
/// Per-triangle energy density W_i of (16), the failure indicator of the energy-density objective:
///
///     W_i = Ŵ_i^memb / Â_i  +  Σ_j  Â_i / (3 Â_ij²) · Ŵ_ij^bend,     Â_i = α_i A_i,  Â_ij = (Â_i + Â_j)/3,
///
/// the sum running over the hinges j of triangle i. Read term by term:
///   - membrane: Ŵ_i^memb / Â_i = α_i A_i Ψ_i / (α_i A_i) = Ψ_i, the energy per area of the material
///     that is left — independent of α at a given strain, as a stress-like failure measure must be;
///   - bending: Â_i/(3Â_ij²) Ŵ_ij = [Â_i / (Â_i + Â_j)] · [Ŵ_ij / Â_ij]: the hinge's energy per
///     (remaining) hinge area, weighted by triangle i's share of the hinge. On a uniform mesh the
///     shares are ½, so the bending part is half the sum of the three hinges' densities; Σ_i Â_i W_i
///     is therefore not the total energy (bending is counted 3/2 times) — (16) is used as printed
///     because the objectives (17) and (18) are defined on it.
/// A clamp hinge (shell_model.h) belongs to its face alone: Â_ij = Â_i/3, share 1, contributing
/// Ŵ_clamp / Â_ij = 3 W_clamp / A_i.
///
/// Units: J/m². x: #V×3 positions (m); alpha: #F fill ratios.
#include <Eigen/Core>

#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

/// W (#F, J/m²).
Eigen::VectorXd energy_density(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha);

/// For weights c (#F): Σ_i c_i ∂W_i/∂x into d_positions (#V×3, 1/m·J/m²; rows of fixed vertices
/// zero — they cannot move) and Σ_i c_i ∂W_i/∂α into d_alpha (#F). Either output may be null.
/// This is all an objective built on W needs, e.g. S_stab (17) with c_i = (W_i − β)₊ / m.
void energy_density_vjp(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                        const Eigen::VectorXd& weights, RowMatX3d* d_positions, Eigen::VectorXd* d_alpha);

}  // namespace cutwork::solvers
