// Reading the perforation's lattice from stencils ("lattice": "auto", host/pattern/lattice_order.h):
// measure_lattice on a square grid of stencils turned 20° on a plane (the worst case: every
// stencil ordered, so all 64 candidate axes are scored against every stencil) and on a hexagonal
// one (no candidate). Arg: stencils (an n × n grid).
#include <benchmark/benchmark.h>

#include <cmath>

#include "host/pattern/lattice_order.h"

namespace cutwork {
namespace {

void grid(int count, bool square, RowMatX3d& centres, RowMatX3d& normals) {
  const int n = std::max(2, int(std::lround(std::sqrt(double(count)))));
  const double angle = 20 * std::acos(-1.0) / 180, c = std::cos(angle), s = std::sin(angle);
  centres.resize(n * n, 3);
  normals.resize(n * n, 3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = i + (square ? 0.0 : 0.5 * (j % 2)), y = square ? j : j * std::sqrt(3.0) / 2;
      centres.row(j * n + i) << c * x - s * y, s * x + c * y, 0;
      normals.row(j * n + i) << 0, 0, 1;
    }
}

void BM_MeasureLattice(benchmark::State& state, bool square) {
  RowMatX3d centres, normals;
  grid(int(state.range(0)), square, centres, normals);
  for (auto _ : state) {
    const MeasuredLattice m = measure_lattice(centres, normals);
    benchmark::DoNotOptimize(m.axis);
    if (m.square != square) state.SkipWithError("the grid was read as the other lattice");
  }
  state.counters["stencils"] = double(centres.rows());
}

BENCHMARK_CAPTURE(BM_MeasureLattice, Square, true)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_MeasureLattice, Hexagonal, false)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cutwork
