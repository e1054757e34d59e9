#pragma once
/// Total derivative of a structural objective with respect to the fill ratios by the adjoint method,
/// (13)–(15): with H = ∂²Π/∂x² the Hessian of the converged equilibrium (H = −∂f/∂x),
///     H λ = ∂S/∂x,          dS/dα = ∂S/∂α + λᵀ ∂f/∂α,
/// which equals ∂S/∂α + ∂S/∂x · dx/dα with dx/dα = H⁻¹ ∂f/∂α from differentiating f(x(α), α) = 0.
/// (DESIGN.md writes the same with K = ∂f/∂x = −H: λ_K = K⁻¹ ∂S/∂x = −λ, dS/dα = ∂S/∂α − λ_Kᵀ ∂f/∂α.)
/// The solve reuses the factor of the converged Hessian held by the EquilibriumSolver: one
/// forward/back substitution per objective, no factorisation.
#include <Eigen/Core>

#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/objective_terms.h"

namespace cutwork::solvers {

struct Sensitivity {
  double value = 0;          ///< S at the equilibrium
  Eigen::VectorXd gradient;  ///< dS/dα (#F)
  Eigen::VectorXd adjoint;   ///< λ (#DOF, free DOFs)
  double seconds = 0;        ///< time of the adjoint solve alone
};

/// dS/dα at the solver's last equilibrium (positions(), alpha()). Throws SolveError when it is
/// unstable, InternalError when there is none (see EquilibriumSolver::solve_adjoint).
Sensitivity fill_ratio_sensitivity(const EquilibriumSolver& solver, const StructuralObjectiveFn& objective);

/// The same for objective terms already evaluated at that equilibrium.
Sensitivity fill_ratio_sensitivity(const EquilibriumSolver& solver, const ObjectiveTerms& terms);

}  // namespace cutwork::solvers
