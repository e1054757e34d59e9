#pragma once
/// The joint optimiser of (19): L-BFGS-B rounds over the stencil parameters of a layout, shared
/// by the pattern phase (pattern only, w_S = 0: solvers/optimize/pattern_phase.h) and the
/// structural phase (with a JointTerm w_S·S: solvers/optimize/structure_phase.h).
///
/// One call of optimize_pattern runs rounds: (re-)match the DET neighbourhoods, one L-BFGS-B run
/// of at most `iterations_per_round` iterations against that frozen matching, project the
/// stencils back onto the surface, vote the stencil types (exemplars) — until L-BFGS-B converges
/// with nothing left to change, the iteration budget is spent, or the rounds stall. Then the
/// overlaps the soft collision penalty left are removed by shrinking (host/pattern/overlaps.h).
///
/// Variables per stencil, x = (q/ℓ, s/ℓ[, φ]) with ℓ the context's unit: positions first (#S×3),
/// then scales (#S), then the angles (#S) when a joint term sees them (P does not depend on φ).
/// Scale bounds are taken from the layout when the call starts (PatternContext::scale_bounds);
/// angles stay within ±max_rotation of their start.
#include <cmath>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "host/pattern/pattern_context.h"
#include "host/pattern/random.h"
#include "solvers/optimize/lbfgsb.h"
#include "solvers/optimize/pattern_progress.h"

namespace cutwork::solvers {

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
  /// `gap` (m): the overlap resolution's absolute gap (overlaps.h).
  virtual void finalize(const PatternSurface& surface, double safety, double gap, StencilLayout& layout) {
    (void)surface, (void)safety, (void)gap, (void)layout;
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

/// The state of an optimize_pattern call at the start of a round or between two L-BFGS-B
/// iterations (checkpoints): given back to optimize_pattern, the call continues exactly where it
/// was, bit for bit (the energy's matching is a function of the layout and is recomputed).
struct JointOptimizerState {
  StencilLayout layout;                 ///< at the start of the current round
  /// The stencil types the current round's DET matching was made with (#S): after a round the
  /// layout is matched, then the types are voted, so they may differ from the layout's.
  std::vector<int> matched_types;
  Eigen::VectorXd lower, upper;         ///< the call's scale bounds (#S, m)
  Eigen::VectorXd angle0;               ///< the call's start angles (#S, rad)
  int used = 0;                         ///< iterations of the call's budget spent
  double scale = 0;                     ///< last inverse-curvature estimate (next round's first step)
  int round = 0;                        ///< rounds ended in this call
  double best_round_end = INFINITY;     ///< the stall rule: best round end so far
  int stalled_rounds = 0;               ///< the stall rule: rounds in a row without progress
  std::optional<LbfgsbState> lbfgsb;    ///< inside a round (resume only): the minimisation's state
};

/// Sees the state at every boundary; `lbfgsb` is the minimisation's state inside a round, null
/// at a round's start (JointOptimizerState::lbfgsb is not filled: it is this).
using JointCheckpoint = std::function<void(const JointOptimizerState& state, const LbfgsbState* lbfgsb)>;

struct JointOptimizerOptions {
  int max_iterations = -1;        ///< total L-BFGS-B iterations; −1: pattern.max_iterations
  int iterations_per_round = 0;   ///< 0: 20 for exemplars (re-match between rounds), 100 packing
  /// The rounds stop when three in a row end less than this (relative) below the best round
  /// end so far ("stalled").
  double round_tolerance = 1e-4;
  std::function<bool(const PatternProgress&)> progress;
  /// The joint optimisation (19): the objective becomes w_P·P + joint (not owned), the angles
  /// φ join the variables within ±max_rotation (rad) of their start, and the overlap resolution
  /// at the end is followed by the term's restoration. Null: pattern only.
  JointTerm* joint = nullptr;
  double w_P = 1.0;
  double max_rotation = 0.0;
  /// The final overlap resolution keeps this much material (m) between the stencils' bounding
  /// circles and between one and the border (overlaps.h's gap): the structural phase passes
  /// fabrication.min_feature, a hard constraint met by shrinking, as the overlaps are.
  double min_gap = 0.0;
  JointCheckpoint checkpoint;     ///< may be empty
};

/// What optimisations did; accumulated over the calls that receive the same object.
struct JointOptimizerStats {
  int rounds = 0;                  ///< L-BFGS-B runs (DET: match/optimise rounds)
  int iterations = 0;              ///< accepted L-BFGS-B iterations
  int evaluations = 0;             ///< objective evaluations
  int type_changes = 0;            ///< by majority vote
  int removed = 0;                 ///< removed by the final overlap resolution
  /// Why the last optimisation ended: "gradient" or "decrease" (L-BFGS-B's tolerances), "stalled"
  /// (three rounds without progress), "iterations" (budget spent), "callback", or "line search: …".
  std::string stop_reason;
  /// The optimiser's objective after each accepted iterate, one list per round (the first
  /// value of each is the round's start): monotone within a round by construction.
  std::vector<std::vector<double>> round_histories;
  double seconds_optimize = 0;
};

/// Optimisation of `layout` in place (no initialisation): the L-BFGS-B rounds and type votes,
/// then the overlap resolution (and the joint term's finalize). Adds to `stats`. `resume` (a
/// state options.checkpoint saw, with `stats` as they were then) continues that call: `layout`
/// is replaced by the state's.
void optimize_pattern(PatternContext& context, StencilLayout& layout, const JointOptimizerOptions& options,
                      JointOptimizerStats& stats, const JointOptimizerState* resume = nullptr);

/// §6.3 hole filling after an optimisation: re-runs the initialisation on `layout` and, while it
/// adds stencils (counted into `inserted` at once), calls `reoptimize(j)` after the j-th filling
/// (at most `max_rounds` times). `resume_round` j ≥ 1 continues a loop that stopped inside
/// reoptimize(j): that filling is not repeated.
void fill_holes_and_reoptimize(const PatternContext& context, StencilLayout& layout, PatternRng& rng, int max_rounds,
                               int& inserted, const std::function<void(int round)>& reoptimize,
                               int resume_round = 0);

}  // namespace cutwork::solvers
