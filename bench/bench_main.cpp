#include <benchmark/benchmark.h>

#include "solvers/linear/thread_policy.h"

int main(int argc, char** argv) {
  cutwork::solvers::ensure_blas_kernels(argv);  // as the cutwork executable does
  cutwork::solvers::settle_library_threads();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
