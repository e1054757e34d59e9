#pragma once
/// Partial derivatives of the shell's energy and net force with respect to the fill ratios, at fixed
/// positions. Every element energy is linear in α_f (membrane, shape-operator bend, clamp hinge) or in √(α_i α_j)
/// (hinge), so the partials are closed forms of the unit-fill-ratio element quantities:
///   ∂(α W)/∂α = W,   ∂(√(α_i α_j) W)/∂α_i = √(α_i α_j) W / (2 α_i),
/// and likewise for the element gradients. Self-weight adds ∂f_ext/∂α_t = ρ h A_t g / 3 per vertex,
/// a surface load s F_t − (a_t / Σ α a) f (ShellModel::add_load_alpha_product).
///
/// f(x, α) = −∂Ŵ/∂x + f_ext(α) is the net force (12) on the free DOFs (#DOF, N), zero on the DOFs
/// held by supports along some axes (ShellModel::held_dofs: there it is the support's reaction, and
/// the equilibrium's residual is zeroed as well); x is #V×3 (m).
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

/// ∂Ŵ/∂α (#F, J per unit fill ratio).
Eigen::VectorXd energy_alpha_gradient(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha);

/// λᵀ ∂f/∂α (#F) for a vector λ over the free DOFs (#DOF) — the adjoint term of (13)–(15) without
/// forming ∂f/∂α. Deterministic (per-element values, then a fixed-order sum per face).
Eigen::VectorXd force_alpha_product(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                    const Eigen::VectorXd& lambda);

/// ∂f/∂α as a sparse #DOF×#F matrix (N per unit fill ratio): column t is nonzero on the DOFs of the
/// vertices of face t and of the hinges that contain it, and on every vertex a surface load over t
/// loads (dense there). For tests and small problems.
Eigen::SparseMatrix<double> force_alpha_jacobian(const ShellModel& model, const RowMatX3d& x,
                                                 const Eigen::VectorXd& alpha);

}  // namespace cutwork::solvers
