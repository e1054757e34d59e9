#include "solvers/optimize/structure_phase.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/core/timer.h"
#include "host/pattern/overlaps.h"
#include "solvers/objective/energy_density.h"
#include "solvers/objective/structural_quantities.h"

namespace cutwork::solvers {

namespace {

/// The dimensionless S of the chosen objective at the shell's current equilibrium; W (#F) too.
/// (W is the measure: W_peak when `K` is given.)
ObjectiveTerms objective_terms(const StencilledShell& shell, StructuralObjective objective, double beta,
                               double w_ref, double c_ref, const ConcentrationMap* K, Eigen::VectorXd& W) {
  const ShellModel& model = shell.model();
  const RowMatX3d& x = shell.solver().positions();
  const Eigen::VectorXd& alpha = shell.solver().alpha();
  if (objective == StructuralObjective::Compliance) {
    W = energy_density(model, x, alpha);
    return compliance_objective(model, x, alpha, c_ref);
  }
  if (!K) return energy_density_objective(model, x, alpha, beta, w_ref, &W);
  const PeakMeasure peak{K, shell.cell_filter().identity() ? nullptr : &shell.cell_filter().blend(), shell.cover()};
  return energy_density_objective(model, x, alpha, beta, w_ref, &W, &peak);
}

/// The per-face values the adaptive threshold is a statistic of: W, or W_peak.
const Eigen::VectorXd& measured_density(const EquilibriumSummary& s, DensityMeasure measure) {
  if (measure == DensityMeasure::Mean) return s.energy_density;
  if (s.peak_energy_density.size() == 0)
    throw InputError("structure.measure 'peak' needs concentration factors: mechanics.stiffness must be 'homogenised'");
  return s.peak_energy_density;
}

bool same_params(std::span<const StencilParams> a, const std::vector<StencilParams>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].position != b[i].position || a[i].scale != b[i].scale || a[i].angle != b[i].angle ||
        a[i].type != b[i].type)
      return false;
  return true;
}

}  // namespace

StructuralTerm::StructuralTerm(StencilledShell& shell, StructuralObjective objective, double w_S,
                               double beta, double w_ref, double c_ref, double target_covered_area)
    : m_shell(shell),
      m_objective(objective),
      m_w_S(w_S),
      m_beta(beta),
      m_w_ref(w_ref),
      m_c_ref(c_ref),
      m_target(target_covered_area) {
  if (objective == StructuralObjective::None)
    throw InternalError("StructuralTerm: the structural objective is 'none'");
}

void StructuralTerm::set_measure(DensityMeasure measure) {
  m_measure = measure;
  m_K = ConcentrationMap();
  if (measure == DensityMeasure::Mean) return;
  m_K = ConcentrationMap::for_mechanics(m_shell.model().mechanics(), m_shell.model().material());
  if (m_K.empty())
    throw InputError("structure.measure 'peak' needs concentration factors: mechanics.stiffness must be 'homogenised'");
}

void StructuralTerm::place(std::span<const StencilParams> params) {
  if (m_placed_valid && same_params(params, m_placed)) return;
  m_shell.set_stencils(params);
  m_placed.assign(params.begin(), params.end());
  m_placed_valid = true;
}

void StructuralTerm::restore(std::vector<StencilParams>& params) {
  m_restored = true;
  if (!constrained() || params.empty()) return;
  const int S = int(params.size());
  m_scales.resize(S);
  for (int i = 0; i < S; ++i) m_scales[i] = params[size_t(i)].scale;
  // Newton on k: C(q, k s, φ) = target, C the covered area (monotone in k where stencils do
  // not overlap; a step that overshoots is halved).
  std::vector<StencilParams> trial = params;
  auto scaled = [&](int i) { return m_frozen.empty() || !m_frozen[size_t(i)]; };
  auto covered_at = [&](double k, Eigen::VectorXd* dC) {
    for (int i = 0; i < S; ++i) trial[size_t(i)].scale = scaled(i) ? k * m_scales[i] : m_scales[i];
    m_placed_valid = false;
    place(trial);
    return m_shell.covered_area(dC);
  };
  double k = 1;
  Eigen::VectorXd dC;
  double C = covered_at(k, &dC);
  const double tol = 1e-12 * std::max(m_target, 1e-300);
  for (int it = 0; it < 30 && std::abs(C - m_target) > tol; ++it) {
    double dCdk = 0;
    for (int i = 0; i < S; ++i)
      if (scaled(i)) dCdk += m_scales[i] * dC[5 * i + 3];
    if (!(dCdk > 0)) break;  // every stencil off the mesh or clamped: nothing to restore with
    double step = -(C - m_target) / dCdk;
    double Cn = C;
    Eigen::VectorXd dCn;
    for (int half = 0; half < 30; ++half, step *= 0.5) {
      if (!(k + step > 0)) continue;
      Cn = covered_at(k + step, &dCn);
      if (std::abs(Cn - m_target) < std::abs(C - m_target)) break;
    }
    k += step;
    C = Cn;
    dC = std::move(dCn);
  }
  // Unreachable (stencils piled on each other saturate the covered area): the point is not
  // admissible, and evaluate() says so with +∞, which makes the line search back off.
  m_restored = std::abs(C - m_target) <= 1e-9 * std::max(m_target, 1e-300);
  m_k = k;
  m_dC = std::move(dC);
  params = trial;
  ++m_restorations;
  m_max_k_change = std::max(m_max_k_change, std::abs(k - 1));
}

void StructuralTerm::restore_pullback(Eigen::VectorXd& g) const {
  if (!constrained() || m_scales.size() == 0) return;
  // p̃ = (q, k(p) s, φ) with C(p̃) = target: dk/dp = −(∂C/∂p at fixed k) / (∂C/∂k), where
  // ∂C/∂q, ∂C/∂φ are taken at p̃ and ∂C/∂s_i = k ∂C/∂s̃_i; ∂C/∂k = Σ s_i ∂C/∂s̃_i.
  const int S = int(m_scales.size());
  // (Only during the optimisation: finalize() freezes stencils after it, and nothing is
  // differentiated then.)
  double dCdk = 0, a = 0;
  for (int i = 0; i < S; ++i) {
    dCdk += m_scales[i] * m_dC[5 * i + 3];
    a += m_scales[i] * g[5 * i + 3];  // dJ/dk at fixed p
  }
  if (!(dCdk > 0)) return;
  for (int i = 0; i < S; ++i) {
    for (int c = 0; c < 5; ++c) {
      const double dC_dp = c == 3 ? m_k * m_dC[5 * i + 3] : m_dC[5 * i + c];
      if (c == 3) g[5 * i + 3] *= m_k;
      g[5 * i + c] -= a * dC_dp / dCdk;
    }
  }
}

void StructuralTerm::finalize(const PatternSurface& surface, double safety, double gap, StencilLayout& layout) {
  if (!constrained() || layout.empty()) return;
  int S = int(layout.size());
  m_frozen.assign(size_t(S), 0);
  for (int pass = 0; pass < 50 && S > 0; ++pass) {
    std::vector<StencilParams> p = layout_params(layout);
    restore(p);
    for (int i = 0; i < S; ++i) layout[size_t(i)].scale = p[size_t(i)].scale;
    if (!m_restored && gap > 0) {
      // The minimum feature leaves no room for the start's stencil area: keep the largest
      // admissible layout the restoration reached (shrunk where it breaks the gap) and say how far
      // below the target it ends.
      resolve_overlaps(surface, layout, safety, Eigen::VectorXd::Zero(S), gap);
      m_placed_valid = false;
      place(layout_params(layout));
      const double reached = m_shell.covered_area(nullptr);
      m_finalize_note = fmt::format(
          "compliance: the stencil area ends at {:.6g} m², {:.2f}% below the {:.6g} m² it was held at: "
          "fabrication.min_feature ({:.3g} m) leaves no room to restore it",
          reached, 100 * (1 - reached / m_target), m_target, gap);
      break;
    }
    if (!m_restored)
      throw SolveError(fmt::format("the total stencil area cannot be restored to {:.6g} m² once overlapping "
                                   "stencils are shrunk; lower structure.w_S or the stencil density",
                                   m_target));
    if (!find_overlaps(surface, layout, safety, gap).any()) break;
    std::vector<double> before(static_cast<size_t>(S));
    for (int i = 0; i < S; ++i) before[size_t(i)] = layout[size_t(i)].scale;
    // Shrinks only; a stencil is removed only when it would vanish (centre on the boundary).
    if (resolve_overlaps(surface, layout, safety, Eigen::VectorXd::Zero(S), gap) > 0) {
      S = int(layout.size());
      m_frozen.assign(size_t(S), 0);
      continue;
    }
    for (int i = 0; i < S; ++i)
      if (layout[size_t(i)].scale != before[size_t(i)]) m_frozen[size_t(i)] = 1;
  }
  m_frozen.clear();
}

std::optional<ObjectiveTerms> StructuralTerm::solve(std::span<const StencilParams> params) {
  place(params);
  try {
    if (!m_shell.equilibrate().stable) return std::nullopt;
  } catch (const SolveError&) {
    return std::nullopt;
  }
  Eigen::VectorXd W;
  ObjectiveTerms t = objective_terms(m_shell, m_objective, m_beta, m_w_ref, m_c_ref,
                                     m_measure == DensityMeasure::Peak ? &m_K : nullptr, W);
  m_last_S = t.value;
  // W_max over material (structural_quantities.h), as the reports give it: of the mean W also
  // when the objective measures W_peak.
  if (m_measure == DensityMeasure::Peak)
    W = energy_density(m_shell.model(), m_shell.solver().positions(), m_shell.solver().alpha());
  const std::vector<bool> material = material_faces(m_shell.alpha());
  m_last_W_max = 0;
  for (Eigen::Index f = 0; f < W.size(); ++f)
    if (material[size_t(f)]) m_last_W_max = std::max(m_last_W_max, W[f]);
  return t;
}

double StructuralTerm::structure(std::span<const StencilParams> params) {
  const std::optional<ObjectiveTerms> t = solve(params);
  return t ? t->value : INFINITY;
}

double StructuralTerm::evaluate(std::span<const StencilParams> params, Eigen::VectorXd* gradient) {
  if (!m_restored) return INFINITY;
  const std::optional<ObjectiveTerms> t = solve(params);
  if (!t) return INFINITY;
  if (gradient) {
    m_shell.parameter_gradient(*t, *gradient);
    *gradient *= m_w_S;
  }
  return m_w_S * t->value;
}

namespace {

using Objective = StructuralObjective;

AdaptiveThreshold adaptive_mode(const StructureSettings& settings) {
  return settings.adaptive_mode == "median" ? AdaptiveThreshold::Median : AdaptiveThreshold::TopPercent;
}

/// The pattern design's equilibrium gives the references of compliance and adaptivity: c_ref,
/// the covered area the compliance constraint holds, and the first β (in result.beta).
void pattern_design_references(StencilledShell& shell, const StructureSettings& settings, double w_ref,
                               StructurePhaseResult& result) {
  shell.set_stencils(layout_params(result.layout));
  shell.equilibrate();
  const EquilibriumSummary pattern = shell.summary();
  result.c_ref = pattern.compliance;
  result.covered_area_target = shell.covered_area(nullptr);
  result.beta = settings.beta * w_ref;
  if (settings.objective == Objective::Adaptive)
    result.beta = adaptive_threshold(measured_density(pattern, settings.measure), adaptive_mode(settings),
                                     settings.adaptive_y);
  if (settings.objective == Objective::Compliance && !(result.c_ref > 0))
    throw SolveError("the pattern design's loads do no work (compliance 0): nothing to minimise");
}

/// The pattern term per stencil: S is intensive (a mean over triangles), so P is made one too
/// and J does not depend on how many stencils or triangles the design has. The admissibility
/// terms (collision, boundary, tether) keep their pattern-phase strength: they are constraints,
/// not taste, and must not weaken as the design grows. The collision terms keep `gap` of material
/// (the minimum feature) while the phase runs. Restores the energy's scale and gap when done.
class PerStencilPattern {
 public:
  PerStencilPattern(PatternContext& ctx, double gap) : m_ctx(ctx) { m_ctx.energy().set_gap(gap); }
  ~PerStencilPattern() {
    m_ctx.energy().set_admissibility(1.0);
    m_ctx.energy().set_gap(0.0);
  }
  PerStencilPattern(const PerStencilPattern&) = delete;
  PerStencilPattern& operator=(const PerStencilPattern&) = delete;

  /// w_P / #S for `layout` (and the energy's admissibility scaled to match).
  double weight(const StencilLayout& layout) const {
    const double n = double(std::max<size_t>(1, layout.size()));
    m_ctx.energy().set_admissibility(n);
    return m_ctx.settings().w_P / n;
  }
  /// J = w_S S + w_P P at `layout` (fresh matching), with S and P (per stencil).
  double joint_value(StructuralTerm& term, double w_S, const StencilLayout& layout, double& S, double& P) const {
    const double w = weight(layout);
    m_ctx.energy().rematch(layout);
    P = w / m_ctx.settings().w_P * m_ctx.energy().evaluate(layout);
    S = term.structure(layout_params(layout));
    return w_S * S + m_ctx.settings().w_P * P;
  }

 private:
  PatternContext& m_ctx;
};

/// The optimisations of the phase (adaptive β updates, hole filling), from the start or from a
/// checkpoint, with the checkpoint hook at every optimiser boundary.
void optimize_structure(PatternContext& ctx, const StencilledShell& shell, StructuralTerm& term,
                        const PerStencilPattern& pattern, const StructureSettings& settings,
                        const StructurePhaseOptions& options, StructurePhaseResult& result) {
  const PhaseCheckpoints<StructurePhaseResult>& cp = options.checkpoints;
  StencilLayout& layout = result.layout;
  PatternRng rng(options.seed);
  PhaseCursor cursor;
  const JointOptimizerState* from = nullptr;
  if (cp.resume) {
    rng.set_state(cp.resume->rng);
    cursor = cp.resume->cursor;
    from = &cp.resume->optimizer;
  }
  JointOptimizerOptions po;
  po.joint = &term;
  po.max_rotation = settings.max_rotation * std::numbers::pi / 180.0;
  po.min_gap = options.min_feature;
  po.max_iterations = options.max_iterations >= 0 ? options.max_iterations : settings.max_iterations;
  po.progress = options.progress;
  if (cp.save)
    po.checkpoint = [&](const JointOptimizerState& st, const LbfgsbState* lbfgsb) {
      result.beta = term.beta();
      result.restorations = term.restorations();
      result.max_restoring_change = term.max_restoring_change();
      cp.save(result, PhaseSnapshot{cursor, rng, st, lbfgsb});
    };
  auto optimize = [&](int fill) {
    cursor.fill = fill;
    po.w_P = pattern.weight(from ? from->layout : layout);
    optimize_pattern(ctx, layout, po, result, std::exchange(from, nullptr));
    ++result.optimisations;
  };
  const int optimisations = settings.objective == Objective::Adaptive ? settings.max_rounds : 1;
  for (int k = cursor.outer; k < optimisations; ++k) {
    cursor.outer = k;
    const int resume_fill = from ? cursor.fill : 0;
    if (!from) result.beta_history.push_back(term.beta());
    if (resume_fill == 0) optimize(0);
    // §6.3: fill the holes the optimisation opened, and continue when stencils were added.
    if (settings.fill_holes)
      fill_holes_and_reoptimize(ctx, layout, rng, 3, result.inserted_by_hole_filling, [&](int j) {
        if (settings.objective == Objective::Compliance && !from) {
          // New stencils add area; the constraint holds the design's total, so restore it.
          std::vector<StencilParams> p = layout_params(layout);
          term.restore(p);
          for (size_t i = 0; i < layout.size(); ++i) layout[i].scale = p[i].scale;
        }
        optimize(j);
      }, resume_fill);
    if (settings.objective != Objective::Adaptive) break;
    // Adaptive: move β to the statistic of the converged design; stop when it settles.
    if (!std::isfinite(term.structure(layout_params(layout)))) break;
    const double next =
        adaptive_threshold(measured_density(shell.summary(), settings.measure), adaptive_mode(settings), settings.adaptive_y);
    if (std::abs(next - term.beta()) <= 1e-3 * result.w_ref) break;
    term.set_beta(next);
  }
}

}  // namespace

StructurePhaseResult run_structure_phase(PatternContext& ctx, StencilledShell& shell, const StructureSettings& settings,
                                         const StencilLayout& start, double w_ref,
                                         const StructurePhaseOptions& options) {
  Stopwatch clock;
  if (settings.objective == Objective::None) throw InternalError("run_structure_phase: the structural objective is 'none'");
  if (!(w_ref > 0)) throw SolveError("the uncut shell carries no strain energy: W_max is 0");
  const PhaseCheckpoints<StructurePhaseResult>& cp = options.checkpoints;
  // The minimum feature: the start is made to keep it, the pattern term's collision penalties
  // keep it softly while the optimiser runs, and the overlap resolution after each optimisation
  // exactly (compliance: with its area restored, StructuralTerm::finalize).
  const double min_gap = options.min_feature;
  StructurePhaseResult result;
  if (cp.resume) {
    result = *cp.resume_result;
  } else {
    result.objective = settings.objective == Objective::EnergyDensity ? "energy_density"
                       : settings.objective == Objective::Adaptive    ? "adaptive"
                                                                      : "compliance";
    result.w_ref = w_ref;
    result.layout = start;
    if (result.layout.empty())
      throw InputError("the structural phase needs stencils, and the pattern phase placed none");
    if (min_gap > 0) {
      // The phase starts from the pattern design made to keep the minimum feature (shrinking, a
      // stencil removed only below ¾ of its lower scale bound, as after every optimisation): its
      // references (c_ref, the covered area held by compliance) are then reachable ones.
      Eigen::VectorXd lower, upper;
      ctx.scale_bounds(result.layout, lower, upper);
      result.removed_for_min_feature =
          resolve_overlaps(ctx.surface(), result.layout, ctx.settings().s, 0.75 * lower, min_gap);
      if (result.layout.empty())
        throw InputError("no stencil keeps fabrication.min_feature of material to its neighbours and the border");
    }
    pattern_design_references(shell, settings, w_ref, result);
  }
  StructuralTerm term(shell, settings.objective, settings.w_S, result.beta, w_ref, result.c_ref,
                      result.covered_area_target);
  term.set_measure(settings.measure);
  const PerStencilPattern pattern(ctx, min_gap);
  if (cp.resume) {
    term.set_counters(result.restorations, result.max_restoring_change);
  } else {
    result.J_start = pattern.joint_value(term, settings.w_S, result.layout, result.S_start, result.P_start);
    if (!std::isfinite(result.S_start))
      throw SolveError("the pattern design has no stable equilibrium under the scene's loads");
  }
  optimize_structure(ctx, shell, term, pattern, settings, options, result);
  if (!term.finalize_note().empty()) result.notes.push_back(term.finalize_note());

  result.beta = settings.objective == Objective::Compliance ? std::nan("") : term.beta();
  result.J_end = pattern.joint_value(term, settings.w_S, result.layout, result.S_end, result.P_end);
  result.covered_area_final = shell.covered_area(nullptr);
  result.restorations = term.restorations();
  result.max_restoring_change = term.max_restoring_change();
  result.seconds = clock.seconds();
  return result;
}

}  // namespace cutwork::solvers
