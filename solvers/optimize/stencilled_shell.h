#pragma once
/// The stenciled shell as a function of the stencil parameters (§5.2–§5.3), the one place that
/// chains the rooms together for the structural phase, `cutwork simulate --stencils` and the
/// benchmarks:
///
///   p ──► α(p)        fill ratios of the simulation mesh's triangles (FillRatioEvaluator:
///                     frames on the base surface, broad phase, clip and fill kernels on the
///                     chosen backend), with the sparse dα/dp, then the cell filter B
///                     (solvers/shell/cell_filter.h; the identity unless set): the shell sees B α
///     ──► x(α)        static equilibrium (EquilibriumSolver: Newton, warm-started from the
///                     previous equilibrium, CHOLMOD factor kept for the adjoint)
///     ──► S(α, x)     any structural objective's terms (solvers/objective)
///     ──► dS/dp       = (dα/dp)ᵀ Bᵀ dS/dᾱ with dS/dᾱ from the adjoint (13)–(15): one solve
///                     with the converged factor, then the filter's and the fill kernel's
///                     pull-backs.
///
/// Every stencil parameter vector is p = (q_x, q_y, q_z, s, φ) per stencil, stencil-major
/// (#S×5), as in kernels/fill/fill.h. Lengths in metres, energies in joules.
/// Topology is fixed for the object's lifetime: the shell model, the sparsity pattern, CHOLMOD's
/// symbolic analysis and the fill evaluator's device buffers are built once.
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "host/mesh/bvh.h"
#include "host/stencil/fill_ratio.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/objective_terms.h"
#include "solvers/objective/structural_quantities.h"
#include "solvers/shell/cell_filter.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

class StencilledShell {
 public:
  /// `sim` is simulated; stencils sit on the surface of `surface_bvh` (the base mesh) with
  /// tangents from `field`. Everything referenced must outlive this object. Throws what
  /// ShellModel, EquilibriumSolver and FillRatioEvaluator throw for bad input.
  StencilledShell(const SurfaceMesh& sim, const FaceBvh& surface_bvh, const Material& material,
                  const MechanicsSettings& mechanics, const LoadCase& load_case, const StencilLibrary& shapes, const TangentField& field,
                  FillRatioOptions fill_options = {}, NewtonSettings newton = {});
  StencilledShell(const StencilledShell&) = delete;
  StencilledShell& operator=(const StencilledShell&) = delete;

  /// The fill-ratio filter (fill_stiffness_calibration.h's scene_cell_filter; the identity
  /// until set). Set it before the first set_stencils; it must be built on the simulation mesh.
  void set_cell_filter(CellFilter filter);
  const CellFilter& cell_filter() const { return m_filter; }

  /// α for `stencils`, with dα/dp when fill_options.derivatives (the default); an empty span
  /// gives the uncut shell (α = 1). Throws InputError for invalid stencils. Under the homogenised
  /// rule with a calibrated curve and several shapes, the curve follows the shapes' shares of
  /// `stencils` (fill_stiffness_calibration.h's shape_weights): recalibrated (from the memoised
  /// cells) when the shares change, which a minimisation's steps never do (they move and scale
  /// stencils, they do not change their types).
  const Eigen::VectorXd& set_stencils(std::span<const StencilParams> stencils);
  /// The fill ratios the shell sees after the last set_stencils (#F): the filtered B α, which
  /// is the kernels' α without a filter. And its stencils.
  const Eigen::VectorXd& alpha() const { return m_alpha; }
  /// The stencils' cover of each face by shape after the filter (solvers/objective/shape_cover.h)
  /// when W_peak reads its factors by shape and by corner (ConcentrationMap::by_shape() of the
  /// model's curve); null otherwise. summary() and a peak objective (PeakMeasure::cover) read it;
  /// parameter_gradient pulls an objective's ObjectiveTerms::d_cover back through it.
  const ShapeCover* cover() const { return m_cover.empty() ? nullptr : &m_cover; }
  /// The kernels' own fill ratios of the last set_stencils (#F), before the filter.
  const Eigen::VectorXd& face_alpha() const { return m_filter.identity() ? m_alpha : m_face_alpha; }
  const std::vector<StencilParams>& stencils() const { return m_stencils; }

  /// The stencils of the last equilibrium (the last successful equilibrate() or
  /// restore_equilibrium): what a checkpoint must save beside the solver's positions. They differ
  /// from stencils() when stencils were set after it without a solve (the compliance objective's
  /// area restoration after hole filling), and restoring the equilibrium at the later stencils
  /// would factorise another Hessian than the one the uninterrupted run holds.
  const std::vector<StencilParams>& equilibrium_stencils() const { return m_equilibrium_stencils; }

  /// Sets `stencils` and makes `positions` (#V×3, m) their last equilibrium, as if equilibrate()
  /// had just converged there (checkpoints: the next solve is warm-started exactly as it was).
  void restore_equilibrium(std::span<const StencilParams> stencils, const RowMatX3d& positions);

  /// Equilibrium at alpha(), warm-started. Throws SolveError (the solver keeps its last valid
  /// equilibrium).
  const EquilibriumStats& equilibrate();
  /// Quantities of the last equilibrium (W, W_max, compliance, strain energy, displacement).
  EquilibriumSummary summary() const;

  /// dS/dp (#S×5) of an objective whose terms were evaluated at the last equilibrium, by the
  /// adjoint and the pull-back (and the terms' ∂S/∂(cover) through shape_cover_pullback, when they
  /// carry it); needs fill-ratio derivatives and at least one stencil. Returns
  /// dS/dᾱ (#F, with respect to the filtered fill ratios alpha()) too when `d_alpha` is not null.
  void parameter_gradient(const ObjectiveTerms& terms, Eigen::VectorXd& d_params,
                          Eigen::VectorXd* d_alpha = nullptr);

  /// Area removed by the stencils on the simulation mesh, Σ_t A_t (1 − α_t) (m²) with the
  /// kernels' α (face_alpha(): the filter does not conserve it exactly), and its gradient (#S×5)
  /// when `d_params` is not null (needs derivatives).
  double covered_area(Eigen::VectorXd* d_params) const;
  /// Σ α_t A_t / Σ A_t with face_alpha(): the fraction of the shell's material left.
  double material_fraction() const;

  const ShellModel& model() const { return *m_model; }
  const EquilibriumSolver& solver() const { return *m_solver; }
  EquilibriumSolver& solver() { return *m_solver; }
  const FillRatioEvaluator& evaluator() const { return *m_fill; }
  int num_stencils() const { return m_num_stencils; }

  /// Accumulated wall time of the stages (fill, equilibrium, adjoint) and their counts.
  struct StageTimes {
    double fill = 0, equilibrium = 0, adjoint = 0, pullback = 0;
    int fills = 0, equilibria = 0, adjoints = 0, newton_iterations = 0;
    void add(const StageTimes& o) {
      fill += o.fill, equilibrium += o.equilibrium, adjoint += o.adjoint, pullback += o.pullback;
      fills += o.fills, equilibria += o.equilibria, adjoints += o.adjoints, newton_iterations += o.newton_iterations;
    }
  };
  const StageTimes& times() const { return m_times; }

 private:
  const SurfaceMesh* m_sim;
  FaceBvh m_sim_bvh;
  std::unique_ptr<ShellModel> m_model;
  std::unique_ptr<EquilibriumSolver> m_solver;
  std::unique_ptr<FillRatioEvaluator> m_fill;
  // The homogenised curve's calibration: the scene's mechanics (before calibration), the shapes,
  // the material, and the weights the model's curve has (empty: not reweighted).
  MechanicsSettings m_mechanics;
  const StencilLibrary* m_shapes;
  Material m_material;
  std::vector<double> m_weights;
  CellFilter m_filter;
  Eigen::VectorXd m_alpha;       ///< B α (what the shell sees)
  Eigen::VectorXd m_face_alpha;  ///< α (with a filter; empty without)
  ShapeCover m_cover;              ///< cover(); empty when not by shape
  bool m_by_shape = false;         ///< concentration_by_shape of the model's mechanics (its curve's map, built once)
  ShapeCover m_equilibrium_cover;  ///< m_cover of the last equilibrium (summary())
  std::vector<StencilParams> m_stencils;
  std::vector<StencilParams> m_equilibrium_stencils;
  int m_num_stencils = 0;
  bool m_derivatives = false;
  StageTimes m_times;
};

}  // namespace cutwork::solvers
