#pragma once
/// The pattern phase of a design (`cutwork design --phases pattern`): initialisation (§4.3) and
/// pattern-only optimisation with L-BFGS-B (§5.4 with w_S = 0).
///
/// PatternContext gathers everything derived from a scene that pattern code needs — stencil
/// shapes, the orientation field (symmetry matched to the shapes and exemplar), the sizing
/// field, the surface queries, the exemplar, the units — so that the joint optimiser of the
/// structural phase reuses the same objective, bounds, re-matching and hole filling.
///
/// Units and automatic choices (documented in docs/PATTERNS.md terms):
///  - ℓ (`unit`): the nominal stencil scale (bounding radius, m): pattern.scale when given;
///    else from pattern.count (packing: a maximal Poisson-disk packing of that many stencils;
///    exemplar: the exemplar's density); else automatic: the scale at which ~300 stencils
///    (the paper's Table 1: 185–462) cover the surface, but at least one base-mesh edge length.
///  - ε = pattern.epsilon × the object's length (longest bounding-box side), §4.2.
///  - σ_0 (exemplar → metres) = ℓ / the exemplar's mean element scale.
///  - Scale bounds: packing [scale_min, scale_max] × ℓ × sizing at the stencil's start;
///    exemplar [scale_min × smallest, scale_max × largest] exemplar scale × σ_0 × sizing.
///  - The field symmetry N: pattern.symmetry, or field_symmetry_for(shapes, exemplar).
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/pattern/det.h"
#include "host/pattern/pattern_energy.h"
#include "host/pattern/pattern_surface.h"
#include "host/scene/scene.h"
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

/// Live progress of the phase (a callback may show it; returning false stops the optimiser).
struct PatternProgress {
  std::string stage;       ///< "initialise", "optimise"
  int round = 0;           ///< DET: match/optimise round
  int iteration = 0;       ///< accepted L-BFGS-B iterations so far (over rounds)
  double objective = 0;    ///< P of the current iterate
  int stencils = 0;
  double seconds = 0;      ///< since the phase started
};

struct PatternPhaseOptions {
  int max_iterations = -1;        ///< total L-BFGS-B iterations; −1: pattern.max_iterations
  int iterations_per_round = 0;   ///< 0: 20 for exemplars (re-match between rounds), 100 packing
  bool optimize = true;           ///< false: initialisation only
  /// §6.3: after convergence re-run the initialisation on the layout and optimise again when
  /// it added stencils, at most max_fill_rounds times (scene: structure.fill_holes).
  bool fill_holes = false;
  int max_fill_rounds = 3;
  std::function<bool(const PatternProgress&)> progress;
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
  std::string stop_reason;
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
