#pragma once
/// The Vulkan twin of the clip and fill kernels, with the CPU twins' interface: the same
/// ClipInputs / FillInputs / FillOutputs spans in, the same arrays out (kernels/clip/clip.h,
/// kernels/fill/fill.h). One ClipFillVk lives as long as an optimisation: its device buffers
/// and pipelines persist across calls, and each call transfers only the bytes that changed
/// (the mesh once, the pair list when the broad phase changed it, the stencil frames each
/// iteration; see host/vulkan/buffer.h).
///
/// evaluate() runs clip → fill in ONE submission: the per-pair results stay on the device
/// between the two kernels, and only α, dα/dp (and, on request, the per-pair results) come
/// back. pullback_last() then reuses the device-resident pairs and dα/dp of that evaluation.
///
/// Precision: double, as in the CPU twins, on devices with shaderFloat64 (the Context is made
/// with require_float64; backend selection falls back to the CPU without it). Why not float:
/// the fill ratios feed a Newton solve and an adjoint gradient that is checked against finite
/// differences to 1e-6; in float the clipped areas of triangles small against their stencil
/// lose ~1e-7·(stencil radius / triangle size) relative accuracy and the quotient-rule
/// derivatives lose more, while the kernels cost little next to the CHOLMOD solve even at the
/// 1/32–1/64 fp64 rate of consumer GPUs. The shaders mirror the C++ line by line with every
/// double `precise` (no FMA contraction), so on an IEEE double implementation (lavapipe) the
/// twins agree bit for bit. Vulkan allows double division and sqrt a few ULP of error on
/// GPUs, so the parity CONTRACT, tested in tests/kernels/*_vk_test.cpp, is:
///   |Δ fraction|, |Δ α| ≤ 1e-12 (both dimensionless, O(1));
///   |Δ ∂fraction/∂p_k|, |Δ ∂α/∂p_k| ≤ 1e-9 · (|value| + u_k) + 64 ε · (P/A) · u_k, with
///     u_k = 1/s for q and s (per metre: moving a stencil by its own radius changes a fraction
///     by O(1)), u_φ = 1, and P/A the triangle's perimeter over its projected area in stencil
///     units — the round-off floor of the quotient rule, which both twins share (a triangle
///     10⁻⁶ of the stencil's size, fully covered, has analytic derivative 0 and numerical
///     derivatives of ~10⁻¹⁰·u in either twin);
///   pull-back: |Δ g_k| ≤ 1e-9 · Σ_pairs |g_α · ∂α/∂p_k| (+ 1e-300).
#include <cstdint>
#include <memory>
#include <span>

#include "host/vulkan/buffer.h"
#include "host/vulkan/command_batch.h"
#include "host/vulkan/pipeline.h"
#include "kernels/clip/clip.h"
#include "kernels/fill/fill.h"

namespace cutwork::vulkan {

class Context;

class ClipFillVk {
 public:
  /// `workgroup_size` 0: each kernel's default (64). Pipelines are built on first use.
  explicit ClipFillVk(std::shared_ptr<Context> context, uint32_t workgroup_size = 0);
  ~ClipFillVk();
  ClipFillVk(const ClipFillVk&) = delete;
  ClipFillVk& operator=(const ClipFillVk&) = delete;

  /// clip then fill, one submission; equal to clip_tbb followed by fill_tbb within the
  /// tolerance above. `face_offsets` (#F+1) groups the sorted pairs by face.
  /// Outputs: `results` (#P, or empty to leave them on the device), out.alpha (#F),
  /// out.d_alpha (#P×5 when fill_params.derivatives, may be empty to skip the download).
  /// Throws std::invalid_argument for inconsistent inputs (an index out of range would be an
  /// out-of-bounds read on the device), DeviceError when the device fails.
  void evaluate(const kernels::ClipInputs& in, const kernels::ClipOptions& clip_options,
                std::span<const int32_t> face_offsets, const kernels::FillParams& fill_params,
                std::span<kernels::ClipResult> results, const kernels::FillOutputs& out);

  /// The clip kernel alone (clip_tbb's contract).
  void clip(const kernels::ClipInputs& in, const kernels::ClipOptions& options,
            std::span<kernels::ClipResult> results);
  /// The fill kernel alone (fill_tbb's contract); uploads in.clip.
  void fill(const kernels::FillInputs& in, const kernels::FillParams& params,
            const kernels::FillOutputs& out);
  /// The pull-back alone (fill_pullback_tbb's contract); uploads everything it reads.
  void pullback(const kernels::FillPullbackInputs& in, std::span<const double> d_objective_d_alpha,
                std::span<double> d_objective_d_params);
  /// The pull-back against the pairs and dα/dp of the last evaluate() (which must have had
  /// derivatives on), still on the device: uploads only the grouping by stencil (when it
  /// changed) and dS/dα (#F). d_objective_d_params: #S×5.
  void pullback_last(std::span<const int32_t> stencil_pairs,
                     std::span<const int32_t> stencil_offsets,
                     std::span<const double> d_objective_d_alpha,
                     std::span<double> d_objective_d_params);

  /// Timings and transfer volumes of the last call.
  const BatchReport& last_report() const { return m_report; }
  Context& context() { return *m_ctx; }

 private:
  struct Stage {
    std::unique_ptr<ComputePipeline> pipeline;
    std::unique_ptr<DescriptorSet> set;
  };
  Stage& clip_stage();
  Stage& fill_stage();
  Stage& pullback_stage();
  void upload_clip_inputs(CommandBatch& batch, const kernels::ClipInputs& in);

  std::shared_ptr<Context> m_ctx;
  uint32_t m_workgroup_size;
  // Device arrays, named as in clip.h / fill.h.
  StorageBuffer m_vertices, m_faces, m_shapes, m_polygons, m_stencils, m_pairs, m_results;
  StorageBuffer m_face_offsets, m_alpha, m_d_alpha;
  StorageBuffer m_stencil_pairs, m_stencil_offsets, m_d_objective_d_alpha, m_d_objective_d_params;
  Stage m_clip, m_fill, m_pullback;
  size_t m_last_pairs = 0;  ///< #P of the last evaluate()
  bool m_last_derivatives = false;
  BatchReport m_report;
};

}  // namespace cutwork::vulkan
