#include "solvers/optimize/design_pipeline.h"

#include <memory>

#include "host/core/error.h"
#include "host/pattern/overlaps.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/objective/energy_density_reference.h"

namespace cutwork::solvers {

DesignState evaluate_design(StencilledShell& shell, const PatternContext& ctx, const StencilLayout& layout) {
  DesignState d;
  d.stencils = int(layout.size());
  shell.set_stencils(layout_params(layout));
  d.stats = shell.equilibrate();
  d.summary = shell.summary();
  d.displacement = shell.solver().displacements();
  if (!shell.cell_filter().identity()) d.concentration_weight = shell.cell_filter().blend();
  if (shell.cover()) d.cover = *shell.cover();
  d.alpha = shell.alpha();
  d.material_fraction = shell.material_fraction();
  if (!layout.empty()) d.overlaps = find_overlaps(ctx.surface(), layout, ctx.settings().s);
  return d;
}

namespace {

/// The pattern phase, or what a checkpoint says of it.
PatternPhaseResult pattern_phase(PatternContext& ctx, const DesignOptions& options) {
  const DesignResume* resume = options.resume;
  if (resume && resume->stage != DesignStage::Pattern) return resume->pattern;
  PatternPhaseOptions po;
  po.max_iterations = options.pattern_iterations;
  if (options.progress) po.progress = [&](const PatternProgress& p) { return options.progress("pattern", p); };
  if (options.checkpoint)
    po.checkpoints.save = [&](const PatternPhaseResult& partial, const PhaseSnapshot& phase) {
      options.checkpoint({DesignStage::Pattern, partial, nullptr, &phase, nullptr, nullptr});
    };
  if (resume) {
    po.checkpoints.resume_result = &resume->pattern;
    po.checkpoints.resume = &resume->phase;
  }
  PatternPhaseResult pattern = run_pattern_phase(ctx, po);
  if (options.checkpoint) options.checkpoint({DesignStage::PatternEnd, pattern, nullptr, nullptr, nullptr, nullptr});
  return pattern;
}

}  // namespace

double beta_reference(const DesignState& uncut, const SurfaceMesh& sim) {
  const EnergyDensityQuantile q =
      energy_density_quantile(uncut.summary.energy_density, sim.face_areas(), material_faces(uncut.alpha));
  return q.value > 0 ? q.value : uncut.summary.W_max;
}

namespace {

/// The structural phase (from the pattern design), or what a checkpoint says of it; the shell is
/// restored to a checkpoint's state first.
StructurePhaseResult structure_phase(const Scene& scene, PatternContext& ctx, StencilledShell& shell,
                                     const DesignResult& r, const DesignOptions& options) {
  const DesignResume* resume = options.resume;
  if (resume && resume->stage != DesignStage::Structure && resume->stage != DesignStage::StructureEnd) resume = nullptr;
  if (resume) shell.restore_equilibrium(resume->shell_stencils, resume->equilibrium);
  if (resume && resume->stage == DesignStage::StructureEnd) return resume->structure;
  StructurePhaseOptions so;
  so.max_iterations = options.structure_iterations;
  so.seed = scene.pattern.seed;
  so.min_feature = scene.fabrication.min_feature;
  if (options.progress) so.progress = [&](const PatternProgress& p) { return options.progress("structure", p); };
  if (options.checkpoint)
    so.checkpoints.save = [&](const StructurePhaseResult& partial, const PhaseSnapshot& phase) {
      options.checkpoint({DesignStage::Structure, r.pattern, &partial, &phase, &shell.equilibrium_stencils(),
                          &shell.solver().positions()});
    };
  if (resume) {
    so.checkpoints.resume_result = &resume->structure;
    so.checkpoints.resume = &resume->phase;
  }
  StructurePhaseResult structure =
      run_structure_phase(ctx, shell, scene.structure, r.pattern.layout, beta_reference(r.uncut, shell.model().mesh()), so);
  if (options.checkpoint)
    options.checkpoint({DesignStage::StructureEnd, r.pattern, &structure, nullptr, &shell.equilibrium_stencils(),
                        &shell.solver().positions()});
  return structure;
}

}  // namespace

DesignResult run_design(const Scene& scene, const SceneMeshes& meshes, const LoadCase& load_case,
                        PatternContext& ctx, const DesignOptions& options) {
  DesignResult r;
  Stopwatch sw;
  // A lattice stated to follow the orientation field reads it through the pattern context's field.
  r.mechanics = measured_lattice(scene.mechanics, ctx.surface().bvh(), ctx.surface().field(), {}, r.notes);
  auto build_shell = [&] {
    auto shell = std::make_unique<StencilledShell>(meshes.sim, ctx.surface().bvh(), scene.material, r.mechanics,
                                                   load_case, ctx.shapes(), ctx.surface().field(), options.fill);
    shell->set_cell_filter(scene_cell_filter(scene, ctx, meshes.sim));
    return shell;
  };
  std::unique_ptr<StencilledShell> shell_ptr = build_shell();
  r.timings.add("model", sw.seconds());

  sw.restart();
  r.uncut = evaluate_design(*shell_ptr, ctx, {});
  if (!r.uncut.stats.stable)
    throw SolveError("the uncut shell has no stable equilibrium under the scene's loads (it buckles): "
                     "lower the loads or stiffen the shell");
  r.timings.add("uncut", sw.seconds());

  sw.restart();
  r.pattern = pattern_phase(ctx, options);
  r.timings.add("pattern", sw.seconds());

  // "lattice": "auto" is read from the pattern's layout, which the structural phase starts from, and
  // kept: a lattice read as the stencils move would switch the model under the optimiser. (The
  // uncut shell is the same on either lattice: every face is whole.)
  r.mechanics = measured_lattice(scene.mechanics, ctx.surface().bvh(), ctx.surface().field(),
                                 layout_params(r.pattern.layout), r.notes);
  StencilledShell::StageTimes before;  // of a shell the lattice's reading replaced
  if (r.mechanics.lattice != scene.mechanics.lattice ||
      r.mechanics.lattice_follows_field != scene.mechanics.lattice_follows_field) {
    sw.restart();
    before = shell_ptr->times();
    shell_ptr = build_shell();
    r.timings.add("model", sw.seconds());
  }
  StencilledShell& shell = *shell_ptr;

  sw.restart();
  r.pattern_design = evaluate_design(shell, ctx, r.pattern.layout);
  if (!r.pattern_design.stats.stable)
    throw SolveError("the pattern design has no stable equilibrium under the scene's loads: lower the "
                     "loads, or use fewer or smaller stencils");
  r.timings.add("pattern_equilibrium", sw.seconds());

  r.layout = r.pattern.layout;
  if (options.structure && scene.structure.objective != StructuralObjective::None) {
    sw.restart();
    r.structure = structure_phase(scene, ctx, shell, r, options);
    r.layout = r.structure->layout;
    r.timings.add("structure", sw.seconds());
  }

  sw.restart();
  r.final_design = r.structure ? evaluate_design(shell, ctx, r.layout) : r.pattern_design;
  r.timings.add("final_equilibrium", sw.seconds());
  r.stage_times = shell.times();
  r.stage_times.add(before);
  return r;
}

}  // namespace cutwork::solvers
