// End-to-end designs of the paper's examples at Table 1's sizes (built-in scenes), beside the
// paper's own timings (Table 1: "measured from initial distribution to convergence (for the
// pattern-only objective) or from a pattern-optimized solution to a stability-optimized solution").
//
//   BM_Design_<scene>/<budget>   one whole design (uncut shell, pattern phase, structural phase) on
//                                the TBB twins with all threads, under the paper's linear fill rule; budget = L-BFGS-B iterations per
//                                phase (200: the scenes' default; 3000: until the optimiser stops
//                                on its own tolerances).
// Counters, read off the design's report.json object (solvers/report, the same report
// `cutwork design` writes; it is built after the timed region):
//   pattern_s / paper_pattern_s, structure_s / paper_structure_s, and stencils, v, v_sim,
//   iterations, structure_evaluations_per_iteration (objective evaluations per L-BFGS-B iteration
//   of the structural phase), W_max_pattern, W_max_final and W_ratio = W_max_final / W_max_pattern.
//   design_cpu_s: CPU seconds (user + system, every thread) of the whole design; structure_cpu_s:
//   those from the end of the pattern phase to the end of the design (the structural phase plus the
//   equilibria of the pattern and final designs) — the figures to compare on a shared machine, where
//   wall times are inflated by other work.
// Manual time = pattern_s + structure_s. One iteration per run (a design is seconds long).
#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <vector>

#include "bench/scene_models.h"
#include "solvers/optimize/design_pipeline.h"
#include "solvers/report/design_report.h"

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
  Scene scene = load_scene(row.scene);
  // The paper's fill rule (9)–(10), as Table 1 timed it (the default homogenised rule adds its
  // calibration, a few seconds per process, and the bulk/shear split's elements).
  scene.mechanics.stiffness = FillStiffness::Linear;
  scene.mechanics.filter = FillFilter::None;
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  solvers::DesignResult r;
  std::unique_ptr<PatternContext> ctx;
  double cpu_start = 0, cpu_structure_start = 0, cpu_end = 0;
  for (auto _ : state) {
    cpu_start = bench::process_cpu_total();
    ctx = std::make_unique<PatternContext>(scene, meshes);
    solvers::DesignOptions o;
    o.pattern_iterations = budget;
    o.structure_iterations = budget;
    o.checkpoint = [&](const solvers::DesignSnapshot& snapshot) {
      if (snapshot.stage == solvers::DesignStage::PatternEnd) cpu_structure_start = bench::process_cpu_total();
    };
    r = solvers::run_design(scene, meshes, lc, *ctx, o);
    cpu_end = bench::process_cpu_total();
    const double structure = r.structure ? r.structure->seconds : 0.0;
    state.SetIterationTime(r.pattern.seconds + structure);
  }
  const nlohmann::json report = solvers::finish_design(scene, meshes, *ctx, r, {}, Stopwatch()).report;
  const nlohmann::json& phases = report["phases"];
  const nlohmann::json& st = report["structure"];
  const double structure = phases.size() > 1 ? phases[1]["seconds"].get<double>() : 0.0;
  state.counters["pattern_s"] = phases[0]["seconds"].get<double>();
  state.counters["paper_pattern_s"] = row.pattern_seconds;
  state.counters["structure_s"] = structure;
  state.counters["paper_structure_s"] = row.structure_seconds;
  state.counters["design_cpu_s"] = cpu_end - cpu_start;
  state.counters["structure_cpu_s"] = cpu_end - cpu_structure_start;
  state.counters["stencils"] = report["stencils"]["count"].get<double>();
  state.counters["paper_stencils"] = row.stencils;
  state.counters["v"] = report["mesh"]["vertices"].get<double>();
  state.counters["v_sim"] = report["mesh"]["sim_vertices"].get<double>();
  double iterations = 0;
  for (const auto& p : phases) iterations += p["iterations"].get<double>();
  state.counters["iterations"] = iterations;
  state.counters["W_max_pattern"] = st["W_max_pattern"].get<double>();
  state.counters["W_max_final"] = st["W_max_final"].get<double>();
  state.counters["W_ratio"] = st["W_max_final"].get<double>() / st["W_max_pattern"].get<double>();
  state.counters["C_ratio"] = st["compliance_final"].get<double>() / st["compliance_pattern"].get<double>();
  if (phases.size() > 1 && phases[1]["iterations"].get<double>() > 0)
    state.counters["structure_evaluations_per_iteration"] =
        phases[1]["evaluations"].get<double>() / phases[1]["iterations"].get<double>();
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
