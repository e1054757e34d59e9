#pragma once
/// The fill-ratio kernels' scenario, shared by the clip benchmarks of every twin
/// (bench/clip_benchmark.cpp: reference and TBB; bench/clip_vk_benchmark.cpp: Vulkan) and by the
/// GPU parity tests, so that all of them measure and compare the same thing.
///
/// A built-in shape meshed at `edge_length`; `count` stencils of six built-in shapes (circle,
/// star, flower, leaf, apple, heart: convex and not), placed uniformly over the surface (faces
/// drawn by area, uniform barycentrics), scales uniform in [0.7, 1.3] × the scale whose bounding
/// circles cover `coverage` of the surface, angles uniform in [0, 2π); exact frames (default
/// axis tangent field) and the broad phase's candidate pairs, sorted by face.
/// pavilion, 0.02 m, 10k stencils: 205,350 faces, the benchmarks' scenario (seed 2016).
#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "host/surfaces/generators.h"
#include "host/stencil/broad_phase.h"
#include "host/stencil/frame.h"
#include "host/stencil/stencil_shape.h"
#include "kernels/clip/clip.h"

namespace cutwork {

struct ClipScenario {
  SurfaceMesh mesh;
  std::unique_ptr<FaceBvh> bvh;
  StencilLibrary shapes;
  AxisTangentField field;
  std::vector<StencilParams> stencils;
  std::vector<kernels::ClipStencil> records;
  std::unique_ptr<BroadPhase> broad;
  std::vector<kernels::ClipResult> results;  ///< #P, scratch for the twins

  ClipScenario(const std::string& shape, double edge_length, int count, uint32_t seed = 2016,
               double coverage = 0.5)
      : mesh(generate_shape(shape, {}, edge_length)) {
    bvh = std::make_unique<FaceBvh>(mesh);
    for (const char* kind : {"circle", "star", "flower", "leaf", "apple", "heart"})
      shapes.add(make_builtin_stencil(kind, {}, kind));
    std::mt19937 rng(seed);
    const Eigen::VectorXd& areas = mesh.face_areas();
    std::discrete_distribution<int> face(areas.data(), areas.data() + areas.size());
    std::uniform_real_distribution<double> u(0, 1);
    const double s0 = std::sqrt(coverage * areas.sum() / (3.14159265358979 * count));
    for (int i = 0; i < count; ++i) {
      const int f = face(rng);
      double a = u(rng), b = u(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      StencilParams p;
      p.position = (1 - a - b) * mesh.vertices().row(mesh.faces()(f, 0)).transpose() +
                   a * mesh.vertices().row(mesh.faces()(f, 1)).transpose() +
                   b * mesh.vertices().row(mesh.faces()(f, 2)).transpose();
      p.scale = s0 * (0.7 + 0.6 * u(rng));
      p.angle = 6.283185307 * u(rng);
      p.type = i % shapes.size();
      stencils.push_back(p);
    }
    broad = std::make_unique<BroadPhase>(*bvh);
    refresh();
  }

  /// Recomputes the frames and the candidate pairs after `stencils` changed (what one
  /// optimiser iteration does before the kernels run; the broad phase is incremental).
  void refresh() {
    records.resize(stencils.size());
    std::vector<Vec3> centers;
    std::vector<double> scales;
    for (size_t i = 0; i < stencils.size(); ++i) {
      const StencilParams& p = stencils[i];
      FrameJacobian J;
      const Frame fr = compute_frame(*bvh, field, p.position, &J);
      records[i] = make_clip_stencil(fr, J, p.scale, p.angle, p.type);
      centers.push_back(fr.origin);
      scales.push_back(p.scale);
    }
    broad->update(centers, scales);
    results.resize(broad->pairs().size());
  }

  kernels::ClipInputs inputs() const {
    return {{mesh.vertices().data(), size_t(mesh.vertices().size())},
            {mesh.faces().data(), size_t(mesh.faces().size())},
            shapes.clip_shapes(),
            shapes.packed_polygons(),
            records,
            broad->pairs()};
  }
};

/// The clip benchmarks' scenario — pavilion meshed at 0.02 m (205,350 faces), 10k stencils,
/// seed 2016 — built on first use and shared by every benchmark file of cutwork-bench (an
/// inline function's static is one object program-wide), so BM_Clip_Tbb and BM_Clip_Vk run on
/// the very same pairs.
inline constexpr int kClipBenchStencils = 10'000;
inline constexpr double kClipBenchEdgeLength = 0.02;
inline ClipScenario& clip_benchmark_scenario() {
  static ClipScenario scenario("pavilion", kClipBenchEdgeLength, kClipBenchStencils, 2016);
  return scenario;
}

}  // namespace cutwork
