#pragma once
/// The fill-ratio pipeline behind one interface (DESIGN.md, data flow):
///   stencil parameters p ─► frames (closest point, Phong normal, tangent field, Jacobians)
///   ─► broad phase (candidate pairs, incremental) ─► clip kernel ─► fill kernel
///   ─► α (#F) and the sparse dα/dp.
/// Backends: the reference and TBB twins of the kernels (bit-identical); the Vulkan twin of a
/// later issue plugs in behind the same interface.
///
/// Definition (paper §5.2): α_t = max(min_fill, 1 − Σ_s A(S_s ∩ T_t) / A(T_t)), with both areas
/// measured in stencil s's projected plane (equidistant projection, §4.1). On a flat mesh that
/// is the true covered fraction. See kernels/clip/clip.h for the per-pair details (back-facing
/// triangles, early exits) and kernels/fill/fill.h for the Jacobian layout.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "host/stencil/broad_phase.h"
#include "host/stencil/frame.h"
#include "host/stencil/stencil_shape.h"
#include "kernels/clip/clip.h"
#include "kernels/fill/fill.h"

namespace cutwork {

enum class FillBackend { Reference, Tbb };
const char* to_string(FillBackend backend);

struct FillRatioOptions {
  FillBackend backend = FillBackend::Tbb;
  BroadPhaseOptions broad_phase;
  double min_fill = 1e-4;    ///< lower bound of α (paper §5.2)
  bool derivatives = true;   ///< compute dα/dp
};

class FillRatioEvaluator {
 public:
  /// Stencils live on `surface` (their frames come from it) and cover the triangles of `sim`
  /// (which get fill ratios); pass the same BVH twice when the meshes coincide. `field`
  /// supplies tangents (null: AxisTangentField with its defaults). Everything referenced must
  /// outlive the evaluator. Throws InputError for an empty library or invalid options.
  FillRatioEvaluator(const FaceBvh& surface, const FaceBvh& sim, const StencilLibrary& shapes,
                     const TangentField* field = nullptr, FillRatioOptions options = {});
  FillRatioEvaluator(const FaceBvh& surface, const StencilLibrary& shapes,
                     FillRatioOptions options = {});
  ~FillRatioEvaluator();

  /// Runs the pipeline for `stencils` (#S). Buffers are reused between calls; the broad phase
  /// re-queries only stencils that moved beyond its slack.
  /// Throws InputError naming the stencil for a non-finite position or angle, a scale that is
  /// not finite and positive, or an unknown type.
  void evaluate(std::span<const StencilParams> stencils);

  /// #F fill ratios of the sim mesh's faces, each in [min_fill, 1].
  const Eigen::VectorXd& alpha() const { return m_alpha; }
  /// Candidate pairs (sorted by face) of the last evaluation.
  const std::vector<kernels::ClipPair>& pairs() const { return m_broad.pairs(); }
  /// #P per-pair clip results (fraction, its derivatives, projected areas).
  const std::vector<kernels::ClipResult>& overlaps() const { return m_overlaps; }
  /// #P×5: d_alpha()[5 i + k] = ∂α_{pairs()[i].face} / ∂p_{pairs()[i].stencil, k},
  /// p = (q_x, q_y, q_z, s, φ). Zero where α is clamped. Empty when derivatives are off.
  std::span<const double> d_alpha() const { return m_d_alpha; }
  /// #S frames of the last evaluation.
  const std::vector<Frame>& frames() const { return m_frames; }
  /// Number of stencils the broad phase re-queried in the last evaluation.
  int requeried() const { return m_requeried; }
  const FillRatioOptions& options() const { return m_options; }

  /// g_p = (dα/dp)ᵀ g_α: #F → #S×5 (stencil-major, p order as above). Deterministic.
  void pullback(const Eigen::VectorXd& d_objective_d_alpha,
                Eigen::VectorXd& d_objective_d_params) const;
  /// dα/dp as a sparse #F × 5#S matrix (for tests and small problems).
  Eigen::SparseMatrix<double, Eigen::RowMajor> jacobian() const;

 private:
  const FaceBvh* m_surface;
  const FaceBvh* m_sim;
  const StencilLibrary* m_shapes;
  std::unique_ptr<TangentField> m_own_field;
  const TangentField* m_field;
  FillRatioOptions m_options;
  BroadPhase m_broad;
  kernels::ClipWorkspace m_workspace;

  int m_num_stencils = 0;
  int m_requeried = 0;
  std::vector<Frame> m_frames;
  std::vector<kernels::ClipStencil> m_clip_stencils;
  std::vector<Vec3> m_centers;
  std::vector<double> m_scales;
  std::vector<kernels::ClipResult> m_overlaps;
  Eigen::VectorXd m_alpha;
  std::vector<double> m_d_alpha;
};

}  // namespace cutwork
