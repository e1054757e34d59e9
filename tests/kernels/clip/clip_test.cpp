// Tests of the clip kernel: the polygon ∩ triangle area against an independent computation
// (Green's theorem over the overlap boundary, built edge by edge), its gradient against central
// differences, degenerate placements with hand-computed answers, the early exits against the
// plain clipping path, the per-pair derivatives w.r.t. the stencil parameters against central
// differences of the whole map, and the reference/TBB twins bit for bit.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <random>
#include <vector>

#include "kernels/clip/clip.h"

namespace cutwork::kernels {
namespace {

using Poly = std::vector<double>;  // x0, y0, x1, y1, ...
using Tri = std::array<double, 6>;

// ---------------------------------------------------------------------------------------------
// Independent oracle: area(P ∩ T) = ∮ x dy over ∂(P ∩ T) = (∂P inside T) + (∂T inside P).
// Valid in general position (no edge of P collinear with an edge of T).

double x_dy(double ax, double ay, double bx, double by) { return 0.5 * (ax + bx) * (by - ay); }

bool point_in_polygon(const Poly& p, double x, double y) {
  const size_t n = p.size() / 2;
  bool inside = false;
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const double xi = p[2 * i], yi = p[2 * i + 1], xj = p[2 * j], yj = p[2 * j + 1];
    if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) inside = !inside;
  }
  return inside;
}

double green_overlap(const Poly& p_in, const Tri& t_in) {
  // ∮ x dy sums terms x·Δy: about a far origin they cancel badly for a small overlap, so shift
  // the frame to the triangle's first corner first.
  Poly p = p_in;
  Tri t = t_in;
  const double ox = t_in[0], oy = t_in[1];
  for (size_t i = 0; i < p.size(); i += 2) {
    p[i] -= ox;
    p[i + 1] -= oy;
  }
  for (size_t i = 0; i < 6; i += 2) {
    t[i] -= ox;
    t[i + 1] -= oy;
  }
  const size_t n = p.size() / 2;
  double area = 0;
  // Polygon edges clipped to the (convex) triangle, Cyrus–Beck.
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    const double ax = p[2 * i], ay = p[2 * i + 1], bx = p[2 * j], by = p[2 * j + 1];
    double t0 = 0, t1 = 1;
    for (int k = 0; k < 3; ++k) {
      const int k1 = (k + 1) % 3;
      const double ex = t[2 * k1] - t[2 * k], ey = t[2 * k1 + 1] - t[2 * k + 1];
      // inside: cross(e, x − t_k) ≥ 0, linear along the segment.
      const double fa = ex * (ay - t[2 * k + 1]) - ey * (ax - t[2 * k]);
      const double fb = ex * (by - t[2 * k + 1]) - ey * (bx - t[2 * k]);
      if (fa < 0 && fb < 0) {
        t0 = 1;
        t1 = 0;
        break;
      }
      if (fa < 0) t0 = std::max(t0, fa / (fa - fb));
      if (fb < 0) t1 = std::min(t1, fa / (fa - fb));
    }
    if (t1 > t0) {
      area += x_dy(ax + t0 * (bx - ax), ay + t0 * (by - ay), ax + t1 * (bx - ax),
                   ay + t1 * (by - ay));
    }
  }
  // Triangle edges: split at every crossing with the polygon, keep the pieces inside it.
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const double ax = t[2 * k], ay = t[2 * k + 1], bx = t[2 * k1], by = t[2 * k1 + 1];
    std::vector<double> cuts{0.0, 1.0};
    for (size_t i = 0; i < n; ++i) {
      const size_t j = (i + 1) % n;
      const double cx = p[2 * i], cy = p[2 * i + 1], dx = p[2 * j], dy = p[2 * j + 1];
      const double rx = bx - ax, ry = by - ay, sx = dx - cx, sy = dy - cy;
      const double den = rx * sy - ry * sx;
      if (den == 0) continue;
      const double u = ((cx - ax) * sy - (cy - ay) * sx) / den;
      const double v = ((cx - ax) * ry - (cy - ay) * rx) / den;
      if (u > 0 && u < 1 && v >= 0 && v <= 1) cuts.push_back(u);
    }
    std::sort(cuts.begin(), cuts.end());
    for (size_t c = 0; c + 1 < cuts.size(); ++c) {
      const double u0 = cuts[c], u1 = cuts[c + 1];
      if (u1 <= u0) continue;
      const double um = 0.5 * (u0 + u1);
      if (!point_in_polygon(p, ax + um * (bx - ax), ay + um * (by - ay))) continue;
      area += x_dy(ax + u0 * (bx - ax), ay + u0 * (by - ay), ax + u1 * (bx - ax),
                   ay + u1 * (by - ay));
    }
  }
  return area;
}

double polygon_area(const Poly& p) {
  const size_t n = p.size() / 2;
  double a = 0;
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    a += p[2 * i] * p[2 * j + 1] - p[2 * j] * p[2 * i + 1];
  }
  return 0.5 * a;
}

// ---------------------------------------------------------------------------------------------
// Test polygons (all simple, CCW).

// Star-shaped about the origin with random radii: simple by construction, usually non-convex.
Poly random_star_shaped(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> radius(0.25, 1.0), jitter(-0.4, 0.4);
  Poly p;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * (i + 0.5 + jitter(rng)) / n;
    const double r = radius(rng);
    p.push_back(r * std::cos(a));
    p.push_back(r * std::sin(a));
  }
  return p;
}

// A comb: not star-shaped about any point, deep notches, parallel edges. The notches are cut
// from the top edge y = 0.7 down to y = notch_bottom, alternating with teeth of equal width.
Poly comb(int notches = 3, double notch_bottom = -0.2) {
  Poly p{-1.0, -0.6, 1.0, -0.6, 1.0, 0.7};
  const double w = 2.0 / (2 * notches + 1);
  for (int i = notches - 1; i >= 0; --i) {
    const double a = -1.0 + w * (2 * i + 1), b = a + w;
    p.insert(p.end(), {b, 0.7, b, notch_bottom, a, notch_bottom, a, 0.7});
  }
  p.insert(p.end(), {-1.0, 0.7});
  return p;
}

// A "C" shape: the origin lies outside the polygon.
Poly c_shape(int segments) {
  Poly p;
  const double a0 = 0.6, a1 = 2 * std::numbers::pi - 0.6;
  for (int i = 0; i <= segments; ++i) {
    const double a = a0 + (a1 - a0) * i / segments;
    p.push_back(std::cos(a));
    p.push_back(std::sin(a));
  }
  for (int i = segments; i >= 0; --i) {
    const double a = a0 + (a1 - a0) * i / segments;
    p.push_back(0.55 * std::cos(a));
    p.push_back(0.55 * std::sin(a));
  }
  return p;
}

Tri random_triangle(std::mt19937& rng, double extent, double size) {
  std::uniform_real_distribution<double> c(-extent, extent), d(-size, size);
  for (;;) {
    const double cx = c(rng), cy = c(rng);
    Tri t{cx + d(rng), cy + d(rng), cx + d(rng), cy + d(rng), cx + d(rng), cy + d(rng)};
    const double a = orient2(t[0], t[1], t[2], t[3], t[4], t[5]);
    if (std::abs(a) < 0.05 * size * size) continue;  // keep them reasonably shaped
    if (a < 0) {
      std::swap(t[2], t[4]);
      std::swap(t[3], t[5]);
    }
    return t;
  }
}

double overlap(const Poly& p, const Tri& t, double* grad = nullptr) {
  const int n = int(p.size() / 2);
  std::vector<ClipVertex> buf(2 * size_t(clip_scratch_capacity(n)));
  return polygon_triangle_overlap(p.data(), n, t.data(), grad, buf.data(),
                                  buf.data() + clip_scratch_capacity(n));
}

std::vector<Poly> test_polygons() {
  std::mt19937 rng(7);
  std::vector<Poly> polys{comb(), c_shape(24)};
  for (int i = 0; i < 6; ++i) polys.push_back(random_star_shaped(rng, 5 + 7 * i));
  return polys;
}

TEST(ClipPolygon, TestPolygonsAreCounterClockwise) {
  for (const Poly& p : test_polygons()) EXPECT_GT(polygon_area(p), 0.1);
}

TEST(ClipPolygon, NonConvexAreaMatchesGreenIntegral) {
  std::mt19937 rng(11);
  int nonzero = 0, partial = 0;
  for (const Poly& p : test_polygons()) {
    const double full = polygon_area(p);
    for (int trial = 0; trial < 300; ++trial) {
      const double size = trial % 3 == 0 ? 1.5 : (trial % 3 == 1 ? 0.4 : 0.08);
      const Tri t = random_triangle(rng, 1.1, size);
      const double a = overlap(p, t);
      const double ref = green_overlap(p, t);
      ASSERT_NEAR(a, ref, 1e-12 * full) << "trial " << trial << " n=" << p.size() / 2;
      nonzero += a > 0;
      const double tri_area = 0.5 * orient2(t[0], t[1], t[2], t[3], t[4], t[5]);
      partial += a > 1e-3 * tri_area && a < (1 - 1e-3) * tri_area;
    }
  }
  EXPECT_GT(nonzero, 800);  // the sweep exercises overlaps, not only misses
  EXPECT_GT(partial, 400);  // and partial ones
}

TEST(ClipPolygon, TriangleContainingPolygonGivesPolygonArea) {
  for (const Poly& p : test_polygons()) {
    const Tri t{-3.0, -2.0, 3.0, -2.0, 0.0, 4.0};
    EXPECT_NEAR(overlap(p, t), polygon_area(p), 1e-14);
  }
}

TEST(ClipPolygon, GradientMatchesCentralDifferences) {
  std::mt19937 rng(5);
  int checked = 0;
  for (const Poly& p : test_polygons()) {
    for (int trial = 0; trial < 60; ++trial) {
      const Tri t = random_triangle(rng, 1.0, trial % 2 ? 0.9 : 0.3);
      double grad[6];
      const double a = overlap(p, t, grad);
      if (a <= 0) continue;
      double gmax = 0;
      for (double g : grad) gmax = std::max(gmax, std::abs(g));
      const double h = 1e-6;
      for (int k = 0; k < 6; ++k) {
        Tri tp = t, tm = t;
        tp[k] += h;
        tm[k] -= h;
        const double fd = (green_overlap(p, tp) - green_overlap(p, tm)) / (2 * h);
        if (std::abs(fd - grad[k]) > 1e-6 * std::max(gmax, 1e-3)) {
          std::printf("component %d: analytic %.12e\n  step      fd              error\n", k,
                      grad[k]);
          for (double hh = 1e-2; hh >= 1e-9; hh /= 10) {
            Tri a1 = t, a2 = t;
            a1[k] += hh;
            a2[k] -= hh;
            const double f = (green_overlap(p, a1) - green_overlap(p, a2)) / (2 * hh);
            std::printf("  %.0e  %.12e  %.3e\n", hh, f, std::abs(f - grad[k]));
          }
          ADD_FAILURE() << "gradient mismatch, trial " << trial;
        }
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 150);
}

// ---------------------------------------------------------------------------------------------
// Degenerate placements with hand-computed answers.

TEST(ClipPolygon, SharedEdgesAndVertices) {
  const Poly square{0, 0, 1, 0, 1, 1, 0, 1};
  // Triangle with two edges on the square's edges and corners on its corners.
  EXPECT_NEAR(overlap(square, {0, 0, 1, 0, 0, 1}), 0.5, 1e-15);
  // One edge on the square's bottom edge, one corner on it: ∫_{0.5}^{1} (1.5 − x) dx = 0.375.
  EXPECT_NEAR(overlap(square, {0.5, 0, 1.5, 0, 0.5, 1}), 0.375, 1e-15);
  // Triangle equal to half the square, diagonal the other way.
  EXPECT_NEAR(overlap(square, {1, 0, 1, 1, 0, 1}), 0.5, 1e-15);
  // Triangle outside, touching along the edge x = 1.
  EXPECT_NEAR(overlap(square, {1, 0, 2, 0.5, 1, 1}), 0.0, 1e-15);
  // Triangle outside, touching at a corner only.
  EXPECT_NEAR(overlap(square, {1, 1, 2, 1, 2, 2}), 0.0, 1e-15);
  // Polygon vertex exactly on a triangle edge: the diamond's right corner (1, 0) lies on the
  // edge x = 1 of the triangle; the triangle covers the diamond's half x ≥ 0 → area 1.
  const Poly diamond{1, 0, 0, 1, -1, 0, 0, -1};
  EXPECT_NEAR(overlap(diamond, {0, -3, 1, 0, 0, 3}), 1.0, 1e-15);
  // Triangle edge through two opposite polygon vertices (the diagonal y = 0): area 1.
  EXPECT_NEAR(overlap(diamond, {-2, 0, 2, 0, 0, 2}), 1.0, 1e-15);
}

TEST(ClipPolygon, TinyTrianglesOnTheBoundary) {
  // A triangle of size 1e-7 straddling the comb's boundary: the overlap is computed relative
  // to the first clipped vertex, so its relative accuracy is ~ eps · (polygon size / triangle
  // size) = 1e-9; the oracle has the same conditioning.
  const Poly p = comb();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  const size_t n = p.size() / 2;
  for (int trial = 0; trial < 200; ++trial) {
    const size_t i = size_t(trial) % n, j = (i + 1) % n;
    const double s = u(rng);
    const double cx = p[2 * i] + s * (p[2 * j] - p[2 * i]);
    const double cy = p[2 * i + 1] + s * (p[2 * j + 1] - p[2 * i + 1]);
    const double h = 1e-7;
    const double a0 = 2 * std::numbers::pi * u(rng);
    Tri t{cx + h * std::cos(a0), cy + h * std::sin(a0), cx + h * std::cos(a0 + 2.1),
          cy + h * std::sin(a0 + 2.1), cx + h * std::cos(a0 + 4.2), cy + h * std::sin(a0 + 4.2)};
    const double tri_area = 0.5 * orient2(t[0], t[1], t[2], t[3], t[4], t[5]);
    const double a = overlap(p, t);
    EXPECT_NEAR(a, green_overlap(p, t), 1e-6 * tri_area) << trial;
    EXPECT_GE(a, -1e-6 * tri_area);
    EXPECT_LE(a, (1 + 1e-6) * tri_area);
  }
}

TEST(ClipPolygon, ScratchBoundHoldsForWorstCaseComb) {
  // Many teeth crossed by all three triangle edges: the output stays within the capacity.
  const Poly p = comb(40, -0.9);
  const Tri t{-1.2, -0.95, 1.2, -0.95, 0.0, 1.5};
  EXPECT_NEAR(overlap(p, t), green_overlap(p, t), 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Whole-pair tests through clip_pair with a synthetic stencil whose frame depends smoothly on q.

struct PairSetup {
  std::vector<double> vertices;
  std::vector<int32_t> faces;
  std::vector<ClipShape> shapes;
  std::vector<double> polygons;
  std::vector<ClipStencil> stencils;
  std::vector<ClipPair> pairs;
  ClipInputs inputs() const {
    return {vertices, faces, shapes, polygons, stencils, pairs};
  }
};

// Largest origin-centred disk inside p (0 if the origin is outside), shrunk by a hair as the
// host does.
double inner_radius(const Poly& p) {
  if (!point_in_polygon(p, 0, 0)) return 0;
  const size_t n = p.size() / 2;
  double d2 = 1e300;
  for (size_t i = 0; i < n; ++i) {
    const size_t j = (i + 1) % n;
    d2 = std::min(d2, origin_segment_distance2(p[2 * i], p[2 * i + 1], p[2 * j], p[2 * j + 1]));
  }
  return std::sqrt(d2) * (1 - 1e-12);
}

// Scales p about the origin (the test polygons are built in a box; stencils need radius ≤ 1).
Poly scaled(Poly p, double f) {
  for (double& x : p) x *= f;
  return p;
}

void add_shape(PairSetup& s, const Poly& p) {
  double r2 = 0;
  for (size_t i = 0; i < p.size(); i += 2) r2 = std::max(r2, p[i] * p[i] + p[i + 1] * p[i + 1]);
  ASSERT_LE(r2, 1.0 + 1e-15) << "stencil polygons have bounding radius 1";
  ClipShape sh{};
  sh.polygon_offset = int32_t(s.polygons.size() / 2);
  sh.polygon_count = int32_t(p.size() / 2);
  sh.area = polygon_area(p);
  sh.inner_radius = inner_radius(p);
  s.polygons.insert(s.polygons.end(), p.begin(), p.end());
  s.shapes.push_back(sh);
}

// A smooth synthetic frame family: centre c(q) = q + 0.2 (q·q) z, normal from a tilted field,
// tangent = projected x axis, axes rotated by φ. Its Jacobians are taken by central differences
// (accurate to ~1e-10), which is enough to test the kernel's chain rule at 1e-6.
struct SyntheticFrame {
  double c[3], ex[3], ey[3];
};

SyntheticFrame synthetic_frame(const double q[3], double phi) {
  SyntheticFrame f;
  const double qq = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
  f.c[0] = q[0];
  f.c[1] = q[1];
  f.c[2] = q[2] + 0.2 * qq;
  double n[3] = {0.3 * q[0] + 0.1 * q[1], -0.2 * q[1] + 0.1, 1.0 + 0.05 * q[2]};
  const double nl = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (double& x : n) x /= nl;
  double t[3] = {1.0 - n[0] * n[0], -n[0] * n[1], -n[0] * n[2]};
  const double tl = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
  for (double& x : t) x /= tl;
  const double b[3] = {n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2],
                       n[0] * t[1] - n[1] * t[0]};
  for (int i = 0; i < 3; ++i) {
    f.ex[i] = std::cos(phi) * t[i] + std::sin(phi) * b[i];
    f.ey[i] = -std::sin(phi) * t[i] + std::cos(phi) * b[i];
  }
  return f;
}

ClipStencil make_stencil(const double q[3], double scale, double phi, int32_t shape) {
  ClipStencil st{};
  const SyntheticFrame f = synthetic_frame(q, phi);
  std::memcpy(st.origin, f.c, sizeof f.c);
  std::memcpy(st.axis_x, f.ex, sizeof f.ex);
  std::memcpy(st.axis_y, f.ey, sizeof f.ey);
  const double h = 1e-5;
  for (int j = 0; j < 3; ++j) {
    double qp[3] = {q[0], q[1], q[2]}, qm[3] = {q[0], q[1], q[2]};
    qp[j] += h;
    qm[j] -= h;
    const SyntheticFrame fp = synthetic_frame(qp, phi), fm = synthetic_frame(qm, phi);
    for (int i = 0; i < 3; ++i) {
      st.d_origin[3 * i + j] = (fp.c[i] - fm.c[i]) / (2 * h);
      st.d_axis_x[3 * i + j] = (fp.ex[i] - fm.ex[i]) / (2 * h);
      st.d_axis_y[3 * i + j] = (fp.ey[i] - fm.ey[i]) / (2 * h);
    }
  }
  st.scale = scale;
  st.shape = shape;
  return st;
}

// A gently curved triangulated patch z = 0.2 (x² + y²) over [−1.5, 1.5]² with an n×n grid.
void add_curved_patch(PairSetup& s, int n) {
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double x = -1.5 + 3.0 * i / n, y = -1.5 + 3.0 * j / n;
      s.vertices.insert(s.vertices.end(), {x, y, 0.2 * (x * x + y * y)});
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      s.faces.insert(s.faces.end(), {a, b, d, a, d, c});
    }
  }
}

TEST(ClipKernel, EarlyExitsChangeNothing) {
  PairSetup s;
  add_curved_patch(s, 12);
  std::mt19937 shape_rng(2);
  add_shape(s, random_star_shaped(shape_rng, 9));
  add_shape(s, c_shape(16));
  // A 64-gon: big inner radius so that the "fully inside" exit fires.
  Poly circle;
  for (int i = 0; i < 64; ++i) {
    circle.push_back(std::cos(2 * std::numbers::pi * i / 64));
    circle.push_back(std::sin(2 * std::numbers::pi * i / 64));
  }
  add_shape(s, circle);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-0.8, 0.8), sc(0.05, 0.9), ang(-3, 3);
  const int faces = int(s.faces.size() / 3);
  for (int i = 0; i < 30; ++i) {
    const double q[3] = {u(rng), u(rng), 0.0};
    s.stencils.push_back(make_stencil(q, sc(rng), ang(rng), i % 3));
    for (int f = 0; f < faces; ++f) s.pairs.push_back({i, f});
  }
  std::vector<ClipResult> with(s.pairs.size()), without(s.pairs.size());
  ClipWorkspace ws;
  ClipOptions on, off;
  off.early_exits = 0;
  clip_ref(s.inputs(), on, with, ws);
  clip_ref(s.inputs(), off, without, ws);
  int full = 0, empty = 0, partial = 0;
  for (size_t i = 0; i < with.size(); ++i) {
    ASSERT_NEAR(with[i].fraction, without[i].fraction, 1e-13) << i;
    for (int k = 0; k < 5; ++k) {
      ASSERT_NEAR(with[i].d_fraction[k], without[i].d_fraction[k],
                  1e-10 * (1 + std::abs(without[i].d_fraction[k])))
          << i << " " << k;
    }
    full += with[i].fraction == 1.0;
    empty += with[i].fraction == 0.0;
    partial += with[i].fraction > 0 && with[i].fraction < 1;
  }
  EXPECT_GT(full, 20);
  EXPECT_GT(empty, 1000);
  EXPECT_GT(partial, 100);
}

TEST(ClipKernel, PairDerivativesMatchCentralDifferences) {
  PairSetup s;
  add_curved_patch(s, 10);
  std::mt19937 rng(4);
  add_shape(s, random_star_shaped(rng, 11));
  add_shape(s, scaled(comb(), 0.8));
  std::uniform_real_distribution<double> u(-0.6, 0.6), sc(0.2, 0.7), ang(-3, 3);
  const int faces = int(s.faces.size() / 3);
  int checked = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const double q[3] = {u(rng), u(rng), 0.05 * u(rng)};
    const double scale = sc(rng), phi = ang(rng);
    const int32_t shape = trial % 2;
    PairSetup base = s;
    base.stencils = {make_stencil(q, scale, phi, shape)};
    for (int f = 0; f < faces; ++f) base.pairs.push_back({0, f});
    std::vector<ClipResult> r0(base.pairs.size()), rp(r0.size()), rm(r0.size());
    ClipWorkspace ws;
    clip_ref(base.inputs(), {}, r0, ws);
    auto eval = [&](int k, double h, std::vector<ClipResult>& out) {
      double qq[3] = {q[0], q[1], q[2]};
      double ss = scale, pp = phi;
      if (k < 3) qq[k] += h;
      if (k == 3) ss += h;
      if (k == 4) pp += h;
      PairSetup sh = base;
      sh.stencils = {make_stencil(qq, ss, pp, shape)};
      clip_ref(sh.inputs(), {}, out, ws);
    };
    for (int k = 0; k < 5; ++k) {
      const double h = 1e-6;
      eval(k, h, rp);
      eval(k, -h, rm);
      double dmax = 0, emax = 0;
      for (size_t i = 0; i < r0.size(); ++i) {
        const double fd = (rp[i].fraction - rm[i].fraction) / (2 * h);
        dmax = std::max(dmax, std::abs(fd));
        emax = std::max(emax, std::abs(fd - r0[i].d_fraction[k]));
      }
      if (dmax == 0) continue;
      ++checked;
      if (emax > 1e-6 * dmax) {
        std::printf("trial %d parameter %d: max |d| = %.6e\n  step     max error\n", trial, k,
                    dmax);
        for (double hh = 1e-2; hh >= 1e-9; hh /= 10) {
          eval(k, hh, rp);
          eval(k, -hh, rm);
          double e = 0;
          for (size_t i = 0; i < r0.size(); ++i) {
            e = std::max(e, std::abs((rp[i].fraction - rm[i].fraction) / (2 * hh) -
                                     r0[i].d_fraction[k]));
          }
          std::printf("  %.0e  %.3e\n", hh, e);
        }
        ADD_FAILURE() << "derivative mismatch: trial " << trial << " parameter " << k;
      }
    }
  }
  EXPECT_GE(checked, 55);
}

TEST(ClipKernel, BackFacingAndDegenerateTrianglesContributeNothing) {
  PairSetup s;
  // Triangle 0 CCW (front), 1 the same corners CW (back-facing), 2 vertical (edge-on).
  s.vertices = {-0.2, -0.2, 0, 0.3, -0.1, 0, 0.0, 0.3, 0,  //
                0.1, 0.0, 0.0, 0.1, 0.0, 0.3, 0.1, 0.2, 0.0};
  s.faces = {0, 1, 2, 0, 2, 1, 3, 4, 4};
  Poly sq{-0.7, -0.7, 0.7, -0.7, 0.7, 0.7, -0.7, 0.7};
  add_shape(s, sq);
  const double q[3] = {0, 0, 0};
  s.stencils = {make_stencil(q, 1.0, 0.0, 0)};
  s.pairs = {{0, 0}, {0, 1}, {0, 2}};
  std::vector<ClipResult> r(3);
  ClipWorkspace ws;
  clip_ref(s.inputs(), {}, r, ws);
  EXPECT_DOUBLE_EQ(r[0].fraction, 1.0);
  EXPECT_EQ(r[1].fraction, 0.0);
  EXPECT_LT(r[1].triangle_area, 0.0);
  EXPECT_EQ(r[2].fraction, 0.0);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(r[1].d_fraction[k], 0.0);
}

TEST(ClipKernel, ProjectionPreservesDistanceToCentre) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 100; ++i) {
    const double q[3] = {0.5 * u(rng), 0.5 * u(rng), 0.1 * u(rng)};
    const SyntheticFrame f = synthetic_frame(q, 3 * u(rng));
    const double v[3] = {u(rng), u(rng), 0.3 * u(rng)};
    const double scale = 0.5 + std::abs(u(rng));
    double w[2];
    project_equidistant(v, f.c, f.ex, f.ey, scale, nullptr, nullptr, nullptr, w, nullptr);
    const double d = std::sqrt((v[0] - f.c[0]) * (v[0] - f.c[0]) +
                               (v[1] - f.c[1]) * (v[1] - f.c[1]) +
                               (v[2] - f.c[2]) * (v[2] - f.c[2]));
    EXPECT_NEAR(std::hypot(w[0], w[1]) * scale, d, 1e-14);
  }
}

TEST(ClipKernel, ReferenceAndTbbTwinsAgreeBitForBit) {
  PairSetup s;
  add_curved_patch(s, 40);
  std::mt19937 rng(12);
  for (int i = 0; i < 4; ++i) add_shape(s, random_star_shaped(rng, 6 + 9 * i));
  add_shape(s, scaled(comb(), 0.8));
  std::uniform_real_distribution<double> u(-1.2, 1.2), sc(0.05, 0.5), ang(-3, 3);
  const int faces = int(s.faces.size() / 3);
  for (int i = 0; i < 60; ++i) {
    const double q[3] = {u(rng), u(rng), 0.0};
    s.stencils.push_back(make_stencil(q, sc(rng), ang(rng), i % 5));
  }
  for (int f = 0; f < faces; ++f) {
    for (int i = 0; i < 60; ++i) s.pairs.push_back({i, f});
  }
  std::vector<ClipResult> ref(s.pairs.size()), tbb1(s.pairs.size()), tbb2(s.pairs.size());
  ClipWorkspace ws_ref, ws_tbb;
  clip_ref(s.inputs(), {}, ref, ws_ref);
  clip_tbb(s.inputs(), {}, tbb1, ws_tbb);
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    clip_tbb(s.inputs(), {}, tbb2, ws_tbb);
  }
  EXPECT_EQ(std::memcmp(ref.data(), tbb1.data(), ref.size() * sizeof(ClipResult)), 0);
  EXPECT_EQ(std::memcmp(ref.data(), tbb2.data(), ref.size() * sizeof(ClipResult)), 0);
  int partial = 0;
  for (const ClipResult& r : ref) partial += r.fraction > 0 && r.fraction < 1;
  EXPECT_GT(partial, 500);
}

}  // namespace
}  // namespace cutwork::kernels
