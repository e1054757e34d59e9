// Poisson-disk initialisation and the admissibility checks: clearances, saturation, count,
// uniformity (area-weighted sampling), determinism; overlap checks against the brute-force
// twin and overlap resolution.
#include <numbers>

#include <gtest/gtest.h>

#include "host/pattern/overlaps.h"
#include "host/pattern/poisson_disk.h"
#include "host/surfaces/generators.h"
#include "pattern_test_util.h"

namespace cutwork {
namespace {

std::unique_ptr<PatternSurface> make_surface(const SurfaceMesh& mesh, Eigen::VectorXd sizing = {}) {
  if (sizing.size() == 0) sizing = Eigen::VectorXd::Ones(mesh.num_vertices());
  return std::make_unique<PatternSurface>(mesh, OrientationFieldOptions{}, SizingField(sizing), 0.02);
}

TEST(PoissonDisk, AdmissibleMaximalAndDeterministic) {
  for (const char* name : {"plate", "bowl", "pavilion"}) {
    const SurfaceMesh mesh = generate_shape(name, {}, find_shape(name)->base_edge_length);
    const auto surface = make_surface(mesh);
    PoissonDiskOptions o;
    o.unit = 0.02 * surface->length();
    o.safety = 0.2;
    o.num_types = 2;
    PatternRng rng(42);
    StencilLayout layout;
    const int added = poisson_disk_sample(*surface, layout, rng, o);
    EXPECT_EQ(added, int(layout.size()));
    EXPECT_GT(added, 50) << name;
    EXPECT_FALSE(find_overlaps_brute_force(*surface, layout, o.safety).any()) << name;
    for (const auto& s : layout) {
      EXPECT_NEAR(s.scale, o.unit, 1e-15);
      EXPECT_NEAR((mesh.point(s.where) - s.position).norm(), 0.0, 1e-12);
      EXPECT_TRUE(s.type == 0 || s.type == 1);
    }
    // Saturation: random sequential packing of exclusion disks of radius (1+s) r covers about
    // 54.7% of the plane; with boundary losses at least 40% here (flat plate: ≥ 45%).
    const double disk = std::numbers::pi * std::pow((1 + o.safety) * o.unit, 2);
    const double fraction = added * disk / surface->area();
    EXPECT_GT(fraction, 0.40) << name;
    EXPECT_LT(fraction, 0.60) << name;
    // Determinism: the same seed gives the same layout bit for bit.
    PatternRng rng2(42);
    StencilLayout again;
    poisson_disk_sample(*surface, again, rng2, o);
    ASSERT_EQ(again.size(), layout.size());
    for (size_t i = 0; i < layout.size(); ++i) {
      EXPECT_EQ(again[i].position, layout[i].position);
      EXPECT_EQ(again[i].type, layout[i].type);
    }
  }
}

TEST(PoissonDisk, CountSizingAndHoleFilling) {
  const SurfaceMesh mesh = test::flat_plate(0.2, 0.1, 0.005);
  // Sizing 2 on the right half: stencils there are twice as large and about 4× sparser.
  Eigen::VectorXd z(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) z[v] = mesh.vertices()(v, 0) > 0.1 ? 2.0 : 1.0;
  const auto surface = make_surface(mesh, z);
  PoissonDiskOptions o;
  o.unit = 0.003;
  PatternRng rng(1);
  StencilLayout layout;
  poisson_disk_sample(*surface, layout, rng, o);
  int left = 0, right = 0;
  for (const auto& s : layout) {
    if (s.position.x() < 0.095) {
      ++left;
      EXPECT_NEAR(s.scale, 0.003, 1e-15);
    } else if (s.position.x() > 0.105) {
      ++right;
      EXPECT_NEAR(s.scale, 0.006, 1e-15);
    }
  }
  EXPECT_GT(left, 3 * right);
  EXPECT_LT(left, 5 * right);
  EXPECT_FALSE(find_overlaps_brute_force(*surface, layout, o.safety).any());

  // count stops early; an existing layout is kept and completed (hole filling).
  o.count = 40;
  StencilLayout few;
  PatternRng r2(2);
  EXPECT_EQ(poisson_disk_sample(*surface, few, r2, o), 40);
  StencilLayout holed;
  for (const auto& s : layout)
    if ((s.position - Vec3(0.05, 0.05, 0)).norm() > 0.02) holed.push_back(s);
  const size_t before = holed.size();
  const StencilLayout kept = holed;
  o.count = 0;
  const int added = poisson_disk_sample(*surface, holed, r2, o);
  EXPECT_GT(added, 0);
  EXPECT_EQ(holed.size(), before + size_t(added));
  for (size_t i = 0; i < before; ++i) EXPECT_EQ(holed[i].position, kept[i].position);
  EXPECT_FALSE(find_overlaps_brute_force(*surface, holed, o.safety).any());
}

TEST(PoissonDisk, AreaWeightedSampling) {
  // Surface samples are uniform by area: on the plate, the fraction in the left 30% of the
  // width is 0.3 ± 4σ (binomial, n = 20000).
  const SurfaceMesh mesh = test::flat_plate(0.2, 0.1, 0.004);
  const auto surface = make_surface(mesh);
  PatternRng rng(5);
  const int n = 20000;
  int hits = 0;
  for (int k = 0; k < n; ++k) hits += mesh.point(surface->sample(rng)).x() < 0.06;
  const double sd = std::sqrt(0.3 * 0.7 / n);
  EXPECT_NEAR(double(hits) / n, 0.3, 4 * sd);
}

TEST(Overlaps, GridMatchesBruteForceAndResolveMakesAdmissible) {
  for (const char* name : {"plate", "bowl"}) {
    const SurfaceMesh mesh = generate_shape(name, {}, find_shape(name)->base_edge_length);
    const auto surface = make_surface(mesh);
    PatternRng rng(3);
    StencilLayout layout;
    const double r = 0.03 * surface->length();
    for (int k = 0; k < 300; ++k) {
      const SurfacePoint w = surface->sample(rng);
      layout.push_back({mesh.point(w), w, r * rng.uniform(0.5, 1.5), 0.0, 0});
    }
    const OverlapReport a = find_overlaps(*surface, layout, 0.2);
    const OverlapReport b = find_overlaps_brute_force(*surface, layout, 0.2);
    EXPECT_EQ(a.pairs, b.pairs);
    EXPECT_EQ(a.boundary, b.boundary);
    EXPECT_EQ(a.worst, b.worst);
    ASSERT_GT(a.pairs, 10);
    ASSERT_GT(a.boundary, 3);
    StencilLayout fixed = layout;
    const Eigen::VectorXd min_scales = Eigen::VectorXd::Constant(300, 0.2 * r);
    const int removed = resolve_overlaps(*surface, fixed, 0.2, min_scales);
    EXPECT_EQ(int(fixed.size()) + removed, 300);
    const OverlapReport after = find_overlaps_brute_force(*surface, fixed, 0.2);
    EXPECT_EQ(after.pairs, 0) << name;
    EXPECT_EQ(after.boundary, 0) << name;
    for (const auto& s : fixed) EXPECT_GE(s.scale, 0.2 * r);
  }
}

// The absolute gap (the minimum feature as a hard constraint): the grid and the brute force agree
// with it, the resolution leaves at least the gap of material between every two enlarged
// bounding circles and to the border, measured directly, and a gap-free check of the same layout
// passes while the gap check of the gap-free resolution does not.
TEST(Overlaps, GapKeepsAMinimumWidthOfMaterialBetweenStencilsAndToTheBorder) {
  for (const char* name : {"plate", "bowl"}) {
    const SurfaceMesh mesh = generate_shape(name, {}, find_shape(name)->base_edge_length);
    const auto surface = make_surface(mesh);
    PatternRng rng(5);
    StencilLayout layout;
    const double r = 0.03 * surface->length(), gap = 0.25 * r, s = 0.2;
    for (int k = 0; k < 300; ++k) {
      const SurfacePoint w = surface->sample(rng);
      layout.push_back({mesh.point(w), w, r * rng.uniform(0.5, 1.5), 0.0, 0});
    }
    const OverlapReport a = find_overlaps(*surface, layout, s, gap);
    const OverlapReport b = find_overlaps_brute_force(*surface, layout, s, gap);
    EXPECT_EQ(a.pairs, b.pairs);
    EXPECT_EQ(a.boundary, b.boundary);
    EXPECT_EQ(a.worst, b.worst);
    EXPECT_GT(a.pairs, find_overlaps(*surface, layout, s).pairs);  // the gap adds violations

    StencilLayout without = layout, with = layout;
    const Eigen::VectorXd min_scales = Eigen::VectorXd::Constant(300, 0.1 * r);
    resolve_overlaps(*surface, without, s, min_scales);
    EXPECT_TRUE(find_overlaps_brute_force(*surface, without, s, gap).any()) << name;
    resolve_overlaps(*surface, with, s, min_scales, gap);
    EXPECT_FALSE(find_overlaps_brute_force(*surface, with, s, gap).any()) << name;
    // Directly: the material between the enlarged circles.
    double narrowest = INFINITY;
    for (size_t i = 0; i < with.size(); ++i)
      for (size_t j = i + 1; j < with.size(); ++j)
        narrowest = std::min(narrowest, (with[i].position - with[j].position).norm() -
                                            (1 + s) * (with[i].scale + with[j].scale));
    EXPECT_GE(narrowest, gap * (1 - 1e-9)) << name;
    for (const auto& st : with) {
      const auto bp = surface->boundary().nearest_brute_force(st.position, (1 + s) * st.scale + gap);
      if (bp) {
        EXPECT_GE(bp->signed_distance - (1 + s) * st.scale, gap * (1 - 1e-9)) << name;
      }
    }
  }
}

}  // namespace
}  // namespace cutwork
