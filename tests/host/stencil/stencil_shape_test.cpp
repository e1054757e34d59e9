// Stencil shapes: every built-in kind is a valid normalised polygon; user polygons are
// validated, oriented and normalised; bad input gets a message naming what is wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "host/core/error.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork {
namespace {

double signed_area(const std::vector<Vec2>& p) {
  double a = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec2& u = p[i];
    const Vec2& v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - u.y() * v.x();
  }
  return 0.5 * a;
}

double max_radius(const std::vector<Vec2>& p) {
  double r = 0;
  for (const Vec2& v : p) r = std::max(r, v.norm());
  return r;
}

/// Checks the invariants every shape must satisfy.
void expect_normalised(const StencilShape& s) {
  SCOPED_TRACE(s.name);
  ASSERT_GE(s.polygon.size(), 3u);
  EXPECT_NEAR(s.area, signed_area(s.polygon), 1e-14);
  EXPECT_GT(s.area, 1e-4);                      // CCW, not degenerate
  EXPECT_LE(max_radius(s.polygon), 1 + 1e-15);  // inside the unit circle…
  // …and the unit circle is the minimum enclosing one: at least two vertices on it, and they
  // are not all in one open half-plane through the origin (else a smaller circle would fit).
  std::vector<double> angles;
  for (const Vec2& v : s.polygon)
    if (v.norm() > 1 - 1e-9) angles.push_back(std::atan2(v.y(), v.x()));
  ASSERT_GE(angles.size(), 2u);
  std::sort(angles.begin(), angles.end());
  double largest_gap = angles.front() + 2 * std::numbers::pi - angles.back();
  for (size_t i = 0; i + 1 < angles.size(); ++i)
    largest_gap = std::max(largest_gap, angles[i + 1] - angles[i]);
  EXPECT_LE(largest_gap, std::numbers::pi + 1e-6);
  // The inner radius: the disk lies inside (no vertex or edge closer to the origin).
  for (size_t i = 0; i < s.polygon.size(); ++i) {
    const Vec2 a = s.polygon[i], b = s.polygon[(i + 1) % s.polygon.size()];
    const double t = std::clamp(-a.dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    EXPECT_GE((a + t * (b - a)).norm(), s.inner_radius);
  }
}

TEST(StencilShape, EveryBuiltinKindIsValid) {
  ASSERT_EQ(builtin_stencil_kinds().size(), builtin_stencil_info().size());
  for (const std::string& kind : builtin_stencil_kinds()) {
    const StencilShape s = make_builtin_stencil(kind, {}, "my " + kind);
    EXPECT_EQ(s.kind, kind);
    EXPECT_EQ(s.name, "my " + kind);
    expect_normalised(s);
    // Non-degenerate extremes of every parameter are valid too.
    for (const StencilParamInfo& p : builtin_stencil_info()[size_t(
             std::find(builtin_stencil_kinds().begin(), builtin_stencil_kinds().end(), kind) -
             builtin_stencil_kinds().begin())]
                                        .params) {
      for (double v : {p.min, p.max}) {
        if (!p.integer) {
          const double inset = 1e-3 * (p.max - p.min);
          if (v == p.min && !p.min_inclusive) v += inset;
          if (v == p.max && !p.max_inclusive) v -= inset;
          if (v == p.min && p.min == 0) v += inset;  // e.g. a flower of depth 0 is a circle
        }
        expect_normalised(make_builtin_stencil(kind, {{p.name, v}}, kind + " " + p.name));
      }
    }
  }
}

TEST(StencilShape, KnownAreasAndInnerRadii) {
  const double pi = std::numbers::pi;
  const StencilShape c = make_builtin_stencil("circle", {{"segments", 256}}, "c");
  EXPECT_NEAR(c.area, 0.5 * 256 * std::sin(2 * pi / 256), 1e-13);
  EXPECT_NEAR(c.inner_radius, std::cos(pi / 256), 1e-11);
  const StencilShape sq = make_builtin_stencil("square", {}, "sq");
  EXPECT_NEAR(sq.area, 2.0, 1e-14);  // side √2
  EXPECT_NEAR(sq.inner_radius, std::sqrt(0.5), 1e-11);
  const StencilShape e = make_builtin_stencil("ellipse", {{"aspect", 0.5}, {"segments", 512}}, "e");
  EXPECT_NEAR(e.area, pi * 0.5, 1e-4);
  const StencilShape star = make_builtin_stencil("star", {{"points", 6}, {"inner_ratio", 0.4}}, "s");
  EXPECT_EQ(star.polygon.size(), 12u);
  EXPECT_NEAR(star.area, 12 * 0.5 * 0.4 * std::sin(pi / 6), 1e-13);
  // Perimeters, and the hydraulic diameter 4A/P the cell filter measures triangles against: a
  // regular n-gon's is 2 cos(π/n) (its bounding diameter, 2, in the limit); a star's edge joins a
  // point (radius 1) to an inner corner (radius r) π/n away.
  EXPECT_NEAR(c.perimeter, 2 * 256 * std::sin(pi / 256), 1e-13);
  EXPECT_NEAR(stencil_hydraulic_diameter(c), 2 * std::cos(pi / 256), 1e-13);
  EXPECT_NEAR(sq.perimeter, 4 * std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(stencil_hydraulic_diameter(sq), std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(star.perimeter, 12 * std::sqrt(1 + 0.16 - 0.8 * std::cos(pi / 6)), 1e-13);
  const StencilShape star5 = make_builtin_stencil("star", {}, "s5");
  EXPECT_NEAR(stencil_hydraulic_diameter(star5),
              4 * 5 * 0.5 * std::sin(pi / 5) / (10 * std::sqrt(1.25 - std::cos(pi / 5))), 1e-13);
  EXPECT_LT(stencil_hydraulic_diameter(star5), 0.45 * 2);
  // A "C" has the origin outside: no inscribed disk.
  std::vector<Vec2> cee;
  for (int i = 0; i <= 20; ++i) cee.emplace_back(std::cos(0.5 + 5.28 * i / 20), std::sin(0.5 + 5.28 * i / 20));
  for (int i = 20; i >= 0; --i)
    cee.emplace_back(0.6 * std::cos(0.5 + 5.28 * i / 20), 0.6 * std::sin(0.5 + 5.28 * i / 20));
  EXPECT_EQ(make_polygon_stencil("cee", cee).inner_radius, 0.0);
}

TEST(StencilShape, PolygonIsOrientedAndNormalised) {
  // A clockwise rectangle 4 × 2 centred at (10, −3), given with a closing duplicate point.
  const std::vector<Vec2> cw{{8, -2}, {12, -2}, {12, -4}, {8, -4}, {8, -2}};
  const StencilShape s = make_polygon_stencil("rect", cw);
  EXPECT_EQ(s.kind, "polygon");
  ASSERT_EQ(s.polygon.size(), 4u);
  expect_normalised(s);
  // Bounding circle radius √5 about (10, −3): area 8 / 5.
  EXPECT_NEAR(s.area, 8.0 / 5.0, 1e-14);
  for (const Vec2& p : s.polygon) EXPECT_NEAR(p.norm(), 1.0, 1e-15);
  // Minimum enclosing circle, not the centroid: an L-shape's circle centre is the midpoint of
  // its two farthest corners.
  const StencilShape l = make_polygon_stencil("L", {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}});
  expect_normalised(l);
  EXPECT_NEAR(l.polygon[0].x(), -std::sqrt(0.5), 1e-15);  // (0,0) ↦ (−1, −1)/√2
  EXPECT_NEAR(l.polygon[0].y(), -std::sqrt(0.5), 1e-15);
}

void expect_input_error(const std::function<void()>& f, const std::vector<std::string>& needles) {
  try {
    f();
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    for (const std::string& n : needles)
      EXPECT_NE(std::string(e.what()).find(n), std::string::npos) << e.what() << " lacks " << n;
  }
}

TEST(StencilShape, RejectsBadPolygons) {
  expect_input_error([] { make_polygon_stencil("p", {{0, 0}, {1, 0}}); }, {"'p'", "at least 3"});
  expect_input_error([] { make_polygon_stencil("p", {{0, 0}, {1, 0}, {1, 0}, {0, 0}}); },
                     {"at least 3"});
  expect_input_error([] { make_polygon_stencil("p", {{0, 0}, {1, 0}, {0, 1}, {2, 2}}); },
                     {"'p'", "intersect"});  // bow tie
  expect_input_error([] { make_polygon_stencil("p", {{0, 0}, {1, 0}, {2, 0}}); }, {"zero area"});
  expect_input_error([] { make_polygon_stencil("p", {{0, 0}, {1, 0}, {0, std::nan("")}}); },
                     {"non-finite"});
  // Touching: a vertex on a non-adjacent edge.
  expect_input_error(
      [] { make_polygon_stencil("p", {{0, 0}, {2, 0}, {2, 2}, {1, 0}, {0, 2}}); }, {"intersect"});
  // Folding back along an edge.
  expect_input_error([] { make_polygon_stencil("p", {{0, 0}, {2, 0}, {1, 0}, {1, 1}}); },
                     {"folds back"});
  std::vector<Vec2> many;
  for (int i = 0; i < kMaxStencilPolygonVertices + 1; ++i)
    many.emplace_back(std::cos(2 * std::numbers::pi * i / (kMaxStencilPolygonVertices + 1)),
                      std::sin(2 * std::numbers::pi * i / (kMaxStencilPolygonVertices + 1)));
  expect_input_error([&] { make_polygon_stencil("p", many); }, {"at most"});
}

TEST(StencilShape, RejectsBadKindsAndParameters) {
  expect_input_error([] { make_builtin_stencil("blob", {}, "b"); },
                     {"'b'", "unknown kind 'blob'", "circle", "flower"});
  expect_input_error([] { make_builtin_stencil("star", {{"petals", 5}}, "s"); },
                     {"'petals'", "points", "inner_ratio"});
  expect_input_error([] { make_builtin_stencil("star", {{"points", 2}}, "s"); },
                     {"'points'", "[3, 64]"});
  expect_input_error([] { make_builtin_stencil("star", {{"points", 5.5}}, "s"); },
                     {"'points'", "integer"});
  expect_input_error([] { make_builtin_stencil("star", {{"inner_ratio", 1.0}}, "s"); },
                     {"'inner_ratio'", "(0, 1)"});
  expect_input_error([] { make_builtin_stencil("ellipse", {{"aspect", std::nan("")}}, "e"); },
                     {"'aspect'"});
  expect_input_error([] { make_builtin_stencil("square", {{"size", 1}}, "q"); }, {"none"});
}

TEST(StencilShape, LibraryAssignsTypesAndPacksPolygons) {
  StencilLibrary lib;
  EXPECT_EQ(lib.add(make_builtin_stencil("circle", {{"segments", 10}}, "a")), 0);
  EXPECT_EQ(lib.add(make_builtin_stencil("star", {}, "b")), 1);
  EXPECT_EQ(lib.find("b"), 1);
  EXPECT_EQ(lib.find("zzz"), -1);
  EXPECT_EQ(lib[1].type, 1);
  expect_input_error([&] { lib.add(make_builtin_stencil("heart", {}, "a")); }, {"'a'", "twice"});
  ASSERT_EQ(lib.clip_shapes().size(), 2u);
  EXPECT_EQ(lib.clip_shapes()[0].polygon_offset, 0);
  EXPECT_EQ(lib.clip_shapes()[0].polygon_count, 10);
  EXPECT_EQ(lib.clip_shapes()[1].polygon_offset, 10);
  EXPECT_EQ(lib.clip_shapes()[1].polygon_count, 10);
  EXPECT_EQ(lib.packed_polygons().size(), 40u);
  EXPECT_EQ(lib.packed_polygons()[20], lib[1].polygon[0].x());
  EXPECT_EQ(lib.clip_shapes()[1].area, lib[1].area);
}

}  // namespace
}  // namespace cutwork
