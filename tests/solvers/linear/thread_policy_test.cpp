// The thread policy: OpenBLAS and OpenMP get threads only for large factorisations and never more
// than TBB's budget (global_control or the calling arena), and the settings reach the libraries.
#include <dlfcn.h>

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

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
  if (omp_levels) EXPECT_EQ(omp_levels(), 0) << "CHOLMOD's OpenMP regions are inactive";
}

}  // namespace
}  // namespace cutwork::solvers
