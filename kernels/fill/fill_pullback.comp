#version 450
// GPU twin of the fill kernel's pull-back g_p = (dα/dp)ᵀ g_α: one invocation per stencil, a
// segmented reduction over the stencil's pairs in stencil_pairs order — no atomics. Mirrors
// fill_pullback_stencil() in kernels/fill/fill_ref.cpp line by line, in double.
layout(local_size_x_id = 0) in;

struct ClipPair {
  int stencil;
  int face;
};

layout(std430, set = 0, binding = 0) readonly buffer Pairs { ClipPair pairs[]; };
layout(std430, set = 0, binding = 1) readonly buffer DAlpha { double d_alpha[]; };
layout(std430, set = 0, binding = 2) readonly buffer StencilPairs { int stencil_pairs[]; };
layout(std430, set = 0, binding = 3) readonly buffer StencilOffsets { int stencil_offsets[]; };
layout(std430, set = 0, binding = 4) readonly buffer DObjectiveDAlpha { double d_objective_d_alpha[]; };
layout(std430, set = 0, binding = 5) writeonly buffer DObjectiveDParams { double d_objective_d_params[]; };

layout(push_constant, std430) uniform Push {
  uint first;  // DispatchRange
  uint count;
} pc;

void main() {
  const uint local_index = gl_GlobalInvocationID.x;
  if (local_index >= pc.count) return;
  const int stencil = int(pc.first + local_index);
  precise double g[5] = double[5](0.0lf, 0.0lf, 0.0lf, 0.0lf, 0.0lf);
  const int begin = stencil_offsets[stencil];
  const int end = stencil_offsets[stencil + 1];
  for (int j = begin; j < end; ++j) {
    const int i = stencil_pairs[j];
    const double ga = d_objective_d_alpha[pairs[i].face];
    for (int k = 0; k < 5; ++k) g[k] += ga * d_alpha[5 * i + k];
  }
  for (int k = 0; k < 5; ++k) d_objective_d_params[5 * stencil + k] = g[k];
}
