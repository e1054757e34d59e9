// Sparse linear algebra on the shell's reduced Hessian: CHOLMOD supernodal Cholesky
// (symbolic analysis, numeric factorisation, solve) against Eigen's SimplicialLDLT on the very same
// matrix in the same run. Sizes: ~1e4 and ~1e5 DOFs (1e6 with CUTWORK_BENCH_LARGE=1; Eigen at 1e6 also
// needs CUTWORK_BENCH_LARGE_EIGEN=1).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <map>
#include <string>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "bench/shell_bench_model.h"
#include "host/core/timer.h"
#include "solvers/linear/cholmod_solver.h"
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
