// Parity of the fill kernel's Vulkan twins (kernels/fill/fill.comp, fill_pullback.comp) with the
// TBB twins, and of the whole clip → fill evaluation with its persistent buffers across
// "optimiser iterations". fill and the pull-back only add, subtract and multiply (in the same
// order as the C++, without contraction), which Vulkan requires to be correctly rounded, so
// they must agree BIT FOR BIT on any device; the clip → fill chain inherits the clip kernel's
// tolerance (host/vulkan/clip_fill_vk.h). Validation layer on, zero messages required.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "bench/clip_scenario.h"
#include "host/vulkan/clip_fill_vk.h"
#include "host/vulkan/context.h"
#include "kernels/clip/clip.h"
#include "kernels/fill/fill.h"
#include "tests/host/vulkan/vk_test_support.h"
#include "tests/kernels/clip/clip_vk_parity.h"

namespace cutwork::test {
namespace {

using kernels::ClipResult;

std::vector<ClipResult> cpu_clip(const ClipScenario& scene) {
  std::vector<ClipResult> r(scene.broad->pairs().size());
  kernels::ClipWorkspace ws;
  kernels::clip_tbb(scene.inputs(), {}, r, ws);
  return r;
}

struct FillOut {
  std::vector<double> alpha, d_alpha;
};

FillOut cpu_fill(const ClipScenario& scene, const std::vector<ClipResult>& clip,
                 const kernels::FillParams& params = {}) {
  FillOut out{std::vector<double>(size_t(scene.mesh.num_faces())),
              std::vector<double>(5 * clip.size())};
  kernels::fill_tbb({clip, scene.broad->face_offsets()}, params, {out.alpha, out.d_alpha});
  return out;
}

class FillVkTest : public VulkanTest {};

TEST_F(FillVkTest, FillMatchesTbbTwinBitForBit) {
  const ClipScenario scene("pavilion", 0.06, 800, 5);
  const std::vector<ClipResult> clip = cpu_clip(scene);
  const FillOut cpu = cpu_fill(scene, clip);
  FillOut gpu{std::vector<double>(cpu.alpha.size()), std::vector<double>(cpu.d_alpha.size())};
  vulkan::ClipFillVk vk(shared_ctx());
  vk.fill({clip, scene.broad->face_offsets()}, {}, {gpu.alpha, gpu.d_alpha});
  EXPECT_TRUE(same_bits(cpu.alpha, gpu.alpha));
  EXPECT_TRUE(same_bits(cpu.d_alpha, gpu.d_alpha));
  int covered = 0;
  for (double a : cpu.alpha) covered += a < 1;
  EXPECT_GT(covered, 1000);
}

TEST_F(FillVkTest, OverlappingStencilsClampAlphaAndZeroItsDerivatives) {
  // Coverage 3: the bounding circles cover the surface three times over, so many faces are
  // covered more than fully and clamp at min_fill.
  const ClipScenario scene("bowl", 0.04, 300, 9, 3.0);
  const std::vector<ClipResult> clip = cpu_clip(scene);
  kernels::FillParams params;
  params.min_fill = 1e-3;
  const FillOut cpu = cpu_fill(scene, clip, params);
  FillOut gpu{std::vector<double>(cpu.alpha.size()), std::vector<double>(cpu.d_alpha.size())};
  vulkan::ClipFillVk vk(shared_ctx());
  vk.fill({clip, scene.broad->face_offsets()}, params, {gpu.alpha, gpu.d_alpha});
  EXPECT_TRUE(same_bits(cpu.alpha, gpu.alpha));
  EXPECT_TRUE(same_bits(cpu.d_alpha, gpu.d_alpha));
  const auto& off = scene.broad->face_offsets();
  int clamped = 0;
  for (size_t f = 0; f + 1 < off.size(); ++f) {
    if (gpu.alpha[f] != params.min_fill) continue;
    ++clamped;
    for (int32_t i = off[f]; i < off[f + 1]; ++i)
      for (int k = 0; k < 5; ++k) ASSERT_EQ(gpu.d_alpha[5 * size_t(i) + size_t(k)], 0.0);
  }
  EXPECT_GT(clamped, 50);
}

TEST_F(FillVkTest, FillWithoutDerivativesLeavesDAlphaAlone) {
  const ClipScenario scene("bowl", 0.05, 100, 2);
  const std::vector<ClipResult> clip = cpu_clip(scene);
  kernels::FillParams params;
  params.derivatives = 0;
  const FillOut cpu = cpu_fill(scene, clip, params);
  std::vector<double> alpha(cpu.alpha.size());
  vulkan::ClipFillVk vk(shared_ctx());
  vk.fill({clip, scene.broad->face_offsets()}, params, {alpha, {}});
  EXPECT_TRUE(same_bits(cpu.alpha, alpha));
}

TEST_F(FillVkTest, PullbackMatchesTbbTwinBitForBit) {
  const ClipScenario scene("pavilion", 0.06, 800, 6);
  const std::vector<ClipResult> clip = cpu_clip(scene);
  const FillOut f = cpu_fill(scene, clip);
  std::mt19937 rng(4);
  std::normal_distribution<double> n01;
  std::vector<double> g_alpha(f.alpha.size());
  for (double& g : g_alpha) g = n01(rng);
  const kernels::FillPullbackInputs in{scene.broad->pairs(), f.d_alpha,
                                       scene.broad->stencil_pairs(),
                                       scene.broad->stencil_offsets()};
  std::vector<double> cpu(5 * scene.stencils.size()), gpu(cpu.size());
  kernels::fill_pullback_tbb(in, g_alpha, cpu);
  vulkan::ClipFillVk vk(shared_ctx());
  vk.pullback(in, g_alpha, gpu);
  EXPECT_TRUE(same_bits(cpu, gpu));
}

// The whole chain as an optimiser runs it: one ClipFillVk for the whole run; each iteration
// moves some stencils (frames and incremental broad phase on the host), evaluates α and dα/dp
// on the device in one submission, then pulls an objective gradient back through the
// device-resident dα/dp. Every iteration is checked against the CPU twins; the transfers must
// be only what changed.
TEST_F(FillVkTest, OptimiserIterationsMatchCpuAndUploadOnlyWhatChanged) {
  ClipScenario scene("pavilion", 0.08, 400, 13);
  vulkan::ClipFillVk vk(shared_ctx());
  std::mt19937 rng(21);
  std::normal_distribution<double> n01;
  std::uniform_int_distribution<size_t> pick(0, scene.stencils.size() - 1);
  for (int iteration = 0; iteration < 4; ++iteration) {
    SCOPED_TRACE("iteration " + std::to_string(iteration));
    if (iteration >= 2) {  // an optimiser step: move a few stencils, change a scale
      for (int j = 0; j < 5; ++j) {
        StencilParams& p = scene.stencils[pick(rng)];
        p.position += 0.3 * p.scale * Vec3(n01(rng), n01(rng), n01(rng));
        p.angle += 0.1 * n01(rng);
      }
      scene.stencils[pick(rng)].scale *= 1.05;
      scene.refresh();
    }
    const kernels::ClipInputs in = scene.inputs();
    const size_t pairs = in.pairs.size(), faces = size_t(scene.mesh.num_faces());
    std::vector<ClipResult> cpu_clip_r(pairs), gpu_clip_r(pairs);
    kernels::ClipWorkspace ws;
    kernels::clip_tbb(in, {}, cpu_clip_r, ws);
    std::vector<double> cpu_alpha(faces), cpu_d(5 * pairs), gpu_alpha(faces), gpu_d(5 * pairs);
    kernels::fill_tbb({cpu_clip_r, scene.broad->face_offsets()}, {}, {cpu_alpha, cpu_d});
    vk.evaluate(in, {}, scene.broad->face_offsets(), {}, gpu_clip_r, {gpu_alpha, gpu_d});

    // α and dα/dp against the CPU chain, to the clip kernel's tolerance.
    expect_clip_parity(cpu_clip_r, gpu_clip_r, in);
    double max_alpha = 0;
    for (size_t f = 0; f < faces; ++f)
      max_alpha = std::max(max_alpha, std::abs(gpu_alpha[f] - cpu_alpha[f]));
    EXPECT_LE(max_alpha, kFractionTolerance);
    // The fill half of the chain is exact: the device's α and dα/dp are the CPU fill of the
    // device's own clip results, bit for bit (so dα/dp inherits exactly the clip parity above).
    std::vector<double> ref_alpha(faces), ref_d(5 * pairs);
    kernels::fill_tbb({gpu_clip_r, scene.broad->face_offsets()}, {}, {ref_alpha, ref_d});
    EXPECT_TRUE(same_bits(ref_alpha, gpu_alpha));
    EXPECT_TRUE(same_bits(ref_d, gpu_d));

    // Transfers: everything on the first call; afterwards only what changed — never the mesh
    // or the shapes, nothing at all when nothing moved, a few 16-KiB blocks of the stencil
    // records (and of the pair list, where the broad phase changed it) after a step.
    const vulkan::BatchReport& report = vk.last_report();
    ASSERT_EQ(report.dispatches.size(), 2u);  // clip and fill, one submission
    for (const auto& [name, bytes] : report.uploads) {
      SCOPED_TRACE(name);
      if (iteration == 0) {
        EXPECT_GT(bytes, 0u);
      } else if (iteration == 1) {
        EXPECT_EQ(bytes, 0u) << "nothing changed, nothing should move";
      } else if (name == "vertices" || name == "faces" || name == "shapes" || name == "polygons") {
        EXPECT_EQ(bytes, 0u);
      } else if (name == "stencils") {
        EXPECT_GT(bytes, 0u);
        EXPECT_LE(bytes, 6 * vulkan::StorageBuffer::kBlockBytes);
        EXPECT_LT(bytes, scene.records.size() * sizeof(kernels::ClipStencil));
      }
    }
    EXPECT_EQ(report.download_bytes,
              faces * sizeof(double) + pairs * (sizeof(ClipResult) + 5 * sizeof(double)));

    // Pull-back through the device-resident dα/dp (only dS/dα and the grouping go up).
    std::vector<double> g_alpha(faces);
    for (double& g : g_alpha) g = n01(rng);
    std::vector<double> cpu_g(5 * scene.stencils.size()), gpu_g(cpu_g.size());
    kernels::fill_pullback_tbb(
        {in.pairs, gpu_d, scene.broad->stencil_pairs(), scene.broad->stencil_offsets()}, g_alpha,
        cpu_g);
    vk.pullback_last(scene.broad->stencil_pairs(), scene.broad->stencil_offsets(), g_alpha, gpu_g);
    EXPECT_TRUE(same_bits(cpu_g, gpu_g)) << "same dα/dp in, same bits out";
    EXPECT_LE(vk.last_report().upload_bytes,
              faces * sizeof(double) + 2 * (pairs + scene.stencils.size() + 1) * sizeof(int32_t));
  }
}

TEST_F(FillVkTest, PullbackLastNeedsAnEvaluationWithDerivatives) {
  vulkan::ClipFillVk vk(shared_ctx());
  std::vector<int32_t> sp, so{0};
  std::vector<double> g, out;
  EXPECT_THROW(vk.pullback_last(sp, so, g, out), std::invalid_argument);
}

}  // namespace
}  // namespace cutwork::test
