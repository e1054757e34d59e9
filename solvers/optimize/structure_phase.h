#pragma once
/// The structural phase of a design (§5.3–§5.4, §6): the joint minimisation of
///     J(p) = w_S S(α(p), x(α(p))) + w_P P(p)                                         (19)
/// with L-BFGS-B, starting from the pattern phase's layout.
///
/// Every evaluation is consistent: the fill ratios of p, then a warm-started Newton solve to
/// equilibrium, then S and — for the gradient — the adjoint with the converged factor, the
/// fill kernel's exact dα/dp pulled back, and dP/dp from the pattern objective. A point where no
/// stable equilibrium exists evaluates to +∞ (the line search backs off). The rounds of the
/// pattern phase carry over: DET neighbourhoods are re-matched and stencil types voted between
/// L-BFGS-B runs (solvers/optimize/joint_optimizer.h, optimize_pattern with a JointTerm).
///
/// Objectives (scene `structure.objective`, solvers/objective/structural_objective.h):
///  - energy_density (17): β = structure.beta × W_ref, W_ref = the uncut W_q (design_pipeline.h beta_reference);
///    with structure.measure "peak" the per-face W is the ligament peak W_peak (peak_energy_density.h)
///    — for adaptive too, whose statistic is then taken of W_peak;
///  - adaptive: β starts at, and after every converged optimisation moves to, the median of W or
///    the mean of its top y% (structure.adaptive_mode, adaptive_y); the optimisation continues
///    until β changes by less than 1e-3 W_ref, at most structure.max_rounds times;
///  - compliance (18): the total stencil area is held at the pattern design's. The constraint
///    is restored before every evaluation by one uniform factor k on all scales (Newton on k,
///    to 1e-12 relative), so J is evaluated only on the constraint and its gradient is the
///    chain rule through the restoration — the projection of ∇J onto the constraint's tangent
///    space along the restoring direction. (The paper projects orthogonally and then restores;
///    projecting along the direction that restores keeps the line search's function smooth and
///    exact.)
/// Angles φ join the variables within ±structure.max_rotation of the field-aligned start.
/// After the optimisation the overlaps left by the soft collision penalty are removed by
/// shrinking (host/pattern/overlaps.h) and the area constraint restored again.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "host/scene/scene.h"
#include "solvers/objective/structural_objective.h"
#include "solvers/optimize/joint_optimizer.h"
#include "solvers/optimize/phase_state.h"
#include "solvers/optimize/stencilled_shell.h"

namespace cutwork::solvers {

/// The joint term w_S·S of (19) on a StencilledShell (see the file comment for the objectives).
class StructuralTerm final : public JointTerm {
 public:
  /// `w_ref` (J/m²) scales energy densities (the uncut shell's beta_reference); `c_ref` (J) compliance.
  /// For Compliance, `target_covered_area` (m², simulation mesh) is the constraint's value.
  StructuralTerm(StencilledShell& shell, StructuralObjective objective, double w_S, double beta,
                 double w_ref, double c_ref, double target_covered_area);

  void restore(std::vector<StencilParams>& params) override;
  void restore_pullback(Eigen::VectorXd& gradient) const override;
  double evaluate(std::span<const StencilParams> params, Eigen::VectorXd* gradient) override;
  /// Compliance: alternates restoring the area and shrinking overlapping stencils, freezing
  /// every stencil that had to shrink, so that the design ends both admissible and restored.
  void finalize(const PatternSurface& surface, double safety, double gap, StencilLayout& layout) override;
  double last_structure() const override { return m_last_S; }
  double last_W_max() const override { return m_last_W_max; }

  /// S (unweighted) at `params`, or +∞ without a stable equilibrium. Leaves the shell there.
  double structure(std::span<const StencilParams> params);
  double beta() const { return m_beta; }
  void set_beta(double beta) { m_beta = beta; }
  /// What S thresholds (energy_density, adaptive): W (default) or W_peak, whose concentration
  /// factors come from the shell's mechanics. Throws InputError for Peak when it has none.
  void set_measure(DensityMeasure measure);
  DensityMeasure measure() const { return m_measure; }
  /// Why finalize() left the compliance constraint below its target (the minimum feature left no
  /// room); empty when it did not.
  const std::string& finalize_note() const { return m_finalize_note; }

  /// Restorations so far and the largest |k − 1| among them.
  int restorations() const { return m_restorations; }
  double max_restoring_change() const { return m_max_k_change; }
  /// Sets those counters (a phase resumed from a checkpoint).
  void set_counters(int restorations, double max_restoring_change) {
    m_restorations = restorations;
    m_max_k_change = max_restoring_change;
  }

 private:
  bool constrained() const { return m_objective == StructuralObjective::Compliance; }
  /// Sets the shell's stencils unless they are already the ones of the last restore().
  void place(std::span<const StencilParams> params);
  /// Equilibrium and objective terms at `params`; nothing without a stable equilibrium.
  std::optional<ObjectiveTerms> solve(std::span<const StencilParams> params);

  StencilledShell& m_shell;
  StructuralObjective m_objective;
  double m_w_S, m_beta, m_w_ref, m_c_ref, m_target;
  DensityMeasure m_measure = DensityMeasure::Mean;
  ConcentrationMap m_K;  ///< the shell's concentration factors (Peak)
  std::string m_finalize_note;
  double m_last_S = std::nan(""), m_last_W_max = std::nan("");
  // The last restoration: k, the original scales, ∂C/∂p at the restored parameters (#S×5).
  double m_k = 1;
  Eigen::VectorXd m_scales, m_dC;
  std::vector<char> m_frozen;  ///< stencils restore() does not scale (finalize); empty: none
  bool m_restored = true;      ///< the last restore() reached the constraint
  std::vector<StencilParams> m_placed;
  bool m_placed_valid = false;
  int m_restorations = 0;
  double m_max_k_change = 0;
};

/// The structural phase's result; the optimiser's figures (rounds, iterations, evaluations, type
/// changes, removed, stop reason, round histories) come from JointOptimizerStats, accumulated
/// over all its optimisations.
struct StructurePhaseResult : JointOptimizerStats {
  StencilLayout layout;
  std::string objective;           ///< energy_density, adaptive or compliance
  double beta = std::nan("");      ///< final threshold (J/m²; energy density and adaptive)
  std::vector<double> beta_history;///< adaptive: β of each optimisation
  double w_ref = 0, c_ref = 0;     ///< references of the dimensionless S (J/m², J)
  double J_start = 0, J_end = 0, S_start = 0, S_end = 0, P_start = 0, P_end = 0;
  int optimisations = 0;           ///< L-BFGS-B sequences (adaptive β updates, hole filling)
  int inserted_by_hole_filling = 0;
  int removed_for_min_feature = 0;  ///< pattern stencils removed to keep the minimum feature at the start
  double covered_area_target = 0, covered_area_final = 0;  ///< m² (compliance)
  int restorations = 0;
  double max_restoring_change = 0;
  double seconds = 0;
  std::vector<std::string> notes;
};

struct StructurePhaseOptions {
  int max_iterations = -1;  ///< L-BFGS-B iterations per optimisation; −1: structure.max_iterations
  std::function<bool(const PatternProgress&)> progress;
  unsigned seed = 1;        ///< hole filling's random order
  /// The minimum feature (m, fabrication.min_feature) kept between stencils and to the border:
  /// the start is shrunk to keep it, the collision penalties keep it softly during the phase
  /// (PatternEnergySettings::gap) and the overlap resolution after every optimisation exactly
  /// (JointOptimizerOptions::min_gap).
  double min_feature = 0;
  /// Checkpoints inside the phase (at every optimiser boundary; the partial result's `beta` is
  /// the live β) and resuming from one. The shell's state (its stencils and last equilibrium)
  /// is the caller's to save and, before resuming, to restore (StencilledShell::restore_equilibrium).
  PhaseCheckpoints<StructurePhaseResult> checkpoints;
};

/// Runs the structural phase from `start` (the pattern design on ctx's surface). `shell` must be
/// built on the scene's simulation mesh with the context's shapes and field; `w_ref` is the uncut
/// shell's reference energy density (design_pipeline.h's beta_reference). Throws SolveError when the pattern design itself has no stable equilibrium.
StructurePhaseResult run_structure_phase(PatternContext& ctx, StencilledShell& shell, const StructureSettings& settings,
                                         const StencilLayout& start, double w_ref,
                                         const StructurePhaseOptions& options = {});

}  // namespace cutwork::solvers
