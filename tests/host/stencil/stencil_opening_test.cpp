// The tool's cut of a stencil (stencil_opening.h): the opening of its polygon by a disc, against
// closed forms (a square's rounded corners, a star's rounded tips and sharp notches), brute-force
// containment, the pieces of a dumbbell and a slot narrower than the tool.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "host/core/error.h"
#include "host/stencil/stencil_opening.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork {
namespace {

double signed_area(const std::vector<Vec2>& p) {
  double a = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec2 &u = p[i], &v = p[(i + 1) % p.size()];
    a += u.x() * v.y() - u.y() * v.x();
  }
  return 0.5 * a;
}

/// Signed distance of q to the polygon's outline: negative inside (brute force, even–odd rule).
double signed_distance(const std::vector<Vec2>& p, const Vec2& q) {
  double d = 1e300;
  bool inside = false;
  for (size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) {
    d = std::min(d, segment_distance(p[j], p[i], q));
    if ((p[i].y() > q.y()) != (p[j].y() > q.y()) &&
        q.x() < (p[j].x() - p[i].x()) * (q.y() - p[i].y()) / (p[j].y() - p[i].y()) + p[i].x())
      inside = !inside;
  }
  return inside ? -d : d;
}

std::vector<Vec2> square(double a) { return {{-a, -a}, {a, -a}, {a, a}, {-a, a}}; }

/// A five-pointed star: tips at radius 1, notches at `inner`.
std::vector<Vec2> star(double inner) {
  std::vector<Vec2> p;
  for (int i = 0; i < 10; ++i) {
    const double a = std::numbers::pi / 2 + i * std::numbers::pi / 5, r = i % 2 ? inner : 1.0;
    p.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return p;
}

TEST(PolygonOpening, ASquaresCornersBecomeQuarterCirclesOfTheToolsRadius) {
  const double a = 0.7, r = 0.1;
  const OpenedPolygon o = open_polygon(square(a), r);
  ASSERT_EQ(o.components, 1);
  EXPECT_FALSE(o.unchanged);
  // Area (2a)² − (4 − π) r², less what the 5° chords of the four quarter circles cut off
  // (a full circle's worth: π r² (1 − sin Δ / Δ), Δ = 5°).
  const double delta = kOpeningArcStep, exact = 4 * a * a - (4 - std::numbers::pi) * r * r;
  const double chords = r * r * (std::numbers::pi - 0.5 * (2 * std::numbers::pi / delta) * std::sin(delta));
  EXPECT_NEAR(signed_area(o.polygon), exact - chords, 1e-6 * exact);
  // Every point on the square's sides or on a quarter circle about (±(a − r), ±(a − r)).
  for (const Vec2& p : o.polygon) {
    const Vec2 c(std::copysign(a - r, p.x()), std::copysign(a - r, p.y()));
    const bool on_side = std::abs(std::abs(p.x()) - a) < 1e-9 || std::abs(std::abs(p.y()) - a) < 1e-9;
    const bool on_arc = std::abs((p - c).norm() - r) < 1e-6 && std::abs(p.x()) >= a - r - 1e-9 &&
                        std::abs(p.y()) >= a - r - 1e-9;
    EXPECT_TRUE(on_side || on_arc) << p.transpose();
  }
}

TEST(PolygonOpening, AStarsTipsAreRoundedAndItsNotchesStaySharp) {
  const std::vector<Vec2> drawn = star(0.45);
  for (double r : {0.02, 0.05, 0.1}) {
    SCOPED_TRACE(r);
    const OpenedPolygon o = open_polygon(drawn, r);
    ASSERT_EQ(o.components, 1);
    // Inside the drawn star (brute force), up to the offsets' approximation: CGAL rounds the ends
    // of the straight pieces to rational points (ε = 1e-6 r per offset, measured up to 5e-6 r off).
    for (const Vec2& p : o.polygon) EXPECT_LE(signed_distance(drawn, p), 1e-5 * r) << p.transpose();
    for (size_t i = 0; i < drawn.size(); ++i) {
      const Vec2& v = drawn[i];
      double nearest = 1e300;
      for (const Vec2& p : o.polygon) nearest = std::min(nearest, (p - v).norm());
      if (i % 2 == 0) {
        // A tip of interior angle θ: the disc of radius r tangent to both sides has its centre
        // r / sin(θ/2) from the tip, so the cut ends r (1 / sin(θ/2) − 1) short of it.
        const Vec2 prev = drawn[(i + 9) % 10] - v, next = drawn[(i + 1) % 10] - v;
        const double theta = std::acos(prev.normalized().dot(next.normalized()));
        const double gap = r * (1 / std::sin(0.5 * theta) - 1);
        EXPECT_NEAR(nearest, gap, 2e-3 * r);
      } else {
        // A notch turns away from the material: the tool reaches it, up to the inset's
        // circumscribed arcs (r (1 / cos(π/16) − 1)).
        EXPECT_LE(nearest, 0.025 * r);
      }
    }
    // The tool leaves material at the tips: the opening is smaller than the drawn star.
    EXPECT_LT(signed_area(o.polygon), signed_area(drawn));
  }
}

// A tool far smaller than the polygon (below kFilletOpening of its size) opens it into its fillets:
// CGAL's offsets there left needles of no width (the default heart at 1e-4 of its size had a vertex
// on another edge, the leaf at 1e-7), which the cut made into holes touching at a point. Each
// opening is simple, inside the drawn polygon, and its area the drawn one's less the fillets'
// closed form r² (tan(φ/2) − φ/2) per corner turning by φ, and the chords' r²/2 (Δ − sin Δ) per
// segment of Δ = φ/m. The fillets match CGAL's opening of the star (kept above the threshold), and
// a neck narrower than 2r is no place for them.
TEST(PolygonOpening, AToolFarSmallerThanThePolygonOpensItIntoItsFillets) {
  for (const char* kind : {"heart", "leaf", "star", "cross"})
    for (const double r : {1e-4, 1e-7}) {
      SCOPED_TRACE(std::string(kind) + " at " + std::to_string(r));
      const std::vector<Vec2> drawn = make_builtin_stencil(kind, {}, kind).polygon;
      const OpenedPolygon o = open_polygon(drawn, r);
      ASSERT_EQ(o.components, 1);
      ASSERT_FALSE(o.unchanged);
      const std::vector<Vec2>& p = o.polygon;
      const size_t n = p.size();
      double closest = INFINITY;  // a vertex to an edge not its own
      for (size_t i = 0; i < n; ++i)
        for (size_t j = 0; j < n; ++j)
          if (j != i && (j + 1) % n != i) closest = std::min(closest, segment_distance(p[j], p[(j + 1) % n], p[i]));
      EXPECT_GT(closest, 0.01 * r);  // an arc's shortest chord, 2r sin(1.25°) = 0.044 r; a needle's 0
      double outside = -INFINITY, removed = 0;
      for (const Vec2& q : p) outside = std::max(outside, signed_distance(drawn, q));
      EXPECT_LT(outside, 1e-12);
      const size_t m = drawn.size();
      for (size_t i = 0; i < m; ++i) {
        const Vec2 a = drawn[i] - drawn[(i + m - 1) % m], b = drawn[(i + 1) % m] - drawn[i];
        const double phi = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
        if (phi <= kOpeningArcStep) continue;
        const int segments = int(std::ceil(phi / kOpeningArcStep));
        const double delta = phi / segments;
        removed += r * r * (std::tan(0.5 * phi) - 0.5 * phi) + segments * 0.5 * r * r * (delta - std::sin(delta));
      }
      ASSERT_GT(removed, 0.0);
      if (r > 1e-6)  // (at 1e-7 the fillets' 1e-14 is below the shoelace sums' round-off)
        EXPECT_NEAR(signed_area(drawn) - signed_area(p), removed, 1e-4 * removed);
    }
  // The twin above the threshold: the star's fillets at r = 0.01 against CGAL's opening, each
  // vertex of one within the arcs' chord height (r (1 − cos 2.5°), 1e-3 r) of the other's outline.
  const std::vector<Vec2> s = make_builtin_stencil("star", {}, "star").polygon;
  const double r = 0.01;
  std::vector<Vec2> fillets;
  ASSERT_TRUE(fillet_polygon(s, r, kOpeningArcStep, fillets));
  const OpenedPolygon cgal = open_polygon(s, r);
  ASSERT_GT(cgal.polygon.size(), 0u);
  const std::vector<Vec2>& opened = cgal.polygon;
  for (const Vec2& q : fillets) EXPECT_LT(std::abs(signed_distance(opened, q)), 2e-3 * r) << q.transpose();
  for (const Vec2& q : opened) EXPECT_LT(std::abs(signed_distance(fillets, q)), 2e-3 * r) << q.transpose();
  // A neck narrower than 2r: no fillets (open_polygon splits it, above).
  const std::vector<Vec2> dumbbell = {{-0.9, -0.3}, {-0.3, -0.3}, {-0.3, -0.05}, {0.3, -0.05}, {0.3, -0.3}, {0.9, -0.3},
                                      {0.9, 0.3},   {0.3, 0.3},   {0.3, 0.05},   {-0.3, 0.05}, {-0.3, 0.3}, {-0.9, 0.3}};
  EXPECT_FALSE(fillet_polygon(dumbbell, 0.06, kOpeningArcStep, fillets));
  EXPECT_TRUE(fillet_polygon(dumbbell, 0.04, kOpeningArcStep, fillets));
}

TEST(PolygonOpening, ASmoothConvexPolygonIsKeptAndADumbbellSplits) {
  std::vector<Vec2> circle;
  for (int i = 0; i < 96; ++i) circle.emplace_back(std::cos(2 * std::numbers::pi * i / 96), std::sin(2 * std::numbers::pi * i / 96));
  const OpenedPolygon kept = open_polygon(circle, 0.3);
  EXPECT_TRUE(kept.unchanged);
  EXPECT_EQ(kept.polygon, circle);
  // A circle smaller than the tool: its fillets do not fit, and nothing fits.
  const OpenedPolygon none = open_polygon(circle, 1.2);
  EXPECT_TRUE(none.polygon.empty());
  EXPECT_EQ(none.components, 0);
  // Two 0.6 squares joined by a neck 0.1 wide: a tool of radius 0.1 cuts the squares, not the neck.
  const std::vector<Vec2> dumbbell = {{-0.9, -0.3}, {-0.3, -0.3}, {-0.3, -0.05}, {0.3, -0.05}, {0.3, -0.3}, {0.9, -0.3},
                                      {0.9, 0.3},   {0.3, 0.3},   {0.3, 0.05},   {-0.3, 0.05}, {-0.3, 0.3}, {-0.9, 0.3}};
  const double r = 0.1;
  const OpenedPolygon split = open_polygon(dumbbell, r);
  EXPECT_EQ(split.components, 2);
  // One square with its four corners rounded, and the cap the discs push into the neck: centred up
  // to r cos(π/6) from the square's side, where their chord on it is the neck's width (segment of
  // half-angle π/6); less the 5° chords of a full circle, as for the square above.
  const double delta = kOpeningArcStep;
  const double chords = r * r * (std::numbers::pi - 0.5 * (2 * std::numbers::pi / delta) * std::sin(delta));
  const double cap = r * r * (std::numbers::pi / 6 - std::sqrt(3.0) / 4);
  const double one_square = 0.36 - (4 - std::numbers::pi) * r * r + cap - chords;
  EXPECT_NEAR(signed_area(split.polygon), one_square, 1e-4 * one_square);
}

// A flower's petals are rounds written as segments turning about 15° each: at a tool far smaller
// than the rounds the tool follows them (the drawn polygon is kept, its kinks are no corners); at a
// tool larger than the rounds (0.27 of the radius) it cannot, and the petals are cut rounder.
TEST(PolygonOpening, AFlowersPetalsAreRoundedOnlyByAToolLargerThanTheirRounds) {
  const StencilShape flower = make_builtin_stencil("flower", {}, "flower");
  const OpenedPolygon small = open_polygon(flower.polygon, 0.01);
  EXPECT_TRUE(small.unchanged);
  EXPECT_EQ(small.components, 1);
  EXPECT_EQ(small.polygon, flower.polygon);
  const OpenedPolygon large = open_polygon(flower.polygon, 0.4);
  EXPECT_FALSE(large.unchanged);
  EXPECT_EQ(large.components, 1);
  EXPECT_LT(signed_area(large.polygon), flower.area);
  double reach = 0;  // the petals' tips (radius 1) are cut back
  for (const Vec2& p : large.polygon) reach = std::max(reach, p.norm());
  EXPECT_LT(reach, 0.99);
  // The notches (turning away from the material) are kept: the opening reaches radius 1 − depth.
  double inner = 1;
  for (const Vec2& p : large.polygon) inner = std::min(inner, p.norm());
  EXPECT_NEAR(inner, 0.65, 0.02);
}

TEST(PolygonOpening, BadInputIsRefused) {
  EXPECT_THROW(open_polygon(square(0.5), 0), InputError);
  EXPECT_THROW(open_polygon(square(0.5), NAN), InputError);
  EXPECT_THROW(open_polygon(std::vector<Vec2>{{0, 0}, {1, 0}}, 0.1), InputError);
}

TEST(ToolCutStencils, EachStencilIsOpenedAtTheToolsRadiusOverItsOwnScale) {
  StencilLibrary shapes;
  shapes.add(make_builtin_stencil("star", {}, "star"));
  shapes.add(make_builtin_stencil("circle", {}, "circle"));
  std::vector<StencilParams> stencils(3);
  stencils[0] = {Vec3(0, 0, 0), 0.01, 0.3, 0};
  stencils[1] = {Vec3(1, 0, 0), 0.02, 0.0, 0};
  stencils[2] = {Vec3(2, 0, 0), 0.02, 0.0, 1};
  const double tool = 0.0005;
  const ToolCutStencils cut = tool_cut_stencils(shapes, stencils, tool);
  ASSERT_EQ(cut.shapes.size(), 3);
  ASSERT_EQ(cut.stencils.size(), 3u);
  EXPECT_EQ(cut.rounded, 2);  // the stars; the circle is smooth at the tool's radius
  EXPECT_EQ(cut.too_small, 0);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(cut.stencils[size_t(i)].type, i);
    EXPECT_EQ(cut.stencils[size_t(i)].scale, stencils[size_t(i)].scale);
    EXPECT_EQ(cut.stencils[size_t(i)].position, stencils[size_t(i)].position);
    const OpenedPolygon o = open_polygon(shapes[stencils[size_t(i)].type].polygon, tool / stencils[size_t(i)].scale);
    const std::vector<Vec2> expected = o.unchanged ? shapes[stencils[size_t(i)].type].polygon : o.polygon;
    ASSERT_EQ(cut.shapes[i].polygon.size(), expected.size());
    for (size_t k = 0; k < expected.size(); ++k) EXPECT_LE((cut.shapes[i].polygon[k] - expected[k]).norm(), 1e-15);
    EXPECT_NEAR(cut.shapes[i].area, signed_area(cut.shapes[i].polygon), 1e-15);
  }
  // The smaller star loses more of its reference area (its tool radius is twice the other's).
  const double drawn = shapes[0].area;
  EXPECT_GT(drawn - cut.shapes[0].area, 3 * (drawn - cut.shapes[1].area));
  // Without a tool every outline is the drawn one.
  const ToolCutStencils sharp = tool_cut_stencils(shapes, stencils, 0);
  EXPECT_EQ(sharp.rounded, 0);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(sharp.shapes[i].polygon, shapes[stencils[size_t(i)].type].polygon);
  // A stencil into which the tool does not fit is kept as drawn and counted.
  const ToolCutStencils tiny = tool_cut_stencils(shapes, std::vector<StencilParams>{{Vec3::Zero(), 0.0004, 0, 0}}, tool);
  EXPECT_EQ(tiny.too_small, 1);
  EXPECT_EQ(tiny.shapes[0].polygon, shapes[0].polygon);
  EXPECT_THROW(tool_cut_stencils(shapes, std::vector<StencilParams>{{Vec3::Zero(), 0.01, 0, 5}}, tool), InputError);
}

}  // namespace
}  // namespace cutwork
