// The thread policy: OpenBLAS and OpenMP get threads only for large factorisations and never more
// than TBB's budget (global_control or the calling arena), and the settings reach the libraries.
#include <dlfcn.h>

#include <cstdlib>
#include <iostream>
#include <string>

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <Eigen/Dense>

#include "solvers/linear/block_assembly.h"
#include "solvers/linear/cholmod_solver.h"
#include "solvers/linear/thread_policy.h"

namespace cutwork::solvers {
namespace {

TEST(ThreadPolicy, SerialBelowTheThresholdAndWithinTheBudgetAbove) {
  const double small = 0.5 * kParallelFactorFlops, large = 2 * kParallelFactorFlops;
  EXPECT_EQ(factorization_threads(small, 8).blas, 1);
  EXPECT_EQ(factorization_threads(small, 8).openmp, 1);
  EXPECT_EQ(factorization_threads(large, 1).blas, 1);
  EXPECT_EQ(factorization_threads(large, kMinParallelBlasThreads - 1).blas, 1);
  EXPECT_EQ(factorization_threads(large, kMinParallelBlasThreads).blas, kMinParallelBlasThreads);
  // CHOLMOD's OpenMP team has a fixed size: only when the budget covers it.
  EXPECT_EQ(factorization_threads(large, 2).openmp, 1);
  EXPECT_EQ(factorization_threads(large, 16).blas, 16);
  EXPECT_GT(factorization_threads(large, 16).openmp, 1);
  EXPECT_LE(factorization_threads(large, 16).openmp, 16);
}

TEST(ThreadPolicy, BudgetFollowsTbb) {
  {
    const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    EXPECT_EQ(thread_budget(), 1);
  }
  tbb::task_arena two(2);
  two.execute([] { EXPECT_LE(thread_budget(), 2); });
  tbb::task_arena one(1);
  one.execute([] { EXPECT_EQ(thread_budget(), 1); });
}

TEST(ThreadPolicy, SettingsReachOpenBlasAndOpenMp) {
  using GetInt = int (*)();
  const auto blas_threads = reinterpret_cast<GetInt>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  const auto omp_levels = reinterpret_cast<GetInt>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"));
  if (!blas_threads || !blas_threads_controllable()) GTEST_SKIP() << "the BLAS is not OpenBLAS";
  const double large = 2 * kParallelFactorFlops;
  {
    // A budget of four, whatever the machine: OpenBLAS gets all of it.
    const tbb::global_control four(tbb::global_control::max_allowed_parallelism, 4);
    tbb::task_arena arena(4);
    arena.execute([&] {
      ASSERT_EQ(thread_budget(), 4);
      const FactorizationThreads t = set_factorization_threads(large);
      EXPECT_EQ(t.blas, 4);
      EXPECT_EQ(blas_threads(), 4);
    });
  }
  {
    const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    EXPECT_EQ(set_factorization_threads(large).blas, 1);
    EXPECT_EQ(blas_threads(), 1);
  }
  EXPECT_EQ(set_factorization_threads(0.5 * kParallelFactorFlops).blas, 1);
  EXPECT_EQ(blas_threads(), 1);
  if (omp_levels) {
    EXPECT_EQ(omp_levels(), 0) << "CHOLMOD's OpenMP regions are inactive";
  }
}

/// A 2-D grid Laplacian plus the identity, 3 DOFs per node, as BlockAssembly lays it out.
struct GridSystem {
  BlockAssembly assembly;
  std::vector<double> values;
  explicit GridSystem(int side) : assembly(side * side, edges(side)), values(std::size_t(assembly.num_nonzeros()), 0.0) {
    Eigen::Matrix<double, 6, 6> local;
    local << Eigen::Matrix3d::Identity(), -Eigen::Matrix3d::Identity(), -Eigen::Matrix3d::Identity(),
        Eigen::Matrix3d::Identity();
    for (int e = 0; e < int(edges(side).size()); ++e) assembly.scatter_matrix<2>(e, local, values.data());
    for (int j = 0; j < assembly.num_dofs(); ++j) values[std::size_t(assembly.column_starts()[j + 1] - 1)] += 0.1;
  }
  static std::vector<BlockAssembly::ElementNodes> edges(int side) {
    std::vector<BlockAssembly::ElementNodes> e;
    for (int i = 0; i < side; ++i)
      for (int j = 0; j < side; ++j) {
        if (j + 1 < side) e.push_back(BlockAssembly::nodes({i * side + j, i * side + j + 1}));
        if (i + 1 < side) e.push_back(BlockAssembly::nodes({i * side + j, (i + 1) * side + j}));
      }
    return e;
  }
};

TEST(ThreadPolicy, OpenMpGateRunsInactiveRegionsInlineAndForwardsActiveOnes) {
  // The executable exports GOMP_parallel and CHOLMOD's calls reach it (this fails when the symbol
  // is not exported or libgomp's comes first).
  ASSERT_TRUE(openmp_gate_installed());
  const GridSystem grid(40);
  const BlockAssembly& a = grid.assembly;
  Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.num_dofs(), -1.0, 2.0), serial(a.num_dofs());
  {
    const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    CholmodSolver chol;
    chol.analyze(a.num_dofs(), a.column_starts(), a.row_indices());
    const long before = openmp_regions_inlined();
    ASSERT_TRUE(chol.factorize(grid.values.data()));
    EXPECT_GT(openmp_regions_inlined(), before) << "CHOLMOD's regions ran inline, without a libgomp team";
    chol.solve(b.data(), serial.data());
  }
  const auto omp_levels = reinterpret_cast<int (*)()>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"));
  if (!omp_levels) GTEST_SKIP() << "no OpenMP runtime: every region runs inline";
  // A budget that covers CHOLMOD's team and a threshold of zero: the regions go to libgomp and
  // the result is the serial one.
  const double threshold = parallel_factor_flops();
  set_parallel_factor_flops(0);
  const tbb::global_control many(tbb::global_control::max_allowed_parallelism, 16);
  tbb::task_arena arena(16);
  arena.execute([&] {
    CholmodSolver chol;
    chol.analyze(a.num_dofs(), a.column_starts(), a.row_indices());
    const long before = openmp_regions_inlined();
    ASSERT_TRUE(chol.factorize(grid.values.data()));
    EXPECT_EQ(openmp_regions_inlined(), before) << "active regions go to libgomp";
    EXPECT_EQ(omp_levels(), 1);
    Eigen::VectorXd x(a.num_dofs());
    chol.solve(b.data(), x.data());
    EXPECT_LE((x - serial).norm(), 1e-12 * serial.norm());
  });
  set_parallel_factor_flops(threshold);
}

// OpenBLAS's generic fallback kernels are replaced where the CPU has AVX2 and FMA (Haswell's), and
// this test executable runs with the kernels the cutwork executable would use: its main() made the
// same check (tests/support/test_main.cpp), so generic kernels remain only by the user's own
// OPENBLAS_CORETYPE.
TEST(ThreadPolicy, OpenBlasRunsWithKernelsForThisCpu) {
  EXPECT_EQ(preferred_blas_kernels("Haswell"), "");
  EXPECT_EQ(preferred_blas_kernels("SkylakeX"), "");
  EXPECT_EQ(preferred_blas_kernels(""), "");
#if defined(__x86_64__)
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  EXPECT_EQ(preferred_blas_kernels("Prescott"), avx2 ? "Haswell" : "");
#endif
  const std::string kernels = blas_kernels();
  std::cout << "OpenBLAS kernels: " << (kernels.empty() ? "(not OpenBLAS)" : kernels)
            << (std::getenv("OPENBLAS_CORETYPE") ? std::string(", OPENBLAS_CORETYPE=") + std::getenv("OPENBLAS_CORETYPE")
                                                 : std::string())
            << "\n";
  if (!preferred_blas_kernels(kernels).empty()) {
    EXPECT_NE(std::getenv("OPENBLAS_CORETYPE"), nullptr) << "generic kernels " << kernels << " without the user's choice";
  }
}

}  // namespace
}  // namespace cutwork::solvers
