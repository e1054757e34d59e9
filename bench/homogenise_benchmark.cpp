// Cell homogenisation (solvers/homogenise/cell_homogenisation.h): one periodic cell problem —
// cut, remesh, tile, assemble, factorise, six unit cases — and its stress concentration, read on
// the rim by the rim recovery.
//   BM_CellHomogenisation/<shape>/<alpha %>/<rim edges>: rim edges 0 = the resolution alone
//   (24 per spacing, raised for narrow ligaments); 16 = the default, the rim resolved for the peak.
//   BM_ToolCell/<shape>/<alpha %>/<64 τ>: the hole as a tool of radius τ bounding radii cuts it
//   (CellOptions::tool_radius; 0 = as drawn), its rounds refined to 12 edges per radius: what the
//   calibration by the tool pays per node and distinct fill ratio.
//   BM_ToolCalibration/<threads>: the default star's calibration by the tool
//   (calibrate_fill_stiffness with tool_cut: every distinct fill ratio's drawn cell and its cells
//   at the tool nodes, side by side) in an arena of that many threads; each iteration a polygon
//   the cache has not seen (the star scaled by 1 + 1e-9 k).
// Counters: faces of the cell, resolution (edges per spacing), K_m and K_b (the largest states).
#include <benchmark/benchmark.h>

#include <string>

#include <tbb/task_arena.h>

#include "host/stencil/stencil_shape.h"
#include "solvers/homogenise/cell_homogenisation.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"

namespace cutwork {
namespace {

/// Times homogenise_cell of `kind` at α = range(0) % with `options`; the cell's size and factors
/// as counters.
void time_cell(benchmark::State& state, const std::string& kind, const solvers::CellOptions& options) {
  const StencilShape shape = make_builtin_stencil(kind, {}, kind);
  const Material material;  // PA12; K and the ratios depend on ν only
  const double alpha = 0.01 * double(state.range(0));
  solvers::CellStiffness cell;
  for (auto _ : state) {
    cell = solvers::homogenise_cell(shape, material, alpha, options);
    benchmark::DoNotOptimize(cell.membrane_concentration);
  }
  state.counters["faces"] = cell.faces;
  state.counters["resolution"] = cell.resolution;
  state.counters["K_m"] = cell.membrane_concentration;
  state.counters["K_b"] = cell.bending_concentration;
}

void BM_CellHomogenisation(benchmark::State& state, const std::string& kind) {
  solvers::CellOptions options;
  options.rim_edges = double(state.range(1));
  time_cell(state, kind, options);
}

void BM_ToolCell(benchmark::State& state, const std::string& kind) {
  solvers::CellOptions options;
  options.tool_radius = double(state.range(1)) / 64;
  time_cell(state, kind, options);
}

void BM_ToolCalibration(benchmark::State& state) {
  const Material material;
  tbb::task_arena arena(int(state.range(0)));
  static int fresh = 0;  // across repetitions too: every run misses the cache
  size_t samples = 0;
  for (auto _ : state) {
    StencilLibrary shapes;
    StencilShape star = make_builtin_stencil("star", {}, "star");
    ++fresh;
    for (Vec2& p : star.polygon) p *= 1 + 1e-9 * fresh;
    shapes.add(star);
    arena.execute([&] {
      const FillStiffnessCurve c = solvers::calibrate_fill_stiffness(shapes, material, solvers::CellOptions{}, {}, true);
      samples = c.alpha.size();
    });
  }
  state.counters["samples"] = double(samples);
}

BENCHMARK(BM_ToolCalibration)->Arg(1)->Arg(2)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_CAPTURE(BM_ToolCell, star, std::string("star"))
    ->Args({75, 0})
    ->Args({75, 1})
    ->Args({75, 8})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_CAPTURE(BM_CellHomogenisation, circle, std::string("circle"))
    ->Args({90, 0})
    ->Args({90, 16})
    ->Args({60, 0})
    ->Args({60, 16})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_CellHomogenisation, flower, std::string("flower"))
    ->Args({75, 0})
    ->Args({75, 16})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace cutwork
