#version 450
// GPU twin of the fill kernel: one invocation per face, a segmented reduction over the pair
// list sorted by face, summed in pair order — no atomics, so the result does not depend on
// scheduling. Mirrors fill_face() in kernels/fill/fill_ref.cpp line by line, in double; change
// one twin, change the other (tests/kernels/fill/fill_vk_test.cpp compares them).
layout(local_size_x_id = 0) in;

struct ClipResult {
  double fraction;
  double d_fraction[5];
  double overlap_area;
  double triangle_area;
};

layout(std430, set = 0, binding = 0) readonly buffer Clip { ClipResult clip[]; };
layout(std430, set = 0, binding = 1) readonly buffer FaceOffsets { int face_offsets[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Alpha { double alpha[]; };
layout(std430, set = 0, binding = 3) writeonly buffer DAlpha { double d_alpha[]; };

layout(push_constant, std430) uniform Push {
  uint first;       // DispatchRange
  uint count;
  double min_fill;  // FillParams
  int derivatives;
  int pad;
} pc;

void main() {
  const uint local_index = gl_GlobalInvocationID.x;
  if (local_index >= pc.count) return;
  const int face = int(pc.first + local_index);
  const int begin = face_offsets[face];
  const int end = face_offsets[face + 1];
  precise double covered = 0.0lf;
  for (int i = begin; i < end; ++i) covered += clip[i].fraction;
  precise double raw = 1.0lf - covered;
  const bool clamped = !(raw > pc.min_fill);
  alpha[face] = clamped ? pc.min_fill : (raw < 1.0lf ? raw : 1.0lf);
  if (pc.derivatives == 0) return;
  for (int i = begin; i < end; ++i) {
    for (int k = 0; k < 5; ++k) {
      d_alpha[5 * i + k] = clamped ? 0.0lf : -clip[i].d_fraction[k];
    }
  }
}
