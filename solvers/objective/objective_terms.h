#pragma once
/// The value of a structural objective S(α, x) with its partial derivatives — what the adjoint
/// (solvers/sensitivity) needs from any objective.
#include <functional>

#include <Eigen/Core>

#include "host/core/types.h"

namespace cutwork::solvers {

class ShellModel;

struct ObjectiveTerms {
  double value = 0;
  /// ∂S/∂x (#V×3, per metre). Rows of fixed vertices are ignored (those positions cannot move).
  RowMatX3d d_positions;
  /// ∂S/∂α (#F), the explicit dependence on the fill ratios at fixed positions.
  Eigen::VectorXd d_alpha;
  /// ∂S/∂h (#F × shapes) where S depends on the shapes' covered fractions of each face as well
  /// (the peak measure's factors by shape, peak_energy_density.h); empty where it does not. The
  /// equilibrium does not depend on h: this part pulls back directly (StencilledShell).
  Eigen::MatrixXd d_covered;
};

/// S(α, x) evaluated at positions x (#V×3) and fill ratios alpha (#F) of `model`. (Which objective
/// a scene asks for is the enum cutwork::StructuralObjective in host/scene/scene.h.)
using StructuralObjectiveFn =
    std::function<ObjectiveTerms(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha)>;

}  // namespace cutwork::solvers
