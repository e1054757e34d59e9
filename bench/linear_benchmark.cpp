// Sparse linear algebra on the shell's reduced Hessian: CHOLMOD supernodal Cholesky
// (symbolic analysis, numeric factorisation, solve) against Eigen's SimplicialLDLT on the very same
// matrix in the same run. Sizes: ~1e4 and ~1e5 DOFs (1e6 with CUTWORK_BENCH_LARGE=1; Eigen at 1e6 also
// needs CUTWORK_BENCH_LARGE_EIGEN=1).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <limits>
#include <map>
#include <tbb/task_arena.h>
#include <string>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "bench/scene_models.h"
#include "bench/shell_bench_model.h"
#include "host/core/timer.h"
#include "solvers/linear/cholmod_solver.h"
#include "solvers/linear/thread_policy.h"
#include "solvers/shell/shell_energy.h"

namespace {

using namespace cutwork;
using namespace cutwork::solvers;

/// The reduced Hessian of the benchmark model at its rest state (upper-triangular CSC values in the
/// model's pattern; the pattern, and so the cost of every operation, is that of any Newton step)
/// and a right-hand side. Computed once per size.
struct BenchMatrix {
  const BlockAssembly* pattern = nullptr;
  std::vector<double> values;
  Eigen::VectorXd rhs;
  double cholmod_factorize_seconds = 0;  ///< best of 3, for the Eigen comparison counter
};

const BenchMatrix& bench_matrix(int dofs) {
  static std::map<int, BenchMatrix> cache;
  auto it = cache.find(dofs);
  if (it != cache.end()) return it->second;
  const ShellModel& model = *bench::bench_model(dofs).model;
  const Eigen::VectorXd alpha = Eigen::VectorXd::Ones(model.num_faces());
  ShellAssembly a;
  assemble_shell(model, model.rest_positions(), alpha, true, a);
  BenchMatrix m;
  m.pattern = &model.assembly();
  m.values = std::move(a.hessian);
  m.rhs = model.gather_free(model.external_forces(alpha));  // the load: the first Newton step's right-hand side
  CholmodSolver chol;
  chol.analyze(model.num_dofs(), m.pattern->column_starts(), m.pattern->row_indices());
  m.cholmod_factorize_seconds = INFINITY;
  for (int i = 0; i < 3; ++i) {
    Stopwatch sw;
    chol.factorize(m.values.data());
    m.cholmod_factorize_seconds = std::min(m.cholmod_factorize_seconds, sw.seconds());
  }
  return cache.emplace(dofs, std::move(m)).first->second;
}

Eigen::SparseMatrix<double> eigen_upper(const BenchMatrix& m) {
  const BlockAssembly& p = *m.pattern;
  return Eigen::Map<const Eigen::SparseMatrix<double>>(p.num_dofs(), p.num_dofs(), p.num_nonzeros(),
                                                        p.column_starts().data(), p.row_indices().data(),
                                                        m.values.data());
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int dofs : bench::bench_sizes()) b->Arg(dofs);
}

/// Eigen's simplicial factorisation at 1e6 DOFs takes far longer than CHOLMOD's (tens of minutes on
/// a laptop); it joins the 1e6 run only with CUTWORK_BENCH_LARGE_EIGEN=1 as well.
void eigen_sizes(benchmark::internal::Benchmark* b) {
  const char* e = std::getenv("CUTWORK_BENCH_LARGE_EIGEN");
  for (int dofs : bench::bench_sizes())
    if (dofs < 1000000 || (e && std::string(e) == "1")) b->Arg(dofs);
}

void BM_Analyze_Cholmod(benchmark::State& state) {
  const BenchMatrix& m = bench_matrix(int(state.range(0)));
  for (auto _ : state) {
    CholmodSolver chol;
    chol.analyze(m.pattern->num_dofs(), m.pattern->column_starts(), m.pattern->row_indices());
    benchmark::DoNotOptimize(chol.factor_nonzeros());
  }
  state.counters["dofs"] = m.pattern->num_dofs();
}
BENCHMARK(BM_Analyze_Cholmod)->Apply(sizes)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Factorize_Cholmod(benchmark::State& state) {
  const BenchMatrix& m = bench_matrix(int(state.range(0)));
  CholmodSolver chol;
  chol.analyze(m.pattern->num_dofs(), m.pattern->column_starts(), m.pattern->row_indices());
  for (auto _ : state) {
    if (!chol.factorize(m.values.data())) state.SkipWithError("not positive definite");
  }
  state.counters["dofs"] = m.pattern->num_dofs();
  state.counters["matrix_nonzeros"] = double(m.pattern->num_nonzeros());
  state.counters["factor_nonzeros"] = double(chol.factor_nonzeros());
  state.SetLabel("supernodal, ordering " + chol.ordering());
}
BENCHMARK(BM_Factorize_Cholmod)->Apply(sizes)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Solve_Cholmod(benchmark::State& state) {
  const BenchMatrix& m = bench_matrix(int(state.range(0)));
  CholmodSolver chol;
  chol.analyze(m.pattern->num_dofs(), m.pattern->column_starts(), m.pattern->row_indices());
  chol.factorize(m.values.data());
  Eigen::VectorXd x(m.rhs.size());
  for (auto _ : state) {
    chol.solve(m.rhs.data(), x.data());
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["dofs"] = m.pattern->num_dofs();
}
BENCHMARK(BM_Solve_Cholmod)->Apply(sizes)->Unit(benchmark::kMillisecond)->UseRealTime();

/// The sheet-like sizes of the scaling table (≈ 2e3 / 2e4 / 2e5 faces: 3e3 / 3e4 / 3e5 DOFs).
void scaling_sizes(benchmark::internal::Benchmark* b, const std::vector<int>& second) {
  for (int dofs : {3000, 30000, 300000})
    for (int k : second) b->Args({dofs, k});
}

/// Symbolic analysis and one numeric factorisation with each ordering CHOLMOD offers (0 AMD,
/// 1 METIS, 2 NESDIS): what Ordering::Automatic chooses by size from.
void BM_Ordering_Cholmod(benchmark::State& state) {
  const BenchMatrix& m = bench_matrix(int(state.range(0)));
  const Ordering orderings[] = {Ordering::Amd, Ordering::Metis, Ordering::Nesdis};
  double analyze = 0, factorize = 0;
  CholmodSolver chol(orderings[state.range(1)]);
  for (auto _ : state) {
    chol = CholmodSolver(orderings[state.range(1)]);
    Stopwatch sw;
    chol.analyze(m.pattern->num_dofs(), m.pattern->column_starts(), m.pattern->row_indices());
    analyze += sw.seconds();
    sw.restart();
    if (!chol.factorize(m.values.data())) state.SkipWithError("not positive definite");
    factorize += sw.seconds();
  }
  const double n = double(state.iterations());
  state.counters["dofs"] = m.pattern->num_dofs();
  state.counters["analyze_s"] = analyze / n;
  state.counters["factorize_s"] = factorize / n;
  state.counters["factor_nonzeros"] = double(chol.factor_nonzeros());
  state.counters["gflop"] = chol.factorization_flops() * 1e-9;
  state.SetLabel(chol.ordering());
}
BENCHMARK(BM_Ordering_Cholmod)
    ->Apply([](benchmark::internal::Benchmark* b) { scaling_sizes(b, {0, 1, 2}); })
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

/// Numeric factorisation with OpenBLAS serial (second argument 1) or given the whole thread
/// budget of a task_arena of that many threads: where kParallelFactorFlops comes from.
/// user_s, sys_s: CPU time of the process per factorisation (spinning pools show up in sys_s).
void BM_Factorize_Threads(benchmark::State& state) {
  const BenchMatrix& m = bench_matrix(int(state.range(0)));
  const int threads = int(state.range(1));
  tbb::task_arena arena(threads);
  CholmodSolver chol;
  chol.analyze(m.pattern->num_dofs(), m.pattern->column_starts(), m.pattern->row_indices());
  const double saved = parallel_factor_flops();
  set_parallel_factor_flops(threads > 1 ? 0.0 : std::numeric_limits<double>::infinity());
  const auto [user0, sys0] = bench::process_cpu_seconds();
  for (auto _ : state) {
    arena.execute([&] {
      if (!chol.factorize(m.values.data())) state.SkipWithError("not positive definite");
    });
  }
  const auto [user1, sys1] = bench::process_cpu_seconds();
  set_parallel_factor_flops(saved);
  state.counters["dofs"] = m.pattern->num_dofs();
  state.counters["gflop"] = chol.factorization_flops() * 1e-9;
  state.counters["user_s"] = (user1 - user0) / double(state.iterations());
  state.counters["sys_s"] = (sys1 - sys0) / double(state.iterations());
  state.SetLabel(chol.ordering());
}
BENCHMARK(BM_Factorize_Threads)
    ->Apply([](benchmark::internal::Benchmark* b) { scaling_sizes(b, {1, 2}); })
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

/// Eigen's SimplicialLDLT (AMD ordering, analysed once outside the loop) on the same matrix;
/// cholmod_speedup = this numeric factorisation time / CHOLMOD's on the same matrix in this run.
void BM_Factorize_EigenLDLT(benchmark::State& state) {
  const BenchMatrix& m = bench_matrix(int(state.range(0)));
  const Eigen::SparseMatrix<double> A = eigen_upper(m);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper> ldlt;
  ldlt.analyzePattern(A);
  double seconds = 0;
  for (auto _ : state) {
    Stopwatch sw;
    ldlt.factorize(A);
    seconds += sw.seconds();
    if (ldlt.info() != Eigen::Success) state.SkipWithError("Eigen LDLT failed");
  }
  state.counters["dofs"] = m.pattern->num_dofs();
  state.counters["cholmod_speedup"] = seconds / double(state.iterations()) / m.cholmod_factorize_seconds;
}
BENCHMARK(BM_Factorize_EigenLDLT)->Apply(eigen_sizes)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_Solve_EigenLDLT(benchmark::State& state) {
  const BenchMatrix& m = bench_matrix(int(state.range(0)));
  const Eigen::SparseMatrix<double> A = eigen_upper(m);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper> ldlt(A);
  Eigen::VectorXd x;
  for (auto _ : state) {
    x = ldlt.solve(m.rhs);
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["dofs"] = m.pattern->num_dofs();
}
BENCHMARK(BM_Solve_EigenLDLT)->Apply(eigen_sizes)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
