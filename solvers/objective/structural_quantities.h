#pragma once
/// Scalar quantities of an equilibrium and, for those that serve as objectives, their partials.
///   strain energy  Ŵ(x, α)                    (J)  — the total elastic energy (11)
///   compliance     C = f_ext(α) · (x − X)      (J)  — the work of the external loads
///   max displacement  max_v |x_v − X_v|        (m)
///   W_max          max_i W_i of (16)           (J/m²)
/// At a linear-elastic equilibrium C = 2Ŵ; with the geometric nonlinearity of the shell they
/// differ, which is why both are reported. x: #V×3 (m); alpha: #F.
#include <Eigen/Core>

#include "solvers/objective/objective_terms.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

struct EquilibriumSummary {
  double strain_energy = 0;      ///< J
  double compliance = 0;         ///< J
  double max_displacement = 0;   ///< m
  int max_displacement_vertex = -1;
  double W_max = 0;              ///< J/m²
  int W_max_face = -1;
  Eigen::VectorXd energy_density;  ///< #F, J/m²
};

EquilibriumSummary summarize_equilibrium(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha);

/// S = Ŵ(x, α): ∂S/∂x = ∂Ŵ/∂x (fixed rows zero), ∂S/∂α = ∂Ŵ/∂α.
ObjectiveTerms strain_energy_terms(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha);

/// S = f_ext(α)·(x − X): ∂S/∂x = f_ext (fixed rows zero), ∂S/∂α_t = (ρ h A_t g / 3)·Σ_{v∈t} u_v.
ObjectiveTerms compliance_terms(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha);

}  // namespace cutwork::solvers
