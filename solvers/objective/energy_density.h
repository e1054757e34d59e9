#pragma once
/// Per-triangle energy density W_i of (16), the failure indicator of the energy-density objective:
/// the elastic energy per area of the material that is left, Â_i = α_i A_i.
///
/// Shape-operator bending (default): face i owns its membrane and its bending element, both scaled
/// by α_i, so W_i = (α_i U_i^memb + α_i U_i^bend)/Â_i = (U_i^memb + U_i^bend)/A_i: the energy per
/// area at the local strain and curvature — independent of α at a given state, as a stress-like
/// failure measure must be — and Σ_i Â_i W_i is the total elastic energy.
///
/// Homogenised fill stiffness (mechanics.stiffness, fill_stiffness_map.h): the elements are scaled by
/// g(α_i) = α_i r(α_i) instead of α_i, and W_i = (g_m U_i^memb + g_b U_i^bend)/Â_i
/// = (r_m U_i^memb + r_b U_i^bend)/A_i stays the energy per area of the material left — the mean
/// energy density of the perforated sheet, which now depends on α through r (its α-derivative is
/// in energy_density_vjp).
///
/// Hinge bending (the paper's model): (16) as printed,
///     W_i = Ŵ_i^memb / Â_i  +  Σ_j  Â_i / (3 Â_ij²) · Ŵ_ij^bend,     Â_ij = (Â_i + Â_j)/3,
/// the sum running over the hinges j of triangle i: the hinge's energy per (remaining) hinge area,
/// weighted by triangle i's share of the hinge. On a uniform mesh the shares are ½, so the bending
/// part is half the sum of the three hinges' densities and Σ_i Â_i W_i counts bending 3/2 times.
/// A clamp hinge belongs to its face alone: Â_ij = Â_i/3, share 1, contributing 3 W_clamp / A_i.
///
/// Units: J/m². x: #V×3 positions (m); alpha: #F fill ratios.
#include <Eigen/Core>

#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

/// Which elements' energy a density counts: all of them (W of (16)), or the membranes' only
/// (W^memb_i = r_m U_i^memb / A_i, summed over the parts of a split membrane).
enum class DensityElements { All, Membrane };

/// W (#F, J/m²).
Eigen::VectorXd energy_density(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                               DensityElements which = DensityElements::All);

/// For weights c (#F): Σ_i c_i ∂W_i/∂x into d_positions (#V×3, 1/m·J/m²; rows of fixed vertices
/// zero — they cannot move) and Σ_i c_i ∂W_i/∂α into d_alpha (#F). Either output may be null.
/// This is all an objective built on W needs, e.g. S_stab (17) with c_i = (W_i − β)₊ / m.
void energy_density_vjp(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                        const Eigen::VectorXd& weights, RowMatX3d* d_positions, Eigen::VectorXd* d_alpha,
                        DensityElements which = DensityElements::All);

}  // namespace cutwork::solvers
