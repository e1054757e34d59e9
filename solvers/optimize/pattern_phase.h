#pragma once
/// The pattern phase of a design (`cutwork design --phases pattern`): initialisation (§4.3) and
/// pattern-only optimisation with L-BFGS-B (§5.4 with w_S = 0).
///
/// The context (shapes, fields, surface queries, exemplar, units, automatic choices) is
/// host/pattern/pattern_context.h; the optimiser, shared with the structural phase, is
/// solvers/optimize/joint_optimizer.h.
#include <string>
#include <vector>

#include "host/pattern/pattern_context.h"
#include "host/scene/scene.h"
#include "solvers/optimize/joint_optimizer.h"
#include "solvers/optimize/phase_state.h"

namespace cutwork::solvers {

/// The pattern phase's result; the optimiser's figures (rounds, iterations, evaluations, type
/// changes, removed, stop reason, round histories, seconds_optimize) come from
/// JointOptimizerStats.
struct PatternPhaseResult : JointOptimizerStats {
  StencilLayout layout;            ///< final stencils on the base mesh
  RowMatX3d normals;               ///< #S×3 Phong normals
  RowMatX3d tangents;              ///< #S×3 field tangents t (φ = 0 direction)
  Eigen::VectorXd bounding_radii;  ///< #S (m) = scales (shapes have bounding radius 1)
  std::string objective;           ///< "packing" or "exemplar"
  std::string exemplar;            ///< exemplar name ("inline" for a document)
  int field_symmetry = 1;
  double unit = 0;                 ///< ℓ (m)
  double epsilon = 0;              ///< ε (m)
  int initial_count = 0;           ///< stencils after initialisation
  int inserted_by_hole_filling = 0;
  double objective_start = 0;      ///< P after initialisation
  double objective_end = 0;        ///< P at the end (after overlap resolution, fresh matching)
  PatternTerms terms_end;
  double seconds = 0;              ///< whole phase
  double seconds_initialize = 0;
  std::vector<std::string> notes;
};

/// The pattern phase's options: the optimiser's (w_S = 0: `joint` stays null; its `checkpoint`
/// is the phase's own) and the phase's.
struct PatternPhaseOptions : JointOptimizerOptions {
  bool optimize = true;           ///< false: initialisation only
  /// §6.3: after convergence re-run the initialisation on the layout and optimise again when
  /// it added stencils, at most max_fill_rounds times (scene: structure.fill_holes).
  bool fill_holes = false;
  int max_fill_rounds = 3;
  /// Checkpoints inside the phase (at every optimiser boundary) and resuming from one.
  PhaseCheckpoints<PatternPhaseResult> checkpoints;
};


/// Builds the context, initialises and runs the pattern-only optimisation.
PatternPhaseResult run_pattern_phase(const Scene& scene, const SceneMeshes& meshes,
                                     const PatternPhaseOptions& options = {});
/// The same on an existing context (the joint optimiser keeps the context).
PatternPhaseResult run_pattern_phase(PatternContext& context, const PatternPhaseOptions& options = {});

}  // namespace cutwork::solvers
