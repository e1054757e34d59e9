// The minimum-feature check: ligaments between stencil holes and to the border, measured on
// the cut surface and compared with the printable minimum.
#include "host/export/min_feature.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <random>

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

TEST(MinFeature, OnASymmetryPlaneAHoleMeetsItsImage) {
  // The plate as the half of a whole on the plane y = −0.05: a square 0.4 mm from the plane has
  // 0.8 mm of material to its image (a ligament between two holes of the whole, too narrow), not
  // 0.4 mm to a border; at 0.6 mm it passes; the other sides stay a border.
  const Plate plate;
  const double half = 0.01, c = -0.05;
  const Vec3 planes(NAN, c, NAN);
  const CutSurface near = plate.cut({{0.0, c + 0.0004 + half}}, half);
  const MinFeatureReport plain = check_min_feature(near, plate.mesh, 0.001);
  ASSERT_EQ(plain.violations.size(), 1u);
  EXPECT_EQ(plain.violations[0].kind, "boundary");
  const MinFeatureReport r = check_min_feature(near, plate.mesh, 0.001, planes);
  EXPECT_NEAR(r.narrowest_between_stencils, 0.0008, 1e-9);
  EXPECT_NEAR(r.narrowest_to_boundary, 0.1 - 2 * half - 0.0004, 1e-9);  // to the edge y = 0.05
  ASSERT_EQ(r.violations.size(), 1u);
  EXPECT_EQ(r.violations[0].kind, "stencils");
  EXPECT_NEAR(r.violations[0].point_a.y(), c + 0.0004, 1e-9);
  EXPECT_NEAR(r.violations[0].point_b.y(), c - 0.0004, 1e-9);
  EXPECT_TRUE(check_min_feature(plate.cut({{0.0, c + 0.0006 + half}}, half), plate.mesh, 0.001, planes).violations.empty());
  const MinFeatureReport side = check_min_feature(plate.cut({{0.1 - 0.0004 - half, 0}}, half), plate.mesh, 0.001, planes);
  ASSERT_EQ(side.violations.size(), 1u);
  EXPECT_EQ(side.violations[0].kind, "boundary");
  // The narrow-ligament search pairs the hole with its image (and finds nothing without the plane).
  EXPECT_TRUE(find_ligaments(near, plate.mesh, 0.5).empty());
  const std::vector<Ligament> ls = find_ligaments(near, plate.mesh, 0.5, planes);
  ASSERT_EQ(ls.size(), 1u);
  EXPECT_NEAR(ls[0].width, 0.0008, 1e-9);
  EXPECT_EQ(ls[0].loop_a, ls[0].loop_b);
  EXPECT_NEAR(ls[0].point_a.y(), c + 0.0004, 1e-9);
  EXPECT_NEAR(ls[0].point_b.y(), c - 0.0004, 1e-9);
  EXPECT_NEAR(ls[0].point_a.x(), ls[0].point_b.x(), 1e-15);
  EXPECT_NEAR(ls[0].size_a, half, 1e-9);
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


/// The hole loops of `cut` as lists of boundary edges (the border, which touches the plate's
/// outline at x = ±0.1, left out), found by brute force: boundary edges by counting, loops by
/// joining edges that share a vertex.
std::vector<std::vector<std::array<int, 2>>> hole_loops(const CutSurface& cut) {
  std::map<std::pair<int, int>, int> count;
  for (Eigen::Index f = 0; f < cut.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = cut.faces(f, k), b = cut.faces(f, (k + 1) % 3);
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  std::vector<int> parent(size_t(cut.vertices.rows()));
  for (size_t v = 0; v < parent.size(); ++v) parent[v] = int(v);
  const auto root = [&](int v) {
    while (parent[size_t(v)] != v) v = parent[size_t(v)] = parent[size_t(parent[size_t(v)])];
    return v;
  };
  std::vector<std::array<int, 2>> edges;
  for (const auto& [e, n] : count)
    if (n == 1) {
      edges.push_back({e.first, e.second});
      parent[size_t(root(e.first))] = root(e.second);
    }
  std::map<int, std::vector<std::array<int, 2>>> by_root;
  for (const auto& e : edges) by_root[root(e[0])].push_back(e);
  std::vector<std::vector<std::array<int, 2>>> loops;
  for (auto& [r, l] : by_root) {
    double xmax = -1;
    for (const auto& e : l) xmax = std::max(xmax, std::abs(cut.vertices(e[0], 0)));
    if (xmax < 0.1 - 1e-9) loops.push_back(std::move(l));
  }
  return loops;
}

TEST(Ligaments, TheSweepFindsThePairsOfTheBruteForceScan) {
  // 110 circles and squares of random sizes at random places (no two overlapping, all inside the
  // plate), and every pair of holes closer than the relative width listed by scanning every pair of
  // rim edges of every pair of holes.
  const Mixed plate;
  std::mt19937 rng(20261126);
  std::uniform_real_distribution<double> x(-0.09, 0.09), y(-0.04, 0.04), radius(0.002, 0.008), kind(0, 1);
  std::vector<Mixed::Hole> holes;
  for (int tries = 0; holes.size() < 110 && tries < 100000; ++tries) {
    const Mixed::Hole h{x(rng), y(rng), radius(rng), kind(rng) < 0.5 ? 0 : 1};
    bool fits = std::abs(h.x) + h.radius < 0.098 && std::abs(h.y) + h.radius < 0.048;
    for (const Mixed::Hole& o : holes) fits = fits && std::hypot(h.x - o.x, h.y - o.y) > h.radius + o.radius + 2e-4;
    if (fits) holes.push_back(h);
  }
  ASSERT_EQ(holes.size(), 110u);
  const CutSurface cut = plate.cut(holes);
  const auto loops = hole_loops(cut);
  ASSERT_EQ(loops.size(), holes.size());
  const double relative = 1.0;
  auto size = [&](const std::vector<std::array<int, 2>>& l) {
    Eigen::AlignedBox3d box;
    for (const auto& e : l) box.extend(Vec3(cut.vertices.row(e[0])));
    return 0.5 * (box.max() - box.min()).maxCoeff();
  };
  std::vector<double> expected;
  for (size_t i = 0; i < loops.size(); ++i)
    for (size_t j = i + 1; j < loops.size(); ++j) {
      double d = std::numeric_limits<double>::infinity();
      for (const auto& ea : loops[i])
        for (const auto& eb : loops[j])
          d = std::min(d, segment_distance(cut.vertices.row(ea[0]), cut.vertices.row(ea[1]), cut.vertices.row(eb[0]),
                                           cut.vertices.row(eb[1]), nullptr, nullptr));
      if (d <= relative * std::min(size(loops[i]), size(loops[j]))) expected.push_back(d);
    }
  std::sort(expected.begin(), expected.end());
  const std::vector<Ligament> found = find_ligaments(cut, plate.mesh, relative);
  ASSERT_GE(expected.size(), 40u) << "too few pairs for the comparison to say much";
  ASSERT_EQ(found.size(), expected.size());
  for (size_t k = 0; k < found.size(); ++k) {
    EXPECT_NEAR(found[k].width, expected[k], 1e-12) << "ligament " << k;
    EXPECT_NEAR((found[k].point_a - found[k].point_b).norm(), found[k].width, 1e-12);
  }
}

}  // namespace
}  // namespace cutwork
