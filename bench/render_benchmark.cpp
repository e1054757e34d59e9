// The pictures' rasteriser, both twins through the interface pictures.cpp uses
// (render::Rasterizer): BM_Render_Cpu (TBB) and BM_Render_Vk (raster.comp on the Vulkan device
// select_compute_backend(vulkan) opens; CUTWORK_VK_DEVICE picks one). One iso panel of the
// pavilion surface (0.05 m edges) with per-face colours, args {width, height} of the panel
// (2×2 supersampled inside). The Vk figure is wall-clock per panel: the view upload (the mesh
// and colours stay on the device after the first call, which is not measured), the four passes,
// the image download. Counter `pixels/s`. Without a Vulkan device BM_Render_Vk reports an error.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "host/core/error.h"
#include "host/render/rasterizer.h"
#include "host/surfaces/generators.h"
#include "host/vulkan/backend.h"

namespace cutwork {
namespace {

struct RenderScene {
  SurfaceMesh mesh = generate_shape("pavilion", {}, 0.05);
  std::vector<render::Rgb> colours;
  render::ViewSetup setup;
  RenderScene() {
    for (Eigen::Index f = 0; f < mesh.num_faces(); ++f)
      colours.push_back({0.2 + 0.6 * double(f % 7) / 7, 0.5, 0.8 - 0.6 * double(f % 5) / 5});
    for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) setup.frame.extend(mesh.vertices().row(v).transpose());
  }
};

const RenderScene& render_scene() {
  static const RenderScene scene;
  return scene;
}

void run(benchmark::State& state, const render::Rasterizer& rasterizer) {
  const RenderScene& s = render_scene();
  const int w = int(state.range(0)), h = int(state.range(1));
  benchmark::DoNotOptimize(rasterizer.rasterize(s.mesh.vertices(), s.mesh.faces(), s.colours, s.setup, w, h));
  for (auto _ : state)
    benchmark::DoNotOptimize(rasterizer.rasterize(s.mesh.vertices(), s.mesh.faces(), s.colours, s.setup, w, h));
  state.counters["pixels/s"] = benchmark::Counter(double(w) * h * double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["faces"] = double(s.mesh.num_faces());
}

void BM_Render_Cpu(benchmark::State& state) { run(state, render::Rasterizer{}); }

void BM_Render_Vk(benchmark::State& state) {
  static std::string error;
  static const render::Rasterizer vk = []() -> render::Rasterizer {
    try {
      return render::Rasterizer::for_backend(select_compute_backend(DeviceRequest::Vulkan, nullptr));
    } catch (const DeviceError& e) {
      error = e.what();
      return {};
    }
  }();
  if (!vk.on_device()) {
    state.SkipWithError(("no Vulkan device: " + error).c_str());
    return;
  }
  run(state, vk);
}

BENCHMARK(BM_Render_Cpu)->Args({400, 300})->Args({1200, 900})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Render_Vk)->Args({400, 300})->Args({1200, 900})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace cutwork
