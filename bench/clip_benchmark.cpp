// Benchmarks of the fill-ratio kernels on the pavilion (≥ 200k triangles, 10k stencils of six
// shapes, convex and not, covering about half the surface):
//   BM_Clip_Ref / BM_Clip_Tbb       the clip kernel alone (fractions + exact derivatives)
//   BM_Fill_Ref / BM_Fill_Tbb       the fill kernel alone (segmented reduction + Jacobian)
//   BM_FillRatio_Ref / _Tbb         the whole pipeline: frames, broad phase (incremental, no
//                                   stencil moved), clip, fill
// Args({stencils, threads}); counter `pairs`: candidate pairs processed per second.
// The mesh, the stencils and the candidate pairs are built once and shared (bench/clip_scenario.h).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <random>
#include <thread>
#include <vector>

#include "bench/clip_scenario.h"
#include "host/surfaces/generators.h"
#include "host/stencil/fill_ratio.h"

namespace cutwork {
namespace {

// The scenario (pavilion, 0.02 m, 10k stencils) lives in bench/clip_scenario.h, shared with the
// Vulkan twin's benchmarks (clip_vk_benchmark.cpp) so that both measure the same pairs.
constexpr int kStencils = kClipBenchStencils;
using ClipBenchData = ClipScenario;

ClipBenchData& data() { return clip_benchmark_scenario(); }

void set_counters(benchmark::State& state, size_t pairs) {
  state.counters["pairs"] = benchmark::Counter(double(pairs) * double(state.iterations()),
                                               benchmark::Counter::kIsRate);
  state.counters["threads"] = double(state.range(1));
}

template <bool Tbb>
void BM_Clip(benchmark::State& state) {
  ClipBenchData& d = data();
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  const kernels::ClipInputs in = d.inputs();
  kernels::ClipWorkspace ws;
  for (auto _ : state) {
    if constexpr (Tbb)
      kernels::clip_tbb(in, {}, d.results, ws);
    else
      kernels::clip_ref(in, {}, d.results, ws);
    benchmark::DoNotOptimize(d.results.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, in.pairs.size());
}

template <bool Tbb>
void BM_Fill(benchmark::State& state) {
  ClipBenchData& d = data();
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  kernels::ClipWorkspace ws;
  kernels::clip_tbb(d.inputs(), {}, d.results, ws);
  std::vector<double> alpha(size_t(d.mesh.num_faces())), d_alpha(5 * d.results.size());
  const kernels::FillInputs in{d.results, d.broad->face_offsets()};
  for (auto _ : state) {
    if constexpr (Tbb)
      kernels::fill_tbb(in, {}, {alpha, d_alpha});
    else
      kernels::fill_ref(in, {}, {alpha, d_alpha});
    benchmark::DoNotOptimize(alpha.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, d.results.size());
}

template <FillBackend Backend>
void BM_FillRatio(benchmark::State& state) {
  ClipBenchData& d = data();
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  FillRatioOptions opt;
  opt.backend = Backend;
  FillRatioEvaluator ev(*d.bvh, d.shapes, opt);
  ev.evaluate(d.stencils);  // first call queries every stencil; the loop measures the reuse
  for (auto _ : state) {
    ev.evaluate(d.stencils);
    benchmark::DoNotOptimize(ev.alpha().data());
  }
  set_counters(state, ev.pairs().size());
}

void thread_args(benchmark::internal::Benchmark* b) {
  const int all = int(std::max(2u, std::thread::hardware_concurrency()));
  b->Args({kStencils, 1});
  b->Args({kStencils, 2});
  if (all > 2) b->Args({kStencils, all});
  b->ArgNames({"stencils", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

void single_thread(benchmark::internal::Benchmark* b) {
  b->Args({kStencils, 1})->ArgNames({"stencils", "threads"})->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_Clip<false>)->Name("BM_Clip_Ref")->Apply(single_thread);
BENCHMARK(BM_Clip<true>)->Name("BM_Clip_Tbb")->Apply(thread_args);
BENCHMARK(BM_Fill<false>)->Name("BM_Fill_Ref")->Apply(single_thread);
BENCHMARK(BM_Fill<true>)->Name("BM_Fill_Tbb")->Apply(thread_args);
BENCHMARK(BM_FillRatio<FillBackend::Reference>)->Name("BM_FillRatio_Ref")->Apply(single_thread);
BENCHMARK(BM_FillRatio<FillBackend::Tbb>)->Name("BM_FillRatio_Tbb")->Apply(thread_args);

}  // namespace
}  // namespace cutwork
