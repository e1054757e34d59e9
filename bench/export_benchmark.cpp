// The designer's files: the rasteriser (BM_Rasterize_Tbb, pixels/s), the solid's CGAL check and
// the minimum-feature check on a cut plate. Args: {stencils} (a plate with that many circles).
// The tool's cut (BM_ToolCut): stars on the plate, opened by a 0.5 mm tool and cut, against the cut
// of the drawn stars.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "host/cut/cut_surface.h"
#include "host/export/min_feature.h"
#include "host/export/solid.h"
#include "host/mesh/bvh.h"
#include "host/render/pictures.h"
#include "host/stencil/stencil_opening.h"
#include "host/surfaces/generators.h"

namespace cutwork {
namespace {

/// An nx × nx/2 grid of about n stencils on the 0.4 m × 0.2 m plate, scale `scale` × the cell's
/// width; with `varied`, scales from 40% to 100% of that and turned from cell to cell.
std::vector<StencilParams> plate_grid(int stencils, double scale, bool varied) {
  const int nx = std::max(1, int(std::lround(std::sqrt(2.0 * stencils)))), ny = std::max(1, nx / 2);
  std::vector<StencilParams> p;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      StencilParams s;
      s.position = Vec3(-0.2 + 0.4 * (i + 0.5) / nx, -0.1 + 0.2 * (j + 0.5) / ny, 0);
      s.scale = scale * 0.4 / nx * (varied ? 0.4 + 0.6 * double((i * 7 + j * 3) % 10) / 9.0 : 1.0);
      s.angle = varied ? 0.37 * (i + j) : 0.0;
      p.push_back(s);
    }
  return p;
}

/// A 0.4 m × 0.2 m plate with an n × n/2 grid of circles, cut.
struct CutPlate {
  SurfaceMesh mesh = generate_shape("plate", {{"width", 0.4}, {"height", 0.2}}, 0.004);
  FaceBvh bvh{mesh};
  CutSurface cut;
  explicit CutPlate(int stencils) {
    StencilLibrary shapes;
    shapes.add(make_builtin_stencil("circle", {}, "circle"));
    const AxisTangentField field;
    cut = cut_stencils(bvh, shapes, field, plate_grid(stencils, 0.35, false));
  }
};

/// Arg 0: stencils; arg 1: 1 = opened by a 0.5 mm tool (tool_cut_stencils, then the cut), 0 = the
/// drawn stars cut.
void BM_ToolCut(benchmark::State& state) {
  const SurfaceMesh mesh = generate_shape("plate", {{"width", 0.4}, {"height", 0.2}}, 0.004);
  const FaceBvh bvh(mesh);
  StencilLibrary shapes;
  shapes.add(make_builtin_stencil("star", {}, "star"));
  const AxisTangentField field;
  const std::vector<StencilParams> stars = plate_grid(int(state.range(0)), 0.5, true);
  const bool tool = state.range(1) != 0;
  int faces = 0;
  for (auto _ : state) {
    if (tool) {
      const ToolCutStencils cut = tool_cut_stencils(shapes, stars, 0.0005);
      faces = int(cut_stencils(bvh, cut.shapes, field, cut.stencils).faces.rows());
    } else {
      faces = int(cut_stencils(bvh, shapes, field, stars).faces.rows());
    }
    benchmark::DoNotOptimize(faces);
  }
  state.counters["stencils/s"] =
      benchmark::Counter(double(stars.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["faces"] = faces;
}
BENCHMARK(BM_ToolCut)->Args({100, 0})->Args({100, 1})->Args({400, 0})->Args({400, 1})->Unit(benchmark::kMillisecond);

void BM_Rasterize_Tbb(benchmark::State& state) {
  const CutPlate plate(int(state.range(0)));
  const std::vector<render::Rgb> colours(size_t(plate.cut.faces.rows()), render::material_colour());
  render::ViewSetup setup;
  for (Eigen::Index v = 0; v < plate.cut.vertices.rows(); ++v) setup.frame.extend(plate.cut.vertices.row(v).transpose());
  for (auto _ : state) benchmark::DoNotOptimize(render::rasterize(plate.cut.vertices, plate.cut.faces, colours, setup, 800, 600));
  state.counters["pixels/s"] = benchmark::Counter(800.0 * 600.0 * double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["faces"] = double(plate.cut.faces.rows());
}
BENCHMARK(BM_Rasterize_Tbb)->Arg(50)->Arg(200)->Unit(benchmark::kMillisecond);

void BM_SolidCheck_Cgal(benchmark::State& state) {
  const CutPlate plate(int(state.range(0)));
  const Solid solid = thicken_surface(plate.cut.vertices, plate.cut.faces, 0.003);
  for (auto _ : state) benchmark::DoNotOptimize(check_solid(solid));
  state.counters["faces/s"] = benchmark::Counter(double(solid.faces.rows()) * double(state.iterations()),
                                                 benchmark::Counter::kIsRate);
  state.counters["faces"] = double(solid.faces.rows());
}
BENCHMARK(BM_SolidCheck_Cgal)->Arg(50)->Arg(200)->Unit(benchmark::kMillisecond);

void BM_MinFeature(benchmark::State& state) {
  const CutPlate plate(int(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(check_min_feature(plate.cut, plate.mesh, 0.001));
  state.counters["holes"] = double(check_min_feature(plate.cut, plate.mesh, 0.001).holes);
}
BENCHMARK(BM_MinFeature)->Arg(50)->Arg(200)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cutwork
