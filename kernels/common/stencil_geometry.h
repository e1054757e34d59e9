#pragma once
/// Scalar geometry shared by the CPU twins of the clip kernel (clip_ref.cpp, clip_tbb.cpp) and
/// mirrored line by line by the GLSL twin (clip.comp, a later issue): the equidistant projection
/// of a mesh vertex into a stencil's reference frame with its Jacobian, one Sutherland–Hodgman
/// stage that carries edge labels, and the overlap area of a (possibly non-convex) stencil
/// polygon with a triangle together with the area's gradient w.r.t. the triangle's corners.
///
/// Only plain doubles, int32 and fixed-size arrays: no Eigen, no STL containers, no recursion,
/// no dynamic allocation — everything here has a direct GLSL counterpart.
///
/// Conventions
/// - Stencil parameters p = (q_x, q_y, q_z, s, φ), in this order (kStencilDofs = 5): the 3-D
///   position q (m), the scale s (bounding-circle radius, m) and the angle φ (rad, CCW about
///   the normal from the tangent direction t).
/// - 3×3 Jacobians are row-major: J[3*i + j] = ∂(component i) / ∂q_j.
/// - Reference frame: the stencil's own 2-D frame, in which its polygon has bounding radius 1
///   about the origin. A surface point x maps to
///       d = x − c,   a = (d·e_x, d·e_y),   w = (|d| / |a|) · a / s,
///   where c is the stencil centre on the surface and e_x = cos φ t + sin φ b,
///   e_y = −sin φ t + cos φ b are the stencil's axes in its tangent plane (t the tangent, b = n×t).
///   That is: orthogonal projection onto the tangent plane, radial rescaling so that the
///   distance to the centre is preserved (equidistant, paper §4.1), rotation by −φ and division
///   by s. |w| = |x − c| / s exactly.
#include <cmath>
#include <cstdint>

namespace cutwork::kernels {

/// Number of parameters per stencil: (q_x, q_y, q_z, s, φ).
inline constexpr int kStencilDofs = 5;

/// A vertex of a polygon being clipped, with the label of the edge that ENDS at it:
/// −1 for a piece of the stencil's boundary, 0/1/2 for a piece of triangle edge k (from
/// triangle corner k to corner (k+1)%3). 16 bytes; std430-compatible as {double x, y; int…}
/// is not needed on the GPU (it lives in private memory), but keep it POD.
struct ClipVertex {
  double x;
  double y;
  int32_t label;
  int32_t pad;
};

/// Twice the signed area of the triangle (o, a, b): > 0 when counter-clockwise.
inline double orient2(double ox, double oy, double ax, double ay, double bx, double by) {
  return (ax - ox) * (by - oy) - (ay - oy) * (bx - ox);
}

/// Equidistant projection of the 3-D point v into the reference frame of a stencil.
/// Inputs: v[3] (m); c[3] the stencil centre; ex[3], ey[3] its unit tangent-plane axes (already
///   rotated by φ); scale s > 0 (m).
///   For derivatives (jac != nullptr): dc[9] = ∂c/∂q, dex[9] = ∂e_x/∂q, dey[9] = ∂e_y/∂q
///   (row-major 3×3).
/// Outputs: w[2] (reference units, |w| = |v − c| / s);
///   jac[10] (nullable), row-major 2×5: jac[5*i + k] = ∂w_i / ∂p_k, p = (q_x, q_y, q_z, s, φ).
/// A point on the normal line through c (|a| = 0, including v = c) has no projected direction;
/// it maps to w = 0 and its Jacobian is taken with the radial factor fixed at 1 — the value of
/// the map there is exact (|w| = |d|/s is 0 only when v = c; otherwise the point is folded
/// onto the axis, a non-injective configuration the paper also excludes, §7).
inline void project_equidistant(const double* v, const double* c, const double* ex,
                                const double* ey, double scale, const double* dc,
                                const double* dex, const double* dey, double* w, double* jac) {
  const double d0 = v[0] - c[0], d1 = v[1] - c[1], d2 = v[2] - c[2];
  const double a1 = d0 * ex[0] + d1 * ex[1] + d2 * ex[2];
  const double a2 = d0 * ey[0] + d1 * ey[1] + d2 * ey[2];
  const double r3 = std::sqrt(d0 * d0 + d1 * d1 + d2 * d2);
  const double r2 = std::sqrt(a1 * a1 + a2 * a2);
  const bool on_axis = !(r2 > 0.0);
  const double k = on_axis ? 1.0 : r3 / r2;
  const double inv_s = 1.0 / scale;
  w[0] = on_axis ? 0.0 : k * a1 * inv_s;
  w[1] = on_axis ? 0.0 : k * a2 * inv_s;
  if (jac == nullptr) return;
  for (int j = 0; j < 3; ++j) {
    // ∂d/∂q_j = −∂c/∂q_j (column j of dc).
    const double dd0 = -dc[0 + j], dd1 = -dc[3 + j], dd2 = -dc[6 + j];
    const double da1 = dd0 * ex[0] + dd1 * ex[1] + dd2 * ex[2] +
                       d0 * dex[0 + j] + d1 * dex[3 + j] + d2 * dex[6 + j];
    const double da2 = dd0 * ey[0] + dd1 * ey[1] + dd2 * ey[2] +
                       d0 * dey[0 + j] + d1 * dey[3 + j] + d2 * dey[6 + j];
    double dk = 0.0;
    if (!on_axis) {
      const double dr3 = r3 > 0.0 ? (d0 * dd0 + d1 * dd1 + d2 * dd2) / r3 : 0.0;
      const double dr2 = (a1 * da1 + a2 * da2) / r2;
      dk = (dr3 - k * dr2) / r2;
    }
    jac[0 + j] = (dk * a1 + k * da1) * inv_s;
    jac[5 + j] = (dk * a2 + k * da2) * inv_s;
  }
  // ∂w/∂s = −w/s;  ∂w/∂φ = (w_y, −w_x) because ∂e_x/∂φ = e_y and ∂e_y/∂φ = −e_x.
  jac[3] = -w[0] * inv_s;
  jac[8] = -w[1] * inv_s;
  jac[4] = w[1];
  jac[9] = -w[0];
}

/// Signed distance (times the line's length) of (x, y) from the directed line a→b: ≥ 0 on
/// the left, i.e. inside the half-plane kept by a stage.
inline double line_side(double ax, double ay, double ex, double ey, double x, double y) {
  return ex * (y - ay) - ey * (x - ax);
}

/// One Sutherland–Hodgman stage: clips the closed polygon in[0..n) by the closed half-plane to
/// the LEFT of the directed line (ax, ay) → (bx, by) and writes the result to out.
/// Returns the output count, at most n + (number of boundary crossings)/2 ≤ 1.5 n.
/// Labels: an output vertex keeps the label of the input edge it lies on; the edges the stage
/// creates along the line (from an exit point to the next entry point) get `line_label`.
/// For a non-convex subject the result may contain zero-width "bridges" along the line; they
/// cancel exactly in the shoelace area and in the edge integrals of the area gradient.
inline int clip_half_plane(const ClipVertex* in, int n, double ax, double ay, double bx,
                           double by, int32_t line_label, ClipVertex* out) {
  if (n == 0) return 0;
  const double ex = bx - ax, ey = by - ay;
  int m = 0;
  ClipVertex prev = in[n - 1];
  double dprev = line_side(ax, ay, ex, ey, prev.x, prev.y);
  for (int i = 0; i < n; ++i) {
    const ClipVertex cur = in[i];
    const double dcur = line_side(ax, ay, ex, ey, cur.x, cur.y);
    const bool prev_in = dprev >= 0.0;
    const bool cur_in = dcur >= 0.0;
    if (prev_in != cur_in) {
      // The edge prev→cur crosses the line; dprev − dcur ≠ 0 since the signs differ.
      const double t = dprev / (dprev - dcur);
      ClipVertex x;
      x.x = prev.x + t * (cur.x - prev.x);
      x.y = prev.y + t * (cur.y - prev.y);
      x.label = prev_in ? cur.label : line_label;  // exit: on edge prev→cur; entry: along line
      x.pad = 0;
      out[m++] = x;
    }
    if (cur_in) out[m++] = cur;  // cur keeps the label of the edge prev→cur (or its piece)
    prev = cur;
    dprev = dcur;
  }
  return m;
}

/// The first stage, reading the stencil polygon poly[2n] directly (every edge labelled −1);
/// identical in result to copying it into ClipVertex form and calling clip_half_plane.
inline int clip_polygon_half_plane(const double* poly, int n, double ax, double ay, double bx,
                                   double by, int32_t line_label, ClipVertex* out) {
  const double ex = bx - ax, ey = by - ay;
  int m = 0;
  double px = poly[2 * n - 2], py = poly[2 * n - 1];
  double dprev = line_side(ax, ay, ex, ey, px, py);
  for (int i = 0; i < n; ++i) {
    const double cx = poly[2 * i], cy = poly[2 * i + 1];
    const double dcur = line_side(ax, ay, ex, ey, cx, cy);
    const bool prev_in = dprev >= 0.0;
    const bool cur_in = dcur >= 0.0;
    if (prev_in != cur_in) {
      const double t = dprev / (dprev - dcur);
      out[m].x = px + t * (cx - px);
      out[m].y = py + t * (cy - py);
      out[m].label = prev_in ? -1 : line_label;
      out[m].pad = 0;
      ++m;
    }
    if (cur_in) {
      out[m].x = cx;
      out[m].y = cy;
      out[m].label = -1;
      out[m].pad = 0;
      ++m;
    }
    px = cx;
    py = cy;
    dprev = dcur;
  }
  return m;
}

/// Area of (polygon ∩ triangle), both in the same 2-D frame, and its gradient w.r.t. the
/// triangle's corners.
/// Inputs: poly[2n] (x0, y0, x1, y1, …) a simple polygon, counter-clockwise, any convexity;
///   tri[6] the triangle's corners, counter-clockwise (positive area);
///   buf_a, buf_b: scratch of at least clip_scratch_capacity(n) vertices each.
/// Output: the area; grad[6] (nullable) = ∂area/∂tri.
/// Method: the polygon is clipped by the triangle's three half-planes (Sutherland–Hodgman;
/// exact in area for a non-convex subject against a convex clip region), the area is the
/// shoelace sum. The gradient follows from the transport theorem: only the parts of the
/// clipped boundary that lie on a triangle edge move with the triangle, so
///   ∂area/∂w_k = Σ over clipped edges on triangle edge (k→k+1) of ν ∫(1−λ)dλ
///                + Σ over clipped edges on triangle edge (k−1→k) of ν ∫λ dλ,
/// with λ the parameter along the triangle edge and ν = (e_y, −e_x) its outward normal scaled
/// by the edge length. The integrals are signed by the direction of the clipped edge, so the
/// bridges of a non-convex result cancel.
inline double polygon_triangle_overlap(const double* poly, int n, const double* tri,
                                       double* grad, ClipVertex* buf_a, ClipVertex* buf_b) {
  int m = clip_polygon_half_plane(poly, n, tri[0], tri[1], tri[2], tri[3], 0, buf_b);
  m = clip_half_plane(buf_b, m, tri[2], tri[3], tri[4], tri[5], 1, buf_a);
  m = clip_half_plane(buf_a, m, tri[4], tri[5], tri[0], tri[1], 2, buf_b);
  const ClipVertex* q = buf_b;
  if (grad != nullptr) {
    for (int k = 0; k < 6; ++k) grad[k] = 0.0;
  }
  if (m < 3) return 0.0;
  // Shoelace about the first vertex keeps the terms small.
  const double ox = q[0].x, oy = q[0].y;
  double twice_area = 0.0;
  for (int i = 1; i + 1 < m; ++i) {
    twice_area += (q[i].x - ox) * (q[i + 1].y - oy) - (q[i].y - oy) * (q[i + 1].x - ox);
  }
  if (grad != nullptr) {
    for (int i = 0; i < m; ++i) {
      const int label = q[i].label;
      if (label < 0) continue;
      const ClipVertex a = q[i == 0 ? m - 1 : i - 1];
      const ClipVertex b = q[i];
      const int k0 = label, k1 = label == 2 ? 0 : label + 1;
      const double wx = tri[2 * k0], wy = tri[2 * k0 + 1];
      const double ex = tri[2 * k1] - wx, ey = tri[2 * k1 + 1] - wy;
      const double inv_len2 = 1.0 / (ex * ex + ey * ey);
      const double la = ((a.x - wx) * ex + (a.y - wy) * ey) * inv_len2;
      const double lb = ((b.x - wx) * ex + (b.y - wy) * ey) * inv_len2;
      const double i_lambda = 0.5 * (lb * lb - la * la);  // ∫_{la}^{lb} λ dλ
      const double i_one_minus = (lb - la) - i_lambda;    // ∫_{la}^{lb} (1−λ) dλ
      grad[2 * k0] += ey * i_one_minus;
      grad[2 * k0 + 1] += -ex * i_one_minus;
      grad[2 * k1] += ey * i_lambda;
      grad[2 * k1 + 1] += -ex * i_lambda;
    }
  }
  return 0.5 * twice_area;
}

/// Scratch vertices needed per buffer to clip a polygon of n vertices by a triangle:
/// each stage yields at most 1.5× its input, so 1.5³ n < 3.4 n; rounded up with headroom.
inline int clip_scratch_capacity(int n) { return 4 * n + 8; }

/// Squared distance from the origin to the segment a→b.
inline double origin_segment_distance2(double ax, double ay, double bx, double by) {
  const double ex = bx - ax, ey = by - ay;
  const double len2 = ex * ex + ey * ey;
  double t = len2 > 0.0 ? -(ax * ex + ay * ey) / len2 : 0.0;
  t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
  const double px = ax + t * ex, py = ay + t * ey;
  return px * px + py * py;
}

}  // namespace cutwork::kernels
