// Shell mechanics benchmarks: parallel assembly (energy + gradient + Hessian into the fixed
// pattern), energy-only evaluation (the line search), a full Newton equilibrium from rest, a
// warm-started re-solve after a fill-ratio change, and the adjoint as a fraction of one equilibrium.
// Sizes: ~1e4 and ~1e5 free DOFs (1e6 with CUTWORK_BENCH_LARGE=1); threads: 1 and all.
#include <benchmark/benchmark.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <cmath>

#include "bench/shell_bench_model.h"
#include "host/core/timer.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/structural_quantities.h"
#include "solvers/sensitivity/adjoint.h"
#include "solvers/shell/shell_energy.h"

namespace {

using namespace cutwork;
using namespace cutwork::solvers;

/// A smoothly sagged state (not the rest state, so every element does real work).
RowMatX3d sagged(const ShellModel& model) {
  RowMatX3d x = model.rest_positions();
  for (int v = 0; v < x.rows(); ++v)
    if (!model.fixed()[v]) x(v, 2) -= 0.002 * std::sin(3 * x(v, 0)) * std::sin(3 * x(v, 1));
  return x;
}

void size_and_threads(benchmark::internal::Benchmark* b) {
  const int all = tbb::info::default_concurrency();
  for (int dofs : bench::bench_sizes()) {
    b->Args({dofs, 1});
    if (all > 1) b->Args({dofs, all});
  }
}

void sizes_all_threads(benchmark::internal::Benchmark* b) {
  for (int dofs : bench::bench_sizes()) b->Args({dofs, tbb::info::default_concurrency()});
}

void BM_ShellAssembly_Tbb(benchmark::State& state) {
  const ShellModel& model = *bench::bench_model(int(state.range(0))).model;
  tbb::task_arena arena(int(state.range(1)));
  const RowMatX3d x = sagged(model);
  const Eigen::VectorXd alpha = Eigen::VectorXd::Ones(model.num_faces());
  ShellAssembly out;
  for (auto _ : state) {
    arena.execute([&] { assemble_shell(model, x, alpha, true, out); });
    benchmark::DoNotOptimize(out.hessian.data());
  }
  state.counters["dofs"] = model.num_dofs();
  state.counters["nonzeros"] = double(model.assembly().num_nonzeros());
  state.counters["colours"] = double(model.assembly().colours().size());
  state.counters["elements/s"] =
      benchmark::Counter(double(model.num_elements()) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ShellAssembly_Tbb)->Apply(size_and_threads)->Unit(benchmark::kMillisecond)->UseRealTime();

/// Building the model: the rest state of every element (the shape operator's patch fit, one SVD per
/// face), the support check and the assembly's pattern; every refined level of the discretisation
/// estimate and of verify builds one.
void BM_ShellModelBuild(benchmark::State& state) {
  const bench::BenchModel& bm = bench::bench_model(int(state.range(0)));
  tbb::task_arena arena(int(state.range(1)));
  for (auto _ : state) {
    arena.execute([&] {
      const ShellModel model(*bm.mesh, bm.model->material(), bm.model->load_case());
      benchmark::DoNotOptimize(model.num_elements());
    });
  }
  state.counters["faces"] = bm.mesh->num_faces();
  state.counters["faces/s"] =
      benchmark::Counter(double(bm.mesh->num_faces()) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ShellModelBuild)->Apply(size_and_threads)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ShellEnergy_Tbb(benchmark::State& state) {
  const ShellModel& model = *bench::bench_model(int(state.range(0))).model;
  tbb::task_arena arena(int(state.range(1)));
  const RowMatX3d x = sagged(model);
  const Eigen::VectorXd alpha = Eigen::VectorXd::Ones(model.num_faces());
  for (auto _ : state) {
    double e = 0;
    arena.execute([&] { e = shell_energy(model, x, alpha); });
    benchmark::DoNotOptimize(e);
  }
  state.counters["dofs"] = model.num_dofs();
  state.counters["elements/s"] =
      benchmark::Counter(double(model.num_elements()) * double(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ShellEnergy_Tbb)->Apply(size_and_threads)->Unit(benchmark::kMillisecond)->UseRealTime();

/// Newton from rest to equilibrium, then the adjoint of the compliance at that equilibrium with the
/// factor Newton left behind. adjoint_fraction = (objective partials + solve + λᵀ∂f/∂α) / equilibrium;
/// adjoint_solve_fraction = the forward/back substitution alone / equilibrium.
void BM_Equilibrium_Newton(benchmark::State& state) {
  const ShellModel& model = *bench::bench_model(int(state.range(0))).model;
  tbb::task_arena arena(int(state.range(1)));
  EquilibriumSolver solver(model);
  const Eigen::VectorXd alpha = Eigen::VectorXd::Ones(model.num_faces());
  double equilibrium = 0, adjoint = 0, adjoint_solve = 0, assembly = 0, factorization = 0, solves = 0;
  double iterations = 0, line_search = 0;
  for (auto _ : state) {
    solver.reset();
    arena.execute([&] {
      Stopwatch sw;
      const EquilibriumStats& stats = solver.solve(alpha);
      equilibrium += sw.seconds();
      iterations += stats.newton_iterations;
      assembly += stats.assembly_seconds;
      factorization += stats.factorization_seconds;
      solves += stats.solve_seconds;
      line_search += stats.line_search_seconds;
      sw.restart();
      const Sensitivity s = fill_ratio_sensitivity(solver, compliance_terms);
      adjoint += sw.seconds();
      adjoint_solve += s.seconds;
      benchmark::DoNotOptimize(s.gradient.data());
    });
  }
  const double n = double(state.iterations());
  state.counters["dofs"] = model.num_dofs();
  state.counters["newton_iterations"] = iterations / n;
  state.counters["assembly_s"] = assembly / n;
  state.counters["factorization_s"] = factorization / n;
  state.counters["solve_s"] = solves / n;
  state.counters["line_search_s"] = line_search / n;
  state.counters["adjoint_s"] = adjoint / n;
  state.counters["adjoint_fraction"] = adjoint / equilibrium;
  state.counters["adjoint_solve_fraction"] = adjoint_solve / equilibrium;
}
BENCHMARK(BM_Equilibrium_Newton)->Apply(sizes_all_threads)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The optimiser's inner loop: a small fill-ratio change, then a warm-started Newton solve.
void BM_Equilibrium_WarmStart(benchmark::State& state) {
  const ShellModel& model = *bench::bench_model(int(state.range(0))).model;
  tbb::task_arena arena(int(state.range(1)));
  EquilibriumSolver solver(model);
  Eigen::VectorXd alpha = Eigen::VectorXd::Ones(model.num_faces());
  arena.execute([&] { solver.solve(alpha); });
  double iterations = 0;
  int flip = 0;
  for (auto _ : state) {
    alpha.head(model.num_faces() / 10).setConstant(++flip % 2 ? 0.95 : 1.0);
    arena.execute([&] { iterations += solver.solve(alpha).newton_iterations; });
  }
  state.counters["dofs"] = model.num_dofs();
  state.counters["newton_iterations"] = iterations / double(state.iterations());
}
BENCHMARK(BM_Equilibrium_WarmStart)->Apply(sizes_all_threads)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
