#pragma once
/// Meshes and helpers shared by the host/stencil tests.
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "host/mesh/surface_mesh.h"
#include "host/stencil/fill_ratio.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork::test {

/// One of every built-in kind the derivative and parity tests mix: convex (circle) and
/// non-convex (star, flower, leaf, apple, heart) outlines, types 0..5 in this order.
inline StencilLibrary mixed_library() {
  StencilLibrary lib;
  lib.add(make_builtin_stencil("circle", {}, "circle"));
  lib.add(make_builtin_stencil("star", {{"points", 6}}, "star"));
  lib.add(make_builtin_stencil("flower", {{"petals", 5}}, "flower"));
  lib.add(make_builtin_stencil("leaf", {}, "leaf"));
  lib.add(make_builtin_stencil("apple", {}, "apple"));
  lib.add(make_builtin_stencil("heart", {}, "heart"));
  return lib;
}

/// n stencils at random points inside random faces of `mesh` (barycentrics ≥ 0.1, so the centre's
/// face is stable under finite-difference steps), scales uniform in [smin, smax], angles in
/// (−3.1, 3.1), types cycling through 0..types−1. `keep` may reject a centre (it is then drawn
/// again); the random sequence is the same with or without it until it rejects.
inline std::vector<StencilParams> random_stencils(const SurfaceMesh& mesh, int n, double smin, double smax,
                                                  int types, unsigned seed,
                                                  const std::function<bool(const Vec3&)>& keep = {}) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> face(0, mesh.num_faces() - 1);
  std::uniform_real_distribution<double> u(0, 1), s(smin, smax), ang(-3.1, 3.1);
  std::vector<StencilParams> out;
  while (int(out.size()) < n) {
    const int f = face(rng);
    const double a = 0.1 + 0.7 * u(rng), b = 0.1 + (0.8 - a) * u(rng);
    const Vec3 bary(1 - a - b, a, b);
    if (bary.minCoeff() < 0.1) continue;
    StencilParams p;
    for (int k = 0; k < 3; ++k) p.position += bary[k] * mesh.vertices().row(mesh.faces()(f, k)).transpose();
    if (keep && !keep(p.position)) continue;
    p.scale = s(rng);
    p.angle = ang(rng);
    p.type = int(out.size()) % types;
    out.push_back(p);
  }
  return out;
}

/// Regular grid of n×n square cells of size h over [0, n h]² in the plane z = 0, each cell
/// split along its (i, j)–(i+1, j+1) diagonal into a lower-right and an upper-left triangle
/// (faces 2 (j n + i) and 2 (j n + i) + 1), CCW seen from +z.
inline SurfaceMesh flat_grid(int n, double h) {
  RowMatX3d v((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) v.row(j * (n + 1) + i) << i * h, j * h, 0.0;
  RowMatX3i f(2 * n * n, 3);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      f.row(2 * (j * n + i)) << a, b, d;
      f.row(2 * (j * n + i) + 1) << a, d, c;
    }
  }
  return SurfaceMesh(std::move(v), std::move(f), "flat grid");
}

/// Exact area of (grid triangle `face` of flat_grid(n, h)) ∩ [X0, X1] × [Y0, Y1]: the integral
/// over x of the covered length of the vertical line, a piecewise-linear function integrated
/// exactly by the trapezoid rule between its breakpoints.
inline double grid_triangle_rectangle_overlap(int n, double h, int face, double X0, double X1,
                                              double Y0, double Y1) {
  const int cell = face / 2, i = cell % n, j = cell / n;
  const bool lower = face % 2 == 0;  // lower: y0 ≤ y ≤ y0 + (x − x0); upper: above the diagonal
  const double x0 = i * h, x1 = x0 + h, y0 = j * h, y1 = y0 + h;
  auto bottom = [&](double x) { return lower ? y0 : y0 + (x - x0); };
  auto top = [&](double x) { return lower ? y0 + (x - x0) : y1; };
  auto g = [&](double x) { return std::max(0.0, std::min(top(x), Y1) - std::max(bottom(x), Y0)); };
  const double xa = std::max(x0, X0), xb = std::min(x1, X1);
  if (!(xb > xa)) return 0.0;
  // Breakpoints: where the diagonal y = y0 + (x − x0) meets Y0 or Y1.
  std::vector<double> xs{xa, xb, x0 + (Y0 - y0), x0 + (Y1 - y0)};
  std::sort(xs.begin(), xs.end());
  double area = 0;
  for (size_t k = 0; k + 1 < xs.size(); ++k) {
    const double a = std::max(xs[k], xa), b = std::min(xs[k + 1], xb);
    if (b > a) area += 0.5 * (g(a) + g(b)) * (b - a);
  }
  return area;
}

}  // namespace cutwork::test
