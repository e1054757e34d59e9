// Face BVH: construction, and closest-point queries against the brute-force twin.
// Arg: target face count (a bumpy n×n grid with 2n² ≈ faces triangles).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "host/mesh/bvh.h"

namespace cutwork {
namespace {

SurfaceMesh bench_grid(int target_faces) {
  const int n = std::max(1, int(std::lround(std::sqrt(target_faces / 2.0))));
  RowMatX3d v((n + 1) * (n + 1), 3);
  RowMatX3i f(2 * n * n, 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = double(i) / n, y = double(j) / n;
      v.row(j * (n + 1) + i) << x, y, 0.1 * std::sin(6 * x) * std::cos(4 * y);
    }
  int k = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      f.row(k++) << a, b, c;
      f.row(k++) << a, c, d;
    }
  return SurfaceMesh(std::move(v), std::move(f), "benchmark grid");
}

std::vector<Vec3> bench_queries(int count) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> xy(-0.1, 1.1), z(-0.3, 0.3);
  std::vector<Vec3> q(count);
  for (Vec3& p : q) p = Vec3(xy(rng), xy(rng), z(rng));
  return q;
}

void BM_BvhBuild(benchmark::State& state) {
  const SurfaceMesh mesh = bench_grid(int(state.range(0)));
  for (auto _ : state) {
    FaceBvh bvh(mesh);
    benchmark::DoNotOptimize(bvh);
  }
  state.SetItemsProcessed(state.iterations() * mesh.num_faces());
  state.counters["faces"] = mesh.num_faces();
}

void BM_ClosestPoint_Bvh(benchmark::State& state) {
  const SurfaceMesh mesh = bench_grid(int(state.range(0)));
  const FaceBvh bvh(mesh);
  const std::vector<Vec3> queries = bench_queries(4096);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(bvh.closest_point(queries[i++ % queries.size()]));
  }
  state.SetItemsProcessed(state.iterations());  // queries/s
  state.counters["faces"] = mesh.num_faces();
}

void BM_ClosestPoint_BruteForce(benchmark::State& state) {
  const SurfaceMesh mesh = bench_grid(int(state.range(0)));
  const std::vector<Vec3> queries = bench_queries(4096);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(closest_point_brute_force(mesh, queries[i++ % queries.size()]));
  }
  state.SetItemsProcessed(state.iterations());  // queries/s
  state.counters["faces"] = mesh.num_faces();
}

void BM_FacesInBall_Bvh(benchmark::State& state) {
  const SurfaceMesh mesh = bench_grid(int(state.range(0)));
  const FaceBvh bvh(mesh);
  const std::vector<Vec3> queries = bench_queries(4096);
  const double radius = 3 * mesh.mean_edge_length();
  std::vector<int> out;
  std::size_t i = 0;
  for (auto _ : state) {
    bvh.faces_in_ball(queries[i++ % queries.size()], radius, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations());  // queries/s
  state.counters["faces"] = mesh.num_faces();
}

BENCHMARK(BM_BvhBuild)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ClosestPoint_Bvh)->Arg(10000)->Arg(100000);
BENCHMARK(BM_ClosestPoint_BruteForce)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FacesInBall_Bvh)->Arg(10000)->Arg(100000);

}  // namespace
}  // namespace cutwork
