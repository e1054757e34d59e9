// Isotropic remeshing of a cut surface: the plate with one circular and one star stencil cut out,
// remeshed to a target edge length. The outlines must stay where the cut put them (every output
// boundary vertex on an input boundary edge), corners stay, the area barely moves, and the
// needles and slivers of the cut are gone.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "host/core/error.h"
#include "host/cut/cut_surface.h"
#include "host/mesh/bvh.h"
#include "host/mesh/isotropic_remesh.h"
#include "host/scene/scene.h"
#include "host/surfaces/generators.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork {
namespace {

struct CutPlate {
  SurfaceMesh plate = generate_shape("plate", {{"width", 0.2}, {"height", 0.1}}, 0.005);
  FaceBvh bvh{plate};
  StencilLibrary shapes;
  AxisTangentField field;
  CutSurface cut;
  CutPlate() {
    shapes.add(make_builtin_stencil("circle", {}, "circle"));
    shapes.add(make_builtin_stencil("star", {}, "star"));
    StencilParams a, b;
    a.position = Vec3(-0.04, 0.003, 0);
    a.scale = 0.025;
    b.position = Vec3(0.045, -0.002, 0);
    b.scale = 0.03;
    b.angle = 0.4;
    b.type = 1;
    const std::vector<StencilParams> stencils{a, b};
    cut = cut_stencils(bvh, shapes, field, stencils);
  }
};

const CutPlate& cut_plate() {
  static const CutPlate c;
  return c;
}

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * d)).norm();
}

double min_angle_degrees(const SurfaceMesh& m) { return min_angle(m) * 180 / std::numbers::pi; }

/// The largest distance of an output boundary vertex from the input's boundary edges.
double outline_drift(const SurfaceMesh& input, const SurfaceMesh& out) {
  std::vector<std::pair<Vec3, Vec3>> border;
  for (int e = 0; e < input.num_edges(); ++e)
    if (input.edge_faces()(e, 1) < 0)
      border.emplace_back(input.vertices().row(input.edges()(e, 0)), input.vertices().row(input.edges()(e, 1)));
  double worst = 0;
  for (int v = 0; v < out.num_vertices(); ++v) {
    if (!out.is_boundary_vertex()[v]) continue;
    double d = INFINITY;
    for (const auto& [a, b] : border) d = std::min(d, distance_to_segment(out.vertices().row(v), a, b));
    worst = std::max(worst, d);
  }
  return worst;
}

TEST(IsotropicRemesh, KeepsOutlinesCornersAndAreaOfACutPlate) {
  const CutPlate& c = cut_plate();
  const SurfaceMesh input(c.cut.vertices, c.cut.faces, "cut plate");
  const double L = 0.004;
  const RemeshedMesh r = remesh_isotropic(c.cut.vertices, c.cut.faces, {L, 5, 30.0});
  const SurfaceMesh out(r.vertices, r.faces, "remeshed");  // valid: no degenerate or non-manifold face
  EXPECT_EQ(out.boundary_loops().size(), 3u);  // the plate's outline and two holes
  EXPECT_EQ(out.num_components(), 1);
  // Every output boundary vertex lies on an input boundary edge (round-off only).
  EXPECT_LT(outline_drift(input, out), 1e-12);
  // The plate's four corners and the star's tips are kept.
  for (const Vec3& corner : {Vec3(-0.1, -0.05, 0), Vec3(0.1, -0.05, 0), Vec3(0.1, 0.05, 0), Vec3(-0.1, 0.05, 0)}) {
    double d = INFINITY;
    for (int v = 0; v < out.num_vertices(); ++v) d = std::min(d, (out.vertices().row(v).transpose() - corner).norm());
    EXPECT_LT(d, 1e-15) << corner.transpose();
  }
  EXPECT_EQ(r.corner_vertices, 4 + 5 + 5);  // the plate's corners, the star's tips and inner corners
  // Area: only the collapsed short boundary edges (< 0.1 L) move the outline. Measured 1.2e-5
  // relative on this plate; bound with a margin of about 2.5.
  const double area_in = input.face_areas().sum(), area_out = out.face_areas().sum();
  EXPECT_LT(std::abs(area_out - area_in) / area_in, 3e-5) << area_in << " " << area_out;
  EXPECT_GT(r.collapsed_boundary_edges, 0);
  // Edge lengths near the target; the cut's needles are gone.
  EXPECT_GT(out.mean_edge_length(), 0.75 * L);
  EXPECT_LT(out.mean_edge_length(), 1.25 * L);  // measured 1.03 L
  const double before = min_angle_degrees(input), after = min_angle_degrees(out);
  EXPECT_GT(after, before);
  // Measured 0.03° before, 1.78° after: the protected outline keeps short segments beside the
  // star's tips (one triangle of 2°, one of 4.5°, all others above 5°).
  EXPECT_GT(after, 1.0) << "before: " << before;
}

double longest_edge(const SurfaceMesh& m, int f) {
  double longest = 0;
  for (int k = 0; k < 3; ++k)
    longest = std::max(longest, (m.vertices().row(m.faces()(f, k)) - m.vertices().row(m.faces()(f, (k + 1) % 3))).norm());
  return longest;
}

/// Two circles of radius 0.02 m 3 mm apart (a ligament of 3 mm at x = 0) and a star, cut from the
/// 0.2 m × 0.1 m plate.
struct LigamentPlate {
  SurfaceMesh plate = generate_shape("plate", {{"width", 0.2}, {"height", 0.1}}, 0.005);
  FaceBvh bvh{plate};
  StencilLibrary shapes;
  AxisTangentField field;
  CutSurface cut;
  Vec3 star_centre{0.07, 0.0, 0};
  LigamentPlate() {
    shapes.add(make_builtin_stencil("circle", {}, "circle"));
    shapes.add(make_builtin_stencil("star", {}, "star"));
    StencilParams a, b, star;
    a.position = Vec3(-0.0215, 0, 0);
    b.position = Vec3(0.0215, 0, 0);
    a.scale = b.scale = 0.02;
    star.position = star_centre;
    star.scale = 0.02;
    star.type = 1;
    const std::vector<StencilParams> stencils{a, b, star};
    cut = cut_stencils(bvh, shapes, field, stencils);
  }
};

// Graded remeshing (isotropic_remesh.h): at L = 8 mm with 3 triangles across and depth 3, the
// 3 mm ligament needs L/8 (3 mm < 3 × 2 mm); the star's tips (an inward turn of the outline) are
// refined on every pass; far from both the mesh keeps L. Then the same at L/2 with feature scale
// 2 (the next level of a verification): the same regions, every size halved.
TEST(IsotropicRemesh, GradedMeshResolvesTheLigamentAndTheTipsAndKeepsLFarAway) {
  const LigamentPlate c;
  const SurfaceMesh input(c.cut.vertices, c.cut.faces, "cut plate");
  const double L = 0.008;
  for (const int level : {0, 1}) {
    const double h = L / (1 << level);
    RemeshOptions ro{h, 5, 30.0};
    ro.grading.depth = 3;
    ro.grading.elements_across = 3;
    ro.grading.feature_scale = double(1 << level);
    const RemeshedMesh r = remesh_isotropic(c.cut.vertices, c.cut.faces, ro);
    const SurfaceMesh out(r.vertices, r.faces, "graded");
    SCOPED_TRACE(level);
    ASSERT_EQ(int(r.graded_faces.size()), ro.grading.depth);  // every pass selected faces
    EXPECT_EQ(out.boundary_loops().size(), 4u);
    EXPECT_LT(outline_drift(input, out), 1e-12);
    EXPECT_LT(std::abs(out.face_areas().sum() - input.face_areas().sum()) / input.face_areas().sum(), 1e-4);
    // The ligament (|x| < 1 mm, |y| < 2 mm): edges near h/8, so about 3 triangles across. CGAL
    // splits edges above 4/3 of the target; its relaxation stretches a few a little beyond
    // (measured: 1.2 h/8 on the ligament, 1.01 × 4/3 h/8 at the tips), hence 1.5. Without the
    // grading both are h. Far from the holes (x < −0.06 m): the mean edge stays near h.
    double ligament = 0, far_sum = 0, tips = 0;
    int ligament_faces = 0, far_edges = 0;
    for (int f = 0; f < out.num_faces(); ++f) {
      Vec3 centroid = Vec3::Zero();
      for (int k = 0; k < 3; ++k) centroid += out.vertices().row(out.faces()(f, k)).transpose() / 3.0;
      if (std::abs(centroid.x()) < 0.001 && std::abs(centroid.y()) < 0.002) {
        ligament = std::max(ligament, longest_edge(out, f));
        ++ligament_faces;
      }
      if (centroid.x() < -0.06) {
        for (int k = 0; k < 3; ++k)
          far_sum += (out.vertices().row(out.faces()(f, k)) - out.vertices().row(out.faces()(f, (k + 1) % 3))).norm();
        far_edges += 3;
      }
      // Faces at one of the star's tips (the boundary vertices farthest from its centre).
      for (int k = 0; k < 3; ++k) {
        const Vec3 p = out.vertices().row(out.faces()(f, k));
        if (out.is_boundary_vertex()[out.faces()(f, k)] && std::abs((p - c.star_centre).norm() - 0.02) < 1e-4)
          tips = std::max(tips, longest_edge(out, f));
      }
    }
    EXPECT_GT(ligament_faces, 3);
    EXPECT_LT(ligament, 1.5 * h / 8) << "ligament faces: " << ligament_faces;
    EXPECT_GT(far_sum / far_edges, 0.75 * h);
    EXPECT_LT(far_sum / far_edges, 1.25 * h);
    EXPECT_GT(tips, 0);
    EXPECT_LT(tips, 1.5 * h / 8);
    // Graded: far fewer triangles than the uniform mesh at the finest size (measured 15 and 26
    // times fewer).
    const RemeshedMesh fine = remesh_isotropic(c.cut.vertices, c.cut.faces, {h / 8, 5, 30.0});
    EXPECT_LT(8 * r.faces.rows(), fine.faces.rows()) << r.faces.rows() << " vs " << fine.faces.rows();
    // No slivers beyond what the outline's own short segments force (star tips: see above).
    EXPECT_GT(min_angle_degrees(out), 1.0);
    std::printf("level %d: %d graded triangles (passes %d, %d, %d), uniform at h/8 %d; ligament %.3g mm, far mean edge "
                "%.3g h, min angle %.3g deg\n",
                level, int(r.faces.rows()), r.graded_faces.size() > 0 ? r.graded_faces[0] : 0, r.graded_faces.size() > 1 ? r.graded_faces[1] : 0, r.graded_faces.size() > 2 ? r.graded_faces[2] : 0,
                int(fine.faces.rows()), 1e3 * ligament, far_sum / far_edges / h, min_angle_degrees(out));
  }
}

// Focus (the verification's peak zoom): about a point on the circle's rim, two more halvings within
// R = 4 mm: the rim there gets L/2^(depth + 2), the ball's inside is at most that size over 4/3,
// sizes change gradually, and away from the widest ball the mesh is the one without focus.
TEST(IsotropicRemesh, FocusRefinesABallAndLeavesTheRestAsItWas) {
  const CutPlate& c = cut_plate();
  const SurfaceMesh input(c.cut.vertices, c.cut.faces, "cut plate");
  const double L = 0.004;
  RemeshOptions ro{L, 5, 30.0};
  ro.grading.depth = 1;
  const RemeshedMesh plain = remesh_isotropic(c.cut.vertices, c.cut.faces, ro);
  const Vec3 centre(-0.04 + 0.025, 0.003, 0);  // the circle's rim at +x
  const double R = 0.004;
  ro.grading.focus = {centre};
  ro.grading.focus_radius = R;
  ro.grading.focus_depth = 2;
  const RemeshedMesh focused = remesh_isotropic(c.cut.vertices, c.cut.faces, ro);
  const SurfaceMesh a(plain.vertices, plain.faces, "plain"), b(focused.vertices, focused.faces, "focused");
  EXPECT_EQ(focused.focused_faces.size(), 3u);  // passes to L/2, L/4, L/8 each selected faces
  EXPECT_LT(outline_drift(input, b), 1e-12);
  EXPECT_LT(std::abs(b.face_areas().sum() - input.face_areas().sum()) / input.face_areas().sum(), 1e-4);
  auto centroid = [](const SurfaceMesh& m, int f) {
    Vec3 x = Vec3::Zero();
    for (int k = 0; k < 3; ++k) x += m.vertices().row(m.faces()(f, k)).transpose() / 3.0;
    return x;
  };
  // Inside R: every edge near L/8 (CGAL splits above 4/3 of the target; relaxation stretches a
  // few a little beyond, as in the graded test above).
  const double target = L / 8;
  double inside = 0;
  int inside_faces = 0;
  for (int f = 0; f < b.num_faces(); ++f)
    if ((centroid(b, f) - centre).norm() < R) {
      inside = std::max(inside, longest_edge(b, f));
      ++inside_faces;
    }
  EXPECT_GT(inside_faces, 50);
  EXPECT_LT(inside, 1.5 * target);
  // The widest ball is R (1 + (depth + focus_depth − 1)/2) = 2R; beyond it plus two rings of L the
  // faces are those of the plain mesh (same centroids).
  std::vector<Vec3> far_a, far_b;
  const double reach = 2 * R + 3 * L;
  for (int f = 0; f < a.num_faces(); ++f)
    if ((centroid(a, f) - centre).norm() > reach) far_a.push_back(centroid(a, f));
  for (int f = 0; f < b.num_faces(); ++f)
    if ((centroid(b, f) - centre).norm() > reach) far_b.push_back(centroid(b, f));
  ASSERT_EQ(far_a.size(), far_b.size());
  auto less = [](const Vec3& p, const Vec3& q) { return std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3); };
  std::sort(far_a.begin(), far_a.end(), less);
  std::sort(far_b.begin(), far_b.end(), less);
  double moved = 0;
  for (std::size_t i = 0; i < far_a.size(); ++i) moved = std::max(moved, (far_a[i] - far_b[i]).norm());
  EXPECT_LT(moved, 1e-12);
  // Gradual: no sliver from the transitions, where the focus remeshed (within the reach).
  auto smallest_within_reach = [&](const SurfaceMesh& m) {
    double smallest = 180;
    for (int f = 0; f < m.num_faces(); ++f) {
      if ((centroid(m, f) - centre).norm() > reach) continue;
      for (int k = 0; k < 3; ++k) {
        const Vec3 p = m.vertices().row(m.faces()(f, k)), q = m.vertices().row(m.faces()(f, (k + 1) % 3)),
                   r = m.vertices().row(m.faces()(f, (k + 2) % 3));
        smallest = std::min(smallest, std::acos(std::clamp((q - p).normalized().dot((r - p).normalized()), -1.0, 1.0)) *
                                          180 / std::numbers::pi);
      }
    }
    return smallest;
  };
  const double smallest = smallest_within_reach(b), smallest_plain = smallest_within_reach(a);
  EXPECT_GT(smallest, 0.8 * smallest_plain);
  std::printf("focus: %d triangles (plain %d), %d inside R, longest there %.3g L/8, smallest angle within the reach "
              "%.3g deg (plain %.3g)\n",
              int(b.num_faces()), int(a.num_faces()), inside_faces, inside / target, smallest, smallest_plain);
  // A focus without a radius is refused.
  ro.grading.focus_radius = 0;
  EXPECT_THROW(remesh_isotropic(c.cut.vertices, c.cut.faces, ro), InputError);
}

// refine_about (the peak zoom's submodel): the focus passes alone on a remeshed mesh, some faces
// frozen. About the circle's rim, a ball of 12 mm, one grading halving and two focus halvings: the
// frozen faces (centroids beyond 20 mm) come out bit for bit, the rim within the ball gets L/8, and
// the last pass refines only within its band (8 × L/8 = 4 mm) of the outline, so faces in the ball
// 7 mm and more from the rim stay at L/4.
TEST(IsotropicRemesh, RefineAboutKeepsFrozenFacesAndRefinesAlongTheRim) {
  const CutPlate& c = cut_plate();
  const double L = 0.004;
  RemeshOptions ro{L, 5, 30.0};
  ro.grading.depth = 1;
  const RemeshedMesh plain = remesh_isotropic(c.cut.vertices, c.cut.faces, ro);
  const SurfaceMesh a(plain.vertices, plain.faces, "plain");
  const Vec3 hole(-0.04, 0.003, 0), centre = hole + Vec3(0.025, 0, 0);
  auto centroid = [](const SurfaceMesh& m, int f) {
    Vec3 x = Vec3::Zero();
    for (int k = 0; k < 3; ++k) x += m.vertices().row(m.faces()(f, k)).transpose() / 3.0;
    return x;
  };
  std::vector<bool> frozen(size_t(a.num_faces()));
  std::set<std::array<double, 9>> frozen_faces;
  for (int f = 0; f < a.num_faces(); ++f) {
    frozen[size_t(f)] = (centroid(a, f) - centre).norm() > 0.02;
    if (!frozen[size_t(f)]) continue;
    std::array<double, 9> key;
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) key[size_t(3 * k + d)] = a.vertices()(a.faces()(f, k), d);
    frozen_faces.insert(key);
  }
  ro.grading.focus = {centre};
  ro.grading.focus_radius = 0.012;
  ro.grading.focus_depth = 2;
  const RemeshedMesh r = refine_about(plain.vertices, plain.faces, frozen, c.cut.vertices, c.cut.faces, ro);
  const SurfaceMesh b(r.vertices, r.faces, "refined");
  EXPECT_GT(b.num_faces(), a.num_faces());
  std::size_t kept = 0;
  for (int f = 0; f < b.num_faces(); ++f) {
    std::array<double, 9> key;
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) key[size_t(3 * k + d)] = b.vertices()(b.faces()(f, k), d);
    kept += frozen_faces.count(key);
  }
  EXPECT_EQ(kept, frozen_faces.size());
  double rim = 0, off_rim = 1;
  for (int f = 0; f < b.num_faces(); ++f) {
    const Vec3 x = centroid(b, f);
    if ((x - centre).norm() > 0.008) continue;
    const double from_rim = std::abs((x - hole).norm() - 0.025);
    if (from_rim < 0.001) rim = std::max(rim, longest_edge(b, f));
    if (from_rim > 0.007) off_rim = std::min(off_rim, longest_edge(b, f));
  }
  EXPECT_LT(rim, 1.5 * L / 8);
  EXPECT_GT(off_rim, 1.5 * L / 8);
  EXPECT_LT(outline_drift(SurfaceMesh(c.cut.vertices, c.cut.faces, "cut"), b), 1e-12);
  std::printf("refine_about: %d triangles (from %d), %zu frozen kept; longest edge at the rim %.3g L/8, shortest "
              "7 mm off it %.3g L/8\n",
              b.num_faces(), a.num_faces(), kept, rim / (L / 8), off_rim / (L / 8));
  // One flag per face.
  frozen.pop_back();
  EXPECT_THROW(refine_about(plain.vertices, plain.faces, frozen, c.cut.vertices, c.cut.faces, ro), InputError);
}

TEST(IsotropicRemesh, FeatureLinesAreKeptThroughTheRemeshAndTheGrading) {
  // The cut plate clamped over x < −0.07 (an area support, as the chair's runner on the floor): the
  // outline of the clamped area is a jagged line of input edges (support_outline_edges). Kept as
  // feature lines, every output mesh — uniform and graded, coarse and fine — has edges along all
  // of it, so the clamped region is the same on each; without them the remeshing cuts across it.
  const CutPlate& c = cut_plate();
  const SurfaceMesh input(c.cut.vertices, c.cut.faces, "cut plate");
  std::vector<bool> fixed(size_t(input.num_vertices()), false);
  for (int v = 0; v < input.num_vertices(); ++v) fixed[size_t(v)] = input.vertices()(v, 0) < -0.07;
  const std::vector<int> outline = support_outline_edges(input, fixed);
  ASSERT_GT(outline.size(), 3u);
  std::vector<std::array<int, 2>> pairs;
  std::vector<std::pair<Vec3, Vec3>> segments;
  double length = 0;
  for (int e : outline) {
    const int a = input.edges()(e, 0), b = input.edges()(e, 1);
    pairs.push_back({a, b});
    segments.emplace_back(input.vertices().row(a), input.vertices().row(b));
    length += (input.vertices().row(a) - input.vertices().row(b)).norm();
  }
  // The output edges whose ends both lie on one segment of the line, and their length.
  auto along = [&](const SurfaceMesh& out, int& count) {
    double sum = 0;
    count = 0;
    for (int e = 0; e < out.num_edges(); ++e) {
      const Vec3 p = out.vertices().row(out.edges()(e, 0)), q = out.vertices().row(out.edges()(e, 1));
      for (const auto& [a, b] : segments)
        if (distance_to_segment(p, a, b) < 1e-12 && distance_to_segment(q, a, b) < 1e-12) {
          sum += (p - q).norm();
          ++count;
          break;
        }
    }
    return sum;
  };
  for (const int depth : {0, 2})
    for (const double L : {0.01, 0.005}) {
      SCOPED_TRACE(::testing::Message() << "depth " << depth << ", L " << L);
      RemeshOptions ro{L, 5, 30.0};
      ro.grading.depth = depth;
      ro.feature_edges = pairs;
      const RemeshedMesh r = remesh_isotropic(c.cut.vertices, c.cut.faces, ro);
      const SurfaceMesh out(r.vertices, r.faces, "with features");
      int count = 0;
      EXPECT_NEAR(along(out, count), length, 1e-9 * length);
      EXPECT_EQ(count, r.feature_edges);
      EXPECT_LT(outline_drift(input, out), 1e-12);
      ro.feature_edges.clear();
      const RemeshedMesh plain = remesh_isotropic(c.cut.vertices, c.cut.faces, ro);
      EXPECT_EQ(plain.feature_edges, 0);
      EXPECT_LT(along(SurfaceMesh(plain.vertices, plain.faces, "without"), count), 0.9 * length);
    }
  // A pair that is no interior edge: a boundary edge, two vertices far apart.
  RemeshOptions bad{0.01, 5, 30.0};
  for (int e = 0; e < input.num_edges(); ++e)
    if (input.edge_faces()(e, 1) < 0) {
      bad.feature_edges = {{input.edges()(e, 0), input.edges()(e, 1)}};
      break;
    }
  EXPECT_THROW(remesh_isotropic(c.cut.vertices, c.cut.faces, bad), InputError);
  bad.feature_edges = {{pairs.front()[0], pairs.back()[1] == pairs.front()[0] ? pairs.back()[0] : pairs.back()[1]}};
  EXPECT_THROW(remesh_isotropic(c.cut.vertices, c.cut.faces, bad), InputError);
}

// Step 1b: the chair's mesh at 5 mm remeshed at 20.4 mm, the level that failed verify with a
// zero-area face: the straight sides keep their 5 mm edges under 20 mm triangles, and a triangle
// spanning two collinear side edges has no area. With coarsen_straight_runs the sides' runs are
// coarsened to edges of at most L first, the outline and its corners kept exactly.
TEST(IsotropicRemesh, StraightRunsAreCoarsenedToTheLevel) {
  const SurfaceMesh input = generate_shape("chair", {}, 0.005);
  RemeshOptions o;
  o.target_edge_length = 0.0204;
  const RemeshedMesh plain = remesh_isotropic(input.vertices(), input.faces(), o);
  EXPECT_THROW(SurfaceMesh(plain.vertices, plain.faces, "plain"), InputError);
  o.coarsen_straight_runs = true;
  const RemeshedMesh r = remesh_isotropic(input.vertices(), input.faces(), o);
  EXPECT_EQ(plain.merged_line_vertices, 0);
  EXPECT_GT(r.merged_line_vertices, 0);
  const SurfaceMesh out(r.vertices, r.faces, "coarsened");  // valid: no zero-area face
  EXPECT_LT(outline_drift(input, out), 1e-12);
  // Measured 7.0e-4 relative: step 1 collapses the short side edges where the fillets' rows are close.
  EXPECT_NEAR(out.face_areas().sum(), input.face_areas().sum(), 1.5e-3 * input.face_areas().sum());
  EXPECT_EQ(r.corner_vertices, plain.corner_vertices);
  std::printf("%d vertices merged, %d corners; min angle %.1f deg; area %.6g of %.6g\n", r.merged_line_vertices,
              r.corner_vertices, min_angle_degrees(out), out.face_areas().sum(), input.face_areas().sum());
  EXPECT_GT(min_angle_degrees(out), 1.0);
}

TEST(IsotropicRemesh, RejectsABadTargetLength) {
  const CutPlate& c = cut_plate();
  for (const double L : std::vector<double>{0.0, -1.0, NAN, INFINITY})
    EXPECT_THROW(remesh_isotropic(c.cut.vertices, c.cut.faces, {L, 5, 30.0}), InputError) << L;
}

}  // namespace
}  // namespace cutwork
