#include "solvers/optimize/pattern_phase.h"

#include <utility>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/timer.h"
#include "host/pattern/overlaps.h"

namespace cutwork::solvers {

namespace {

/// The phase up to the optimisation: what the context chose, the initial layout, P there.
PatternPhaseResult initialize(PatternContext& ctx, const PatternPhaseOptions& options, PatternRng& rng,
                              const Stopwatch& clock, StencilLayout& layout) {
  PatternPhaseResult result;
  result.objective = ctx.kind() == PatternKind::Exemplar ? "exemplar" : "packing";
  if (ctx.exemplar()) result.exemplar = ctx.exemplar()->exemplar().name;
  result.field_symmetry = ctx.symmetry();
  result.unit = ctx.unit();
  result.epsilon = ctx.epsilon();
  result.notes = ctx.notes();

  layout = ctx.initialize(rng);
  result.initial_count = int(layout.size());
  result.seconds_initialize = clock.seconds();
  if (options.progress) options.progress({"initialise", 0, 0, 0.0, int(layout.size()), clock.seconds()});
  if (layout.empty())
    throw InputError(fmt::format(
        "{}: no stencil fits on the surface at scale {:.4g} m with safety factor {:.4g}; lower "
        "pattern.scale or pattern.s",
        ctx.settings().objective == PatternObjective::Exemplar ? "pattern (exemplar)" : "pattern",
        ctx.unit(), ctx.settings().s));
  ctx.energy().rematch(layout);
  result.objective_start = ctx.energy().evaluate(layout);
  return result;
}

/// The optimisation, then (§6.3) hole filling and re-optimisation, from the start or from a
/// checkpoint, with the checkpoint hook at every optimiser boundary.
void optimize_phase(PatternContext& ctx, const PatternPhaseOptions& options, PatternRng& rng, PhaseCursor& cursor,
                    StencilLayout& layout, PatternPhaseResult& result) {
  const PhaseCheckpoints<PatternPhaseResult>& cp = options.checkpoints;
  JointOptimizerOptions jo = options;
  if (cp.save)
    jo.checkpoint = [&](const JointOptimizerState& st, const LbfgsbState* lbfgsb) {
      cp.save(result, PhaseSnapshot{cursor, rng, st, lbfgsb});
    };
  const JointOptimizerState* from = cp.resume ? &cp.resume->optimizer : nullptr;
  auto optimize = [&](int fill) {
    cursor.fill = fill;
    optimize_pattern(ctx, layout, jo, result, std::exchange(from, nullptr));
  };
  if (cursor.fill == 0) optimize(0);
  if (options.fill_holes)
    fill_holes_and_reoptimize(ctx, layout, rng, options.max_fill_rounds, result.inserted_by_hole_filling, optimize,
                              from ? cursor.fill : 0);
}

}  // namespace

PatternPhaseResult run_pattern_phase(PatternContext& ctx, const PatternPhaseOptions& options) {
  Stopwatch clock;
  const PhaseCheckpoints<PatternPhaseResult>& cp = options.checkpoints;
  PatternRng rng(ctx.settings().seed);
  StencilLayout layout;
  PhaseCursor cursor;
  PatternPhaseResult result;
  if (cp.resume) {
    result = *cp.resume_result;
    rng.set_state(cp.resume->rng);
    cursor = cp.resume->cursor;
  } else {
    result = initialize(ctx, options, rng, clock, layout);
  }
  if (options.optimize) {
    optimize_phase(ctx, options, rng, cursor, layout, result);
  } else {
    Eigen::VectorXd lower, upper;
    ctx.scale_bounds(layout, lower, upper);
    result.removed = resolve_overlaps(ctx.surface(), layout, ctx.settings().s, lower);
  }
  ctx.energy().rematch(layout);
  result.objective_end = ctx.energy().evaluate(layout, &result.terms_end);

  const int S = int(layout.size());
  result.normals.resize(S, 3);
  result.tangents.resize(S, 3);
  result.bounding_radii.resize(S);
  for (int i = 0; i < S; ++i) {
    Vec3 n, t, b;
    ctx.surface().frame_at(layout[size_t(i)].where, n, t, b);
    result.normals.row(i) = n.transpose();
    result.tangents.row(i) = t.transpose();
    result.bounding_radii[i] = layout[size_t(i)].scale;
  }
  result.layout = std::move(layout);
  result.seconds = clock.seconds();
  return result;
}

PatternPhaseResult run_pattern_phase(const Scene& scene, const SceneMeshes& meshes,
                                     const PatternPhaseOptions& options) {
  PatternContext ctx(scene, meshes);
  return run_pattern_phase(ctx, options);
}

}  // namespace cutwork::solvers
