#include <benchmark/benchmark.h>

#include "solvers/linear/thread_policy.h"

int main(int argc, char** argv) {
  cutwork::solvers::settle_library_threads();  // as the cutwork executable does
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
