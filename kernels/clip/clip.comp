#version 450
// GPU twin of the clip kernel: one invocation per (stencil, triangle) pair.
//
// Mirrors, line by line and in double precision, clip_pair() in kernels/clip/clip_ref.cpp and
// the helpers of kernels/common/stencil_geometry.h (project_equidistant, clip_half_plane,
// polygon_triangle_overlap, origin_segment_distance2, orient2); the section numbers below are
// clip_pair's. Change one twin, change the other: tests/kernels/clip/clip_vk_test.cpp compares
// them.
//
// Differences forced by GLSL (no pointers, no recursion, and private arrays that would have to
// be sized for kMaxStencilPolygonVertices = 2048 — 400 KB per invocation, which no GPU keeps):
//  - Sutherland–Hodgman runs STREAMING: the three half-plane stages are chained, each keeping
//    only its first and previous vertex, and the clipped polygon is consumed vertex by vertex
//    (shoelace and gradient terms accumulated as they arrive), so an invocation needs O(1)
//    memory whatever the polygon size. Every clipped vertex is computed by the same formula
//    from the same operands as in clip_half_plane, so it has the same bits. What differs is the
//    cyclic START: the C++ stage processes its closing edge (last → first) first, the stream
//    processes it last, so the clipped polygon comes out rotated, the shoelace sum starts at
//    another vertex and the gradient terms are added in rotated order — round-off-level
//    differences (the parity tolerance in host/vulkan/clip_fill_vk.h covers them);
//  - the projected corners, their Jacobians and the overlap gradient live in private globals
//    (g_w, g_jac, g_grad) instead of local arrays passed by pointer;
//  - every double variable is `precise`: no fused multiply-adds, the operations happen in the
//    C++ order (the CPU twins are compiled without FMA contraction), and double literals carry
//    the `lf` suffix (a bare 2e-12 would be a float).
layout(local_size_x_id = 0) in;

struct ClipShape {
  int polygon_offset;
  int polygon_count;
  double area;
  double inner_radius;
};
struct ClipStencil {
  double origin[3];
  double axis_x[3];
  double axis_y[3];
  double d_origin[9];
  double d_axis_x[9];
  double d_axis_y[9];
  double scale;
  int shape;
  int pad;
};
struct ClipPair {
  int stencil;
  int face;
};
struct ClipResult {
  double fraction;
  double d_fraction[5];
  double overlap_area;
  double triangle_area;
};
struct ClipVertex {
  double x;
  double y;
  int label;
};

layout(std430, set = 0, binding = 0) readonly buffer Vertices { double vertices[]; };
layout(std430, set = 0, binding = 1) readonly buffer Faces { int faces[]; };
layout(std430, set = 0, binding = 2) readonly buffer Shapes { ClipShape shapes[]; };
layout(std430, set = 0, binding = 3) readonly buffer Polygons { double polygons[]; };
layout(std430, set = 0, binding = 4) readonly buffer Stencils { ClipStencil stencils[]; };
layout(std430, set = 0, binding = 5) readonly buffer Pairs { ClipPair pairs[]; };
layout(std430, set = 0, binding = 6) writeonly buffer Results { ClipResult results[]; };

layout(push_constant, std430) uniform Push {
  uint first;       // DispatchRange
  uint count;
  int derivatives;  // ClipOptions
  int early_exits;
} pc;

// Private globals. Not `precise` themselves (glslang 12 emits invalid SPIR-V for precise
// globals): every value stored into them is computed into a precise local first.
double g_w[6];     // projected corners w_0, w_1, w_2
double g_jac[30];  // ∂w_k/∂p, row-major 2×5 at 10 k
double g_grad[6];  // ∂overlap/∂w

// stencil_geometry.h: orient2.
double orient2(double ox, double oy, double ax, double ay, double bx, double by) {
  precise double r = (ax - ox) * (by - oy) - (ay - oy) * (bx - ox);
  return r;
}

// stencil_geometry.h: project_equidistant(v, c, ex, ey, scale, dc, dex, dey, w, jac), for mesh
// vertex `vtx` and stencil `s`; writes g_w[2k], g_w[2k+1] and (want_jac) g_jac[10k …].
void project_equidistant(int vtx, int s, bool want_jac, int k) {
  precise double v0 = vertices[3 * vtx], v1 = vertices[3 * vtx + 1], v2 = vertices[3 * vtx + 2];
  precise double c0 = stencils[s].origin[0], c1 = stencils[s].origin[1], c2 = stencils[s].origin[2];
  precise double ex0 = stencils[s].axis_x[0], ex1 = stencils[s].axis_x[1], ex2 = stencils[s].axis_x[2];
  precise double ey0 = stencils[s].axis_y[0], ey1 = stencils[s].axis_y[1], ey2 = stencils[s].axis_y[2];
  precise double scale = stencils[s].scale;
  precise double d0 = v0 - c0, d1 = v1 - c1, d2 = v2 - c2;
  precise double a1 = d0 * ex0 + d1 * ex1 + d2 * ex2;
  precise double a2 = d0 * ey0 + d1 * ey1 + d2 * ey2;
  precise double r3 = sqrt(d0 * d0 + d1 * d1 + d2 * d2);
  precise double r2 = sqrt(a1 * a1 + a2 * a2);
  const bool on_axis = !(r2 > 0.0lf);
  precise double kk = on_axis ? 1.0lf : r3 / r2;
  precise double inv_s = 1.0lf / scale;
  precise double w0 = on_axis ? 0.0lf : kk * a1 * inv_s;
  precise double w1 = on_axis ? 0.0lf : kk * a2 * inv_s;
  g_w[2 * k] = w0;
  g_w[2 * k + 1] = w1;
  if (!want_jac) return;
  const int J = 10 * k;
  for (int j = 0; j < 3; ++j) {
    // ∂d/∂q_j = −∂c/∂q_j (column j of dc).
    precise double dd0 = -stencils[s].d_origin[0 + j], dd1 = -stencils[s].d_origin[3 + j],
                   dd2 = -stencils[s].d_origin[6 + j];
    precise double da1 = dd0 * ex0 + dd1 * ex1 + dd2 * ex2 + d0 * stencils[s].d_axis_x[0 + j] +
                         d1 * stencils[s].d_axis_x[3 + j] + d2 * stencils[s].d_axis_x[6 + j];
    precise double da2 = dd0 * ey0 + dd1 * ey1 + dd2 * ey2 + d0 * stencils[s].d_axis_y[0 + j] +
                         d1 * stencils[s].d_axis_y[3 + j] + d2 * stencils[s].d_axis_y[6 + j];
    precise double dk = 0.0lf;
    if (!on_axis) {
      precise double dr3 = r3 > 0.0lf ? (d0 * dd0 + d1 * dd1 + d2 * dd2) / r3 : 0.0lf;
      precise double dr2 = (a1 * da1 + a2 * da2) / r2;
      dk = (dr3 - kk * dr2) / r2;
    }
    precise double j0 = (dk * a1 + kk * da1) * inv_s;
    precise double j1 = (dk * a2 + kk * da2) * inv_s;
    g_jac[J + 0 + j] = j0;
    g_jac[J + 5 + j] = j1;
  }
  // ∂w/∂s = −w/s;  ∂w/∂φ = (w_y, −w_x).
  precise double js0 = -w0 * inv_s, js1 = -w1 * inv_s;
  g_jac[J + 3] = js0;
  g_jac[J + 8] = js1;
  g_jac[J + 4] = w1;
  g_jac[J + 9] = -w0;
}

// ---- stencil_geometry.h: clip_polygon_half_plane / clip_half_plane, as a stream ----------
// Stage k clips by the half-plane left of triangle edge k (corner k → corner k+1), with
// line_label k, exactly as the three stages of polygon_triangle_overlap (the first,
// clip_polygon_half_plane, reads the polygon with every edge labelled −1, as stage 0 here).
ClipVertex g_first[3];  // the stage's first input vertex and its signed distance
double g_dfirst[3];
ClipVertex g_prev[3];   // the previous input vertex ("prev" in clip_half_plane)
double g_dprev[3];
int g_seen[3];          // input vertices received

// line_side(ax, ay, ex, ey, cur.x, cur.y) = ex * (cur.y − ay) − ey * (cur.x − ax) for stage
// k's line (ex, ey = b − a, as the C++ computes them once per stage).
double stage_side(int k, ClipVertex v) {
  const int k1 = k == 2 ? 0 : k + 1;
  precise double ax = g_w[2 * k], ay = g_w[2 * k + 1];
  precise double ex = g_w[2 * k1] - ax, ey = g_w[2 * k1 + 1] - ay;
  precise double d = ex * (v.y - ay) - ey * (v.x - ax);
  return d;
}

// The body of clip_half_plane's loop for the edge prev → cur: emits 0, 1 or 2 vertices.
int stage_edge(int k, ClipVertex prev, double dprev, ClipVertex cur, double dcur,
               out ClipVertex e0, out ClipVertex e1) {
  int m = 0;
  e0 = cur;
  e1 = cur;
  const bool prev_in = dprev >= 0.0lf;
  const bool cur_in = dcur >= 0.0lf;
  if (prev_in != cur_in) {
    // The edge prev→cur crosses the line; dprev − dcur ≠ 0 since the signs differ.
    precise double t = dprev / (dprev - dcur);
    precise double xx = prev.x + t * (cur.x - prev.x);
    precise double xy = prev.y + t * (cur.y - prev.y);
    ClipVertex x;
    x.x = xx;
    x.y = xy;
    x.label = prev_in ? cur.label : k;  // exit: on edge prev→cur; entry: along line
    e0 = x;
    m = 1;
  }
  if (cur_in) {  // cur keeps the label of the edge prev→cur (or its piece)
    if (m == 0) e0 = cur; else e1 = cur;
    m++;
  }
  return m;
}

// A new input vertex for stage k: the first is remembered for the closing edge.
int stage_push(int k, ClipVertex cur, out ClipVertex e0, out ClipVertex e1) {
  precise double dcur = stage_side(k, cur);
  int m = 0;
  e0 = cur;
  e1 = cur;
  if (g_seen[k] == 0) {
    g_first[k] = cur;
    g_dfirst[k] = dcur;
  } else {
    m = stage_edge(k, g_prev[k], g_dprev[k], cur, dcur, e0, e1);
  }
  g_prev[k] = cur;
  g_dprev[k] = dcur;
  g_seen[k]++;
  return m;
}

// End of stage k's input: the closing edge last → first (clip_half_plane's first edge).
int stage_close(int k, out ClipVertex e0, out ClipVertex e1) {
  e0 = g_prev[k];
  e1 = g_prev[k];
  if (g_seen[k] == 0) return 0;  // if (n == 0) return 0;
  return stage_edge(k, g_prev[k], g_dprev[k], g_first[k], g_dfirst[k], e0, e1);
}

// ---- the clipped polygon, consumed vertex by vertex ---------------------------------------
int g_m;              // clipped vertices so far
ClipVertex g_q0;      // the first (shoelace origin)
ClipVertex g_qprev;   // the previous
double g_twice_area;
bool g_want_grad;

// polygon_triangle_overlap's gradient term for the clipped edge a → b.
void gradient_term(ClipVertex a, ClipVertex b) {
  const int label = b.label;
  if (label < 0) return;
  const int k0 = label, k1 = label == 2 ? 0 : label + 1;
  precise double wx = g_w[2 * k0], wy = g_w[2 * k0 + 1];
  precise double ex = g_w[2 * k1] - wx, ey = g_w[2 * k1 + 1] - wy;
  precise double inv_len2 = 1.0lf / (ex * ex + ey * ey);
  precise double la = ((a.x - wx) * ex + (a.y - wy) * ey) * inv_len2;
  precise double lb = ((b.x - wx) * ex + (b.y - wy) * ey) * inv_len2;
  precise double i_lambda = 0.5lf * (lb * lb - la * la);  // ∫_{la}^{lb} λ dλ
  precise double i_one_minus = (lb - la) - i_lambda;     // ∫_{la}^{lb} (1−λ) dλ
  precise double g0 = g_grad[2 * k0] + ey * i_one_minus;
  precise double g1 = g_grad[2 * k0 + 1] + -ex * i_one_minus;
  g_grad[2 * k0] = g0;
  g_grad[2 * k0 + 1] = g1;
  precise double g2 = g_grad[2 * k1] + ey * i_lambda;
  precise double g3 = g_grad[2 * k1 + 1] + -ex * i_lambda;
  g_grad[2 * k1] = g2;
  g_grad[2 * k1 + 1] = g3;
}

void consume(ClipVertex v) {
  if (g_m == 0) {
    g_q0 = v;
  } else {
    if (g_m >= 2) {  // shoelace term (q[i], q[i+1]) about the first vertex, i ≥ 1
      precise double twice = g_twice_area + ((g_qprev.x - g_q0.x) * (v.y - g_q0.y) -
                                             (g_qprev.y - g_q0.y) * (v.x - g_q0.x));
      g_twice_area = twice;
    }
    if (g_want_grad) gradient_term(g_qprev, v);
  }
  g_qprev = v;
  g_m++;
}

// The chain stage 0 → stage 1 → stage 2 → consume (GLSL has no recursion or function
// pointers, hence one function per link).
void push2(ClipVertex v) {
  ClipVertex e0, e1;
  const int m = stage_push(2, v, e0, e1);
  for (int i = 0; i < m; ++i) consume(i == 0 ? e0 : e1);
}
void push1(ClipVertex v) {
  ClipVertex e0, e1;
  const int m = stage_push(1, v, e0, e1);
  for (int i = 0; i < m; ++i) push2(i == 0 ? e0 : e1);
}
void push0(ClipVertex v) {
  ClipVertex e0, e1;
  const int m = stage_push(0, v, e0, e1);
  for (int i = 0; i < m; ++i) push1(i == 0 ? e0 : e1);
}
void close_all() {
  ClipVertex e0, e1;
  int m = stage_close(0, e0, e1);
  for (int i = 0; i < m; ++i) push1(i == 0 ? e0 : e1);
  m = stage_close(1, e0, e1);
  for (int i = 0; i < m; ++i) push2(i == 0 ? e0 : e1);
  m = stage_close(2, e0, e1);
  for (int i = 0; i < m; ++i) consume(i == 0 ? e0 : e1);
}

// stencil_geometry.h: polygon_triangle_overlap(poly, n, tri, grad, …) with poly = polygons
// from vertex `poly`, tri = g_w, grad = g_grad (when want_grad).
double polygon_triangle_overlap(int poly, int n, bool want_grad) {
  for (int k = 0; k < 3; ++k) g_seen[k] = 0;
  g_m = 0;
  g_twice_area = 0.0lf;
  g_want_grad = want_grad;
  for (int k = 0; k < 6; ++k) g_grad[k] = 0.0lf;
  for (int i = 0; i < n; ++i) {
    ClipVertex v;
    v.x = polygons[2 * (poly + i)];
    v.y = polygons[2 * (poly + i) + 1];
    v.label = -1;
    push0(v);
  }
  close_all();
  if (g_m < 3) {
    for (int k = 0; k < 6; ++k) g_grad[k] = 0.0lf;
    return 0.0lf;
  }
  if (want_grad) gradient_term(g_qprev, g_q0);  // the closing edge q[m−1] → q[0]
  precise double area = 0.5lf * g_twice_area;
  return area;
}

// stencil_geometry.h: origin_segment_distance2.
double origin_segment_distance2(double ax, double ay, double bx, double by) {
  precise double ex = bx - ax, ey = by - ay;
  precise double len2 = ex * ex + ey * ey;
  precise double t = len2 > 0.0lf ? -(ax * ex + ay * ey) / len2 : 0.0lf;
  t = t < 0.0lf ? 0.0lf : (t > 1.0lf ? 1.0lf : t);
  precise double px = ax + t * ex, py = ay + t * ey;
  precise double d2 = px * px + py * py;
  return d2;
}

void store(int pair_index, ClipResult r) { results[pair_index] = r; }

// clip_ref.cpp: clip_pair(in, options, pair_index, scratch).
void main() {
  const uint local_index = gl_GlobalInvocationID.x;
  if (local_index >= pc.count) return;
  const int pair_index = int(pc.first + local_index);

  ClipResult r;
  r.fraction = 0.0lf;
  for (int j = 0; j < 5; ++j) r.d_fraction[j] = 0.0lf;
  r.overlap_area = 0.0lf;
  r.triangle_area = 0.0lf;
  const ClipPair pair = pairs[pair_index];
  const int s = pair.stencil;
  const ClipShape shape = shapes[stencils[s].shape];
  const bool derivatives = pc.derivatives != 0;

  // 1. Corners in the reference frame, with ∂w_k/∂p (2×5 each).
  for (int k = 0; k < 3; ++k) {
    project_equidistant(faces[3 * pair.face + k], s, derivatives, k);
  }

  // 2. Projected triangle; back-facing or edge-on triangles contribute nothing.
  precise double scale = stencils[s].scale;
  precise double s2 = scale * scale;
  precise double twice_tri = orient2(g_w[0], g_w[1], g_w[2], g_w[3], g_w[4], g_w[5]);
  r.triangle_area = 0.5lf * twice_tri * s2;
  precise double longest2 = 0.0lf;
  for (int k = 0; k < 3; ++k) {
    const int k1 = k == 2 ? 0 : k + 1;
    precise double ex = g_w[2 * k1] - g_w[2 * k], ey = g_w[2 * k1 + 1] - g_w[2 * k + 1];
    precise double len2 = ex * ex + ey * ey;  // a named precise temporary: no fma in max()
    longest2 = max(longest2, len2);
  }
  if (!(twice_tri > 2e-12lf * longest2)) {
    store(pair_index, r);
    return;
  }

  // 3. Early exits.
  const int n = shape.polygon_count;
  const int poly = shape.polygon_offset;
  precise double overlap = 0.0lf;
  for (int k = 0; k < 6; ++k) g_grad[k] = 0.0lf;
  bool need_clip = true;
  if (pc.early_exits != 0) {
    precise double edge_fn[3];  // twice the signed area of (w_k, w_k+1, origin)
    bool origin_inside = true;
    for (int k = 0; k < 3; ++k) {
      const int k1 = k == 2 ? 0 : k + 1;
      edge_fn[k] = orient2(g_w[2 * k], g_w[2 * k + 1], g_w[2 * k1], g_w[2 * k1 + 1], 0.0lf, 0.0lf);
      origin_inside = origin_inside && edge_fn[k] >= 0.0lf;
    }
    if (!origin_inside) {
      precise double d2 = origin_segment_distance2(g_w[0], g_w[1], g_w[2], g_w[3]);
      d2 = min(d2, origin_segment_distance2(g_w[2], g_w[3], g_w[4], g_w[5]));
      d2 = min(d2, origin_segment_distance2(g_w[4], g_w[5], g_w[0], g_w[1]));
      if (d2 >= 1.0lf) {  // disjoint from the bounding circle
        store(pair_index, r);
        return;
      }
    }
    precise double inner2 = shape.inner_radius * shape.inner_radius;
    precise double r0 = g_w[0] * g_w[0] + g_w[1] * g_w[1], r1 = g_w[2] * g_w[2] + g_w[3] * g_w[3],
                   r2 = g_w[4] * g_w[4] + g_w[5] * g_w[5];
    if (max(r0, max(r1, r2)) <= inner2) {  // triangle ⊂ inscribed disk ⊂ polygon
      r.fraction = 1.0lf;
      r.overlap_area = r.triangle_area;
      store(pair_index, r);
      return;
    }
    if (origin_inside) {
      // Distance from the origin to edge line k is edge_fn[k] / |edge k|.
      bool circle_inside = true;
      for (int k = 0; k < 3; ++k) {
        const int k1 = k == 2 ? 0 : k + 1;
        precise double ex = g_w[2 * k1] - g_w[2 * k], ey = g_w[2 * k1 + 1] - g_w[2 * k + 1];
        precise double lhs = edge_fn[k] * edge_fn[k], rhs = ex * ex + ey * ey;
        circle_inside = circle_inside && lhs >= rhs;
      }
      if (circle_inside) {  // bounding circle ⊂ triangle: the whole polygon is covered
        overlap = shape.area;
        need_clip = false;
      }
    }
  }

  // 4. Clip.
  if (need_clip) overlap = polygon_triangle_overlap(poly, n, derivatives);

  // 5. Fraction and its derivatives.
  precise double tri = 0.5lf * twice_tri;
  r.fraction = overlap / tri;
  r.overlap_area = overlap * s2;
  if (!derivatives) {
    store(pair_index, r);
    return;
  }
  precise double d_frac_dw[6];
  for (int k = 0; k < 3; ++k) {
    const int kn = k == 2 ? 0 : k + 1, kp = k == 0 ? 2 : k - 1;
    // ∂A_T/∂w_k = ½ (w_{k+1} − w_{k−1})^⊥ with (x, y)^⊥ = (y, −x).
    precise double g_x = 0.5lf * (g_w[2 * kn + 1] - g_w[2 * kp + 1]);
    precise double g_y = -0.5lf * (g_w[2 * kn] - g_w[2 * kp]);
    d_frac_dw[2 * k] = (g_grad[2 * k] - r.fraction * g_x) / tri;
    d_frac_dw[2 * k + 1] = (g_grad[2 * k + 1] - r.fraction * g_y) / tri;
  }
  for (int j = 0; j < 5; ++j) {
    precise double sum = 0.0lf;
    for (int k = 0; k < 3; ++k) {
      sum += d_frac_dw[2 * k] * g_jac[10 * k + j] + d_frac_dw[2 * k + 1] * g_jac[10 * k + 5 + j];
    }
    r.d_fraction[j] = sum;
  }
  store(pair_index, r);
}
