// Fill ratios on flat meshes, where the projected metric is the true one and every answer is
// known exactly: analytic α for axis-aligned squares, the area of a 256-gon, invariance under
// rigid motions, and the robustness cases (across the boundary, larger / smaller than a
// triangle, centred on a vertex or an edge, overlapping stencils clamping at 1e-4).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "host/core/error.h"
#include "host/stencil/fill_ratio.h"
#include "tests/host/stencil/fd_check.h"
#include "tests/host/stencil/stencil_fixtures.h"

namespace cutwork {
namespace {

using test::flat_grid;
using test::grid_triangle_rectangle_overlap;

constexpr int kN = 12;
constexpr double kH = 0.1;

struct FlatFixture {
  SurfaceMesh mesh = flat_grid(kN, kH);
  FaceBvh bvh{mesh};
};

StencilParams at(double x, double y, double scale, double angle = 0, int type = 0) {
  StencilParams p;
  p.position = Vec3(x, y, 0);
  p.scale = scale;
  p.angle = angle;
  p.type = type;
  return p;
}

/// Analytic α for axis-aligned squares (library type 0 = "square", half side s/√2).
Eigen::VectorXd analytic_square_alpha(const StencilLibrary& lib,
                                      const std::vector<StencilParams>& squares) {
  const double half = lib[0].polygon[2].x();  // the (1, 1)/√2 corner, as stored
  Eigen::VectorXd alpha(2 * kN * kN);
  for (int f = 0; f < alpha.size(); ++f) {
    double covered = 0;
    for (const StencilParams& s : squares) {
      const double a = half * s.scale;
      covered += grid_triangle_rectangle_overlap(kN, kH, f, s.position.x() - a,
                                                 s.position.x() + a, s.position.y() - a,
                                                 s.position.y() + a) /
                 (0.5 * kH * kH);
    }
    alpha[f] = std::max(1e-4, 1 - covered);
  }
  return alpha;
}

StencilLibrary square_library() {
  StencilLibrary lib;
  lib.add(make_builtin_stencil("square", {}, "square"));
  return lib;
}

TEST(FillRatioFlat, AxisAlignedSquaresGiveAnalyticAlpha) {
  FlatFixture fx;
  const StencilLibrary lib = square_library();
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> pos(0.15, 1.05), size(0.04, 0.3);
  for (FillBackend backend : {FillBackend::Reference, FillBackend::Tbb}) {
    FillRatioOptions opt;
    opt.backend = backend;
    FillRatioEvaluator ev(fx.bvh, lib, opt);
    for (int trial = 0; trial < 5; ++trial) {
      std::vector<StencilParams> squares;
      for (int i = 0; i < 6; ++i) squares.push_back(at(pos(rng), pos(rng), size(rng)));
      ev.evaluate(squares);
      const Eigen::VectorXd expected = analytic_square_alpha(lib, squares);
      int partial = 0;
      for (int f = 0; f < expected.size(); ++f) {
        ASSERT_NEAR(ev.alpha()[f], expected[f], 1e-12) << "face " << f << " trial " << trial;
        partial += expected[f] > 1e-4 && expected[f] < 1;
      }
      EXPECT_GT(partial, 20);
    }
  }
}

double regular_polygon_area(int n, double r) {
  return 0.5 * n * r * r * std::sin(2 * std::numbers::pi / n);
}

TEST(FillRatioFlat, Regular256GonAreaIsRecovered) {
  FlatFixture fx;
  StencilLibrary lib;
  lib.add(make_builtin_stencil("circle", {{"segments", 256}}, "256-gon"));
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> pos(0.3, 0.9), ang(-3.2, 3.2);
  const Eigen::VectorXd& areas = fx.mesh.face_areas();
  FillRatioEvaluator ev(fx.bvh, lib);
  for (int trial = 0; trial < 10; ++trial) {
    // Diameter 0.8 h: no triangle (legs h) is covered entirely, so α never clamps and
    // Σ (1 − α_t) A_t is exactly the covered area.
    const double r = 0.4 * kH;
    ev.evaluate(std::vector<StencilParams>{at(pos(rng), pos(rng), r, ang(rng))});
    const double covered = ((1 - ev.alpha().array()) * areas.array()).sum();
    EXPECT_NEAR(covered, regular_polygon_area(256, r), 1e-12 * regular_polygon_area(256, r));
    // A large one (clamped interior faces): the per-pair fractions still add up to the area.
    const double big = 3.3 * kH;
    ev.evaluate(std::vector<StencilParams>{at(0.6 + 0.01 * trial, 0.6, big, ang(rng))});
    double sum = 0, sum_overlap = 0;
    for (size_t i = 0; i < ev.pairs().size(); ++i) {
      sum += ev.overlaps()[i].fraction * areas[ev.pairs()[i].face];
      sum_overlap += ev.overlaps()[i].overlap_area;
    }
    EXPECT_NEAR(sum, regular_polygon_area(256, big), 1e-12 * regular_polygon_area(256, big));
    EXPECT_NEAR(sum_overlap, regular_polygon_area(256, big),
                1e-12 * regular_polygon_area(256, big));
  }
}

TEST(FillRatioFlat, MovingAndRotatingKeepsCoveredAreaConstant) {
  FlatFixture fx;
  StencilLibrary lib;
  lib.add(make_builtin_stencil("star", {{"points", 5}, {"inner_ratio", 0.45}}, "star"));
  lib.add(make_builtin_stencil("flower", {{"petals", 7}}, "flower"));
  const Eigen::VectorXd& areas = fx.mesh.face_areas();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> pos(0.35, 0.85), ang(-3.2, 3.2);
  FillRatioEvaluator ev(fx.bvh, lib);
  const double small = 0.45 * kH;  // diameter < h: nothing clamps
  const double big = 2.7 * kH;
  for (int trial = 0; trial < 12; ++trial) {
    ev.evaluate(std::vector<StencilParams>{at(pos(rng), pos(rng), small, ang(rng), 0)});
    const double covered = ((1 - ev.alpha().array()) * areas.array()).sum();
    EXPECT_NEAR(covered, lib[0].area * small * small, 1e-12 * lib[0].area * small * small);
    ev.evaluate(std::vector<StencilParams>{at(pos(rng), pos(rng), big, ang(rng), 1)});
    double sum = 0;
    for (size_t i = 0; i < ev.pairs().size(); ++i)
      sum += ev.overlaps()[i].fraction * areas[ev.pairs()[i].face];
    EXPECT_NEAR(sum, lib[1].area * big * big, 1e-12 * lib[1].area * big * big);
  }
}

TEST(FillRatioFlat, StencilAcrossTheBoundary) {
  FlatFixture fx;
  const StencilLibrary lib = square_library();
  FillRatioEvaluator ev(fx.bvh, lib);
  // Centre on the surface, half of the square hanging over the edge x = 0.
  std::vector<StencilParams> s{at(0.02, 0.53, 0.2), at(0.61, 1.19, 0.17)};
  ev.evaluate(s);
  Eigen::VectorXd expected = analytic_square_alpha(lib, s);
  for (int f = 0; f < expected.size(); ++f) ASSERT_NEAR(ev.alpha()[f], expected[f], 1e-12) << f;
  // Centre off the surface beyond the boundary: it is projected onto the boundary edge.
  std::vector<StencilParams> off{at(-0.05, 0.53, 0.2)};
  off[0].position.z() = 0.1;
  ev.evaluate(off);
  EXPECT_NEAR(ev.frames()[0].origin.x(), 0.0, 1e-15);
  EXPECT_NEAR(ev.frames()[0].origin.y(), 0.53, 1e-15);
  expected = analytic_square_alpha(lib, {at(0.0, 0.53, 0.2)});
  for (int f = 0; f < expected.size(); ++f) ASSERT_NEAR(ev.alpha()[f], expected[f], 1e-12) << f;
  // Its derivatives: only motion along the boundary edge (y) and the scale/angle matter.
  const test::FdReport r = test::check_fill_derivatives(fx.bvh, lib, off, FillBackend::Tbb, false);
  EXPECT_EQ(r.checked, 5);
}

TEST(FillRatioFlat, LargerThanATriangleClampsCoveredFaces) {
  FlatFixture fx;
  StencilLibrary lib;
  lib.add(make_builtin_stencil("circle", {{"segments", 96}}, "circle"));
  FillRatioEvaluator ev(fx.bvh, lib);
  const double r = 4.2 * kH;
  ev.evaluate(std::vector<StencilParams>{at(0.6, 0.55, r, 0.3)});
  int covered = 0;
  for (size_t i = 0; i < ev.pairs().size(); ++i) {
    const int f = ev.pairs()[i].face;
    if (ev.overlaps()[i].fraction == 1.0) {
      ++covered;
      EXPECT_EQ(ev.alpha()[f], 1e-4);
      for (int k = 0; k < 5; ++k) EXPECT_EQ(ev.d_alpha()[5 * i + size_t(k)], 0.0);
    }
  }
  EXPECT_GT(covered, 60);
  // The centre lies on the grid line x = 6 h: it changes face under the x step, harmless on
  // a flat mesh.
  const test::FdReport rep =
      test::check_fill_derivatives(fx.bvh, lib, {at(0.6, 0.55, r, 0.3)}, FillBackend::Tbb, false);
  EXPECT_EQ(rep.checked, 5);
}

TEST(FillRatioFlat, SmallerThanATriangle) {
  FlatFixture fx;
  StencilLibrary lib;
  lib.add(make_builtin_stencil("flower", {}, "flower"));
  FillRatioEvaluator ev(fx.bvh, lib);
  // Inside the lower-right triangle of cell (3, 4), ≥ 0.28 h from its edges, radius 0.1 h:
  // the early exit "bounding circle inside the triangle" applies.
  const double x = 3 * kH + 0.7 * kH, y = 4 * kH + 0.28 * kH, s = 0.1 * kH;
  ev.evaluate(std::vector<StencilParams>{at(x, y, s, 0.4)});
  const int face = 2 * (4 * kN + 3);
  const double tri = 0.5 * kH * kH;
  EXPECT_NEAR(ev.alpha()[face], 1 - lib[0].area * s * s / tri, 1e-14);
  for (int f = 0; f < ev.alpha().size(); ++f) {
    if (f == face) continue;
    EXPECT_EQ(ev.alpha()[f], 1.0);
  }
  const auto J = Eigen::MatrixXd(ev.jacobian());
  EXPECT_NEAR(J(face, 3), -2 * lib[0].area * s / tri, 1e-12 * 2 * lib[0].area * s / tri);
  for (int k : {0, 1, 2, 4}) EXPECT_NEAR(J(face, k), 0.0, 1e-9);
}

TEST(FillRatioFlat, CentredExactlyOnAVertexOrAnEdge) {
  FlatFixture fx;
  const StencilLibrary lib = square_library();
  FillRatioEvaluator ev(fx.bvh, lib);
  const std::vector<std::vector<StencilParams>> cases = {
      {at(5 * kH, 6 * kH, 0.13)},                  // on a vertex
      {at(5.5 * kH, 6 * kH, 0.13)},                // on a horizontal edge's midpoint
      {at(5 * kH, 6.25 * kH, 0.09)},               // on a vertical edge
      {at(5.5 * kH, 6.5 * kH, 0.11)},              // on a diagonal
  };
  for (const auto& c : cases) {
    ev.evaluate(c);
    const Eigen::VectorXd expected = analytic_square_alpha(lib, c);
    for (int f = 0; f < expected.size(); ++f) ASSERT_NEAR(ev.alpha()[f], expected[f], 1e-12) << f;
    // Derivatives at the same centre. With φ = 0 the squares' corners sit exactly on the grid
    // diagonals through the centre, where α'' jumps and central differences converge only at
    // first order; a generic angle keeps the check sharp. The centre is on an edge or vertex,
    // so it changes face under the steps (harmless on a flat mesh).
    std::vector<StencilParams> turned = c;
    turned[0].angle = 0.3;
    const test::FdReport r =
        test::check_fill_derivatives(fx.bvh, lib, turned, FillBackend::Reference, false);
    EXPECT_EQ(r.checked, 5);
  }
  // Square edges exactly on grid lines (a kink of α: values only).
  const std::vector<StencilParams> aligned{at(5 * kH, 6 * kH, kH * std::sqrt(2.0))};
  ev.evaluate(aligned);
  const Eigen::VectorXd expected = analytic_square_alpha(lib, aligned);
  int full = 0;
  for (int f = 0; f < expected.size(); ++f) {
    ASSERT_NEAR(ev.alpha()[f], expected[f], 1e-12) << f;
    full += expected[f] == 1e-4;
  }
  EXPECT_EQ(full, 8);
}

TEST(FillRatioFlat, OverlappingStencilsClampAtMinimum) {
  FlatFixture fx;
  StencilLibrary lib;
  lib.add(make_builtin_stencil("circle", {}, "circle"));
  lib.add(make_builtin_stencil("star", {}, "star"));
  FillRatioEvaluator ev(fx.bvh, lib);
  const std::vector<StencilParams> s{at(0.6, 0.6, 0.35, 0.0, 0), at(0.62, 0.58, 0.3, 0.5, 1),
                                     at(0.5, 0.7, 0.25, 1.0, 1)};
  ev.evaluate(s);
  const auto& pairs = ev.pairs();
  int clamped = 0;
  for (int f = 0; f < ev.alpha().size(); ++f) {
    double covered = 0;
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (pairs[i].face == f) covered += ev.overlaps()[i].fraction;
    }
    EXPECT_EQ(ev.alpha()[f], std::max(1e-4, 1 - covered));
    EXPECT_GE(ev.alpha()[f], 1e-4);
    if (1 - covered > 1e-4) continue;
    ++clamped;
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (pairs[i].face != f) continue;
      for (int k = 0; k < 5; ++k) EXPECT_EQ(ev.d_alpha()[5 * i + size_t(k)], 0.0);
    }
  }
  EXPECT_GT(clamped, 30);
}

TEST(FillRatioFlat, StencilsOnTheSurfaceCoverTheSimulationMesh) {
  // Frames from a fine surface mesh, fill ratios on the coarse simulation grid.
  const SurfaceMesh fine = flat_grid(3 * kN, kH / 3);
  const FaceBvh fine_bvh(fine);
  FlatFixture coarse;
  const StencilLibrary lib = square_library();
  FillRatioEvaluator ev(fine_bvh, coarse.bvh, lib);
  const std::vector<StencilParams> s{at(0.33, 0.71, 0.21), at(0.8, 0.4, 0.13)};
  ev.evaluate(s);
  ASSERT_EQ(ev.alpha().size(), coarse.mesh.num_faces());
  const Eigen::VectorXd expected = analytic_square_alpha(lib, s);
  for (int f = 0; f < expected.size(); ++f) ASSERT_NEAR(ev.alpha()[f], expected[f], 1e-12) << f;
  EXPECT_LT(ev.frames()[0].where.face, fine.num_faces());
}

TEST(FillRatioFlat, SnappingToTheSurfaceChangesNothing) {
  FlatFixture fx;
  StencilLibrary lib;
  lib.add(make_builtin_stencil("star", {}, "star"));
  FillRatioEvaluator ev(fx.bvh, lib);
  std::vector<StencilParams> s{at(0.43, 0.61, 0.2, 0.3)};
  s[0].position.z() = 0.07;
  ev.evaluate(s);
  const Eigen::VectorXd before = ev.alpha();
  snap_to_surface(fx.bvh, s);
  EXPECT_EQ(s[0].position.z(), 0.0);
  EXPECT_EQ(s[0].position.x(), 0.43);
  ev.evaluate(s);
  EXPECT_EQ((ev.alpha() - before).lpNorm<Eigen::Infinity>(), 0.0);
}

TEST(FillRatioFlat, RejectsInvalidStencils) {
  FlatFixture fx;
  const StencilLibrary lib = square_library();
  FillRatioEvaluator ev(fx.bvh, lib);
  auto expect_error = [&](StencilParams p, const std::string& needle) {
    try {
      ev.evaluate(std::vector<StencilParams>{at(0.5, 0.5, 0.1), p});
      ADD_FAILURE() << "no error for " << needle;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("stencil 1"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error(at(0.5, 0.5, 0.0), "scale");
  expect_error(at(0.5, 0.5, -1.0), "scale");
  expect_error(at(0.5, 0.5, std::nan("")), "scale");
  expect_error(at(std::nan(""), 0.5, 0.1), "position");
  expect_error(at(0.5, 0.5, 0.1, std::numeric_limits<double>::infinity()), "angle");
  expect_error(at(0.5, 0.5, 0.1, 0, 3), "type");
  expect_error(at(0.5, 0.5, 0.1, 0, -1), "type");
}

TEST(FillRatioFlat, PullbackIsTheJacobianTranspose) {
  FlatFixture fx;
  StencilLibrary lib;
  lib.add(make_builtin_stencil("apple", {}, "apple"));
  lib.add(make_builtin_stencil("leaf", {}, "leaf"));
  std::vector<StencilParams> s;
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> pos(0.1, 1.1), size(0.05, 0.2), ang(-3, 3);
  for (int i = 0; i < 12; ++i) s.push_back(at(pos(rng), pos(rng), size(rng), ang(rng), i % 2));
  for (FillBackend backend : {FillBackend::Reference, FillBackend::Tbb}) {
    FillRatioOptions opt;
    opt.backend = backend;
    FillRatioEvaluator ev(fx.bvh, lib, opt);
    ev.evaluate(s);
    Eigen::VectorXd g(ev.alpha().size());
    for (int f = 0; f < g.size(); ++f) g[f] = std::cos(0.37 * f);
    Eigen::VectorXd gp;
    ev.pullback(g, gp);
    const Eigen::VectorXd expected = ev.jacobian().transpose() * g;
    ASSERT_EQ(gp.size(), 60);
    EXPECT_LE((gp - expected).lpNorm<Eigen::Infinity>(), 1e-12 * expected.lpNorm<Eigen::Infinity>());
  }
}

}  // namespace
}  // namespace cutwork
