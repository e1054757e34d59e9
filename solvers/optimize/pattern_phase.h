#pragma once
/// The pattern phase of a design (`cutwork design --phases pattern`): initialisation (§4.3) and
/// pattern-only optimisation with L-BFGS-B (§5.4 with w_S = 0).
///
/// PatternContext gathers everything derived from a scene that pattern code needs — stencil
/// shapes, the orientation field (symmetry matched to the shapes and exemplar), the sizing
/// field, the surface queries, the exemplar, the units — so that the joint optimiser of the
/// structural phase reuses the same objective, bounds, re-matching and hole filling.
///
/// Units and automatic choices:
///  - ℓ (`unit`): the nominal stencil scale (bounding radius, m): pattern.scale when given;
///    else from pattern.count (packing: a maximal Poisson-disk packing of that many stencils;
///    exemplar: the exemplar's density); else automatic: the scale at which ~300 stencils
///    (the paper's Table 1: 185–462) cover the surface, but at least one base-mesh edge length.
///  - ε = pattern.epsilon × the object's length (longest bounding-box side), §4.2.
///  - σ_0 (exemplar → metres) = ℓ / the exemplar's mean element scale.
///  - Scale bounds: packing [scale_min, scale_max] × ℓ × sizing at the stencil's start;
///    exemplar [scale_min × smallest, scale_max × largest] exemplar scale × σ_0 × sizing.
///  - The field symmetry N: pattern.symmetry, or field_symmetry_for(shapes, exemplar).
#include <cmath>
#include <functional>
#include <span>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/pattern/det.h"
#include "host/pattern/pattern_energy.h"
#include "host/pattern/pattern_surface.h"
#include "host/scene/scene.h"
#include "host/stencil/frame.h"
#include "host/stencil/stencil_shape.h"
#include "solvers/optimize/lbfgsb.h"

namespace cutwork {

/// The stencil shapes of a scene as a library (type id = index in scene.shapes); a scene
/// without shapes gets one built-in circle.
StencilLibrary scene_stencil_library(const Scene& scene);

class PatternContext {
 public:
  /// Builds shapes, fields, surface queries and the exemplar for the scene's base mesh
  /// (`meshes.base`, which must outlive the context). Throws InputError for a bad exemplar,
  /// sizing file, or stroke.
  PatternContext(const Scene& scene, const SceneMeshes& meshes);
  PatternContext(const PatternContext&) = delete;
  PatternContext& operator=(const PatternContext&) = delete;

  const PatternSettings& settings() const { return m_settings; }
  const StencilLibrary& shapes() const { return m_shapes; }
  const PatternSurface& surface() const { return *m_surface; }
  PatternKind kind() const { return m_kind; }
  /// Exemplar model (nullptr for packing).
  const DetExemplar* exemplar() const { return m_exemplar.get(); }
  PatternEnergy& energy() { return *m_energy; }
  const PatternEnergy& energy() const { return *m_energy; }
  double unit() const { return m_unit; }
  double epsilon() const { return m_epsilon; }
  int symmetry() const { return m_symmetry; }
  /// Notes for the report (automatic choices, adjustments).
  const std::vector<std::string>& notes() const { return m_notes; }

  /// A fresh initial layout (Poisson disk or DET growth), deterministic for the seed.
  StencilLayout initialize(PatternRng& rng) const;
  /// §6.3: re-runs the initialisation on an existing layout; returns the number added.
  int fill_holes(StencilLayout& layout, PatternRng& rng) const;
  /// Scale bounds (m) of each stencil of `layout` (see the file comment).
  void scale_bounds(const StencilLayout& layout, Eigen::VectorXd& lower, Eigen::VectorXd& upper) const;

 private:
  PatternSettings m_settings;
  StencilLibrary m_shapes;
  std::unique_ptr<PatternSurface> m_surface;
  PatternKind m_kind = PatternKind::Packing;
  std::unique_ptr<DetExemplar> m_exemplar;
  std::unique_ptr<PatternEnergy> m_energy;
  double m_unit = 0, m_epsilon = 0;
  int m_symmetry = 1;
  std::vector<std::string> m_notes;
};

/// A term the joint optimiser adds to w_P·P in (19): the structural part w_S·S(p), evaluated at
/// every point the optimiser visits (solvers/optimize/structure_phase.h implements it). A
/// constraint on p (compliance: constant total stencil area) is restored before anything is
/// evaluated, so the optimiser minimises J(R(p)) and every value it sees is admissible.
class JointTerm {
 public:
  virtual ~JointTerm() = default;
  /// Maps the optimiser's parameters onto the constraint, in place (default: none).
  virtual void restore(std::vector<StencilParams>& params) { (void)params; }
  /// Chain rule through the last restore(): a gradient (#S×5) at the restored parameters becomes
  /// the gradient at the parameters restore() was given, in place.
  virtual void restore_pullback(Eigen::VectorXd& gradient) const { (void)gradient; }
  /// w_S·S at `params` (already restored) and, when `gradient` is not null, its gradient
  /// (#S×5, (q, s, φ) per stencil), written. +inf where S cannot be evaluated (no stable
  /// equilibrium): the line search then backs off.
  virtual double evaluate(std::span<const StencilParams> params, Eigen::VectorXd* gradient) = 0;
  /// After the optimisation and the overlap resolution (which shrinks stencils and may break the
  /// constraint): make `layout` admissible and restored at once (default: nothing to do).
  virtual void finalize(const PatternSurface& surface, double safety, StencilLayout& layout) {
    (void)surface, (void)safety, (void)layout;
  }
  /// S (unweighted) and W_max (J/m²) of the last successful evaluation, for progress displays.
  virtual double last_structure() const = 0;
  virtual double last_W_max() const = 0;
};

/// The optimiser's objective at `params` (#S, restored onto the joint term's constraint in
/// place first): w_P·P + joint, or P alone when `joint` is null; `gradient` (#S×5, (q, s, φ) per
/// stencil, w.r.t. the parameters before restoration) is written when not null — its φ entries
/// are zero without a joint term. The pattern energy's current matching is used (frozen).
/// Non-finite values come with a NaN gradient.
double joint_objective(const PatternEnergy& energy, JointTerm* joint, double w_P, std::vector<StencilParams>& params,
                       const Eigen::VectorXi& types, Eigen::VectorXd* gradient);

/// Live progress of a phase (a callback may show it; returning false stops the optimiser).
struct PatternProgress {
  std::string stage;       ///< "initialise", "optimise"
  int round = 0;           ///< match/optimise round (DET), or optimiser run
  int iteration = 0;       ///< accepted L-BFGS-B iterations so far (over rounds)
  double objective = 0;    ///< the objective of the current iterate: P, or J = w_S S + w_P P
  int stencils = 0;
  double seconds = 0;      ///< since the phase started
  double gradient_norm = 0;///< ‖∇‖₂ of the objective at the last evaluation (optimiser units)
  double structure = std::nan("");  ///< S (joint phase only)
  double W_max = std::nan("");      ///< J/m² (joint phase only)
};

struct PatternPhaseOptions {
  int max_iterations = -1;        ///< total L-BFGS-B iterations; −1: pattern.max_iterations
  int iterations_per_round = 0;   ///< 0: 20 for exemplars (re-match between rounds), 100 packing
  /// The rounds stop when three in a row end less than this (relative) below the best round
  /// end so far ("stalled").
  double round_tolerance = 1e-4;
  bool optimize = true;           ///< false: initialisation only
  /// §6.3: after convergence re-run the initialisation on the layout and optimise again when
  /// it added stencils, at most max_fill_rounds times (scene: structure.fill_holes).
  bool fill_holes = false;
  int max_fill_rounds = 3;
  std::function<bool(const PatternProgress&)> progress;
  /// The joint optimisation (19): the objective becomes w_P·P + joint (not owned), the angles
  /// φ join the variables within ±max_rotation (rad) of their start, and the overlap resolution
  /// at the end is followed by the term's restoration. Null: pattern only.
  JointTerm* joint = nullptr;
  double w_P = 1.0;
  double max_rotation = 0.0;
};

struct PatternPhaseResult {
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
  int removed = 0;                 ///< removed by the final overlap resolution
  int inserted_by_hole_filling = 0;
  int rounds = 0;                  ///< optimiser runs (DET: match/optimise rounds)
  int iterations = 0;              ///< accepted L-BFGS-B iterations
  int evaluations = 0;             ///< objective evaluations
  int type_changes = 0;            ///< by majority vote
  /// Why the phase ended: "gradient" or "decrease" (L-BFGS-B's tolerances), "stalled"
  /// (three rounds without progress), "iterations" (budget spent),
  /// "callback", or "line search: …".
  std::string stop_reason;
  /// The optimiser's objective after each accepted iterate, one list per round (the first
  /// value of each is the round's start): monotone within a round by construction.
  std::vector<std::vector<double>> round_histories;
  double objective_start = 0;      ///< P after initialisation
  double objective_end = 0;        ///< P at the end (after overlap resolution, fresh matching)
  PatternTerms terms_end;
  double seconds = 0;              ///< whole phase
  double seconds_initialize = 0;
  double seconds_optimize = 0;
  std::vector<std::string> notes;

  /// The layout as stencil parameters (position on the surface, scale, angle, type).
  std::vector<StencilParams> params() const;
};

/// Builds the context, initialises and runs the pattern-only optimisation.
PatternPhaseResult run_pattern_phase(const Scene& scene, const SceneMeshes& meshes,
                                     const PatternPhaseOptions& options = {});
/// The same on an existing context (the joint optimiser keeps the context).
PatternPhaseResult run_pattern_phase(PatternContext& context, const PatternPhaseOptions& options = {});

/// Pattern-only optimisation of `layout` in place (no initialisation): the L-BFGS-B rounds
/// and type votes of run_pattern_phase, then the overlap resolution. Fills the optimisation
/// fields of `result` (rounds, iterations, evaluations, type changes, stop reason, seconds).
void optimize_pattern(PatternContext& context, StencilLayout& layout, const PatternPhaseOptions& options,
                      PatternPhaseResult& result);

}  // namespace cutwork
