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

/// Stencils of the types of `Plate` plus a 128-gon circle (type 1), each at (x, y) with its
/// bounding radius.
struct Mixed : Plate {
  Mixed() { shapes.add(make_builtin_stencil("circle", {{"segments", 128}}, "circle")); }
  struct Hole {
    double x, y, radius;
    int type;
  };
  CutSurface cut(const std::vector<Hole>& holes) const {
    std::vector<StencilParams> stencils;
    for (const Hole& h : holes) {
      StencilParams p;
      p.position = Vec3(h.x, h.y, 0);
      p.scale = h.radius;
      p.type = h.type;
      stencils.push_back(p);
    }
    return cut_stencils(bvh, shapes, field, stencils);
  }
};

TEST(Ligaments, TwoCirclesGiveTheirWidthAndRadii) {
  const Mixed plate;
  const double ra = 0.02, rb = 0.03, gap = 0.001;
  // The 128-gons have a vertex on the line of centres: the closest points are those vertices.
  const CutSurface cut = plate.cut({{-0.045, 0, ra, 1}, {-0.045 + ra + gap + rb, 0, rb, 1}});
  const std::vector<Ligament> ls = find_ligaments(cut, plate.mesh, 0.5);
  ASSERT_EQ(ls.size(), 1u);
  const Ligament& l = ls[0];
  EXPECT_NEAR(l.width, gap, 1e-9);
  EXPECT_NEAR(l.midpoint().x(), -0.045 + ra + gap / 2, 1e-9);
  EXPECT_NEAR(l.midpoint().y(), 0, 1e-9);
  // The rims' radii from the least-squares circle through the rim's vertices about the neck: the
  // polygon's vertices lie on the circle, the points where the base mesh's edges cross its sides
  // up to R (1 − cos(π/128)) = 3e-4 R inside it, over an arc of ±8–15°: measured 0.6% off for ρ_b.
  const double rA = std::min(l.radius_a, l.radius_b), rB = std::max(l.radius_a, l.radius_b);
  EXPECT_NEAR(rA, ra, 0.02 * ra);
  EXPECT_NEAR(rB, rb, 0.02 * rb);
  EXPECT_NEAR(std::min(l.size_a, l.size_b), ra, 0.01 * ra);
  EXPECT_NEAR(l.neck_radius(), 2 * ra * rb / (ra + rb), 0.02 * ra);
  EXPECT_NEAR(l.pair_radius(), (ra * ra + rb * rb) / (ra + rb), 0.02 * ra);
}

TEST(Ligaments, AStraightRimCountsAsLargeAsItsHoleAndWideOnesAreNotListed) {
  const Mixed plate;
  const double r = 0.01, half = 0.01, gap = 0.0008;
  // A circle beside a square's straight side; a second circle far away (8 mm: 0.8 of the smaller
  // size, beyond the search's 0.5); a third 1 mm from the border (a border loop is no ligament).
  const CutSurface cut = plate.cut({{-0.05, 0, r, 1},
                                    {-0.05 + r + gap + half, 0, half * std::sqrt(2.0), 0},
                                    {-0.05 - r - 0.008 - r, 0, r, 1},
                                    {0.1 - 0.001 - r, 0, r, 1}});
  const std::vector<Ligament> ls = find_ligaments(cut, plate.mesh, 0.5);
  ASSERT_EQ(ls.size(), 1u);
  const Ligament& l = ls[0];
  EXPECT_NEAR(l.width, gap, 1e-9);
  const bool circle_is_a = l.point_a.x() < l.point_b.x();
  const double circle_radius = circle_is_a ? l.radius_a : l.radius_b;
  const double square_radius = circle_is_a ? l.radius_b : l.radius_a;
  EXPECT_NEAR(circle_radius, r, 0.02 * r);
  // Straight there: no circle (or, once the fit reaches the square's corners, one larger than it).
  EXPECT_GE(square_radius, half);
  // Capped at the square's size (half its side): R_h = 2 r s/(r + s) with s = half.
  EXPECT_NEAR(l.neck_radius(), 2 * circle_radius * half / (circle_radius + half), 1e-9 * r);
  // With the search widened to the far circle, it is listed too (8 mm, radii r).
  const std::vector<Ligament> wide = find_ligaments(cut, plate.mesh, 1.0);
  ASSERT_EQ(wide.size(), 2u);
  EXPECT_NEAR(wide[1].width, 0.008, 1e-9);
}

}  // namespace
}  // namespace cutwork
