// FillRatioEvaluator::covered_by_shape and pullback_by_shape: each shape's covered part of every
// face on a curved mesh (the bowl) with mixed convex and non-convex stencils — the columns add up
// to 1 − α where α is not clamped, and each column is what an evaluator of that shape's stencils
// alone says — and the pull-back against central differences of Σ G ∘ h(p) along random
// directions.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "host/core/internal_error.h"
#include "host/surfaces/generators.h"
#include "host/stencil/fill_ratio.h"
#include "tests/host/stencil/stencil_fixtures.h"
#include "tests/solvers/support/finite_difference.h"

namespace cutwork {
namespace {

std::vector<StencilParams> bowl_stencils(const FaceBvh& bvh, int types, unsigned seed) {
  const AxisTangentField field;
  return test::random_stencils(*bvh.mesh(), 12, 0.015, 0.04, types, seed, [&](const Vec3& position) {
    return std::abs(compute_frame(bvh, field, position, nullptr).normal.x()) <= 0.9;
  });
}

TEST(CoveredByShape, ColumnsAddUpToTheUncoveredPartAndSplitByShape) {
  const SurfaceMesh mesh = generate_shape("bowl", {}, 0.01);
  const FaceBvh bvh(mesh);
  const StencilLibrary lib = test::mixed_library();
  const std::vector<StencilParams> stencils = bowl_stencils(bvh, lib.size(), 5);
  for (FillBackend backend : {FillBackend::Reference, FillBackend::Tbb}) {
    FillRatioOptions options;
    options.backend = backend;
    FillRatioEvaluator ev(bvh, lib, options);
    ev.evaluate(stencils);
    const Eigen::MatrixXd h = ev.covered_by_shape();
    ASSERT_EQ(h.rows(), mesh.num_faces());
    ASSERT_EQ(h.cols(), lib.size());
    EXPECT_GE(h.minCoeff(), 0.0);
    int cut = 0;
    for (int t = 0; t < mesh.num_faces(); ++t) {
      const double a = ev.alpha()[t];
      if (a <= options.min_fill || a >= 1) continue;
      EXPECT_NEAR(h.row(t).sum(), 1 - a, 1e-12) << "face " << t;
      ++cut;
    }
    EXPECT_GT(cut, 100);
    // Shape by shape: the same numbers as the stencils of that shape alone.
    for (int k = 0; k < lib.size(); ++k) {
      std::vector<StencilParams> own;
      for (const StencilParams& p : stencils)
        if (p.type == k) own.push_back(p);
      ASSERT_FALSE(own.empty());
      FillRatioEvaluator alone(bvh, lib, options);
      alone.evaluate(own);
      EXPECT_NEAR((alone.covered_by_shape().col(k) - h.col(k)).cwiseAbs().maxCoeff(), 0.0, 1e-14) << "shape " << k;
      for (int t = 0; t < mesh.num_faces(); ++t) {
        const double a = alone.alpha()[t];
        if (a > options.min_fill && a < 1) {
          EXPECT_NEAR(h(t, k), 1 - a, 1e-12) << "shape " << k << " face " << t;
        }
      }
    }
  }
}

TEST(CoveredByShape, PullbackMatchesCentralDifferences) {
  const SurfaceMesh mesh = generate_shape("bowl", {}, 0.01);
  const FaceBvh bvh(mesh);
  const StencilLibrary lib = test::mixed_library();
  const std::vector<StencilParams> p0 = bowl_stencils(bvh, lib.size(), 6);
  FillRatioEvaluator ev(bvh, lib);
  ev.evaluate(p0);
  std::mt19937 rng(7);
  std::normal_distribution<double> n;
  Eigen::MatrixXd G(mesh.num_faces(), lib.size());
  for (Eigen::Index i = 0; i < G.size(); ++i) G.data()[i] = n(rng);
  // Weighted by a function of each stencil's scale (the corner rule's ε = r/s), and not.
  const auto weights = [](const std::vector<StencilParams>& p, std::vector<double>& w, std::vector<double>* slope) {
    w.clear();
    if (slope) slope->clear();
    for (const StencilParams& q : p) {
      w.push_back(0.001 / q.scale);
      if (slope) slope->push_back(-0.001 / (q.scale * q.scale));
    }
  };
  for (const bool weighted : {false, true}) {
    SCOPED_TRACE(weighted ? "weighted by 1 mm / scale" : "unweighted");
    std::vector<double> w0, slope0;
    if (weighted) weights(p0, w0, &slope0);
    Eigen::VectorXd g;
    ev.pullback_by_shape(G, g, w0, slope0);
    ASSERT_EQ(g.size(), 5 * Eigen::Index(p0.size()));
    EXPECT_GT(g.norm(), 0.0);
    FillRatioEvaluator moved(bvh, lib);
    const int S = int(p0.size());
    for (int dir = 0; dir < 4; ++dir) {
      // Positions and scales in units of the stencil's size, angles in radians.
      Eigen::VectorXd d(5 * S);
      for (int i = 0; i < S; ++i) {
        for (int k = 0; k < 5; ++k) d[5 * i + k] = n(rng) * (k == 4 ? 1.0 : p0[size_t(i)].scale);
      }
      const auto along = [&](const Eigen::VectorXd& t) {
        std::vector<StencilParams> p = p0;
        for (int i = 0; i < S; ++i) {
          p[size_t(i)].position += t[0] * d.segment<3>(5 * i);
          p[size_t(i)].scale += t[0] * d[5 * i + 3];
          p[size_t(i)].angle += t[0] * d[5 * i + 4];
        }
        moved.evaluate(p);
        std::vector<double> w;
        if (weighted) weights(p, w, nullptr);
        return (G.array() * moved.covered_by_shape(w).array()).sum();
      };
      const test::DerivativeCheck c =
          test::check_gradient(along, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, g.dot(d)), 1.0);
      EXPECT_LE(c.best, 1e-6) << "direction " << dir << "\n" << c.table();
    }
  }
  Eigen::VectorXd g;
  // The wrong size is the caller's bug.
  EXPECT_THROW(ev.pullback_by_shape(Eigen::MatrixXd::Zero(mesh.num_faces(), 1), g), InternalError);
}

}  // namespace
}  // namespace cutwork
