// The minimum-feature check: ligaments between stencil holes and to the border, measured on
// the cut surface and compared with the printable minimum.
#include "host/export/min_feature.h"

#include <gtest/gtest.h>

#include <cmath>

#include "host/mesh/bvh.h"
#include "host/surfaces/generators.h"

namespace cutwork {
namespace {

/// A 0.2 m × 0.1 m plate with square stencils (sides along x and y).
struct Plate {
  SurfaceMesh mesh = generate_shape("plate", {{"width", 0.2}, {"height", 0.1}}, 0.005);
  FaceBvh bvh{mesh};
  StencilLibrary shapes;
  AxisTangentField field;
  Plate() { shapes.add(make_builtin_stencil("square", {}, "square")); }

  /// Squares of half side `half` centred at `centres` (z = 0).
  CutSurface cut(const std::vector<Vec2>& centres, double half) const {
    std::vector<StencilParams> stencils;
    for (const Vec2& c : centres) {
      StencilParams p;
      p.position = Vec3(c.x(), c.y(), 0);
      p.scale = half * std::sqrt(2.0);  // bounding radius of the square
      stencils.push_back(p);
    }
    return cut_stencils(bvh, shapes, field, stencils);
  }
};

TEST(MinFeature, TwoStencilsHalfAMillimetreApartAreFlagged) {
  const Plate plate;
  const double half = 0.01, gap = 0.0005;
  const double x = half + gap / 2;
  const CutSurface cut = plate.cut({{-x, 0.003}, {x, 0.003}}, half);
  const MinFeatureReport r = check_min_feature(cut, plate.mesh, 0.001);
  EXPECT_EQ(r.holes, 2);
  EXPECT_EQ(r.borders, 1);
  EXPECT_NEAR(r.narrowest_between_stencils, gap, 1e-9);
  EXPECT_NEAR(r.narrowest_to_boundary, 0.05 - 0.003 - half, 1e-9);  // to the edge y = 0.05
  ASSERT_EQ(r.violations.size(), 1u);
  EXPECT_EQ(r.violations[0].kind, "stencils");
  EXPECT_NEAR(r.violations[0].width, gap, 1e-9);
  EXPECT_NEAR(r.violations[0].point_a.x(), -gap / 2, 1e-9);
  EXPECT_NEAR(r.violations[0].point_b.x(), gap / 2, 1e-9);
}

TEST(MinFeature, TwoMillimetresApartPass) {
  const Plate plate;
  const double half = 0.01, x = half + 0.001;
  const MinFeatureReport r = check_min_feature(plate.cut({{-x, 0}, {x, 0}}, half), plate.mesh, 0.001);
  EXPECT_NEAR(r.narrowest_between_stencils, 0.002, 1e-9);
  EXPECT_TRUE(r.violations.empty());
}

TEST(MinFeature, AStencilNearTheBorderIsABoundaryViolation) {
  const Plate plate;
  const double half = 0.01;
  // The square's right side at x = 0.1 − 0.0004: 0.4 mm of material to the border.
  const MinFeatureReport r = check_min_feature(plate.cut({{0.1 - 0.0004 - half, 0}}, half), plate.mesh, 0.001);
  EXPECT_EQ(r.holes, 1);
  EXPECT_TRUE(std::isinf(r.narrowest_between_stencils));
  EXPECT_NEAR(r.narrowest_to_boundary, 0.0004, 1e-9);
  ASSERT_EQ(r.violations.size(), 1u);
  EXPECT_EQ(r.violations[0].kind, "boundary");
  EXPECT_NEAR(r.violations[0].point_a.x(), 0.1 - 0.0004, 1e-9) << "the hole's point first";
}

TEST(MinFeature, SegmentDistanceCases) {
  Vec3 p, q;
  // Crossing at a right angle, 1 apart in z.
  EXPECT_NEAR(segment_distance({-1, 0, 0}, {1, 0, 0}, {0, -1, 1}, {0, 1, 1}, &p, &q), 1.0, 1e-15);
  EXPECT_NEAR((p - Vec3(0, 0, 0)).norm(), 0, 1e-15);
  // Parallel, overlapping.
  EXPECT_NEAR(segment_distance({0, 0, 0}, {2, 0, 0}, {1, 0.5, 0}, {3, 0.5, 0}, &p, &q), 0.5, 1e-15);
  // End to end.
  EXPECT_NEAR(segment_distance({0, 0, 0}, {1, 0, 0}, {2, 1, 0}, {3, 1, 0}, &p, &q), std::sqrt(2.0), 1e-15);
  EXPECT_EQ(p, Vec3(1, 0, 0));
  EXPECT_EQ(q, Vec3(2, 1, 0));
  // Degenerate segments (points).
  EXPECT_NEAR(segment_distance({0, 0, 0}, {0, 0, 0}, {0, 3, 4}, {0, 3, 4}, &p, &q), 5.0, 1e-15);
  EXPECT_NEAR(segment_distance({0, 0, 0}, {0, 0, 0}, {-1, 1, 0}, {1, 1, 0}, &p, &q), 1.0, 1e-15);
}

}  // namespace
}  // namespace cutwork
