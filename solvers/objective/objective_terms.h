#pragma once
/// The value of a structural objective S(α, x) with its partial derivatives — what the adjoint
/// (solvers/sensitivity) needs from any objective.
#include <functional>

#include <Eigen/Core>

#include "host/core/types.h"

namespace cutwork::solvers {

class ShellModel;

/// The stencils' cover of each face, shape by shape (#F × shapes each): what W_peak's factors by
/// shape and by corner read (solvers/objective/peak_energy_density.h).
struct ShapeCover {
  Eigen::MatrixXd covered;  ///< h_ts: the part of face t the stencils of shape s cover
  /// Σ f ε over the same pieces, ε = corner_radius / the stencil's scale (the corner rule's radius in
  /// its bounding radii): ε̄_ts = corner_ts / h_ts. Empty: ε = 0.
  Eigen::MatrixXd corner;
  bool empty() const { return covered.size() == 0; }
};

struct ObjectiveTerms {
  double value = 0;
  /// ∂S/∂x (#V×3, per metre). Rows of fixed vertices are ignored (those positions cannot move).
  RowMatX3d d_positions;
  /// ∂S/∂α (#F), the explicit dependence on the fill ratios at fixed positions.
  Eigen::VectorXd d_alpha;
  /// ∂S/∂(the cover) where S depends on the stencils' cover of each face as well (the peak
  /// measure's factors by shape, peak_energy_density.h); empty where it does not. The equilibrium
  /// does not depend on it: this part pulls back directly (StencilledShell).
  ShapeCover d_cover;
};

/// S(α, x) evaluated at positions x (#V×3) and fill ratios alpha (#F) of `model`. (Which objective
/// a scene asks for is the enum cutwork::StructuralObjective in host/scene/scene.h.)
using StructuralObjectiveFn =
    std::function<ObjectiveTerms(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha)>;

}  // namespace cutwork::solvers
