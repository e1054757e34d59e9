// Loads integrated over selector regions (host/scene/load_regions.h): the region integrals against
// closed forms and a brute-force quadrature twin, and the loads of resolve_load_case against mesh
// refinement, jittered meshes and a matched load case.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Geometry>

#include "host/core/error.h"
#include "host/mesh/surface_mesh.h"
#include "host/scene/load_regions.h"
#include "host/scene/scene.h"

namespace cutwork {
namespace {

using nlohmann::json;
constexpr double kPi = std::numbers::pi;

Selector ball(const Vec3& c, double r) {
  Selector s;
  s.near_point = c;
  s.near_radius = r;
  return s;
}

/// Brute-force twin: the triangle split into n² similar triangles, each counted whole when its
/// centroid is inside the region (error O(1/n) of the region's boundary length).
RegionMoment brute_triangle(const Vec3& a, const Vec3& b, const Vec3& c, const Selector& sel, int n) {
  auto inside = [&](const Vec3& x) {
    for (int k = 0; k < 3; ++k)
      if (!(x[k] > sel.above[k] && x[k] < sel.below[k])) return false;
    return !sel.near_point || !std::isfinite(sel.near_radius) || (x - *sel.near_point).norm() <= sel.near_radius;
  };
  RegionMoment m;
  const double sub_area = 0.5 * (b - a).cross(c - a).norm() / double(n * n);
  auto point = [&](double i, double j) { return Vec3(a + (b - a) * (i / n) + (c - a) * (j / n)); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; i + j < n; ++j) {
      const Vec3 g1 = (point(i, j) + point(i + 1, j) + point(i, j + 1)) / 3.0;
      if (inside(g1)) m.measure += sub_area, m.first_moment += sub_area * g1;
      if (i + j + 2 <= n) {
        const Vec3 g2 = (point(i + 1, j) + point(i, j + 1) + point(i + 1, j + 1)) / 3.0;
        if (inside(g2)) m.measure += sub_area, m.first_moment += sub_area * g2;
      }
    }
  return m;
}

TEST(LoadRegions, DiscInsideATriangleIsTheDisc) {
  // A tilted triangle; the ball's centre sits 0.03 off its plane, so the disc has radius
  // √(0.1² − 0.03²) around the centre's projection.
  const Vec3 a(0, 0, 0), b(2, 0, 1), c(0, 2, 0.5);
  const Vec3 n = (b - a).cross(c - a).normalized();
  const Vec3 o = (a + b + c) / 3.0;
  const RegionMoment m = triangle_in_region(a, b, c, ball(o + 0.03 * n, 0.1));
  const double R2 = 0.1 * 0.1 - 0.03 * 0.03;
  EXPECT_NEAR(m.measure, kPi * R2, 1e-14);
  EXPECT_NEAR((m.first_moment / m.measure - o).norm(), 0, 1e-13);
  // Off the plane by more than the radius: nothing.
  EXPECT_EQ(triangle_in_region(a, b, c, ball(o + 0.11 * n, 0.1)).measure, 0);
}

TEST(LoadRegions, HalfDiscAtAnEdgeHasItsClosedFormCentroid) {
  // Centre on the edge y = 0 of a large triangle: half the disc, centroid 4R/(3π) inside.
  const Vec3 a(-1, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const double R = 0.2;
  const RegionMoment m = triangle_in_region(a, b, c, ball(Vec3(0, 0, 0), R));
  EXPECT_NEAR(m.measure, 0.5 * kPi * R * R, 1e-14);
  const Vec3 g = m.first_moment / m.measure;
  EXPECT_NEAR(g.x(), 0, 1e-14);
  EXPECT_NEAR(g.y(), 4 * R / (3 * kPi), 1e-14);
  // A box that keeps x > 0 leaves the quarter disc.
  Selector q = ball(Vec3(0, 0, 0), R);
  q.above[0] = 0;
  const RegionMoment mq = triangle_in_region(a, b, c, q);
  EXPECT_NEAR(mq.measure, 0.25 * kPi * R * R, 1e-14);
  EXPECT_NEAR(mq.first_moment.x() / mq.measure, 4 * R / (3 * kPi), 1e-14);
}

TEST(LoadRegions, TriangleInsideTheRegionIsWhole) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const RegionMoment m = triangle_in_region(a, b, c, ball(Vec3(0.3, 0.3, 0), 5));
  EXPECT_DOUBLE_EQ(m.measure, 0.5);
  const Vec3 w = triangle_nodal_weights(a, b, c, m);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(w[k], 0.5 / 3, 1e-15);
}

TEST(LoadRegions, RandomTrianglesAgreeWithTheBruteForceTwin) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  auto rv = [&] { return Vec3(u(rng), u(rng), u(rng)); };
  int nonempty = 0, clipped = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const Vec3 a = rv(), b = rv(), c = rv();
    Selector sel;
    for (int k = 0; k < 3; ++k) {
      if (trial % 2) sel.above[k] = 0.6 * u(rng) - 0.3;
      if (trial % 3) sel.below[k] = sel.above[k] > -1 ? sel.above[k] + 0.8 : 0.5 * u(rng);
    }
    if (trial % 4 != 3) sel.near_point = rv() * 0.5, sel.near_radius = 0.3 + 0.5 * std::abs(u(rng));
    const RegionMoment exact = triangle_in_region(a, b, c, sel);
    const RegionMoment brute = brute_triangle(a, b, c, sel, 600);
    const double area = 0.5 * (b - a).cross(c - a).norm();
    SCOPED_TRACE(trial);
    // O(1/n) of the triangle's area, with the boundary of the region crossing it.
    EXPECT_NEAR(exact.measure, brute.measure, 4e-3 * area);
    EXPECT_NEAR((exact.first_moment - brute.first_moment).norm(), 0, 4e-3 * area * 2);
    nonempty += exact.measure > 0;
    clipped += exact.measure > 0 && exact.measure < area * (1 - 1e-9);
    // The nodal weights sum to the measure and reproduce the first moment (N_i is linear).
    const Vec3 w = triangle_nodal_weights(a, b, c, exact);
    EXPECT_NEAR(w.sum(), exact.measure, 1e-14);
    EXPECT_NEAR((w[0] * a + w[1] * b + w[2] * c - exact.first_moment).norm(), 0, 1e-13);
  }
  EXPECT_GT(clipped, 20) << "the trials must cut triangles, not only take or miss them whole";
  EXPECT_GT(nonempty, clipped);
}

TEST(LoadRegions, SegmentsAreClippedExactly) {
  Selector sel = ball(Vec3(0, 0, 0), 1);
  sel.above[0] = 0;
  // The x axis from −2 to 2: inside for 0 < x ≤ 1.
  const RegionMoment m = segment_in_region(Vec3(-2, 0, 0), Vec3(2, 0, 0), sel);
  EXPECT_NEAR(m.measure, 1, 1e-15);
  EXPECT_NEAR(m.first_moment.x(), 0.5, 1e-15);
  const auto w = segment_nodal_weights(Vec3(-2, 0, 0), Vec3(2, 0, 0), m);
  EXPECT_NEAR(w[0] + w[1], 1, 1e-15);
  EXPECT_NEAR(-2 * w[0] + 2 * w[1], 0.5, 1e-15);
  // Parallel to a bound and outside it: nothing; a chord missing the ball: nothing.
  EXPECT_EQ(segment_in_region(Vec3(-1, -2, 0), Vec3(-1, 2, 0), sel).measure, 0);
  EXPECT_EQ(segment_in_region(Vec3(0.5, 2, 0), Vec3(0.5, 2, 1), sel).measure, 0);
}

// ---- loads through resolve_load_case --------------------------------------------------------

/// The unit square [−0.5, 0.5]², n×n cells split into two triangles each, interior vertices moved
/// by up to `jitter` of a cell in the plane (the surface stays the same square).
SurfaceMesh square(int n, double jitter, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  RowMatX3d V((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      double x = double(i) / n - 0.5, y = double(j) / n - 0.5;
      if (i > 0 && i < n) x += u(rng) / n;
      if (j > 0 && j < n) y += u(rng) / n;
      V.row(j * (n + 1) + i) = Vec3(x, y, 0).transpose();
    }
  RowMatX3i F(2 * n * n, 3);
  int f = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int v = j * (n + 1) + i;
      if ((i + j) % 2) {
        F.row(f++) << v, v + 1, v + n + 2;
        F.row(f++) << v, v + n + 2, v + n + 1;
      } else {
        F.row(f++) << v, v + 1, v + n + 1;
        F.row(f++) << v + 1, v + n + 2, v + n + 1;
      }
    }
  return SurfaceMesh(V, F, "square");
}

Scene loaded_square_scene() {
  return parse_scene(json::parse(R"({
    "mesh": {"generator": "sheet"},
    "supports": [{"type": "pinned", "select": {"entity": "boundary_vertices"}}],
    "loads": [
      {"type": "area", "force": [0, 0, -1500], "select": {"entity": "faces", "x": {"above": -0.137}, "y": {"above": 0.0731, "below": 0.4137}}},
      {"type": "point", "force": [3, 0, -20], "select": {"near": {"point": [0.0123, -0.171, 0.01], "radius": 0.0377}}},
      {"type": "pressure", "pressure": 250, "select": {"entity": "faces", "near": {"point": [-0.2, -0.2, 0], "radius": 0.13}}},
      {"type": "edge", "force": [0, 40, 0], "select": {"entity": "boundary_edges", "x": {"above": 0.2113}}}
    ]})"),
                     "test.json");
}

/// Σ F_i and Σ F_i × x_i: the total and the moment of the nodal forces.
std::pair<Vec3, Vec3> total_and_moment(const SurfaceMesh& mesh, const RowMatX3d& forces) {
  Vec3 total = Vec3::Zero(), moment = Vec3::Zero();
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 f = forces.row(v).transpose();
    total += f;
    moment += Vec3(mesh.vertices().row(v).transpose()).cross(f);
  }
  return {total, moment};
}

TEST(LoadRegions, LoadsDoNotDependOnTheMesh) {
  const Scene scene = loaded_square_scene();
  // Closed forms: area 1500 N/m² over 0.637 × 0.3406 m; point 20 N down, 3 N along x; pressure
  // 250 Pa on the disc of radius 0.13 around (−0.2, −0.2), inside the square, along its normal;
  // edge 40 N/m along x ∈ (0.2113, 0.5] of both sides y = ±0.5 and the whole side x = 0.5.
  const double area_load = 1500 * (0.5 + 0.137) * (0.4137 - 0.0731);
  const double pressure_load = 250 * kPi * 0.13 * 0.13;
  const double edge_load = 40 * (2 * (0.5 - 0.2113) + 1.0);
  const SurfaceMesh reference = square(8, 0, 1);
  const LoadCase ref = resolve_load_case(scene, reference);
  const auto [ref_total, ref_moment] = total_and_moment(reference, ref.forces);
  const double normal_sign = reference.face_normals()(0, 2);
  EXPECT_NEAR(ref_total.z(), -area_load - 20 + normal_sign * pressure_load, 1e-9 * area_load);
  EXPECT_NEAR(ref_total.x(), 3, 1e-12);
  EXPECT_NEAR(ref_total.y(), edge_load, 1e-12 * edge_load);
  EXPECT_NEAR(ref.load_measures[0], (0.5 + 0.137) * (0.4137 - 0.0731), 1e-15);
  EXPECT_NEAR(ref.load_measures[1], kPi * (0.0377 * 0.0377 - 0.01 * 0.01), 1e-15);
  for (int n : {3, 5, 13, 32}) {
    for (double jitter : {0.0, 0.2}) {
      SCOPED_TRACE(::testing::Message() << n << " cells, jitter " << jitter);
      const SurfaceMesh mesh = square(n, jitter, unsigned(n));
      ASSERT_GT(mesh.face_normals().col(2).minCoeff(), 0) << "no face turned over: the mesh covers the square once";
      const LoadCase lc = resolve_load_case(scene, mesh);
      const auto [total, moment] = total_and_moment(mesh, lc.forces);
      // Same total and moment to round-off (consistent nodal forces reproduce both exactly).
      EXPECT_NEAR((total - ref_total).norm(), 0, 1e-9 * ref_total.norm());
      EXPECT_NEAR((moment - ref_moment).norm(), 0, 1e-9 * ref_total.norm());
      for (size_t i = 0; i < scene.loads.size(); ++i)
        EXPECT_NEAR(lc.load_measures[i], ref.load_measures[i], 1e-12) << "load " << i;
    }
  }
}

TEST(SupportExtent, LinesAreasAndPointsOfTheFixedVertices) {
  // The unit square [−0.5, 0.5]² in n × n cells.
  for (int n : {4, 9, 20}) {
    SCOPED_TRACE(n);
    const SurfaceMesh mesh = square(n, 0, 1);
    auto fixed_where = [&](auto&& pred) {
      std::vector<bool> f(std::size_t(mesh.num_vertices()), false);
      for (int v = 0; v < mesh.num_vertices(); ++v) f[std::size_t(v)] = pred(Vec3(mesh.vertices().row(v).transpose()));
      return f;
    };
    // The whole boundary: 4 m of line and no area (a corner triangle with all its vertices on the
    // boundary is the line turning the corner).
    const SupportExtent ring =
        support_extent(mesh, fixed_where([](const Vec3& x) { return std::abs(x.x()) > 0.4999 || std::abs(x.y()) > 0.4999; }));
    EXPECT_NEAR(ring.length, 4.0, 1e-12);
    EXPECT_EQ(ring.area, 0.0);
    EXPECT_EQ(ring.points, 0);
    // The strip x < −0.25 (a cell boundary when n is a multiple of 4): 0.25 m² of area less the
    // corner triangles with all three vertices on the boundary (at most two, h²/2 each), and its
    // outline on the square's boundary, 2 × 0.25 + 1 m, as line.
    if (n % 4 == 0) {
      const SupportExtent strip = support_extent(mesh, fixed_where([](const Vec3& x) { return x.x() < -0.2499; }));
      EXPECT_LE(strip.area, 0.25 + 1e-12);
      EXPECT_GE(strip.area, 0.25 - 1.0 / (n * n) - 1e-12);
      EXPECT_NEAR(strip.length, 1.5, 1e-12);
      EXPECT_EQ(strip.points, 0);
    }
    // One vertex: a point.
    const SupportExtent corner = support_extent(mesh, fixed_where([](const Vec3& x) { return x.x() < -0.4999 && x.y() < -0.4999; }));
    EXPECT_EQ(corner.points, 1);
    EXPECT_EQ(corner.length, 0.0);
    EXPECT_EQ(corner.area, 0.0);
  }
  // The comparison: equal extents 0; a corner triangle's h² against a line of 4 m is small; a
  // line 10% longer is 10%.
  const SupportExtent a{0.0, 4.0, 0}, b{0.01 * 0.01 / 2, 4.0, 0}, c{0.0, 4.4, 0};
  EXPECT_EQ(support_extent_change(a, a, 0.01), 0.0);
  EXPECT_LT(support_extent_change(a, b, 0.01), 2e-3);
  EXPECT_NEAR(support_extent_change(a, c, 0.01), 0.4 / 4.4, 1e-15);
  EXPECT_EQ(support_extent_change(SupportExtent{0, 0, 1}, SupportExtent{0, 0, 2}, 0.01), 0.5);
  // A stray point beside a line and an area is about one element of area (the chair's coarsest
  // conforming level: 1 point beside 7.2 m of line and 0.10 m² at 0.02 m): 0.4%, not 100%.
  EXPECT_NEAR(support_extent_change(SupportExtent{0.1031, 7.24, 1}, SupportExtent{0.1036, 7.24, 0}, 0.0204),
              std::abs(0.1031 + 0.0204 * 0.0204 - 0.1036) / (0.0204 * 7.24), 1e-12);
}

// A hole inside an area support: its rim is the area's outline. Without the outer-boundary mask it
// counts as line (what support_extent always did); with it, only the surface's own boundary does,
// so a rim each mesh writes differently (a tool's arcs, chords of L/10 per level) does not read as
// a support that holds something else.
TEST(SupportExtent, TheRimOfAHoleInsideAnAreaSupportIsTheAreasOutline) {
  const int n = 20;
  const SurfaceMesh full = square(n, 0, 1);
  // The strip x < −0.1 with the cells of [−0.4, −0.2] × [−0.1, 0.1] removed (a 0.2 × 0.2 hole).
  std::vector<int> kept;
  for (int f = 0; f < full.num_faces(); ++f) {
    Vec3 c = Vec3::Zero();
    for (int k = 0; k < 3; ++k) c += full.vertices().row(full.faces()(f, k)).transpose() / 3.0;
    if (!(c.x() > -0.4 && c.x() < -0.2 && std::abs(c.y()) < 0.1)) kept.push_back(f);
  }
  RowMatX3i F(Eigen::Index(kept.size()), 3);
  for (size_t k = 0; k < kept.size(); ++k) F.row(Eigen::Index(k)) = full.faces().row(kept[k]);
  const SurfaceMesh mesh(full.vertices(), F, "square with a hole");
  std::vector<bool> fixed(size_t(mesh.num_vertices()), false), outer(size_t(mesh.num_vertices()), false);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 x = mesh.vertices().row(v).transpose();
    fixed[size_t(v)] = x.x() < -0.0999;
    outer[size_t(v)] = std::abs(x.x()) > 0.4999 || std::abs(x.y()) > 0.4999;
  }
  const SupportExtent plain = support_extent(mesh, fixed);
  const SupportExtent masked = support_extent(mesh, fixed, &outer);
  // The strip's area less the hole, 0.4 − 0.04 m², less at most two corner triangles (h²/2 each).
  EXPECT_NEAR(masked.area, 0.36, 1.0 / (n * n) + 1e-12);
  EXPECT_EQ(masked.area, plain.area);
  // Its outline on the square's boundary, 2 × 0.4 + 1 m, as line; the hole's rim, 0.8 m, only
  // without the mask.
  EXPECT_NEAR(masked.length, 1.8, 1e-12);
  EXPECT_NEAR(plain.length, 2.6, 1e-12);
  const std::vector<bool> too_few(3, true);
  EXPECT_THROW(support_extent(mesh, fixed, &too_few), InputError);
}

TEST(LoadRegions, MatchedTotalsCarryTheLoadOverHoles) {
  // The square with a 0.2 × 0.2 hole inside the area load's region, as a cut mesh would have it:
  // the faces of an 10×10 grid whose centroids fall in the hole are removed.
  const Scene scene = loaded_square_scene();
  const SurfaceMesh full = square(10, 0, 1);
  const LoadCase coarse = resolve_load_case(scene, full);
  RowMatX3i kept(full.num_faces(), 3);
  int k = 0;
  for (int f = 0; f < full.num_faces(); ++f) {
    Vec3 g = Vec3::Zero();
    for (int c = 0; c < 3; ++c) g += full.vertices().row(full.faces()(f, c)).transpose() / 3.0;
    if (g.x() > -0.1 && g.x() < 0.1 && g.y() > 0.1 && g.y() < 0.3) continue;
    kept.row(k++) = full.faces().row(f);
  }
  const SurfaceMesh holed(full.vertices(), kept.topRows(k), "holed");
  const LoadCase unmatched = resolve_load_case(scene, holed);
  EXPECT_LT(unmatched.load_measures[0], coarse.load_measures[0] - 0.03);  // the hole's 0.04 m², partly
  const LoadCase matched = resolve_load_case(scene, holed, nullptr, &coarse);
  const Vec3 t_coarse = coarse.forces.colwise().sum().transpose();
  const Vec3 t_matched = matched.forces.colwise().sum().transpose();
  const Vec3 t_unmatched = unmatched.forces.colwise().sum().transpose();
  EXPECT_NEAR((t_matched - t_coarse).norm(), 0, 1e-9 * t_coarse.norm());
  EXPECT_GT((t_unmatched - t_coarse).norm(), 40.0);  // 1500 N/m² on the hole's area is missing
  EXPECT_EQ(matched.load_measures, coarse.load_measures);
  // The patch load (point) is a total on both meshes without matching.
  EXPECT_NEAR(unmatched.load_measures[1], coarse.load_measures[1], 1e-15);
}

// What a model of fill ratios moves onto the material (LoadCase::surface_loads): every load spread
// over the surface, face by face, adding up to its part of `forces`, with its area in each face.
TEST(LoadRegions, SurfaceLoadsHoldEachFacesShare) {
  const Scene scene = loaded_square_scene();
  const SurfaceMesh mesh = square(13, 0.2, 13);
  const LoadCase full = resolve_load_case(scene, mesh);
  // The area load, the point load's patch and the pressure disc; the edge load is on a line.
  ASSERT_EQ(full.surface_loads.size(), 3u);
  const std::size_t load_of[3] = {0, 1, 2};  // their entries in scene.loads
  auto check = [&](const LoadCase& lc) {
    RowMatX3d rest = lc.forces;
    for (std::size_t l = 0; l < lc.surface_loads.size(); ++l) {
      const SurfaceLoad& sl = lc.surface_loads[l];
      ASSERT_EQ(sl.areas.size(), sl.faces.size());
      ASSERT_EQ(sl.nodal.size(), sl.faces.size());
      double area = 0;
      for (std::size_t i = 0; i < sl.faces.size(); ++i) {
        EXPECT_GT(sl.areas[i], 0);
        EXPECT_LE(sl.areas[i], mesh.face_areas()[sl.faces[i]] * (1 + 1e-12));
        area += sl.areas[i];
        for (int k = 0; k < 3; ++k) rest.row(mesh.faces()(sl.faces[i], k)) -= sl.nodal[i][std::size_t(k)].transpose();
      }
      // Its region's area on this mesh (the point load's measure is its patch's area too).
      EXPECT_NEAR(area, full.load_measures[load_of[l]], 1e-12);
    }
    // What is left is the edge load: 40 N/m along y, nothing along x or z.
    EXPECT_LE(rest.col(0).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LE(rest.col(2).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(rest.col(1).sum(), 40 * (2 * (0.5 - 0.2113) + 1.0), 1e-9);
  };
  check(full);
  // Matched to another mesh's totals, the shares are scaled with the forces.
  const LoadCase other = resolve_load_case(scene, square(5, 0, 1));
  LoadCase scaled_measures = other;
  scaled_measures.load_measures[0] *= 0.8;  // as if 20% of the area load's region were holes
  const LoadCase matched = resolve_load_case(scene, mesh, nullptr, &scaled_measures);
  RowMatX3d area_share = RowMatX3d::Zero(mesh.num_vertices(), 3);
  for (std::size_t i = 0; i < matched.surface_loads[0].faces.size(); ++i)
    for (int k = 0; k < 3; ++k)
      area_share.row(mesh.faces()(matched.surface_loads[0].faces[i], k)) += matched.surface_loads[0].nodal[i][std::size_t(k)].transpose();
  EXPECT_NEAR(area_share.col(2).sum(), -1500 * scaled_measures.load_measures[0], 1e-9);
}

TEST(LoadRegions, ARegionWithoutSurfaceIsAnError) {
  json d = json::parse(R"({
    "mesh": {"generator": "sheet", "edge_length": 0.1},
    "supports": [{"type": "pinned", "select": {"entity": "boundary_vertices"}}],
    "loads": [{"type": "point", "force": [0, 0, -1], "select": {"near": {"point": [0, 0, 0.5], "radius": 0.2}}}]})");
  const Scene s = parse_scene(d, "test.json");
  const SceneMeshes m = build_scene_meshes(s);
  try {
    resolve_load_case(s, m.sim);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/loads/0/select: its region holds no surface area"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace cutwork
