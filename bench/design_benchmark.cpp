// End-to-end designs of the paper's examples at Table 1's sizes (built-in scenes), beside the
// paper's own timings (Table 1: "measured from initial distribution to convergence (for the
// pattern-only objective) or from a pattern-optimized solution to a stability-optimized solution").
//
//   BM_Design_<scene>/<budget>   one whole design (uncut shell, pattern phase, structural phase) on
//                                the TBB twins with all threads; budget = L-BFGS-B iterations per
//                                phase (200: the scenes' default; 3000: until the optimiser stops
//                                on its own tolerances).
// Counters (seconds, read off the design's own phase timings, as report.json has them):
//   pattern_s / paper_pattern_s, structure_s / paper_structure_s, and stencils, v, v_sim,
//   iterations, structure_evaluations_per_iteration (objective evaluations per L-BFGS-B iteration
//   of the structural phase), W_max_pattern, W_max_final and W_ratio = W_max_final / W_max_pattern.
// Manual time = pattern_s + structure_s. One iteration per run (a design is seconds long).
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "solvers/optimize/design_pipeline.h"

namespace cutwork {
namespace {

struct PaperRow {
  const char* scene;
  double pattern_seconds;    ///< Table 1, pattern-only
  double structure_seconds;  ///< Table 1, the structural objective of the scene
  int stencils, v, v_sim;    ///< Table 1
};

// Table 1 of the paper (the pavilion's pattern-only time is shared by its three variants).
const std::vector<PaperRow>& paper() {
  static const std::vector<PaperRow> rows{
      {"chair", 4.1, 12.1, 436, 1927, 520},
      {"table", 2.0, 21.2, 462, 1418, 581},
      {"bowl", 0.8, 16.6, 185, 1529, 772},
      {"pavilion", 4.2, 43.4, 310, 937, 381},
      {"pavilion-adaptive", 4.2, 150.8, 310, 937, 381},
      {"pavilion-compliance", 4.2, 5.1, 310, 937, 381},
  };
  return rows;
}

void BM_Design(benchmark::State& state, const PaperRow& row) {
  const int budget = int(state.range(0));
  const Scene scene = load_scene(row.scene);
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  solvers::DesignResult r;
  for (auto _ : state) {
    PatternContext ctx(scene, meshes);
    solvers::DesignOptions o;
    o.pattern_iterations = budget;
    o.structure_iterations = budget;
    r = solvers::run_design(scene, meshes, lc, ctx, o);
    const double structure = r.structure ? r.structure->seconds : 0.0;
    state.SetIterationTime(r.pattern.seconds + structure);
  }
  const double structure = r.structure ? r.structure->seconds : 0.0;
  state.counters["pattern_s"] = r.pattern.seconds;
  state.counters["paper_pattern_s"] = row.pattern_seconds;
  state.counters["structure_s"] = structure;
  state.counters["paper_structure_s"] = row.structure_seconds;
  state.counters["stencils"] = double(r.layout.size());
  state.counters["paper_stencils"] = row.stencils;
  state.counters["v"] = meshes.base.num_vertices();
  state.counters["v_sim"] = meshes.sim.num_vertices();
  state.counters["iterations"] = double(r.pattern.iterations + (r.structure ? r.structure->iterations : 0));
  if (r.structure && r.structure->iterations > 0)
    state.counters["structure_evaluations_per_iteration"] =
        double(r.structure->evaluations) / double(r.structure->iterations);
  state.counters["W_max_pattern"] = r.pattern_design.summary.W_max;
  state.counters["W_max_final"] = r.final_design.summary.W_max;
  state.counters["W_ratio"] = r.final_design.summary.W_max / r.pattern_design.summary.W_max;
  state.counters["C_ratio"] = r.final_design.summary.compliance / r.pattern_design.summary.compliance;
  state.SetLabel(r.structure ? r.structure->objective + ", " + r.structure->stop_reason : "pattern only");
}

const bool registered = [] {
  for (const PaperRow& row : paper()) {
    const std::string name = std::string("BM_Design_") + row.scene;
    benchmark::RegisterBenchmark(name.c_str(), [&row](benchmark::State& s) { BM_Design(s, row); })
        ->Arg(200)
        ->Arg(3000)
        ->Iterations(1)
        ->UseManualTime()
        ->Unit(benchmark::kSecond);
  }
  return true;
}();

}  // namespace
}  // namespace cutwork
