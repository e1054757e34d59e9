// FillRatioEvaluator's Vulkan backend against its TBB backend: the whole pipeline (frames and
// broad phase on the CPU, clip → fill → pull-back on the device) on the bowl and the pavilion
// with random mixed stencil layouts, to the parity contract of host/vulkan/clip_fill_vk.h, and
// over "optimiser iterations" through one evaluator (persistent device buffers: later
// iterations upload only the stencil records, and the pair list when the broad phase changed
// it). Validation layer on, zero messages required (VulkanTest).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/surfaces/generators.h"
#include "host/stencil/fill_ratio.h"
#include "host/vulkan/backend.h"
#include "host/vulkan/context.h"
#include "kernels/clip/clip.h"
#include "kernels/fill/fill.h"
#include "tests/host/stencil/stencil_fixtures.h"
#include "tests/host/vulkan/vk_test_support.h"
#include "tests/kernels/clip/clip_vk_parity.h"

namespace cutwork::test {
namespace {

/// What the clip kernel saw in `ev`'s last evaluation.
kernels::ClipInputs clip_inputs(const SurfaceMesh& mesh, const StencilLibrary& lib,
                                const FillRatioEvaluator& ev) {
  kernels::ClipInputs in;
  in.vertices = std::span<const double>(mesh.vertices().data(), size_t(mesh.vertices().size()));
  in.faces = std::span<const int32_t>(mesh.faces().data(), size_t(mesh.faces().size()));
  in.shapes = lib.clip_shapes();
  in.polygons = lib.packed_polygons();
  in.stencils = ev.clip_stencils();
  in.pairs = ev.pairs();
  return in;
}

Eigen::VectorXd random_gradient(Eigen::Index faces, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  Eigen::VectorXd g(faces);
  for (Eigen::Index f = 0; f < faces; ++f) g[f] = n01(rng);
  return g;
}

/// The broad phase's grouping by stencil (BroadPhase::stencil_pairs / stencil_offsets) rebuilt
/// from the pairs, which are sorted by (face, stencil): a stable counting sort by stencil.
struct Grouping {
  std::vector<int32_t> pairs, offsets;
};
Grouping group_by_stencil(std::span<const kernels::ClipPair> pairs, int stencils) {
  Grouping g;
  g.offsets.assign(size_t(stencils) + 1, 0);
  for (const kernels::ClipPair& p : pairs) ++g.offsets[size_t(p.stencil) + 1];
  for (size_t s = 0; s < size_t(stencils); ++s) g.offsets[s + 1] += g.offsets[s];
  std::vector<int32_t> cursor(g.offsets.begin(), g.offsets.end() - 1);
  g.pairs.resize(pairs.size());
  for (size_t i = 0; i < pairs.size(); ++i) g.pairs[size_t(cursor[size_t(pairs[i].stencil)]++)] = int32_t(i);
  return g;
}

/// #F+1 face offsets of pairs sorted by face.
std::vector<int32_t> face_offsets(std::span<const kernels::ClipPair> pairs, size_t faces) {
  std::vector<int32_t> o(faces + 1, 0);
  for (const kernels::ClipPair& p : pairs) ++o[size_t(p.face) + 1];
  for (size_t f = 0; f < faces; ++f) o[f + 1] += o[f];
  return o;
}

/// |Δα| on lavapipe: 1e-14 ≈ 45 ε, a hundredth of the contract's 1e-12 (measured: ≤ 3.4e-16).
constexpr double kIeeeAlphaTolerance = 1e-14;

struct Agreement {
  size_t pairs = 0, faces = 0;
  double max_alpha = 0;         ///< max |Δα|
  double max_d_alpha = 0;       ///< max |Δ ∂α/∂p_k|
  double max_d_alpha_tol = 0;   ///< max |Δ ∂α/∂p_k| / its tolerance (≤ 1 passes)
  double max_pullback_tol = 0;  ///< max |Δ g_k| / its tolerance
  size_t alpha_same = 0, d_alpha_same = 0, pullback_same = 0;
  bool overlaps_same = false;
  FillRatioReport pullback_report;
};

/// `vk` against `tbb` after both evaluated the same stencils: α and dα/dp to the parity
/// contract (host/vulkan/clip_fill_vk.h), the pull-back (through the device-resident dα/dp),
/// the per-pair results; α to round-off on an IEEE double device (`ieee`: lavapipe). And the
/// exact halves of the chain on any device: the device's α and dα/dp are the CPU fill of its
/// own clip results, its pull-back the CPU pull-back of its own dα/dp, bit for bit.
Agreement expect_agreement(const FillRatioEvaluator& tbb, const FillRatioEvaluator& vk,
                           const SurfaceMesh& mesh, const StencilLibrary& lib, bool ieee,
                           unsigned seed) {
  Agreement a;
  a.pairs = tbb.pairs().size();
  a.faces = size_t(tbb.alpha().size());
  EXPECT_TRUE(same_bits<kernels::ClipPair>(tbb.pairs(), vk.pairs())) << "same CPU broad phase";
  EXPECT_EQ(vk.alpha().size(), tbb.alpha().size());
  if (tbb.pairs().size() != vk.pairs().size() || vk.alpha().size() != tbb.alpha().size())
    return a;
  const kernels::ClipInputs in = clip_inputs(mesh, lib, tbb);
  const std::vector<kernels::ClipResult>& tbb_overlaps = tbb.overlaps();

  // α: |Δα| ≤ 1e-12.
  for (size_t f = 0; f < a.faces; ++f) {
    const double c = tbb.alpha()[Eigen::Index(f)], g = vk.alpha()[Eigen::Index(f)];
    a.max_alpha = std::max(a.max_alpha, std::abs(g - c));
    a.alpha_same += std::memcmp(&c, &g, sizeof c) == 0;
  }
  EXPECT_LE(a.max_alpha, kFractionTolerance);

  // dα/dp: 1e-9 (|value| + u_k) + 64 ε (P/A) u_k per entry, as for ∂fraction/∂p.
  const bool derivatives = tbb.options().derivatives;
  EXPECT_EQ(vk.d_alpha().size(), tbb.d_alpha().size());
  if (derivatives && vk.d_alpha().size() == tbb.d_alpha().size()) {
    std::vector<double> tolerance(5 * a.pairs);
    int reported = 0;
    for (size_t i = 0; i < a.pairs; ++i) {
      const kernels::ClipPair& pair = in.pairs[i];
      const double scale = in.stencils[size_t(pair.stencil)].scale;
      double perimeter = 0;
      for (int k = 0; k < 3; ++k) {
        const double* p = &in.vertices[3 * size_t(in.faces[3 * size_t(pair.face) + size_t(k)])];
        const double* q =
            &in.vertices[3 * size_t(in.faces[3 * size_t(pair.face) + size_t((k + 1) % 3)])];
        perimeter += std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                               (p[2] - q[2]) * (p[2] - q[2]));
      }
      const double area = tbb_overlaps[i].triangle_area;
      const double shape_ratio = area > 0 ? perimeter * scale / area : 0.0;
      for (int k = 0; k < 5; ++k) {
        const double c = tbb.d_alpha()[5 * i + size_t(k)], g = vk.d_alpha()[5 * i + size_t(k)];
        const double u = derivative_unit(k, scale);
        const double tol =
            kDerivativeTolerance * (std::abs(c) + u) + kRoundOffFloor * shape_ratio * u;
        tolerance[5 * i + size_t(k)] = tol;
        a.max_d_alpha = std::max(a.max_d_alpha, std::abs(g - c));
        a.max_d_alpha_tol = std::max(a.max_d_alpha_tol, std::abs(g - c) / tol);
        a.d_alpha_same += std::memcmp(&c, &g, sizeof c) == 0;
        if (!(std::abs(g - c) <= tol) && reported++ < 8)
          ADD_FAILURE() << "pair " << i << " (stencil " << pair.stencil << ", face " << pair.face
                        << ") ∂α/∂p_" << k << ": tbb " << c << " vulkan " << g;
      }
    }

    // Pull-back: the kernel's own contract, |Δ g_k| ≤ 1e-9 Σ_pairs |g_α ∂α/∂p_k|, plus what
    // the dα/dp entries may differ by, Σ_pairs |g_α| tol(∂α/∂p_k). The device's pull-back of its
    // own dα/dp: bit for bit.
    const Eigen::VectorXd g_alpha = random_gradient(tbb.alpha().size(), seed);
    Eigen::VectorXd g_tbb, g_vk;
    tbb.pullback(g_alpha, g_tbb);
    vk.pullback(g_alpha, g_vk);
    a.pullback_report = vk.last_report();
    EXPECT_EQ(a.pullback_report.call, "pullback");
    EXPECT_EQ(g_vk.size(), g_tbb.size());
    if (g_vk.size() == g_tbb.size()) {
      Eigen::VectorXd scale = Eigen::VectorXd::Constant(g_tbb.size(), 1e-300);
      for (size_t i = 0; i < a.pairs; ++i)
        for (int k = 0; k < 5; ++k)
          scale[5 * in.pairs[i].stencil + k] +=
              std::abs(g_alpha[in.pairs[i].face]) *
              (1e-9 * std::abs(tbb.d_alpha()[5 * i + size_t(k)]) + tolerance[5 * i + size_t(k)]);
      for (Eigen::Index j = 0; j < g_tbb.size(); ++j) {
        const double e = std::abs(g_vk[j] - g_tbb[j]) / scale[j];
        a.max_pullback_tol = std::max(a.max_pullback_tol, e);
        a.pullback_same += std::memcmp(&g_vk[j], &g_tbb[j], sizeof(double)) == 0;
      }
      EXPECT_LE(a.max_pullback_tol, 1.0);
      const Grouping by = group_by_stencil(vk.pairs(), int(g_vk.size() / 5));
      std::vector<double> own(size_t(g_vk.size()));
      kernels::fill_pullback_tbb({vk.pairs(), vk.d_alpha(), by.pairs, by.offsets},
                                 std::span<const double>(g_alpha.data(), size_t(g_alpha.size())),
                                 own);
      EXPECT_TRUE(same_bits<double>(own, std::span<const double>(g_vk.data(), own.size())))
          << "the device's pull-back of its own dα/dp";
    }
  }

  // Per-pair results (downloaded lazily here), and the exact fill half of the chain.
  const std::vector<kernels::ClipResult>& vk_overlaps = vk.overlaps();
  const ParityStats st = expect_clip_parity(tbb_overlaps, vk_overlaps, in);
  a.overlaps_same = st.bit_identical == st.compared;
  if (vk_overlaps.size() == a.pairs) {
    std::vector<double> alpha(a.faces), d_alpha(derivatives ? 5 * a.pairs : 0);
    kernels::FillParams params;
    params.min_fill = vk.options().min_fill;
    params.derivatives = derivatives ? 1 : 0;
    const std::vector<int32_t> offsets = face_offsets(vk.pairs(), a.faces);
    kernels::fill_tbb({vk_overlaps, offsets}, params, {alpha, d_alpha});
    EXPECT_TRUE(same_bits<double>(alpha, std::span<const double>(vk.alpha().data(), a.faces)))
        << "the device's α is the fill of its own clip results";
    EXPECT_TRUE(same_bits<double>(d_alpha, vk.d_alpha()))
        << "the device's dα/dp is the fill of its own clip results";
  }

  if (ieee) {
    // lavapipe computes IEEE double like the CPU, and every clipped vertex has the same bits
    // in both twins; only the summation order of the clipped polygon's terms differs (the GPU
    // clip is a stream, see host/vulkan/README.md), so α agrees to round-off, far inside the
    // contract. (Not bit for bit: ~5 % of the faces differ in the last bits.)
    EXPECT_LE(a.max_alpha, kIeeeAlphaTolerance) << "lavapipe: α to round-off";
  }
  std::printf(
      "[ fill vk ] %zu faces, %zu pairs: max |Δα| %.3g (%zu/%zu bit-identical), max |Δ∂α/∂p| "
      "%.3g = %.3g of the tolerance (%zu/%zu bit-identical), pull-back %.3g of the tolerance "
      "(%zu bit-identical)\n",
      a.faces, a.pairs, a.max_alpha, a.alpha_same, a.faces, a.max_d_alpha, a.max_d_alpha_tol,
      a.d_alpha_same, vk.d_alpha().size(), a.max_pullback_tol, a.pullback_same);
  return a;
}

class FillRatioVkTest : public VulkanTest {
 protected:
  FillRatioOptions vulkan_options() { return FillRatioOptions::for_backend(vulkan_backend(shared_ctx())); }
  bool ieee() { return is_lavapipe(ctx()); }
};

void print_report(const char* what, const FillRatioReport& r) {
  std::printf("[ fill vk ] %s: %s frames %.2f ms, broad phase %.2f ms, kernels %.2f ms (device ",
              what, r.call.c_str(), r.frames_ms, r.broad_phase_ms, r.kernels_ms);
  for (const FillRatioReport::Dispatch& d : r.dispatches)
    std::printf("%s %u items %.2f ms; ", d.kernel.c_str(), d.items, d.device_ms.value_or(-1));
  std::printf("up %zu B, down %zu B)\n", r.upload_bytes, r.download_bytes);
}

void run_parity(const FillRatioOptions& vulkan, bool ieee, const std::string& shape,
                double edge, int count, double smin, double smax, unsigned seed0) {
  const SurfaceMesh mesh = generate_shape(shape, {}, edge);
  const FaceBvh bvh(mesh);
  const StencilLibrary lib = mixed_library();
  FillRatioEvaluator tbb(bvh, lib), vk(bvh, lib, vulkan);
  size_t partial = 0;
  for (unsigned seed = seed0; seed < seed0 + 3; ++seed) {
    SCOPED_TRACE(shape + ", seed " + std::to_string(seed));
    const auto stencils = random_stencils(mesh, count, smin, smax, lib.size(), seed);
    tbb.evaluate(stencils);
    vk.evaluate(stencils);
    print_report(shape.c_str(), vk.last_report());
    std::printf("[ fill vk ] TBB: frames %.2f ms, broad phase %.2f ms, kernels %.2f ms\n",
                tbb.last_report().frames_ms, tbb.last_report().broad_phase_ms,
                tbb.last_report().kernels_ms);
    expect_agreement(tbb, vk, mesh, lib, ieee, seed);
    for (Eigen::Index f = 0; f < tbb.alpha().size(); ++f)
      partial += tbb.alpha()[f] > vulkan.min_fill && tbb.alpha()[f] < 1;
  }
  EXPECT_GT(partial, 300u) << "the layouts should exercise the clipping";
}

TEST_F(FillRatioVkTest, MatchesTbbOnTheBowl) {
  // Bowl: r = 0.15 m, faces ≈ 1 cm; stencils from 1.5 to 5 face sizes.
  run_parity(vulkan_options(), ieee(), "bowl", 0.01, 40, 0.015, 0.05, 10);
}

TEST_F(FillRatioVkTest, MatchesTbbOnThePavilion) {
  // Pavilion: r = 3 m, faces ≈ 0.1 m; stencils from 1 to 5 face sizes.
  run_parity(vulkan_options(), ieee(), "pavilion", 0.1, 300, 0.1, 0.5, 20);
}

// One evaluator for a whole "optimisation": each iteration moves every stencil a little (well
// inside the broad phase's slack, so the pair list stays), then one iteration moves a few far
// enough to change the pairs. Every iteration agrees with the TBB evaluator; after the first,
// the mesh, shapes and offsets never move again, only the stencil records (and the pair list
// where it changed).
TEST_F(FillRatioVkTest, OptimiserIterationsKeepAgreeingAndUploadOnlyWhatChanged) {
  const SurfaceMesh mesh = generate_shape("pavilion", {}, 0.1);
  const FaceBvh bvh(mesh);
  const StencilLibrary lib = mixed_library();
  FillRatioEvaluator tbb(bvh, lib), vk(bvh, lib, vulkan_options());
  auto stencils = random_stencils(mesh, 200, 0.1, 0.5, lib.size(), 5);
  std::mt19937 rng(9);
  std::normal_distribution<double> n01;
  size_t first_upload = 0;
  for (int iteration = 0; iteration < 6; ++iteration) {
    SCOPED_TRACE("iteration " + std::to_string(iteration));
    if (iteration >= 2 && iteration < 5) {  // small steps: every stencil, within the slack
      for (StencilParams& p : stencils) {
        p.position += 0.002 * p.scale * Vec3(n01(rng), n01(rng), n01(rng));
        p.angle += 0.01 * n01(rng);
      }
    } else if (iteration == 5) {  // a big step for a few stencils: the pair list changes
      for (size_t j = 0; j < stencils.size(); j += 40) stencils[j].position += Vec3(0.4, 0.3, 0);
    }
    const std::vector<kernels::ClipPair> previous_pairs = vk.pairs();
    tbb.evaluate(stencils);
    vk.evaluate(stencils);
    const FillRatioReport report = vk.last_report();
    print_report(("iteration " + std::to_string(iteration)).c_str(), report);
    const bool pairs_changed =
        !same_bits<kernels::ClipPair>(previous_pairs, vk.pairs());
    ASSERT_EQ(report.dispatches.size(), 2u) << "clip and fill in one submission";
    EXPECT_EQ(report.dispatches[0].kernel, "clip");
    EXPECT_EQ(report.dispatches[1].kernel, "fill");
    EXPECT_EQ(report.download_bytes,
              (size_t(mesh.num_faces()) + 5 * vk.pairs().size()) * sizeof(double))
        << "α and dα/dp only: the per-pair results stay on the device";
    if (iteration == 0) {
      first_upload = report.upload_bytes;
      EXPECT_GT(first_upload, 0u);
    } else {
      EXPECT_LT(report.upload_bytes, first_upload);
      for (const auto& [name, bytes] : report.uploads) {
        SCOPED_TRACE(name);
        if (iteration == 1) {
          EXPECT_EQ(bytes, 0u) << "nothing moved, nothing is uploaded";
        } else if (name == "stencils") {
          EXPECT_GT(bytes, 0u);
        } else if (name == "pairs" || name == "face_offsets") {
          EXPECT_EQ(bytes > 0, pairs_changed) << "the pair list uploads when it changed";
        } else {
          EXPECT_EQ(bytes, 0u) << "mesh and shapes stay on the device";
        }
      }
    }
    if (iteration >= 2 && iteration < 5) {
      EXPECT_EQ(vk.requeried(), 0);
      EXPECT_FALSE(pairs_changed);
    }
    if (iteration == 5) {
      EXPECT_GT(vk.requeried(), 0);
      EXPECT_TRUE(pairs_changed);
    }

    const Agreement a =
        expect_agreement(tbb, vk, mesh, lib, ieee(), 100 + unsigned(iteration));
    // The pull-back ran against the device-resident dα/dp: dS/dα goes up, and the grouping by
    // stencil when the pairs changed; nothing else.
    print_report("pull-back", a.pullback_report);
    ASSERT_EQ(a.pullback_report.dispatches.size(), 1u);
    EXPECT_EQ(a.pullback_report.dispatches[0].kernel, "fill_pullback");
    size_t allowed = size_t(mesh.num_faces()) * sizeof(double);
    if (iteration == 0 || pairs_changed)
      allowed += (vk.pairs().size() + stencils.size() + 1) * sizeof(int32_t);
    EXPECT_LE(a.pullback_report.upload_bytes, allowed);
    for (const auto& [name, bytes] : a.pullback_report.uploads) {
      if (name != "d_objective_d_alpha" && !(iteration == 0 || pairs_changed)) {
        EXPECT_EQ(bytes, 0u) << name;
      }
    }
  }
}

TEST_F(FillRatioVkTest, OverlapsDownloadLazilyOrWithEveryEvaluation) {
  const SurfaceMesh mesh = generate_shape("bowl", {}, 0.01);
  const FaceBvh bvh(mesh);
  const StencilLibrary lib = mixed_library();
  FillRatioOptions eager_options = vulkan_options();
  eager_options.download_overlaps = true;
  FillRatioEvaluator lazy(bvh, lib, vulkan_options()), eager(bvh, lib, eager_options);
  const auto stencils = random_stencils(mesh, 30, 0.015, 0.05, lib.size(), 3);
  lazy.evaluate(stencils);
  eager.evaluate(stencils);
  const size_t pairs = lazy.pairs().size();
  ASSERT_GT(pairs, 0u);
  EXPECT_EQ(eager.last_report().download_bytes,
            lazy.last_report().download_bytes + pairs * sizeof(kernels::ClipResult));
  const std::vector<kernels::ClipResult> eager_overlaps = eager.overlaps();
  EXPECT_EQ(eager.last_report().call, "evaluate") << "already downloaded: no device call";
  const std::vector<kernels::ClipResult> lazy_overlaps = lazy.overlaps();
  EXPECT_EQ(lazy.last_report().call, "overlaps");
  ASSERT_EQ(lazy.last_report().dispatches.size(), 1u);
  EXPECT_EQ(lazy.last_report().dispatches[0].kernel, "clip");
  EXPECT_EQ(lazy.last_report().upload_bytes, 0u) << "the inputs are still on the device";
  EXPECT_EQ(lazy.last_report().download_bytes, pairs * sizeof(kernels::ClipResult));
  EXPECT_TRUE(same_bits<kernels::ClipResult>(lazy_overlaps, eager_overlaps))
      << "the re-run clip computes what the evaluation computed";
  (void)lazy.overlaps();
  EXPECT_EQ(lazy.last_report().call, "overlaps");
  EXPECT_EQ(lazy.last_report().dispatches.size(), 1u);

  // The lazy download re-ran the clip, so the pull-back re-uploads the pairs and dα/dp; it
  // still computes the same bits as the eager evaluator's pull-back of the resident dα/dp.
  const Eigen::VectorXd g_alpha = random_gradient(lazy.alpha().size(), 1);
  Eigen::VectorXd g_lazy, g_eager;
  lazy.pullback(g_alpha, g_lazy);
  EXPECT_GT(lazy.last_report().upload_bytes, 0u);
  eager.pullback(g_alpha, g_eager);
  ASSERT_EQ(g_lazy.size(), g_eager.size());
  EXPECT_TRUE(same_bits<double>(std::span<const double>(g_lazy.data(), size_t(g_lazy.size())),
                                std::span<const double>(g_eager.data(), size_t(g_eager.size()))));
  // The next evaluation invalidates the downloaded results again.
  lazy.evaluate(stencils);
  (void)lazy.overlaps();
  EXPECT_EQ(lazy.last_report().call, "overlaps");
}

TEST_F(FillRatioVkTest, WithoutDerivativesAndWithoutStencils) {
  const SurfaceMesh mesh = generate_shape("bowl", {}, 0.01);
  const FaceBvh bvh(mesh);
  const StencilLibrary lib = mixed_library();
  FillRatioOptions cpu_options, vk_options = vulkan_options();
  cpu_options.derivatives = vk_options.derivatives = false;
  FillRatioEvaluator tbb(bvh, lib, cpu_options), vk(bvh, lib, vk_options);
  const auto stencils = random_stencils(mesh, 30, 0.015, 0.05, lib.size(), 4);
  tbb.evaluate(stencils);
  vk.evaluate(stencils);
  EXPECT_TRUE(vk.d_alpha().empty());
  expect_agreement(tbb, vk, mesh, lib, ieee(), 4);
  Eigen::VectorXd g;
  EXPECT_THROW(vk.pullback(Eigen::VectorXd::Ones(vk.alpha().size()), g), InternalError);

  // No stencils: α = 1 everywhere, a zero-length gradient; then stencils again.
  FillRatioEvaluator full(bvh, lib, vulkan_options());
  full.evaluate(std::vector<StencilParams>{});
  EXPECT_TRUE(full.pairs().empty());
  EXPECT_TRUE((full.alpha().array() == 1.0).all());
  EXPECT_TRUE(full.overlaps().empty());
  full.pullback(Eigen::VectorXd::Ones(mesh.num_faces()), g);
  EXPECT_EQ(g.size(), 0);
  full.evaluate(stencils);
  FillRatioEvaluator reference(bvh, lib);
  reference.evaluate(stencils);
  expect_agreement(reference, full, mesh, lib, ieee(), 5);
}

TEST_F(FillRatioVkTest, OptionsForABackendAndErrors) {
  EXPECT_STREQ(to_string(FillBackend::Vulkan), "vulkan");
  const FillRatioOptions vk = vulkan_options();
  EXPECT_EQ(vk.backend, FillBackend::Vulkan);
  EXPECT_EQ(vk.vulkan_context, shared_ctx());
  const FillRatioOptions cpu = FillRatioOptions::for_backend(cpu_backend());
  EXPECT_EQ(cpu.backend, FillBackend::Tbb);
  EXPECT_EQ(cpu.vulkan_context, nullptr);
  ComputeBackend no_context;
  no_context.kind = ComputeBackend::Kind::Vulkan;
  EXPECT_THROW(FillRatioOptions::for_backend(no_context), InternalError);

  const SurfaceMesh mesh = generate_shape("bowl", {}, 0.02);
  const FaceBvh bvh(mesh);
  const StencilLibrary lib = mixed_library();
  FillRatioOptions missing;
  missing.backend = FillBackend::Vulkan;
  EXPECT_THROW({ FillRatioEvaluator e(bvh, lib, missing); }, InternalError);
  // Bad stencils are rejected before anything reaches the device.
  FillRatioEvaluator ev(bvh, lib, vk);
  StencilParams bad;
  bad.scale = -1;
  EXPECT_THROW(ev.evaluate(std::vector<StencilParams>{bad}), InputError);
}

}  // namespace
}  // namespace cutwork::test
