#pragma once
/// The fill-ratio pipeline behind one interface (DESIGN.md, data flow):
///   stencil parameters p ─► frames (closest point, Phong normal, tangent field, Jacobians)
///   ─► broad phase (candidate pairs, incremental) ─► clip kernel ─► fill kernel
///   ─► α (#F) and the sparse dα/dp.
///
/// Backends (FillBackend): the reference and TBB twins of the kernels (bit-identical to each
/// other), and the Vulkan twin (host/vulkan/clip_fill_vk.h). Frames and the broad phase always
/// run on the CPU; the backend chooses where clip → fill → pull-back run. With Vulkan the
/// evaluator owns one vulkan::ClipFillVk for its whole life, so the device buffers persist
/// across optimiser iterations and each evaluate() uploads only what changed (the stencil
/// records, and the pair list where the broad phase changed it — never the mesh); clip and fill
/// run in one submission and only α and dα/dp come back; pullback() reuses the device-resident
/// dα/dp. The per-pair clip results stay on the device unless asked for: overlaps() downloads
/// them on first use after an evaluation (or every evaluation downloads them with
/// FillRatioOptions::download_overlaps). Vulkan agrees with TBB to the parity contract stated
/// in host/vulkan/clip_fill_vk.h (|Δα| ≤ 1e-12; dα/dp to ~1e-9 relative), not bit for bit: the
/// GPU clip sums the clipped polygon from a different cyclic start. last_report() says what
/// each call cost (CPU phases, device timestamps, bytes moved).
///
/// This header has no Vulkan types; it compiles with and without CUTWORK_WITH_VULKAN (without
/// it, asking for FillBackend::Vulkan throws DeviceError).
///
/// Definition (paper §5.2): α_t = max(min_fill, 1 − Σ_s A(S_s ∩ T_t) / A(T_t)), with both areas
/// measured in stencil s's projected plane (equidistant projection, §4.1). On a flat mesh that
/// is the true covered fraction. See kernels/clip/clip.h for the per-pair details (back-facing
/// triangles, early exits) and kernels/fill/fill.h for the Jacobian layout.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "host/stencil/broad_phase.h"
#include "host/stencil/frame.h"
#include "host/stencil/stencil_shape.h"
#include "kernels/clip/clip.h"
#include "kernels/fill/fill.h"

namespace cutwork {

namespace vulkan {
class Context;
}
struct ComputeBackend;

/// Where clip → fill → pull-back run: the reference (serial) or TBB C++ twin, or the Vulkan
/// twin on FillRatioOptions::vulkan_context.
enum class FillBackend { Reference, Tbb, Vulkan };
/// "reference", "tbb", "vulkan".
const char* to_string(FillBackend backend);

struct FillRatioOptions {
  FillBackend backend = FillBackend::Tbb;
  /// The device for FillBackend::Vulkan (shared with everything else that dispatches kernels,
  /// see ComputeBackend::context); must have shaderFloat64. Ignored by the CPU backends.
  std::shared_ptr<vulkan::Context> vulkan_context;
  BroadPhaseOptions broad_phase;
  double min_fill = 1e-4;    ///< lower bound of α (paper §5.2)
  bool derivatives = true;   ///< compute dα/dp
  /// Vulkan only: download the #P per-pair clip results with every evaluation (same
  /// submission). Off, they stay on the device and overlaps() fetches them on first use after
  /// an evaluation (one more clip dispatch); an optimiser, which never reads them, saves the
  /// #P × sizeof(ClipResult) download per iteration.
  bool download_overlaps = false;

  /// The options that run the kernels on `backend` (select_compute_backend's result): TBB for
  /// the CPU, Vulkan on backend.context for Vulkan; everything else default. Throws InternalError
  /// for a Vulkan backend without a context.
  static FillRatioOptions for_backend(const ComputeBackend& backend);
};

/// What one call of a FillRatioEvaluator cost (FillRatioEvaluator::last_report()). Times in
/// milliseconds, host clock unless named device.
struct FillRatioReport {
  struct Dispatch {
    std::string kernel;               ///< "clip", "fill", "fill_pullback"
    uint32_t items = 0;               ///< invocations (pairs, faces, stencils)
    std::optional<double> device_ms;  ///< from GPU timestamps; none when the queue has none
  };
  std::string call;           ///< "evaluate", "pullback" or "overlaps" (the lazy download)
  double frames_ms = 0;       ///< evaluate(): the #S frames (CPU)
  double broad_phase_ms = 0;  ///< evaluate(): the incremental broad phase (CPU)
  /// The kernels: the CPU twins' run, or the device round trip (uploads, submission, wait,
  /// downloads) for Vulkan.
  double kernels_ms = 0;
  double total_ms = 0;  ///< the whole call
  // Vulkan only; empty / zero for the CPU backends.
  std::vector<Dispatch> dispatches;
  std::vector<std::pair<std::string, size_t>> uploads;  ///< per device array: bytes that changed
  size_t upload_bytes = 0;                              ///< Σ uploads
  size_t download_bytes = 0;

  /// Σ dispatches' device_ms; none for the CPU backends or without timestamps.
  std::optional<double> device_ms() const;
};

class FillRatioEvaluator {
 public:
  /// Stencils live on `surface` (their frames come from it) and cover the triangles of `sim`
  /// (which get fill ratios); pass the same BVH twice when the meshes coincide. `field`
  /// supplies tangents (null: AxisTangentField with its defaults). Everything referenced must
  /// outlive the evaluator. Throws InputError for an empty library or invalid options,
  /// InternalError for a BVH without a mesh or a Vulkan backend without vulkan_context,
  /// DeviceError for FillBackend::Vulkan in a build without CUTWORK_WITH_VULKAN.
  FillRatioEvaluator(const FaceBvh& surface, const FaceBvh& sim, const StencilLibrary& shapes,
                     const TangentField* field = nullptr, FillRatioOptions options = {});
  FillRatioEvaluator(const FaceBvh& surface, const StencilLibrary& shapes,
                     FillRatioOptions options = {});
  ~FillRatioEvaluator();

  /// Runs the pipeline for `stencils` (#S). Buffers are reused between calls; the broad phase
  /// re-queries only stencils that moved beyond its slack.
  /// Throws InputError naming the stencil for a non-finite position or angle, a scale that is
  /// not finite and positive, or an unknown type; DeviceError when the device fails (Vulkan).
  void evaluate(std::span<const StencilParams> stencils);

  /// #F fill ratios of the sim mesh's faces, each in [min_fill, 1].
  const Eigen::VectorXd& alpha() const { return m_alpha; }
  /// Candidate pairs (sorted by face) of the last evaluation.
  const std::vector<kernels::ClipPair>& pairs() const { return m_broad.pairs(); }
  /// #P per-pair clip results (fraction, its derivatives, projected areas). Vulkan without
  /// download_overlaps: the first call after an evaluation re-runs the clip kernel on the
  /// device and downloads its results (the same bits the evaluation computed; a following
  /// pullback() then uploads dα/dp again). Not thread-safe for that reason.
  const std::vector<kernels::ClipResult>& overlaps() const;
  /// #P×5: d_alpha()[5 i + k] = ∂α_{pairs()[i].face} / ∂p_{pairs()[i].stencil, k},
  /// p = (q_x, q_y, q_z, s, φ). Zero where α is clamped. Empty when derivatives are off.
  std::span<const double> d_alpha() const { return m_d_alpha; }
  /// #S frames of the last evaluation.
  const std::vector<Frame>& frames() const { return m_frames; }
  /// #S kernel records of the last evaluation (centre, rotated axes, scale, shape; Jacobians
  /// when derivatives are on): what the clip kernel projected with.
  const std::vector<kernels::ClipStencil>& clip_stencils() const { return m_clip_stencils; }
  /// Number of stencils the broad phase re-queried in the last evaluation.
  int requeried() const { return m_requeried; }
  const FillRatioOptions& options() const { return m_options; }
  /// Cost of the last evaluate(), pullback() or lazy overlaps() download.
  const FillRatioReport& last_report() const { return m_report; }

  /// g_p = (dα/dp)ᵀ g_α: #F → #S×5 (stencil-major, p order as above). Deterministic; the
  /// Vulkan twin equals the TBB twin bit for bit given the same dα/dp (it runs on the device
  /// against the dα/dp the last evaluation left there). Throws InternalError when derivatives are
  /// off or the size is wrong, DeviceError when the device fails.
  void pullback(const Eigen::VectorXd& d_objective_d_alpha,
                Eigen::VectorXd& d_objective_d_params) const;
  /// The part of each face each shape covers (#F × the library's shapes): h(t, k) = Σ fraction(s, t)
  /// over the pairs (s, t) whose stencil s has shape k — unclamped, so Σ_k h(t, k) = 1 − α_t wherever
  /// α_t is above min_fill and below 1. With `weight` (#S), each piece weighted by its stencil's:
  /// Σ w_s fraction(s, t). From overlaps() (Vulkan without download_overlaps: one clip re-run, see
  /// there).
  Eigen::MatrixXd covered_by_shape(std::span<const double> weight = {}) const;
  /// g_p = (dh/dp)ᵀ g_h for h = covered_by_shape(weight): d_objective_d_params[5 s + k] = Σ over the
  /// pairs (s, t) of g_h(t, shape of s) (w_s ∂fraction(s, t)/∂p_k + fraction(s, t) ∂w_s/∂p_k), a
  /// weight depending on the stencil's scale alone (`d_weight_d_scale`, #S, with `weight`)
  /// (#S×5, stencil-major). Serial over the pairs in list order (deterministic). Throws
  /// InternalError when derivatives are off or a size is wrong.
  void pullback_by_shape(const Eigen::MatrixXd& d_objective_d_covered, Eigen::VectorXd& d_objective_d_params,
                         std::span<const double> weight = {}, std::span<const double> d_weight_d_scale = {}) const;
  /// dα/dp as a sparse #F × 5#S matrix (for tests and small problems).
  Eigen::SparseMatrix<double, Eigen::RowMajor> jacobian() const;

 private:
  struct Device;  ///< the Vulkan twin's state (fill_ratio.cpp); null for the CPU backends
  kernels::ClipInputs clip_inputs() const;
  void evaluate_on_device(const kernels::ClipInputs& in);

  const FaceBvh* m_surface;
  const FaceBvh* m_sim;
  const StencilLibrary* m_shapes;
  std::unique_ptr<TangentField> m_own_field;
  const TangentField* m_field;
  FillRatioOptions m_options;
  BroadPhase m_broad;
  kernels::ClipWorkspace m_workspace;
  std::unique_ptr<Device> m_device;

  int m_num_stencils = 0;
  int m_requeried = 0;
  std::vector<Frame> m_frames;
  std::vector<kernels::ClipStencil> m_clip_stencils;
  std::vector<Vec3> m_centers;
  std::vector<double> m_scales;
  mutable std::vector<kernels::ClipResult> m_overlaps;
  mutable bool m_overlaps_current = true;  ///< false: the last evaluation's are on the device
  Eigen::VectorXd m_alpha;
  std::vector<double> m_d_alpha;
  mutable FillRatioReport m_report;
};

}  // namespace cutwork
