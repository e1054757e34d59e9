#pragma once
/// The whole design of DESIGN.md's data flow as one library call, for `cutwork design`, the
/// end-to-end benchmarks and the tests:
///   uncut shell ─► equilibrium (W_ref = beta_reference: the uncut W_q area quantile, the reference of β)
///   pattern phase (initialisation, pattern-only L-BFGS-B)     ─► the pattern design
///   structural phase (joint L-BFGS-B, the scene's objective)   ─► the final design
/// with the equilibrium of each design (fill ratios on the simulation mesh, W, compliance,
/// material left). The caller writes the outputs; nothing here touches files or JSON.
#include <functional>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "host/core/timer.h"
#include "host/pattern/overlaps.h"
#include "host/scene/scene.h"
#include "solvers/optimize/pattern_phase.h"
#include "solvers/optimize/stencilled_shell.h"
#include "solvers/optimize/structure_phase.h"

namespace cutwork::solvers {

/// Where a design is at a checkpoint.
enum class DesignStage {
  Pattern,       ///< inside the pattern phase
  PatternEnd,    ///< the pattern phase has ended
  Structure,     ///< inside the structural phase
  StructureEnd,  ///< the structural phase has ended
};

/// A design's state at a checkpoint, by reference to the live objects (valid during the call).
struct DesignSnapshot {
  DesignStage stage;
  const PatternPhaseResult& pattern;            ///< so far (Pattern), else complete
  const StructurePhaseResult* structure;        ///< so far (Structure), complete (StructureEnd), else null
  const PhaseSnapshot* phase;                   ///< inside a phase (Pattern, Structure), else null
  /// The shell in the structural phase (Structure, StructureEnd; else null): the stencils of its
  /// fill ratios and its last equilibrium (#V×3, m), which warm-starts the next solve.
  const std::vector<StencilParams>* shell_stencils;
  const RowMatX3d* equilibrium;
};

/// A design's state read back from a checkpoint: run_design continues from it.
struct DesignResume {
  DesignStage stage = DesignStage::PatternEnd;
  PatternPhaseResult pattern;                   ///< (see DesignSnapshot)
  StructurePhaseResult structure;               ///< Structure, StructureEnd
  PhaseResume phase;                            ///< Pattern, Structure
  std::vector<StencilParams> shell_stencils;    ///< Structure, StructureEnd
  RowMatX3d equilibrium;                        ///< Structure, StructureEnd
};

struct DesignOptions {
  bool structure = true;           ///< run the structural phase (when the scene has an objective)
  FillRatioOptions fill;           ///< kernel backend of the fill ratios
  int pattern_iterations = -1;     ///< −1: the scene's pattern.max_iterations
  int structure_iterations = -1;   ///< −1: the scene's structure.max_iterations
  /// Progress of either phase ("pattern", "structure"); return false to stop that phase early.
  std::function<bool(const std::string& phase, const PatternProgress&)> progress;
  /// Checkpoints (`cutwork design --resume`, host/cli/checkpoint.h): called at every optimiser
  /// iteration boundary inside the phases and at each phase end; when and what to save is the
  /// caller's (an exception it throws ends the design).
  std::function<void(const DesignSnapshot&)> checkpoint;
  /// A checkpoint to continue from: the design then runs exactly (bit for bit on the CPU) as the
  /// run that saved it did after that point.
  const DesignResume* resume = nullptr;
};

/// A design's equilibrium and what the report says of it.
struct DesignState {
  int stencils = 0;
  Eigen::VectorXd alpha;             ///< #F of the simulation mesh
  EquilibriumSummary summary;        ///< W (#F), W_max, compliance, strain energy, displacement
  EquilibriumStats stats;
  RowMatX3d displacement;            ///< #V×3 (m): the equilibrium's (what a refined mesh's solve starts from)
  /// What its W_peak was read with besides α (the cell filter's blend, the stencils' cover by
  /// shape; empty where none): the discretisation estimate reads every level with them.
  Eigen::VectorXd concentration_weight;
  ShapeCover cover;
  double material_fraction = 1;      ///< Σ α A / Σ A
  OverlapReport overlaps;            ///< against the scene's safety factor s
};

struct DesignResult {
  DesignState uncut, pattern_design, final_design;
  PatternPhaseResult pattern;
  std::optional<StructurePhaseResult> structure;  ///< when the structural phase ran
  StencilLayout layout;                           ///< the final stencils (on the base mesh)
  /// The scene's mechanics as the design modelled them: with "lattice": "auto", the lattice read
  /// from the pattern's layout, which the structural phase starts from (measured_lattice).
  MechanicsSettings mechanics;
  std::vector<std::string> notes;  ///< what the run found worth telling (the lattice's reading)
  Timings timings;                                ///< per stage (s)
  StencilledShell::StageTimes stage_times;        ///< fill / equilibrium / adjoint totals
};

/// The reference energy density that structure.beta is a fraction of: the uncut shell's W_q, the
/// area quantile of energy_density_reference.h (the faces above it cover 2% of the material),
/// which converges under refinement where W_max diverges (re-entrant clamped corners, point-like
/// loads); W_max when W_q is 0 (nearly all the material unstrained). `uncut.alpha` is all ones.
double beta_reference(const DesignState& uncut, const SurfaceMesh& sim);

/// Runs the design of `scene` on `meshes` with supports and loads `load_case` (resolved on the
/// simulation mesh) and the pattern context `ctx` (built from the same scene and meshes).
/// Throws InputError / SolveError with a message naming the problem (e.g. a pattern design
/// that cannot carry the loads).
DesignResult run_design(const Scene& scene, const SceneMeshes& meshes, const LoadCase& load_case,
                        PatternContext& ctx, const DesignOptions& options = {});

/// The equilibrium of `layout` on `shell` (set_stencils + equilibrate + summary).
DesignState evaluate_design(StencilledShell& shell, const PatternContext& ctx, const StencilLayout& layout);

}  // namespace cutwork::solvers
