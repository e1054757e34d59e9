// Benchmarks of the fill-ratio kernels' Vulkan twin, beside the TBB twin's (clip_benchmark.cpp)
// on the same scenario object (bench/clip_scenario.h: pavilion, 205,350 faces, 10k stencils):
//   BM_Clip_Vk       the clip kernel alone, per-pair results downloaded (clip_tbb's contract)
//   BM_ClipFill_Vk   clip → fill in one submission, α and dα/dp downloaded, the per-pair
//                    results left on the device (what an optimiser iteration does)
// Args({stencils, workgroup size}). Counters: `pairs` — candidate pairs per second of wall
// time, transfers and host-side change detection included (the same counter as BM_Clip_Tbb);
// `device_pairs` — pairs per second of clip-kernel time from GPU timestamps. The label names
// the device. Without a Vulkan device (or shaderFloat64) the benchmarks report an error and
// are skipped; CUTWORK_VK_DEVICE picks the device.
#include <benchmark/benchmark.h>

#include <memory>
#include <string>
#include <vector>

#include "bench/clip_scenario.h"
#include "host/core/error.h"
#include "host/vulkan/clip_fill_vk.h"
#include "host/vulkan/context.h"

namespace cutwork {
namespace {

/// One context for the whole run (creating one compiles nothing, but opening a device is slow).
std::shared_ptr<vulkan::Context> bench_context(std::string& why) {
  static std::string error;
  static std::shared_ptr<vulkan::Context> ctx = []() -> std::shared_ptr<vulkan::Context> {
    try {
      vulkan::ContextOptions o = vulkan::ContextOptions::from_environment();
      o.require_float64 = true;
      return std::make_shared<vulkan::Context>(o);
    } catch (const DeviceError& e) {
      error = e.what();
      return nullptr;
    }
  }();
  why = error;
  return ctx;
}

void set_counters(benchmark::State& state, size_t pairs, double device_seconds,
                  const vulkan::Context& ctx) {
  state.counters["pairs"] =
      benchmark::Counter(double(pairs) * double(state.iterations()), benchmark::Counter::kIsRate);
  if (device_seconds > 0)
    state.counters["device_pairs"] = double(pairs) * double(state.iterations()) / device_seconds;
  state.counters["workgroup"] = double(state.range(1));
  state.SetLabel(ctx.info().name);
}

double clip_device_seconds(const vulkan::BatchReport& report) {
  for (const auto& d : report.dispatches)
    if (d.kernel == "clip" && d.device_ms) return *d.device_ms * 1e-3;
  return 0;
}

void BM_Clip_Vk(benchmark::State& state) {
  std::string why;
  const auto ctx = bench_context(why);
  if (!ctx) {
    state.SkipWithError(("no Vulkan device: " + why).c_str());
    return;
  }
  ClipScenario& d = clip_benchmark_scenario();
  const kernels::ClipInputs in = d.inputs();
  vulkan::ClipFillVk vk(ctx, uint32_t(state.range(1)));
  std::vector<kernels::ClipResult> results(in.pairs.size());
  vk.clip(in, {}, results);  // pipeline build and the first, full upload are not measured
  double device = 0;
  for (auto _ : state) {
    vk.clip(in, {}, results);
    device += clip_device_seconds(vk.last_report());
    benchmark::DoNotOptimize(results.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, in.pairs.size(), device, *ctx);
}

void BM_ClipFill_Vk(benchmark::State& state) {
  std::string why;
  const auto ctx = bench_context(why);
  if (!ctx) {
    state.SkipWithError(("no Vulkan device: " + why).c_str());
    return;
  }
  ClipScenario& d = clip_benchmark_scenario();
  const kernels::ClipInputs in = d.inputs();
  vulkan::ClipFillVk vk(ctx, uint32_t(state.range(1)));
  std::vector<double> alpha(size_t(d.mesh.num_faces())), d_alpha(5 * in.pairs.size());
  const kernels::FillOutputs out{alpha, d_alpha};
  vk.evaluate(in, {}, d.broad->face_offsets(), {}, {}, out);
  double device = 0;
  for (auto _ : state) {
    vk.evaluate(in, {}, d.broad->face_offsets(), {}, {}, out);
    device += clip_device_seconds(vk.last_report());
    benchmark::DoNotOptimize(alpha.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, in.pairs.size(), device, *ctx);
}

void workgroup_args(benchmark::internal::Benchmark* b) {
  for (int wg : {64, 128, 256}) b->Args({kClipBenchStencils, wg});
  b->ArgNames({"stencils", "wg"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_Clip_Vk)->Apply(workgroup_args);
BENCHMARK(BM_ClipFill_Vk)->Apply(workgroup_args);

}  // namespace
}  // namespace cutwork
