// The designer's files: the rasteriser (BM_Rasterize_Tbb, pixels/s), the solid's CGAL check and
// the minimum-feature check on a cut plate. Args: {stencils} (a plate with that many circles).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "host/cut/cut_surface.h"
#include "host/export/min_feature.h"
#include "host/export/solid.h"
#include "host/mesh/bvh.h"
#include "host/render/pictures.h"
#include "host/surfaces/generators.h"

namespace cutwork {
namespace {

/// A 0.4 m × 0.2 m plate with an n × n/2 grid of circles, cut.
struct CutPlate {
  SurfaceMesh mesh = generate_shape("plate", {{"width", 0.4}, {"height", 0.2}}, 0.004);
  FaceBvh bvh{mesh};
  CutSurface cut;
  explicit CutPlate(int stencils) {
    StencilLibrary shapes;
    shapes.add(make_builtin_stencil("circle", {}, "circle"));
    const AxisTangentField field;
    const int nx = std::max(1, int(std::lround(std::sqrt(2.0 * stencils)))), ny = std::max(1, nx / 2);
    std::vector<StencilParams> p;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        StencilParams s;
        s.position = Vec3(-0.2 + 0.4 * (i + 0.5) / nx, -0.1 + 0.2 * (j + 0.5) / ny, 0);
        s.scale = 0.35 * 0.4 / nx;
        p.push_back(s);
      }
    cut = cut_stencils(bvh, shapes, field, p);
  }
};

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
