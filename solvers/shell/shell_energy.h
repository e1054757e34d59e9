#pragma once
/// Total elastic energy (11) of a ShellModel, Ŵ(x, α) = Σ α_f A_f Ψ_f + Σ √(α_i α_j) W_ij + Σ α_f W_clamp,
/// with its gradient and Hessian over the free DOFs, assembled in parallel (TBB) into the fixed
/// pattern of ShellModel::assembly(). Results do not depend on the number of threads.
///
/// x: #V×3 positions (m), rows of fixed vertices equal to their rest positions; alpha: #F fill
/// ratios. Energies in J, gradients in N, Hessian entries in N/m.
#include <vector>

#include <Eigen/Core>

#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

/// Ŵ(x, α) (J). When `unit` is given it receives the per-element energies at unit fill ratio.
/// Returns +inf when an element is degenerate (a collapsed triangle makes θ undefined), which a
/// line search treats as a rejected step.
double shell_energy(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                    ElementEnergies* unit = nullptr);

/// Buffers of one assembly, reused between calls to avoid reallocation.
struct ShellAssembly {
  double energy = 0;              ///< Ŵ (J)
  Eigen::VectorXd gradient;       ///< #DOF: ∂Ŵ/∂x on the free DOFs (N)
  std::vector<double> hessian;    ///< nnz: upper triangle of ∂²Ŵ/∂x² (N/m), in assembly() order
  std::vector<double> element_energy;  ///< per element (membranes, hinges, clamps), scaled by α
};

/// Energy and gradient, plus the Hessian values when with_hessian.
void assemble_shell(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                    bool with_hessian, ShellAssembly& out);

/// Local position vectors of the elements (helpers shared with the sensitivity code).
Vec9 membrane_positions(const ShellModel& model, const RowMatX3d& x, int face);
Vec12 hinge_positions(const ShellHinge& hinge, const RowMatX3d& x);
Vec12 clamp_positions(const ClampHinge& clamp, const RowMatX3d& x);
/// √(α_i α_j) of a hinge.
double hinge_fill_factor(const ShellHinge& hinge, const Eigen::VectorXd& alpha);

}  // namespace cutwork::solvers
