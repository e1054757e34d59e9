// dα/dp on curved shapes (bowl, pavilion) against central differences of the full map
// p → α, on random configurations of mixed convex and non-convex stencils; and the reference
// and TBB backends bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <random>

#include "host/surfaces/generators.h"
#include "host/stencil/fill_ratio.h"
#include "tests/host/stencil/fd_check.h"
#include "tests/host/stencil/stencil_fixtures.h"

namespace cutwork {
namespace {

/// test::random_stencils away from the x-axis tangent field's switch (|n_x| > 0.9), where the
/// frame is not differentiable.
std::vector<StencilParams> random_stencils(const FaceBvh& bvh, int n, double smin, double smax,
                                           int types, unsigned seed) {
  const AxisTangentField field;
  return test::random_stencils(*bvh.mesh(), n, smin, smax, types, seed, [&](const Vec3& position) {
    return std::abs(compute_frame(bvh, field, position, nullptr).normal.x()) <= 0.9;
  });
}

void run_derivative_check(const SurfaceMesh& mesh, double smin, double smax, unsigned seed0) {
  const FaceBvh bvh(mesh);
  const StencilLibrary lib = test::mixed_library();
  int checked = 0, total = 0;
  double worst = 0;
  for (unsigned seed = seed0; seed < seed0 + 3; ++seed) {
    const auto stencils = random_stencils(bvh, 6, smin, smax, lib.size(), seed);
    const test::FdReport r = test::check_fill_derivatives(
        bvh, lib, stencils, seed % 2 ? FillBackend::Tbb : FillBackend::Reference);
    checked += r.checked;
    total += r.checked + r.skipped;
    worst = std::max(worst, r.worst);
  }
  std::printf("checked %d of %d columns, worst relative error %.2e\n", checked, total, worst);
  EXPECT_GE(checked, total * 8 / 10);  // "where the pair set is stable": most of them
}

TEST(FillRatioDerivatives, MatchCentralDifferencesOnTheBowl) {
  // Bowl: r = 0.15 m, faces ≈ 1 cm; stencils from 1.5 to 5 face sizes.
  run_derivative_check(generate_shape("bowl", {}, 0.01), 0.015, 0.05, 10);
}

TEST(FillRatioDerivatives, MatchCentralDifferencesOnThePavilion) {
  // Pavilion: r = 3 m, faces ≈ 0.2 m; stencils from 1.5 to 5 face sizes.
  run_derivative_check(generate_shape("pavilion", {}, 0.2), 0.3, 1.0, 20);
}

void expect_valid(const FillRatioEvaluator& ev) {
  for (Eigen::Index f = 0; f < ev.alpha().size(); ++f) {
    ASSERT_TRUE(ev.alpha()[f] >= 1e-4 && ev.alpha()[f] <= 1.0) << f << " " << ev.alpha()[f];
  }
  for (double d : ev.d_alpha()) ASSERT_TRUE(std::isfinite(d));
}

TEST(FillRatioRobustness, CentredOnVerticesAndEdgesOfCurvedMeshes) {
  // Exactly on a mesh vertex or an edge midpoint the closest-point map has a kink, but α is
  // continuous: nudging the centre by 1e-9 s changes α by O(1e-9) only.
  for (const char* shape : {"bowl", "pavilion"}) {
    const SurfaceMesh mesh = generate_shape(shape, {}, std::string(shape) == "bowl" ? 0.01 : 0.2);
    const FaceBvh bvh(mesh);
    const StencilLibrary lib = test::mixed_library();
    const double s = 3 * mesh.mean_edge_length();
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> vertex(0, mesh.num_vertices() - 1), edge(0, mesh.num_edges() - 1);
    FillRatioEvaluator ev(bvh, lib), nudged(bvh, lib);
    for (int trial = 0; trial < 20; ++trial) {
      StencilParams p;
      if (trial % 2) {
        p.position = mesh.vertices().row(vertex(rng)).transpose();
      } else {
        const int e = edge(rng);
        p.position = 0.5 * (mesh.vertices().row(mesh.edges()(e, 0)) +
                            mesh.vertices().row(mesh.edges()(e, 1)))
                               .transpose();
      }
      p.scale = s;
      p.angle = 0.1 * trial;
      p.type = trial % lib.size();
      ev.evaluate(std::vector<StencilParams>{p});
      expect_valid(ev);
      for (int k = 0; k < 3; ++k) {
        StencilParams q = p;
        q.position[k] += 1e-9 * s;
        nudged.evaluate(std::vector<StencilParams>{q});
        EXPECT_LE((nudged.alpha() - ev.alpha()).lpNorm<Eigen::Infinity>(), 1e-6) << shape << " " << trial;
      }
    }
  }
}

TEST(FillRatioRobustness, StencilsLargerThanTheShapeAndAcrossItsBoundary) {
  const SurfaceMesh mesh = generate_shape("bowl", {}, 0.01);
  const FaceBvh bvh(mesh);
  const StencilLibrary lib = test::mixed_library();
  FillRatioEvaluator ev(bvh, lib);
  // One stencil bigger than the whole bowl, centred at its bottom: the walls seen edge-on or
  // from behind contribute nothing, nothing breaks.
  StencilParams huge;
  huge.position = Vec3::Zero();
  huge.scale = 0.5;
  ev.evaluate(std::vector<StencilParams>{huge});
  expect_valid(ev);
  int clamped = 0;
  for (Eigen::Index f = 0; f < ev.alpha().size(); ++f) clamped += ev.alpha()[f] == 1e-4;
  EXPECT_GT(clamped, mesh.num_faces() / 2);
  // Stencils centred on the rim, half of them hanging over the boundary.
  std::vector<StencilParams> rim;
  for (int i = 0; i < 8; ++i) {
    StencilParams p;
    const double a = 0.3 + 0.785 * i;
    p.position = Vec3(0.15 * std::cos(a), 0.15 * std::sin(a), 0.07);
    p.scale = 0.02;
    p.type = i % lib.size();
    rim.push_back(p);
  }
  ev.evaluate(rim);
  expect_valid(ev);
  int partial = 0;
  for (Eigen::Index f = 0; f < ev.alpha().size(); ++f) partial += ev.alpha()[f] > 1e-4 && ev.alpha()[f] < 1;
  EXPECT_GT(partial, 40);
  // The derivatives still match finite differences there (centres on the boundary edges).
  const test::FdReport r = test::check_fill_derivatives(bvh, lib, rim, FillBackend::Tbb);
  EXPECT_GE(r.checked, 30);
}

TEST(FillRatioDerivatives, ReferenceAndTbbBackendsAgreeBitForBit) {
  const SurfaceMesh mesh = generate_shape("pavilion", {}, 0.1);
  const FaceBvh bvh(mesh);
  const StencilLibrary lib = test::mixed_library();
  const auto stencils = random_stencils(bvh, 300, 0.1, 0.5, lib.size(), 7);
  FillRatioOptions ref_opt, tbb_opt;
  ref_opt.backend = FillBackend::Reference;
  tbb_opt.backend = FillBackend::Tbb;
  FillRatioEvaluator ref(bvh, lib, ref_opt), tbb(bvh, lib, tbb_opt);
  ref.evaluate(stencils);
  tbb.evaluate(stencils);
  ASSERT_EQ(ref.pairs().size(), tbb.pairs().size());
  ASSERT_GT(ref.pairs().size(), 5000u);
  EXPECT_EQ(std::memcmp(ref.alpha().data(), tbb.alpha().data(), sizeof(double) * size_t(ref.alpha().size())), 0);
  EXPECT_EQ(std::memcmp(ref.d_alpha().data(), tbb.d_alpha().data(), sizeof(double) * ref.d_alpha().size()), 0);
  EXPECT_EQ(std::memcmp(ref.overlaps().data(), tbb.overlaps().data(),
                        sizeof(kernels::ClipResult) * ref.overlaps().size()),
            0);
  Eigen::VectorXd g(ref.alpha().size()), gr, gt;
  for (int f = 0; f < g.size(); ++f) g[f] = std::sin(0.1 * f);
  ref.pullback(g, gr);
  tbb.pullback(g, gt);
  EXPECT_EQ(std::memcmp(gr.data(), gt.data(), sizeof(double) * size_t(gr.size())), 0);
  int clamped = 0, partial = 0;
  for (int f = 0; f < ref.alpha().size(); ++f) {
    clamped += ref.alpha()[f] == 1e-4;
    partial += ref.alpha()[f] > 1e-4 && ref.alpha()[f] < 1;
  }
  EXPECT_GT(clamped, 100);
  EXPECT_GT(partial, 1000);
}

}  // namespace
}  // namespace cutwork
