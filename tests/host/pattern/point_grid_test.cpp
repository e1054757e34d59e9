// Accelerated neighbourhood queries against their brute-force twins: the uniform grid over
// stencil centres (static and growing) and the boundary-polyline buckets.
#include <gtest/gtest.h>

#include "host/pattern/boundary_distance.h"
#include "host/pattern/point_grid.h"
#include "host/pattern/random.h"
#include "host/surfaces/generators.h"
#include "pattern_test_util.h"

namespace cutwork {
namespace {

RowMatX3d random_points(int n, PatternRng& rng, double spread, bool clustered) {
  RowMatX3d p(n, 3);
  for (int i = 0; i < n; ++i) {
    const double s = clustered && i % 3 == 0 ? 0.01 * spread : spread;
    p.row(i) << rng.uniform(-s, s), rng.uniform(-s, s), rng.uniform(-0.2 * s, 0.2 * s);
  }
  return p;
}

void expect_same_pairs(const std::vector<PointPair>& a, const std::vector<PointPair>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].i, b[k].i);
    EXPECT_EQ(a[k].j, b[k].j);
    EXPECT_EQ(a[k].distance, b[k].distance);
  }
}

TEST(PointGrid, BallQueriesMatchBruteForce) {
  PatternRng rng(7);
  for (bool clustered : {false, true}) {
    const RowMatX3d p = random_points(600, rng, 1.0, clustered);
    for (double cell : {0.05, 0.2, 3.0}) {
      const PointGrid grid(p, cell);
      std::vector<int> a, b;
      for (int q = 0; q < 200; ++q) {
        const Vec3 c(rng.uniform(-1.2, 1.2), rng.uniform(-1.2, 1.2), rng.uniform(-0.3, 0.3));
        const double r = rng.uniform(0.0, 0.5);
        grid.in_ball(c, r, a);
        in_ball_brute_force(p, c, r, b);
        ASSERT_EQ(a, b) << "cell " << cell << " query " << q;
      }
    }
  }
}

TEST(PointGrid, PairsMatchBruteForce) {
  PatternRng rng(11);
  for (bool clustered : {false, true}) {
    const RowMatX3d p = random_points(500, rng, 1.0, clustered);
    for (double cutoff : {0.01, 0.1, 0.4}) {
      const PointGrid grid(p, cutoff);
      expect_same_pairs(grid.pairs_within(cutoff), pairs_within_brute_force(p, cutoff));
    }
  }
}

TEST(PointGrid, DegenerateInputs) {
  // Coincident points, a huge box with a tiny cutoff (cells get enlarged), no points.
  RowMatX3d same = RowMatX3d::Constant(5, 3, 0.25);
  EXPECT_EQ(PointGrid(same, 0.1).pairs_within(0.0).size(), 10u);
  RowMatX3d far(3, 3);
  far << 0, 0, 0, 1e6, 0, 0, 1e6 + 1e-4, 0, 0;
  const PointGrid g(far, 1e-3);
  expect_same_pairs(g.pairs_within(1e-3), pairs_within_brute_force(far, 1e-3));
  EXPECT_EQ(g.pairs_within(1e-3).size(), 1u);
  const PointGrid empty(RowMatX3d(0, 3), 1.0);
  std::vector<int> out{1};
  empty.in_ball(Vec3::Zero(), 1.0, out);
  EXPECT_TRUE(out.empty());
}

TEST(DynamicPointGrid, MatchesBruteForceWhileGrowing) {
  PatternRng rng(5);
  DynamicPointGrid grid(0.1);
  RowMatX3d all(0, 3);
  std::vector<int> a, b;
  for (int k = 0; k < 400; ++k) {
    const Vec3 p(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    EXPECT_EQ(grid.insert(p), k);
    all.conservativeResize(k + 1, 3);
    all.row(k) = p.transpose();
    if (k % 20 == 0) {
      for (int q = 0; q < 20; ++q) {
        const Vec3 c(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        const double r = rng.uniform(0, q == 0 ? 5.0 : 0.4);  // q == 0: the scan fallback
        grid.in_ball(c, r, a);
        in_ball_brute_force(all, c, r, b);
        ASSERT_EQ(a, b);
      }
    }
  }
}

TEST(BoundaryPolylines, NearestMatchesBruteForceOnShapes) {
  for (const char* name : {"plate", "bowl", "pavilion", "chair"}) {
    const ShapeInfo* info = find_shape(name);
    const SurfaceMesh mesh = generate_shape(name, {}, info->base_edge_length);
    const double size = (mesh.bbox_max() - mesh.bbox_min()).norm();
    const BoundaryPolylines bl(mesh, 0.02 * size);
    ASSERT_FALSE(bl.empty()) << name;
    PatternRng rng(3);
    int found = 0;
    for (int q = 0; q < 400; ++q) {
      // Points near boundary vertices, off the surface in every direction.
      const auto& loop = mesh.boundary_loops()[size_t(rng.below(int(mesh.boundary_loops().size())))];
      const Vec3 v = mesh.vertices().row(loop[size_t(rng.below(int(loop.size())))]).transpose();
      const Vec3 p = v + 0.03 * size * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      const double r = rng.uniform(0.0, 0.05 * size);
      const auto a = bl.nearest(p, r);
      const auto b = bl.nearest_brute_force(p, r);
      ASSERT_EQ(a.has_value(), b.has_value()) << name << " query " << q;
      if (!a) continue;
      ++found;
      EXPECT_EQ(a->segment, b->segment);
      EXPECT_EQ(a->distance, b->distance);
      EXPECT_EQ(a->signed_distance, b->signed_distance);
    }
    EXPECT_GT(found, 100) << name;
  }
}

TEST(BoundaryPolylines, SignedDistanceOnAPlate) {
  // Plate [0, 0.2] × [0, 0.1]: inside, the distance is min(x, w − x, y, h − y); a point pushed
  // beyond a side in the plane gets a negative distance.
  const SurfaceMesh mesh = test::flat_plate(0.2, 0.1, 0.01);
  const BoundaryPolylines bl(mesh, 0.02);
  PatternRng rng(9);
  for (int q = 0; q < 300; ++q) {
    const double x = rng.uniform(0, 0.2), y = rng.uniform(0, 0.1);
    const auto bp = bl.nearest(Vec3(x, y, 0), 1.0);
    ASSERT_TRUE(bp);
    const double expect = std::min({x, 0.2 - x, y, 0.1 - y});
    EXPECT_NEAR(bp->signed_distance, expect, 1e-12);
  }
  for (const Vec3& out : {Vec3(-0.01, 0.05, 0), Vec3(0.21, 0.03, 0), Vec3(0.1, -0.02, 0), Vec3(0.1, 0.13, 0)}) {
    const auto bp = bl.nearest(out, 0.05);
    ASSERT_TRUE(bp);
    EXPECT_LT(bp->signed_distance, 0) << out.transpose();
    EXPECT_NEAR(bp->signed_distance, -bp->distance, 0);
  }
}

TEST(BoundaryPolylines, SurfacePointsAreInsideOnCurvedShapes) {
  // Every point of the surface has a non-negative signed distance (the inward directions are
  // oriented into the surface whatever the loop's orientation).
  for (const char* name : {"bowl", "pavilion"}) {
    const ShapeInfo* info = find_shape(name);
    const SurfaceMesh mesh = generate_shape(name, {}, info->base_edge_length);
    const BoundaryPolylines bl(mesh, 4 * mesh.mean_edge_length());
    int checked = 0;
    for (int f = 0; f < mesh.num_faces(); ++f) {
      SurfacePoint sp{f, Vec3(0.2, 0.3, 0.5)};
      const auto bp = bl.nearest(mesh.point(sp), 3 * mesh.mean_edge_length());
      if (!bp) continue;
      ++checked;
      EXPECT_GE(bp->signed_distance, 0) << name << " face " << f;
    }
    EXPECT_GT(checked, 50) << name;
  }
}

}  // namespace
}  // namespace cutwork
