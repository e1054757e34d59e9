// Reference twin of the fill kernel, and the per-face / per-stencil bodies both twins share.
#include "kernels/fill/fill.h"

namespace cutwork::kernels {

void fill_face(const FillInputs& in, const FillParams& params, const FillOutputs& out,
               int32_t face) {
  const int32_t begin = in.face_offsets[size_t(face)];
  const int32_t end = in.face_offsets[size_t(face) + 1];
  double covered = 0.0;
  for (int32_t i = begin; i < end; ++i) covered += in.clip[size_t(i)].fraction;
  const double raw = 1.0 - covered;
  const bool clamped = !(raw > params.min_fill);
  // Each fraction lies in [0, 1] exactly but in floating point only up to round-off, so a face
  // touched by nothing but slivers can sum to −1e-17: α is capped at 1. The cap is not a kink of
  // α (it is ≤ 1 exactly), so the derivatives stay those of 1 − Σ fraction.
  out.alpha[size_t(face)] = clamped ? params.min_fill : (raw < 1.0 ? raw : 1.0);
  if (params.derivatives == 0) return;
  for (int32_t i = begin; i < end; ++i) {
    for (int k = 0; k < kStencilDofs; ++k) {
      out.d_alpha[5 * size_t(i) + size_t(k)] = clamped ? 0.0 : -in.clip[size_t(i)].d_fraction[k];
    }
  }
}

void fill_ref(const FillInputs& in, const FillParams& params, const FillOutputs& out) {
  const int32_t faces = int32_t(in.face_offsets.size()) - 1;
  for (int32_t f = 0; f < faces; ++f) fill_face(in, params, out, f);
}

void fill_pullback_stencil(const FillPullbackInputs& in,
                           std::span<const double> d_objective_d_alpha,
                           std::span<double> d_objective_d_params, int32_t stencil) {
  double g[kStencilDofs] = {0, 0, 0, 0, 0};
  const int32_t begin = in.stencil_offsets[size_t(stencil)];
  const int32_t end = in.stencil_offsets[size_t(stencil) + 1];
  for (int32_t j = begin; j < end; ++j) {
    const int32_t i = in.stencil_pairs[size_t(j)];
    const double ga = d_objective_d_alpha[size_t(in.pairs[size_t(i)].face)];
    for (int k = 0; k < kStencilDofs; ++k) g[k] += ga * in.d_alpha[5 * size_t(i) + size_t(k)];
  }
  for (int k = 0; k < kStencilDofs; ++k) d_objective_d_params[5 * size_t(stencil) + size_t(k)] = g[k];
}

void fill_pullback_ref(const FillPullbackInputs& in, std::span<const double> d_objective_d_alpha,
                       std::span<double> d_objective_d_params) {
  const int32_t stencils = int32_t(in.stencil_offsets.size()) - 1;
  for (int32_t s = 0; s < stencils; ++s) {
    fill_pullback_stencil(in, d_objective_d_alpha, d_objective_d_params, s);
  }
}

}  // namespace cutwork::kernels
