// The conforming verification's pieces on two small scenes: supports "on the boundary" of the
// sheet land on its outer boundary only (not on the rim of the hole cut into it), and the
// perforated cantilever's point load keeps its total on the conforming mesh; every conforming face
// maps onto a coarse face, and the comparison runs over the material only.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "host/core/error.h"
#include "host/cut/cut_surface.h"
#include "host/mesh/isotropic_remesh.h"
#include "host/mesh/mesh_mapping.h"
#include "host/pattern/stencils_json.h"
#include "host/scene/scene.h"
#include "tests/support/test_support.h"
#include "solvers/conforming/conforming_verification.h"
#include "solvers/conforming/richardson.h"

namespace cutwork::solvers {
namespace {

Scene scene_at(const char* name, double edge_length, double sim_edge_length) {
  nlohmann::json doc = builtin_scene_json(name);
  doc["mesh"]["edge_length"] = edge_length;
  doc["mesh"]["sim_edge_length"] = sim_edge_length;
  return parse_scene(doc, std::string("test:") + name);
}

StencilParams circle_at(double x, double y, double radius) {
  StencilParams s;
  s.position = Vec3(x, y, 0);
  s.scale = radius;
  return s;
}

TEST(ConformingVerification, BoundarySupportsStayOffTheRimsOfHoles) {
  const Scene scene = scene_at("sheet", 0.05, 0.1);
  const SceneMeshes meshes = build_scene_meshes(scene);
  const PatternContext ctx(scene, meshes);
  const std::vector<StencilParams> stencils{circle_at(0.1, -0.05, 0.2)};
  const CutSurface cut = cut_stencils(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), stencils);
  const RemeshedMesh r = remesh_isotropic(cut.vertices, cut.faces, {0.04, 5, 30.0});
  const SurfaceMesh mesh(r.vertices, r.faces, "conforming sheet");
  ASSERT_EQ(mesh.boundary_loops().size(), 2u);
  const std::vector<bool> outer = boundary_vertices_on_boundary_of(mesh, meshes.base, 1e-9);
  const LoadCase lc = resolve_load_case(scene, mesh, &outer);
  int fixed = 0, rim = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 p = mesh.vertices().row(v);
    const bool on_rim = std::abs((p - stencils[0].position).norm() - 0.2) < 1e-3;
    const bool on_outline = std::abs(std::abs(p.x()) - 0.5) < 1e-12 || std::abs(std::abs(p.y()) - 0.5) < 1e-12;
    EXPECT_EQ(bool(lc.fixed[v]), on_outline) << p.transpose();
    fixed += lc.fixed[v];
    rim += on_rim && mesh.is_boundary_vertex()[v];
  }
  EXPECT_GT(rim, 20);
  EXPECT_GT(fixed, 40);
  // Without the mask the rim would be pinned too (what boundary_vertices means on the raw mesh).
  const LoadCase raw = resolve_load_case(scene, mesh);
  int raw_fixed = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) raw_fixed += raw.fixed[v];
  EXPECT_EQ(raw_fixed, fixed + rim);
}

TEST(ConformingVerification, PerforatedCantileverKeepsItsLoadAndMapsEveryFace) {
  const Scene scene = scene_at("plate", 0.01, 0.02);
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  const PatternContext ctx(scene, meshes);
  const std::vector<StencilParams> stencils{circle_at(-0.05, 0, 0.02), circle_at(0, 0, 0.02),
                                           circle_at(0.05, 0, 0.02)};
  ConformingOptions o;
  o.edge_length = 0.005;
  const ConformingVerification v = verify_conforming(scene, meshes, lc, ctx, stencils, o);
  ASSERT_EQ(v.levels.size(), 1u);
  // 1 N downwards on both meshes (a point load: a total over the selected vertices).
  EXPECT_NEAR(v.coarse.load_total.z(), -1.0, 1e-12);
  EXPECT_NEAR(v.levels[0].load_total.z(), -1.0, 1e-12);
  // Every conforming face lands on a coarse face; the faces inside the holes are not compared.
  ASSERT_EQ(v.conforming_to_coarse.size(), v.conforming_mesh.num_faces());
  EXPECT_GE(v.conforming_to_coarse.minCoeff(), 0);
  EXPECT_LT(v.conforming_to_coarse.maxCoeff(), meshes.sim.num_faces());
  int compared = 0;
  for (int t = 0; t < meshes.sim.num_faces(); ++t) {
    if (!v.compared[size_t(t)]) continue;
    ++compared;
    EXPECT_GT(v.alpha[t], kMaterialFillRatio);
    EXPECT_TRUE(std::isfinite(v.W_on_coarse[t]));
  }
  EXPECT_EQ(compared, v.compared_faces);
  EXPECT_LT(compared, meshes.sim.num_faces());
  // The material areas agree: the cut and the fill ratios measure the same area, and remeshing
  // keeps the outline (host/mesh/isotropic_remesh.h). Measured 1 + 9.6e-6 (the α = 1e-4 filler of
  // the holes, 3 × 1.26e-3 m² × 1e-4 / 0.0162 m² ≈ 2.3e-5, less the short-edge collapses); the
  // bound leaves a margin of about 3.
  EXPECT_NEAR(v.coarse.material_area / v.levels[0].material_area, 1.0, 3e-5);
  EXPECT_TRUE(std::isfinite(v.compliance_ratio));
}

TEST(ConformingVerification, RejectsBadOptions) {
  const Scene scene = scene_at("plate", 0.01, 0.02);
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  const PatternContext ctx(scene, meshes);
  ConformingOptions o;
  EXPECT_THROW(verify_conforming(scene, meshes, lc, ctx, {}, o), InputError);  // no edge length
  o.edge_length = 0.01;
  o.levels = 0;
  EXPECT_THROW(verify_conforming(scene, meshes, lc, ctx, {}, o), InputError);
  o.levels = 1;
  for (const int depth : {-1, 5}) {
    o.grading_depth = depth;
    EXPECT_THROW(verify_conforming(scene, meshes, lc, ctx, {}, o), InputError) << depth;
  }
  o.grading_depth = 1;
  for (const double across : {0.5, 17.0, double(NAN)}) {
    o.elements_across = across;
    EXPECT_THROW(verify_conforming(scene, meshes, lc, ctx, {}, o), InputError) << across;
  }
}

TEST(ConformingVerification, RichardsonRecoversTheLimitAndTheOrder) {
  // C(L) = C∞ + a L^p at L = 1, 1/2, 1/4: the limit and p back to round-off.
  for (double p : {1.0, 1.5, 2.0}) {
    ConformingVerification v;
    for (int k = 0; k < 3; ++k) {
      RunQuantities q;
      q.compliance = 3.0 - 0.7 * std::pow(0.5, k * p);
      v.levels.push_back(q);
    }
    extrapolate_compliance(v);
    EXPECT_NEAR(v.observed_order, p, 1e-12);
    EXPECT_NEAR(v.extrapolated_compliance, 3.0, 1e-12);
    EXPECT_NEAR(v.compliance_error_bar, 0.7 * std::pow(0.25, p), 1e-12);
  }
  // Two levels: first order assumed (the slow end), the last difference as the error bar.
  ConformingVerification two;
  two.levels.resize(2);
  two.levels[0].compliance = 1.0, two.levels[1].compliance = 1.1;
  extrapolate_compliance(two);
  EXPECT_TRUE(std::isnan(two.observed_order));
  EXPECT_NEAR(two.extrapolated_compliance, 1.2, 1e-15);
  EXPECT_NEAR(two.compliance_error_bar, 0.1, 1e-15);
  // Differences that change sign: no extrapolation, the larger difference as the error bar.
  ConformingVerification osc;
  osc.levels.resize(3);
  osc.levels[0].compliance = 1.0, osc.levels[1].compliance = 1.1, osc.levels[2].compliance = 1.05;
  extrapolate_compliance(osc);
  EXPECT_TRUE(std::isnan(osc.observed_order));
  EXPECT_EQ(osc.extrapolated_compliance, 1.05);
  EXPECT_NEAR(osc.compliance_error_bar, 0.1, 1e-15);
}

TEST(ConformingVerification, RefinementStopsAtTheToleranceAndTheErrorBarBracketsAFinerRun) {
  // The sheet under self-weight with one hole of radius 0.2: four conforming levels from L = 0.08.
  const Scene scene = scene_at("sheet", 0.05, 0.1);
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  const PatternContext ctx(scene, meshes);
  const std::vector<StencilParams> stencils{circle_at(0.1, -0.05, 0.2)};
  ConformingOptions o;
  o.edge_length = 0.08;
  o.levels = 4;
  const ConformingVerification all = verify_conforming(scene, meshes, lc, ctx, stencils, o);
  ASSERT_EQ(all.levels.size(), 4u);
  EXPECT_EQ(all.stop, "levels");
  // The conforming peak is the recovered rim peak; its convergence is the last two levels' peaks,
  // and the flag follows it.
  for (const RunQuantities& q : all.levels) {
    EXPECT_GT(q.rim_points, 0);
    ASSERT_TRUE(std::isfinite(q.rim_peak));
    ASSERT_TRUE(std::isfinite(q.interior_peak));
    EXPECT_EQ(q.peak, q.rim_peak);
  }
  {
    const std::vector<double> peaks{all.levels[0].peak, all.levels[1].peak, all.levels[2].peak, all.levels[3].peak};
    const Richardson r = richardson_extrapolate(peaks);
    EXPECT_EQ(all.peak_extrapolated, r.extrapolated);
    EXPECT_EQ(all.peak_error_bar, r.error_bar);
    EXPECT_DOUBLE_EQ(all.W_peak_ratio_extrapolated, all.coarse.W_peak_max / r.extrapolated);
  }
  const double peak_change = std::abs(all.levels[3].peak - all.levels[2].peak) / all.levels[3].peak;
  EXPECT_DOUBLE_EQ(all.peak_change, peak_change);
  EXPECT_EQ(all.peak_converged, peak_change <= kPeakTolerance);
  std::cout << fmt::format("peaks {:.4g} {:.4g} {:.4g} {:.4g} (rim {:.4g} {:.4g} {:.4g} {:.4g}; faces W_max {:.4g} {:.4g} "
                           "{:.4g} {:.4g})\n",
                           all.levels[0].peak, all.levels[1].peak, all.levels[2].peak, all.levels[3].peak,
                           all.levels[0].rim_peak, all.levels[1].rim_peak, all.levels[2].rim_peak,
                           all.levels[3].rim_peak, all.levels[0].W_max, all.levels[1].W_max, all.levels[2].W_max,
                           all.levels[3].W_max);
  // Extrapolating from the first three levels: the fourth lies within the error bar.
  ConformingVerification three;
  three.levels.assign(all.levels.begin(), all.levels.begin() + 3);
  extrapolate_compliance(three);
  ASSERT_TRUE(std::isfinite(three.compliance_error_bar));
  EXPECT_LE(std::abs(all.levels[3].compliance - three.extrapolated_compliance), three.compliance_error_bar)
      << all.levels[2].compliance << " -> " << three.extrapolated_compliance << " ± " << three.compliance_error_bar
      << ", finer " << all.levels[3].compliance;
  // With a tolerance the loop stops at the first level that changes by less, and says so.
  const double change_2 = std::abs(all.levels[2].compliance - all.levels[1].compliance) / all.levels[2].compliance;
  o.tolerance = 1.01 * change_2;
  const ConformingVerification stopped = verify_conforming(scene, meshes, lc, ctx, stencils, o);
  EXPECT_TRUE(stopped.converged);
  EXPECT_EQ(stopped.stop, "tolerance");
  EXPECT_LE(stopped.levels.size(), 3u);
  EXPECT_LT(stopped.last_change, o.tolerance);
  // A face budget below the next level's stops before it.
  o.tolerance = 0;
  o.max_faces = all.levels[2].faces - 1;
  const ConformingVerification budget = verify_conforming(scene, meshes, lc, ctx, stencils, o);
  EXPECT_EQ(budget.levels.size(), 2u);
  EXPECT_EQ(budget.stop, "budget");
  EXPECT_FALSE(budget.converged);
  // One level: nothing to say about the peak's convergence.
  o.levels = 1;
  const ConformingVerification one = verify_conforming(scene, meshes, lc, ctx, stencils, o);
  EXPECT_TRUE(std::isnan(one.peak_change));
  EXPECT_FALSE(one.peak_converged);
}

// Grading (isotropic_remesh.h): the plate clamped on one short side and loaded at the other,
// cut across its width by three holes of radius 15 mm with 2.5 mm ligaments between them and to
// the edges, so the whole bending moment passes through the ligaments. Uniform triangles of
// L = 8 mm span a ligament with a third of one. Reference: one uniform solve at L/8 = 1 mm (2.5
// triangles across). Measured, compliance against the reference:
//   uniform  726 / 2196 / 8748 triangles: +31.3%, +19.3%, +0.07%  (changes 10%, 19%: not converged)
//   graded  1004 / 3616 / 13638 triangles: +12.2%, +0.01%, -0.16% (converged at the third level:
//   its ligaments are 0.5 mm, finer than the reference's)
TEST(ConformingVerification, GradedLevelsResolveTheLigamentsAndConvergeWhereUniformOnesDoNot) {
  const Scene scene = scene_at("plate", 0.01, 0.02);
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  const PatternContext ctx(scene, meshes);
  const std::vector<StencilParams> stencils{circle_at(0, -0.0325, 0.015), circle_at(0, 0, 0.015),
                                           circle_at(0, 0.0325, 0.015)};
  const double L = 0.008;
  ConformingOptions o;
  o.edge_length = L / 8;
  const double reference = verify_conforming(scene, meshes, lc, ctx, stencils, o).levels[0].compliance;
  o.edge_length = L;
  o.levels = 3;
  o.tolerance = 0.01;
  const ConformingVerification uniform = verify_conforming(scene, meshes, lc, ctx, stencils, o);
  o.grading_depth = 2;
  const ConformingVerification graded = verify_conforming(scene, meshes, lc, ctx, stencils, o);
  ASSERT_EQ(uniform.levels.size(), 3u);
  ASSERT_EQ(graded.levels.size(), 3u);
  auto error = [&](const RunQuantities& q) { return q.compliance / reference - 1; };
  for (size_t k = 0; k < 3; ++k)
    RecordProperty(fmt::format("level{}", k),
                   fmt::format("uniform {} triangles {:+.2f}%, graded {} triangles {:+.2f}%", uniform.levels[k].faces,
                               100 * error(uniform.levels[k]), graded.levels[k].faces, 100 * error(graded.levels[k])));
  EXPECT_FALSE(uniform.converged);
  EXPECT_EQ(uniform.stop, "levels");
  EXPECT_TRUE(graded.converged);
  EXPECT_EQ(graded.stop, "tolerance");
  // Closer on the coarse levels, by far on the second.
  EXPECT_LT(std::abs(error(graded.levels[0])), 0.5 * std::abs(error(uniform.levels[0])));
  EXPECT_LT(std::abs(error(graded.levels[1])), 0.01);
  EXPECT_GT(std::abs(error(uniform.levels[1])), 0.1);
  // The graded answer and the independent reference agree within 0.5% (and the error bar is honest
  // about the reference's own 1 mm resolution: within the bar plus the last change).
  EXPECT_LT(std::abs(error(graded.levels[2])), 0.005);
  EXPECT_LT(std::abs(graded.extrapolated_compliance - reference),
            graded.compliance_error_bar + graded.last_change * reference);
  // Slivers: triangles with an angle below 10° measured 1.3%, 0, 0 over the graded levels (the
  // smallest angle 4.3°, 10.5°, 17.7°) against 3.4%, 0.5%, 0.05% uniform (4.3°, 5.2°, 8.3°).
  for (size_t k = 0; k < 3; ++k) EXPECT_LE(graded.levels[k].slivers, uniform.levels[k].slivers) << k;
  EXPECT_EQ(graded.levels[2].slivers, 0.0);
  EXPECT_GT(graded.levels[2].min_angle, 15.0);
  // The levels are one family: every size halves, so the triangles grow about fourfold (less
  // where the outline's own segments are the size).
  for (size_t k = 1; k < 3; ++k) {
    const double growth = double(graded.levels[k].faces) / graded.levels[k - 1].faces;
    EXPECT_GT(growth, 2.5) << k;
    EXPECT_LT(growth, 4.5) << k;
  }
}

TEST(ConformingVerification, PiecesCutLooseAreLeftOutAndSaid) {
  // Eight overlapping circles on a ring of radius 0.2 cut a disc loose from the sheet: it has no
  // support (the sheet is pinned on its outer boundary), so it falls out of the printed part.
  // Solved with it, the conforming stiffness is singular.
  const Scene scene = scene_at("sheet", 0.05, 0.1);
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  const PatternContext ctx(scene, meshes);
  std::vector<StencilParams> stencils;
  for (int k = 0; k < 8; ++k) {
    const double a = 2 * std::numbers::pi * k / 8;
    stencils.push_back(circle_at(0.2 * std::cos(a), 0.2 * std::sin(a), 0.1));
  }
  ConformingOptions o;
  o.edge_length = 0.04;
  const ConformingVerification v = verify_conforming(scene, meshes, lc, ctx, stencils, o);
  ASSERT_EQ(v.levels.size(), 1u);
  EXPECT_EQ(v.conforming_mesh.num_components(), 1);
  bool said = false;
  for (const std::string& n : v.notes) said = said || n.find("cut 1 piece(s) loose") != std::string::npos;
  EXPECT_TRUE(said);
  // Only the outer part is left: nothing within 0.1 of the centre.
  for (int i = 0; i < v.conforming_mesh.num_vertices(); ++i)
    EXPECT_GT(v.conforming_mesh.vertices().row(i).norm(), 0.1) << i;
  EXPECT_TRUE(std::isfinite(v.compliance_ratio));
}

TEST(ConformingVerification, TheChairDesignRemeshesWithoutFlatFaces) {
  // The default chair design (tests/data/designs/chair_stencils.json, `cutwork design chair`), cut
  // and remeshed at verify's default L (half the base mesh's mean edge): CGAL's valence flips
  // left a flat cap on two collinear outline edges ("face 2408 has zero area"); the cap-and-needle
  // repair removes it. Without the repair the same remesh fails.
  const Scene scene = load_scene("chair");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const PatternContext ctx(scene, meshes);
  const StencilsFile sf = read_stencils_json(test::data_dir() / "designs" / "chair_stencils.json", ctx.shapes());
  const CutSurface cut = cut_stencils(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), sf.stencils);
  RemeshOptions ro;
  ro.target_edge_length = 0.5 * meshes.base.mean_edge_length();
  const RemeshedMesh repaired = remesh_isotropic(cut.vertices, cut.faces, ro);
  EXPECT_GT(repaired.repaired_faces, 0);
  const SurfaceMesh mesh(repaired.vertices, repaired.faces, "repaired");
  for (int f = 0; f < mesh.num_faces(); ++f) {
    double longest = 0;
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, (mesh.vertices().row(mesh.faces()(f, k)) - mesh.vertices().row(mesh.faces()(f, (k + 1) % 3))).norm());
    // (measured: 0.019 at the flattest face, about 1.1°; a zero-area face is 0)
    ASSERT_GT(2 * mesh.face_areas()[f] / (longest * longest), 0.01) << "face " << f;
  }
  ro.repair_flatness = 0;  // no repair
  const RemeshedMesh raw = remesh_isotropic(cut.vertices, cut.faces, ro);
  EXPECT_THROW(SurfaceMesh(raw.vertices, raw.faces, "raw"), InputError);
}

TEST(ConformingVerification, TheChairDesignSolvesOnItsConformingMesh) {
  // The same design verified at the default L (0.0109 m): one bending patch on a straight hole rim
  // of the seat had four nodes within 1e-4 m of one line, and its quadratic fit read the
  // across-rim curvature off that wiggle: max|Q|·A = 4.5e5 (typical 0.1–10), 3.4e19 N/m on a
  // stiffness diagonal (typical 1e8), a stiffness that factorised as singular and "the structure
  // can carry only 0.0% of the load". Condensing the modes below 1e-3 σ_max (shape_operator_energy.h)
  // leaves max|Q|·A = 188 and the solve converges (measured: conforming compliance 14.59 J, coarse
  // 12.21 J).
  const Scene scene = load_scene("chair");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const PatternContext ctx(scene, meshes);
  const StencilsFile sf = read_stencils_json(test::data_dir() / "designs" / "chair_stencils.json", ctx.shapes());
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  ConformingOptions o;
  o.edge_length = 0.5 * meshes.base.mean_edge_length();
  const ConformingVerification v = verify_conforming(scene, meshes, lc, ctx, sf.stencils, o);
  ASSERT_EQ(v.levels.size(), 1u);
  EXPECT_GT(v.levels[0].compliance, 0);
  EXPECT_TRUE(std::isfinite(v.compliance_ratio));
  // Every bending patch of the conforming mesh is conditioned.
  const SurfaceMesh& mesh = v.conforming_mesh;
  const std::vector<bool> outer = boundary_vertices_on_boundary_of(mesh, meshes.base, 1e-9);
  const ShellModel model(mesh, scene.material, resolve_load_case(scene, mesh, &outer, &lc));
  double worst = 0;
  for (const ShellBend& b : model.bends()) worst = std::max(worst, b.rest.weights.cwiseAbs().maxCoeff() * b.rest.area);
  EXPECT_LT(worst, 1e3);
}

}  // namespace
}  // namespace cutwork::solvers
