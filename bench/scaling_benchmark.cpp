// Scaling with the mesh (issue 12 item 6), under the process's thread policy
// (solvers/linear/thread_policy.h), on the default (shape-operator) bending element.
//
//   BM_Equilibrium_Sheet/<faces>   the built-in `sheet` scene (1 m, pinned boundary, self-weight,
//                                  h = 2 mm) on its base mesh at about 2e3 / 2e4 / 2e5 faces: one
//                                  equilibrium from rest as `cutwork simulate` runs it (the model and
//                                  CHOLMOD's symbolic analysis built once, outside the timing).
//     Counters: faces, dofs, newton_iterations, factorizations, krylov_steps and krylov_iterations
//     (Newton–Krylov steps and their conjugate-gradient iterations), factor_nonzeros, gflop (one
//     factorisation), assembly_s, factorization_s, solve_s (CG included) per equilibrium, peak_gib;
//     the ordering as label. The 2e5 size takes a minute on two cores; select sizes with
//     --benchmark_filter='Sheet/2000/' etc.
//
//   BM_Design_PavilionScale/<stencils>   the built-in `pavilion` (energy-density objective) with
//                                  `count` = stencils and both edge lengths scaled together so that
//                                  the simulation mesh has about 10 triangles per stencil (issue 12's
//                                  pavilion: 9,880 stencils on 92,256; the scene itself has 2.3), the
//                                  base mesh 2.5 times as many; 5 L-BFGS-B iterations per phase.
//                                  Default sizes 1e3 and 1e4 stencils (about 1e4 and 1e5 simulation
//                                  triangles); 1e5 (about 1e6 triangles) only with CUTWORK_BENCH_LARGE=1
//                                  — it does not fit a 24 GB, 10-minute budget (docs/PERFORMANCE.md).
//     Counters: stencils, sim_faces, base_faces, context_s (pattern context set-up), pattern_s,
//     structure_s, structure_iterations, s_per_iteration (structural phase seconds per L-BFGS-B
//     iteration), cpu_s_per_iteration (CPU seconds of every thread from the end of the pattern phase
//     to the end of the design, the two designs' equilibria included, per iteration),
//     evaluations_per_iteration, equilibria, newton_per_equilibrium, factor_nonzeros and gflop (one
//     factorisation of the uncut shell), peak_gib (the process's resident high-water mark so far). Manual time: context + pattern + structure.
//
// peak_gib is VmHWM of the whole benchmark process: run one size per process for a clean figure.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>

#include "bench/scene_models.h"
#include "host/core/timer.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/optimize/design_pipeline.h"

namespace cutwork {
namespace {

void BM_Equilibrium_Sheet(benchmark::State& state) {
  const solvers::ShellModel& model = bench::sheet_model(int(state.range(0)));
  solvers::EquilibriumSolver solver(model);
  const Eigen::VectorXd alpha = Eigen::VectorXd::Ones(model.num_faces());
  double iterations = 0, factorizations = 0, krylov_steps = 0, krylov_iterations = 0;
  double assembly = 0, factorization = 0, solve = 0;
  for (auto _ : state) {
    solver.reset();
    const solvers::EquilibriumStats& s = solver.solve(alpha);
    iterations += s.newton_iterations;
    factorizations += s.factorizations;
    krylov_steps += s.krylov_steps;
    krylov_iterations += s.krylov_iterations;
    assembly += s.assembly_seconds;
    factorization += s.factorization_seconds;
    solve += s.solve_seconds;
  }
  const double n = double(state.iterations());
  state.counters["faces"] = model.num_faces();
  state.counters["dofs"] = model.num_dofs();
  state.counters["newton_iterations"] = iterations / n;
  state.counters["factorizations"] = factorizations / n;
  state.counters["krylov_steps"] = krylov_steps / n;
  state.counters["krylov_iterations"] = krylov_iterations / n;
  state.counters["assembly_s"] = assembly / n;
  state.counters["factorization_s"] = factorization / n;
  state.counters["solve_s"] = solve / n;
  state.counters["factor_nonzeros"] = double(solver.linear_solver().factor_nonzeros());
  state.counters["gflop"] = solver.linear_solver().factorization_flops() * 1e-9;
  state.counters["peak_gib"] = bench::peak_memory_gib();
  state.SetLabel(solver.linear_solver().ordering());
}
BENCHMARK(BM_Equilibrium_Sheet)->Arg(2000)->Arg(20000)->Arg(200000)->Unit(benchmark::kSecond)->UseRealTime();

void BM_Design_PavilionScale(benchmark::State& state) {
  const int stencils = int(state.range(0));
  Scene scene = load_scene("pavilion");
  // Ten simulation triangles per stencil: edge lengths shrink by √(F0 / (10 stencils)), F0 the
  // scene's own simulation faces.
  const double default_faces = build_scene_meshes(scene).sim.num_faces();
  const double shrink = std::sqrt(default_faces / (10.0 * stencils));
  scene.pattern.count = stencils;
  scene.mesh.edge_length *= shrink;
  scene.mesh.sim_edge_length *= shrink;
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  solvers::DesignOptions options;
  options.pattern_iterations = 5;
  options.structure_iterations = 5;
  solvers::DesignResult r;
  double context = 0, cpu_structure_start = 0, cpu_end = 0;
  options.checkpoint = [&](const solvers::DesignSnapshot& snapshot) {
    if (snapshot.stage == solvers::DesignStage::PatternEnd) cpu_structure_start = bench::process_cpu_total();
  };
  for (auto _ : state) {
    Stopwatch sw;
    auto ctx = std::make_unique<PatternContext>(scene, meshes);
    context = sw.seconds();
    r = solvers::run_design(scene, meshes, lc, *ctx, options);
    cpu_end = bench::process_cpu_total();
    state.SetIterationTime(context + r.pattern.seconds + (r.structure ? r.structure->seconds : 0.0));
  }
  state.counters["stencils"] = r.pattern_design.stencils;
  state.counters["sim_faces"] = meshes.sim.num_faces();
  state.counters["base_faces"] = meshes.base.num_faces();
  state.counters["context_s"] = context;
  state.counters["pattern_s"] = r.pattern.seconds;
  if (r.structure) {
    const solvers::StructurePhaseResult& s = *r.structure;
    state.counters["structure_s"] = s.seconds;
    state.counters["structure_iterations"] = s.iterations;
    if (s.iterations > 0) {
      state.counters["s_per_iteration"] = s.seconds / s.iterations;
      state.counters["cpu_s_per_iteration"] = (cpu_end - cpu_structure_start) / s.iterations;
      state.counters["evaluations_per_iteration"] = double(s.evaluations) / s.iterations;
    }
  }
  state.counters["equilibria"] = r.stage_times.equilibria;
  if (r.stage_times.equilibria > 0)
    state.counters["newton_per_equilibrium"] = double(r.stage_times.newton_iterations) / r.stage_times.equilibria;
  // The uncut shell's factor, as every equilibrium of the design factorises it (analysed once more
  // here, after the timing).
  const solvers::ShellModel model(meshes.sim, scene.material, lc, solvers::scene_mechanics(scene));
  const solvers::EquilibriumSolver solver(model);
  state.counters["factor_nonzeros"] = double(solver.linear_solver().factor_nonzeros());
  state.counters["gflop"] = solver.linear_solver().factorization_flops() * 1e-9;
  state.counters["peak_gib"] = bench::peak_memory_gib();
}

void pavilion_sizes(benchmark::internal::Benchmark* b) {
  b->Arg(1000)->Arg(10000);
  if (const char* e = std::getenv("CUTWORK_BENCH_LARGE"); e && std::string(e) == "1") b->Arg(100000);
}
BENCHMARK(BM_Design_PavilionScale)->Apply(pavilion_sizes)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);

}  // namespace
}  // namespace cutwork
