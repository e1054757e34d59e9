// The discretisation estimate (solvers/conforming/discretisation_estimate.h): the refined meshes,
// Richardson's rule on known sequences, and the verdict on a converged and an unconverged scene.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "host/core/internal_error.h"
#include "host/mesh/bvh.h"
#include "host/scene/scene.h"
#include "host/surfaces/generators.h"
#include "solvers/conforming/discretisation_estimate.h"
#include "solvers/conforming/richardson.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"

namespace cutwork::solvers {
namespace {

Eigen::VectorXd solid(const SurfaceMesh& m) { return Eigen::VectorXd::Ones(m.num_faces()); }

/// The uncut shell of `scene` at its simulation mesh, and the estimate of its discretisation error.
/// With `from_coarse` the first refined level starts from the coarse run's displacements.
DiscretisationEstimate uncut_estimate(const Scene& scene, const DiscretisationOptions& options = {},
                                      bool from_coarse = true) {
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  const MechanicsSettings mechanics = scene_mechanics(scene);
  const ShellModel model(meshes.sim, scene.material, lc, mechanics);
  EquilibriumSolver solver(model);
  const Eigen::VectorXd alpha = solid(meshes.sim);
  solver.solve(alpha);
  const EquilibriumSummary s = summarize_equilibrium(model, solver.positions(), alpha);
  SimulationMeshRefinements refined(scene, meshes, options);
  const RowMatX3d u = solver.displacements();
  return estimate_discretisation(scene, refined, solid, mechanics, s, simulation_edge_length(scene, meshes),
                                 meshes.sim, from_coarse ? &u : nullptr);
}

/// A material field of the plate, smooth over its length: what a design's fill ratios look like to
/// the simulation mesh (holes of varying size along the cantilever), evaluated at face centroids.
Eigen::VectorXd varying_fill(const SurfaceMesh& m) {
  Eigen::VectorXd alpha(m.num_faces());
  for (int f = 0; f < m.num_faces(); ++f) {
    Vec3 c = Vec3::Zero();
    for (int k = 0; k < 3; ++k) c += m.vertices().row(m.faces()(f, k)).transpose() / 3.0;
    alpha[f] = 0.65 + 0.3 * std::cos(2 * std::numbers::pi * c.x() / 0.1) * std::cos(std::numbers::pi * c.y() / 0.1);
  }
  return alpha;
}

/// The shell of `scene` with the fill ratios `fill` gives on its simulation mesh, held on the
/// refinements (coarse_fill_ratios_on), and its estimate; `fine_compliance` (when not null) the
/// same material solved on a mesh of edge length `fine_h`.
DiscretisationEstimate held_estimate(const Scene& scene, const FillRatiosOnMesh& fill, double fine_h = 0,
                                     double* fine_compliance = nullptr) {
  const SceneMeshes meshes = build_scene_meshes(scene);
  const MechanicsSettings mechanics = scene_mechanics(scene);
  const Eigen::VectorXd alpha = fill(meshes.sim);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  const ShellModel model(meshes.sim, scene.material, lc, mechanics);
  EquilibriumSolver solver(model);
  solver.solve(alpha);
  const EquilibriumSummary s = summarize_equilibrium(model, solver.positions(), alpha);
  SimulationMeshRefinements refined(scene, meshes);
  const FillRatiosOnMesh held = coarse_fill_ratios_on(meshes.sim, alpha);
  if (fine_compliance != nullptr) {
    const SurfaceMesh fine = generate_shape(scene.mesh.generator, scene.mesh.params, fine_h);
    const Eigen::VectorXd fine_alpha = held(fine);
    const LoadCase flc = resolve_load_case(scene, fine);
    const ShellModel fine_model(fine, scene.material, flc, mechanics);
    EquilibriumSolver fine_solver(fine_model);
    fine_solver.solve(fine_alpha);
    *fine_compliance = summarize_equilibrium(fine_model, fine_solver.positions(), fine_alpha).compliance;
  }
  return estimate_discretisation(scene, refined, held, mechanics, s, simulation_edge_length(scene, meshes),
                                 meshes.sim);
}

TEST(DiscretisationEstimate, TheCoarseMaterialIsHeldAsAContinuousField) {
  // A refined face takes the coarse faces' fill ratios as a continuous field: each coarse vertex
  // the area-weighted mean of its faces', interpolated at the (brute-force) closest point of the
  // face's centroid; the simulation mesh keeps its own; the material left stays within a percent
  // for a field that changes face by face; where the coarse triangles resolve the stencils the
  // refined faces take the stencils' own fill ratios instead, blended by the resolution.
  const Scene scene = load_scene("plate");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const SurfaceMesh& sim = meshes.sim;
  Eigen::VectorXd alpha(sim.num_faces());
  for (int f = 0; f < alpha.size(); ++f) alpha[f] = 0.5 + 0.45 * std::sin(37.0 * f);  // face by face, unsmooth
  Eigen::VectorXd num = Eigen::VectorXd::Zero(sim.num_vertices()), den = num;
  for (int f = 0; f < sim.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) num[sim.faces()(f, k)] += sim.face_areas()[f] * alpha[f], den[sim.faces()(f, k)] += sim.face_areas()[f];
  const FillRatiosOnMesh held = coarse_fill_ratios_on(sim, alpha);
  EXPECT_EQ(held(sim), alpha);
  const std::vector<RefinedSimulationMesh> refined = refine_simulation_mesh(scene, meshes);
  ASSERT_EQ(refined.size(), 2u);
  const double coarse_material = alpha.dot(sim.face_areas()) / sim.face_areas().sum();
  for (const RefinedSimulationMesh& r : refined) {
    const Eigen::VectorXd fine = held(r.mesh);
    ASSERT_EQ(fine.size(), r.mesh.num_faces());
    for (int f = 0; f < r.mesh.num_faces(); ++f) {
      Vec3 c = Vec3::Zero();
      for (int k = 0; k < 3; ++k) c += r.mesh.vertices().row(r.mesh.faces()(f, k)).transpose() / 3.0;
      // The field is continuous, so a centroid on a coarse edge reads the same from either face.
      const ClosestPoint p = closest_point_brute_force(sim, c);
      double expected = 0;
      for (int k = 0; k < 3; ++k) expected += p.where.bary[k] * num[sim.faces()(p.where.face, k)] / den[sim.faces()(p.where.face, k)];
      ASSERT_NEAR(fine[f], expected, 1e-12) << "face " << f;
    }
    const double material = fine.dot(r.mesh.face_areas()) / r.mesh.face_areas().sum();
    EXPECT_NEAR(material, coarse_material, 0.01 * coarse_material) << r.edge_length;
  }
  // The stencils' own fill ratios where the coarse triangles resolve them.
  const FillRatiosOnMesh own = [](const SurfaceMesh& m) { return Eigen::VectorXd(Eigen::VectorXd::Constant(m.num_faces(), 0.3)); };
  const SurfaceMesh& half = refined[0].mesh;
  const Eigen::VectorXd h0 = held(half);
  const Eigen::VectorXd resolved = coarse_fill_ratios_on(sim, alpha, Eigen::VectorXd::Ones(alpha.size()), own)(half);
  const Eigen::VectorXd unresolved = coarse_fill_ratios_on(sim, alpha, Eigen::VectorXd::Zero(alpha.size()), own)(half);
  const Eigen::VectorXd between = coarse_fill_ratios_on(sim, alpha, Eigen::VectorXd::Constant(alpha.size(), 0.25), own)(half);
  EXPECT_LT((resolved.array() - 0.3).abs().maxCoeff(), 1e-15);
  EXPECT_LT((unresolved - h0).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((between - (0.75 * h0.array() + 0.25 * 0.3).matrix()).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_THROW(coarse_fill_ratios_on(sim, Eigen::VectorXd::Ones(3)), InternalError);
  EXPECT_THROW(coarse_fill_ratios_on(sim, alpha, Eigen::VectorXd::Ones(3), own), InternalError);
}

TEST(DiscretisationEstimate, ThePeakInputsAreCarriedAsTheMaterialIs) {
  // The concentration weight and the cover by shape (and by corner) go onto a refined mesh as α
  // does: the coarse mesh gets its own back, a refined one the same continuous fields (here each
  // column read against coarse_fill_ratios_on's carrying of it), and a constant stays constant.
  const Scene scene = load_scene("plate");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const SurfaceMesh& sim = meshes.sim;
  const int nf = sim.num_faces();
  Eigen::VectorXd weight(nf);
  ShapeCover cover;
  cover.covered.resize(nf, 2);
  cover.corner = Eigen::MatrixXd::Constant(nf, 2, 0.125);
  for (int f = 0; f < nf; ++f) {
    weight[f] = 0.5 + 0.5 * std::sin(11.0 * f);
    cover.covered(f, 0) = 0.2 + 0.1 * std::cos(5.0 * f);
    cover.covered(f, 1) = 0.05;
  }
  const PeakInputsOnMesh carried = coarse_peak_inputs_on(sim, &weight, &cover);
  const PeakInputs own = carried(sim);
  EXPECT_EQ(own.weight, weight);
  EXPECT_EQ(own.cover.covered, cover.covered);
  EXPECT_EQ(own.cover.corner, cover.corner);
  const SurfaceMesh half = refine_simulation_mesh(scene, meshes)[0].mesh;
  const PeakInputs fine = carried(half);
  ASSERT_EQ(fine.weight.size(), half.num_faces());
  ASSERT_EQ(fine.cover.covered.rows(), half.num_faces());
  ASSERT_EQ(fine.cover.corner.cols(), 2);
  EXPECT_LT((fine.weight - coarse_fill_ratios_on(sim, weight)(half)).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((fine.cover.covered.col(0) - coarse_fill_ratios_on(sim, cover.covered.col(0))(half)).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((fine.cover.covered.col(1).array() - 0.05).abs().maxCoeff(), 1e-15);
  EXPECT_LT((fine.cover.corner.array() - 0.125).abs().maxCoeff(), 1e-15);
  // Without a weight or a cover, nothing is carried.
  const PeakInputs none = coarse_peak_inputs_on(sim, nullptr, nullptr)(half);
  EXPECT_EQ(none.weight.size(), 0);
  EXPECT_TRUE(none.cover.empty());
  const Eigen::VectorXd short_weight = weight.head(3);
  EXPECT_THROW(coarse_peak_inputs_on(sim, &short_weight, nullptr), InternalError);
}

TEST(DiscretisationEstimate, ThePeakAwayFromTheSupportsLeavesOneRegionOut) {
  // peak_away_from_supports against its brute-force twin on the plate (clamped at x = −0.1) with a
  // field that grows towards the clamp, at clearances of 0.5, 1 and 3 edge lengths; none held: the
  // plain maximum; all held: none.
  const Scene scene = load_scene("plate");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const SurfaceMesh& m = meshes.sim;
  const std::vector<bool> held = support_held_vertices(resolve_load_case(scene, m));
  Eigen::VectorXd field(m.num_faces());
  std::vector<bool> material(size_t(m.num_faces()), true);
  for (int f = 0; f < m.num_faces(); ++f) {
    const Vec3 c = (m.vertices().row(m.faces()(f, 0)) + m.vertices().row(m.faces()(f, 1)) + m.vertices().row(m.faces()(f, 2))).transpose() / 3;
    field[f] = 1.0 / (0.001 + c.x() + 0.1) + 0.1 * std::sin(37.0 * f);
    material[size_t(f)] = f % 7 != 0;
  }
  const double h = simulation_edge_length(scene, meshes);
  for (double clearance : {0.5 * h, h, 3 * h}) {
    double expected = NAN;
    int expected_face = -1;
    for (int f = 0; f < m.num_faces(); ++f) {
      if (!material[size_t(f)]) continue;
      const Vec3 c = (m.vertices().row(m.faces()(f, 0)) + m.vertices().row(m.faces()(f, 1)) + m.vertices().row(m.faces()(f, 2))).transpose() / 3;
      bool near = false;
      for (int v = 0; v < m.num_vertices(); ++v) near = near || (held[size_t(v)] && (m.vertices().row(v).transpose() - c).norm() <= clearance);
      if (!near && (expected_face < 0 || field[f] > expected)) expected = field[f], expected_face = f;
    }
    int face = -2;
    EXPECT_EQ(peak_away_from_supports(m, field, material, held, clearance, &face), expected) << clearance;
    EXPECT_EQ(face, expected_face) << clearance;
    EXPECT_LT(expected, field.maxCoeff());  // the clamp's faces are left out
  }
  int face = -2;
  const std::vector<bool> none(size_t(m.num_vertices()), false), all(size_t(m.num_vertices()), true);
  double plain = -INFINITY;
  for (int f = 0; f < m.num_faces(); ++f)
    if (material[size_t(f)]) plain = std::max(plain, field[f]);
  EXPECT_EQ(peak_away_from_supports(m, field, material, none, h), plain);
  EXPECT_TRUE(std::isnan(peak_away_from_supports(m, field, material, all, h, &face)));
  EXPECT_EQ(face, -1);
}

TEST(DiscretisationEstimate, AMaterialHeldFixedIsJudgedByItsMesh) {
  // The plate cantilever with fill ratios varying along it (0.35–0.95), held on the refinements:
  // at the default 0.01 m the levels are one structure meshed again, and the estimate brackets the
  // distance to a run eight times finer and says converged (measured: 13.84, 13.78, 13.79 mJ, not
  // asymptotic, 0.9%; 13.79 mJ at 1.25 mm, 0.36% from the first). The plate clamped all round
  // under pressure (bending both ways, the suite's clamped plate) on a mesh four triangles across
  // it is not converged, which the estimate says and the run eight times finer confirms (12.33,
  // 9.867, 9.099 µJ, order 1.68, 40.9%; 8.866 µJ at 3.125 mm, 39% from the first).
  const Scene scene = load_scene("plate");
  double fine = 0;
  const DiscretisationEstimate e = held_estimate(scene, varying_fill, 0.00125, &fine);
  ASSERT_GE(e.levels.size(), 3u);
  EXPECT_TRUE(e.converged) << discretisation_line(e);
  const double c_h = e.levels[0].quantities.compliance;
  EXPECT_LE(std::abs(c_h - fine), e.estimated_error * fine) << discretisation_line(e) << "; fine " << fine;
  nlohmann::json doc = builtin_scene_json("plate");
  doc["mesh"]["sim_edge_length"] = 0.025;
  doc["supports"] = nlohmann::json::array({{{"type", "clamped"}, {"select", {{"entity", "boundary_vertices"}}}}});
  doc["loads"] = nlohmann::json::array({{{"type", "pressure"}, {"pressure", 100.0}, {"select", {{"entity", "faces"}}}}});
  const DiscretisationEstimate coarse = held_estimate(parse_scene(doc, "clamped plate"), varying_fill, 0.003125, &fine);
  EXPECT_FALSE(coarse.converged) << discretisation_line(coarse) << "; fine " << fine;
  EXPECT_GT(std::abs(coarse.levels[0].quantities.compliance - fine) / fine, 0.02) << discretisation_line(coarse);
  EXPECT_LE(std::abs(coarse.levels[0].quantities.compliance - fine), coarse.estimated_error * fine);
}

TEST(Richardson, KnownSequences) {
  for (double p : {1.0, 2.0, 3.0}) {
    const double q[3] = {5 + 2 * 1.0, 5 + 2 * std::pow(0.5, p), 5 + 2 * std::pow(0.25, p)};
    const Richardson r = richardson_extrapolate(q);
    EXPECT_TRUE(r.asymptotic);
    EXPECT_NEAR(r.order, p, 1e-12);
    EXPECT_NEAR(r.extrapolated, 5, 1e-12);
  }
  const double growing[3] = {1.0, 1.1, 1.4};
  const Richardson g = richardson_extrapolate(growing);
  EXPECT_FALSE(g.asymptotic);
  EXPECT_EQ(g.extrapolated, 1.4);
  EXPECT_NEAR(g.error_bar, 0.3, 1e-15);
  EXPECT_TRUE(std::isnan(richardson_extrapolate(std::span<const double>(growing, 1)).error_bar));
}

TEST(DiscretisationEstimate, TheSheetIsConverged) {
  // The unit sheet under self-weight, pinned round its boundary, at its default 0.05 m: compliance
  // 0.04571, 0.04579, 0.04581 J at h, h/2, h/4 (measured): well inside 2%.
  const DiscretisationEstimate e = uncut_estimate(load_scene("sheet"));
  ASSERT_EQ(e.levels.size(), 3u);
  EXPECT_EQ(e.method, "regenerated");
  EXPECT_NEAR(e.levels[1].edge_length, 0.025, 1e-15);
  EXPECT_NEAR(e.levels[2].edge_length, 0.0125, 1e-15);
  EXPECT_GT(e.levels[2].faces, 12 * e.levels[0].faces);
  EXPECT_TRUE(e.converged) << discretisation_line(e);
  EXPECT_LT(e.estimated_error, 0.01);
  // The estimate bounds the distance to the finest level.
  EXPECT_GE(e.estimated_error * std::abs(e.compliance.extrapolated),
            std::abs(e.levels[0].quantities.compliance - e.levels[2].quantities.compliance) * 0.999);
}

TEST(DiscretisationEstimate, SupportsThatGrowUnderRefinementAreCaughtAndNamed) {
  // The pavilion's feet are strips of the rim on z = 0; past each foot's end the rim rises out of
  // z = 0 tangentially (z ≈ 1.2 (π t / 2)²), so "z below 0.01" also fixes up to 0.11 m of rim on
  // each side once the mesh is fine enough: 3.199 m of clamped line at 0.35 m, 3.888 m at 0.0875 m.
  // The levels are then different structures (compliance 1.685, 1.751, 1.188 J), and the estimate
  // must not judge the mesh by them.
  Scene scene = load_scene("pavilion");
  ASSERT_EQ(scene.supports.size(), 1u);
  scene.supports[0].select.below[2] = 0.01;
  const DiscretisationEstimate e = uncut_estimate(scene);
  ASSERT_GE(e.levels.size(), 3u);  // (unsettled: h/8 too)
  EXPECT_NEAR(e.levels[0].clamped.length, 3.2, 0.01);
  EXPECT_GT(e.levels[2].clamped.length, 3.5);
  EXPECT_GT(e.support_change, 0.1);
  EXPECT_FALSE(e.supports_consistent);
  EXPECT_FALSE(e.converged);
  EXPECT_NE(discretisation_line(e).find("the supports hold a different region"), std::string::npos)
      << discretisation_line(e);
  EXPECT_EQ(discretisation_json(e)["supports_consistent"], false);
}

TEST(DiscretisationEstimate, TheDefaultPavilionHoldsItsFeetOnEveryLevel) {
  // Selected exactly ("z below 1e-6"), the feet are the same 4 × 0.8 m on every mesh (chords of
  // the rim: within 3e-4), and the compliance no longer falls under refinement: 1.685, 1.751,
  // 1.694, 1.685 J at 0.35, 0.175, 0.0875, 0.044 m, and 1.689 J at 0.05 m (1.688 J at 0.02 m,
  // measured). The first three do not converge monotonically (the hexagonal rings meet the arches
  // differently at each ring count: ±2% down to 0.1 m, ±0.3% below 0.08 m), and their cautious
  // estimate (4.5%) exceeds the tolerance, so h/8 is solved; the finest three converge (observed
  // order 2.7), and their extrapolation agrees with the finer run to within that ±0.3% of the
  // geometry, which is as close as the estimate can tell.
  const Scene scene = load_scene("pavilion");
  const DiscretisationEstimate e = uncut_estimate(scene);
  ASSERT_EQ(e.levels.size(), 4u) << discretisation_line(e);
  EXPECT_TRUE(e.supports_consistent) << discretisation_line(e);
  EXPECT_LT(e.support_change, 1e-3);
  for (const DiscretisationLevel& l : e.levels) {
    EXPECT_NEAR(l.clamped.length, 3.2, 2e-3);
    EXPECT_EQ(l.clamped.area, 0.0);
    EXPECT_EQ(l.clamped.points, 0);
  }
  EXPECT_EQ(e.rule, "richardson");
  EXPECT_TRUE(e.converged) << discretisation_line(e);
  // A finer run, the generator at 0.05 m.
  Scene fine = scene;
  fine.mesh.sim_edge_length = 0.05;
  const SceneMeshes meshes = build_scene_meshes(fine);
  const LoadCase lc = resolve_load_case(fine, meshes.sim);
  const ShellModel model(meshes.sim, fine.material, lc, scene_mechanics(fine));
  EquilibriumSolver solver(model);
  const Eigen::VectorXd alpha = solid(meshes.sim);
  solver.solve(alpha);
  const double c_fine = summarize_equilibrium(model, solver.positions(), alpha).compliance;
  EXPECT_LT(std::abs(e.compliance.extrapolated - c_fine) / c_fine, 0.005) << discretisation_line(e);
  const double c_h = e.levels[0].quantities.compliance;
  EXPECT_LE(std::abs(c_h - c_fine), (e.estimated_error + 0.005) * c_fine) << discretisation_line(e);
  // Within 2% of it: the 35% "discretisation error" the old selection showed was the supports.
  EXPECT_LT(std::abs(c_h - c_fine) / c_fine, 0.02);
}

TEST(DiscretisationEstimate, TheBuiltinDefaultsAreWithinTwoPercent) {
  // Issue 21 item 1: the uncut default simulation meshes within 2% of converged, the supports the
  // same region on every level. Measured (h, h/2, h/4): plate 6.350, 6.324, 6.309 mJ (1.0%); bowl
  // 1.264, 1.278, 1.283 mJ (1.7%); table 2.909, 2.900, 2.888 J (1.1%, converged about 2.881 J);
  // chair 10.471, 10.434, 10.356 J (1.9%, about 10.31 J). Before the fillet rows and the exact
  // runner the table's was 3.0% (at 0.04 m) and the chair's 12.9% (at 0.043 m). The pavilion's
  // own test is above; the sheet's is TheSheetIsConverged.
  for (const char* name : {"plate", "bowl", "table", "chair"}) {
    SCOPED_TRACE(name);
    const DiscretisationEstimate e = uncut_estimate(load_scene(name));
    ASSERT_EQ(e.levels.size(), 3u);
    EXPECT_TRUE(e.supports_consistent) << discretisation_line(e);
    EXPECT_TRUE(e.converged) << discretisation_line(e);
    EXPECT_LE(e.estimated_error, 0.02) << discretisation_line(e);
  }
}

TEST(DiscretisationEstimate, EachRefinedLevelStartsFromTheLastSolution) {
  // The uncut chair (large deflections: Newton takes 16 iterations from rest on h/2): the refined
  // levels started from the coarse run's displacements, then from each other's, reach the same
  // equilibria to Newton's tolerance in fewer iterations; without the coarse run's, h/2 starts
  // from rest and h/4 from h/2.
  const Scene scene = load_scene("chair");
  const DiscretisationEstimate warm = uncut_estimate(scene);
  const DiscretisationEstimate cold = uncut_estimate(scene, {}, false);
  ASSERT_EQ(warm.levels.size(), cold.levels.size());
  ASSERT_GE(warm.levels.size(), 3u);
  EXPECT_EQ(warm.levels[0].newton_iterations, -1) << "h is solved by the caller";
  for (size_t k = 1; k < warm.levels.size(); ++k) {
    SCOPED_TRACE(k);
    const EquilibriumScalars &w = warm.levels[k].quantities, &c = cold.levels[k].quantities;
    EXPECT_NEAR(w.compliance, c.compliance, 1e-8 * c.compliance);
    EXPECT_NEAR(w.max_displacement, c.max_displacement, 1e-7 * c.max_displacement);
    EXPECT_TRUE(warm.levels[k].warm_started);
    EXPECT_EQ(cold.levels[k].warm_started, k > 1);
  }
  EXPECT_LT(warm.levels[1].newton_iterations, cold.levels[1].newton_iterations);
  EXPECT_LT(cold.levels[2].newton_iterations, cold.levels[1].newton_iterations);
  EXPECT_NEAR(warm.estimated_error, cold.estimated_error, 1e-6);
}

TEST(DiscretisationEstimate, MeshFilesAreSubdividedAndTheBudgetIsKept) {
  Scene scene = load_scene("sheet");
  // A mesh file stands in: the generator's own mesh without its generator.
  const SceneMeshes meshes = build_scene_meshes(scene);
  scene.mesh.generator.clear();
  DiscretisationOptions o;
  o.max_faces = 8 * meshes.sim.num_faces();  // h/2 (4×) fits, h/4 (16×) does not
  const std::vector<RefinedSimulationMesh> r = refine_simulation_mesh(scene, meshes, o);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].method, "subdivided");
  EXPECT_EQ(r[0].mesh.num_faces(), 4 * meshes.sim.num_faces());
  EXPECT_NEAR(r[0].mesh.face_areas().sum(), meshes.sim.face_areas().sum(), 1e-12);
  o.max_faces = 1'000'000;
  EXPECT_EQ(refine_simulation_mesh(scene, meshes, o).size(), 2u);
}

// The levels past those always solved are announced before they are built, once each, with their
// triangles (a sweep takes their memory from its budget there: host/sweep/memory_budget.h); a level
// the face budget leaves out is not.
TEST(DiscretisationEstimate, ExtraLevelsAreAnnouncedBeforeTheyAreBuilt) {
  Scene scene = load_scene("sheet");
  const SceneMeshes meshes = build_scene_meshes(scene);
  scene.mesh.generator.clear();  // subdivided: cheap, and each level exactly 4× the last
  const size_t n = size_t(meshes.sim.num_faces());
  std::vector<std::pair<int, size_t>> announced;
  DiscretisationOptions o;
  o.refinements = 1;
  o.extra_refinements = 2;
  o.max_faces = int(16 * n);  // h/4 fits, h/8 does not
  o.before_extra_level = [&](int level, size_t faces) { announced.emplace_back(level, faces); };
  SimulationMeshRefinements refined(scene, meshes, o);
  ASSERT_NE(refined.level(0), nullptr);
  EXPECT_TRUE(announced.empty()) << "h/2 is always solved";
  const RefinedSimulationMesh* quarter = refined.level(1);
  ASSERT_NE(quarter, nullptr);
  ASSERT_EQ(announced.size(), 1u);
  EXPECT_EQ(announced[0].first, 1);
  EXPECT_EQ(announced[0].second, size_t(quarter->mesh.num_faces()));
  ASSERT_NE(refined.level(1), nullptr);
  EXPECT_EQ(announced.size(), 1u) << "built once, announced once";
  EXPECT_EQ(refined.level(2), nullptr);
  EXPECT_EQ(announced.size(), 1u) << "over the face budget: not built, not announced";
}

}  // namespace
}  // namespace cutwork::solvers
