#pragma once
/// Kernel `fill`: per-triangle fill ratios from the clip kernel's per-pair fractions,
///     α_t = max(min_fill, 1 − Σ_{pairs (s,t)} fraction(s,t))   (capped at 1 against round-off),
/// and the sparse Jacobian dα/dp, plus its transpose product (the pull-back of an objective's
/// gradient dS/dα to dS/dp) that the optimiser needs.
///
/// Deterministic: a segmented reduction over the pair list sorted by face, one face per work
/// item, summed in pair order — no float atomics, so every twin (ref, TBB, Vulkan) gives the
/// same bits regardless of scheduling. The pull-back is the same kind of segmented reduction
/// over the pairs grouped by stencil (a permutation the broad phase provides).
///
/// Jacobian layout (what the optimiser consumes): one 5-vector per pair, aligned with the pair
/// list: d_alpha[5·i + k] = ∂α_face(i) / ∂p_stencil(i),k with p = (q_x, q_y, q_z, s, φ).
/// Entries are exactly zero where α is clamped at min_fill (the clamp is flat there).
/// This is a CSR matrix by face (rows = faces via face_offsets, column block = stencil).
#include <cstdint>
#include <span>

#include "kernels/clip/clip.h"

namespace cutwork::kernels {

/// Parameters (a GPU push-constant block). std430: {double min_fill; int derivatives; int pad;}.
struct FillParams {
  double min_fill = 1e-4;   ///< lower bound on α (paper §5.2: avoids singular stiffness)
  int32_t derivatives = 1;  ///< 0: α only, d_alpha untouched
  int32_t pad = 0;
};
static_assert(sizeof(FillParams) == 16);

struct FillInputs {
  std::span<const ClipResult> clip;          ///< #P, aligned with the pair list
  std::span<const int32_t> face_offsets;     ///< #F+1: face f owns pairs [off[f], off[f+1])
};

struct FillOutputs {
  std::span<double> alpha;    ///< #F
  std::span<double> d_alpha;  ///< #P×5 (may be empty when params.derivatives == 0)
};

/// Reference twin (serial loop over faces).
void fill_ref(const FillInputs& in, const FillParams& params, const FillOutputs& out);
/// TBB twin (parallel loop over faces); bit-identical to fill_ref.
void fill_tbb(const FillInputs& in, const FillParams& params, const FillOutputs& out);

/// Inputs of the pull-back g_p = (dα/dp)ᵀ g_α.
struct FillPullbackInputs {
  std::span<const ClipPair> pairs;              ///< #P (for the face of each pair)
  std::span<const double> d_alpha;              ///< #P×5, from fill
  std::span<const int32_t> stencil_pairs;       ///< #P pair indices grouped by stencil
  std::span<const int32_t> stencil_offsets;     ///< #S+1 into stencil_pairs
};

/// d_params[5·s + k] = Σ_{pairs i of stencil s, in stencil_pairs order} d_alpha_objective[face(i)]
///                    · d_alpha[5·i + k].   d_alpha_objective: #F; d_params: #S×5.
void fill_pullback_ref(const FillPullbackInputs& in, std::span<const double> d_objective_d_alpha,
                       std::span<double> d_objective_d_params);
/// TBB twin (parallel over stencils); bit-identical to fill_pullback_ref.
void fill_pullback_tbb(const FillPullbackInputs& in, std::span<const double> d_objective_d_alpha,
                       std::span<double> d_objective_d_params);

/// The per-work-item bodies both twins share (and the GLSL mirrors).
void fill_face(const FillInputs& in, const FillParams& params, const FillOutputs& out,
               int32_t face);
void fill_pullback_stencil(const FillPullbackInputs& in,
                           std::span<const double> d_objective_d_alpha,
                           std::span<double> d_objective_d_params, int32_t stencil);

}  // namespace cutwork::kernels
