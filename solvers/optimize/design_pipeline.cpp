#include "solvers/optimize/design_pipeline.h"

#include "host/core/error.h"
#include "host/pattern/overlaps.h"

namespace cutwork::solvers {

DesignState evaluate_design(StencilledShell& shell, const PatternContext& ctx, const StencilLayout& layout) {
  DesignState d;
  d.stencils = int(layout.size());
  shell.set_stencils(layout_params(layout));
  d.stats = shell.equilibrate();
  d.summary = shell.summary();
  d.alpha = shell.alpha();
  d.material_fraction = shell.material_fraction();
  if (!layout.empty()) d.overlaps = find_overlaps(ctx.surface(), layout, ctx.settings().s);
  return d;
}

DesignResult run_design(const Scene& scene, const SceneMeshes& meshes, const LoadCase& load_case,
                        PatternContext& ctx, const DesignOptions& options) {
  DesignResult r;
  Stopwatch sw;
  StencilledShell shell(meshes.sim, ctx.surface().bvh(), scene.material, scene.mechanics, load_case, ctx.shapes(),
                        ctx.surface().field(), options.fill);
  r.timings.add("model", sw.seconds());

  sw.restart();
  r.uncut = evaluate_design(shell, ctx, {});
  if (!r.uncut.stats.stable)
    throw SolveError("the uncut shell has no stable equilibrium under the scene's loads (it buckles): "
                     "lower the loads or stiffen the shell");
  r.timings.add("uncut", sw.seconds());

  sw.restart();
  PatternPhaseOptions po;
  po.max_iterations = options.pattern_iterations;
  if (options.progress) po.progress = [&](const PatternProgress& p) { return options.progress("pattern", p); };
  if (options.resume_pattern) {
    r.pattern = *options.resume_pattern;
  } else {
    r.pattern = run_pattern_phase(ctx, po);
    if (options.pattern_done) options.pattern_done(r.pattern);
  }
  r.timings.add("pattern", sw.seconds());

  sw.restart();
  r.pattern_design = evaluate_design(shell, ctx, r.pattern.layout);
  if (!r.pattern_design.stats.stable)
    throw SolveError("the pattern design has no stable equilibrium under the scene's loads: lower the "
                     "loads, or use fewer or smaller stencils");
  r.timings.add("pattern_equilibrium", sw.seconds());

  r.layout = r.pattern.layout;
  if (options.structure && scene.structure.objective != StructuralObjective::None) {
    sw.restart();
    StructurePhaseOptions so;
    so.max_iterations = options.structure_iterations;
    so.seed = scene.pattern.seed;
    if (options.progress) so.progress = [&](const PatternProgress& p) { return options.progress("structure", p); };
    r.structure = run_structure_phase(ctx, shell, scene.structure, r.pattern.layout, r.uncut.summary.W_max, so);
    r.layout = r.structure->layout;
    r.timings.add("structure", sw.seconds());
  }

  sw.restart();
  r.final_design = r.structure ? evaluate_design(shell, ctx, r.layout) : r.pattern_design;
  r.timings.add("final_equilibrium", sw.seconds());
  r.stage_times = shell.times();
  return r;
}

}  // namespace cutwork::solvers
