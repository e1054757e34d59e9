// The peak zoom's submodel (solvers/conforming/zoom_submodel.h): a patch of a solved conforming
// level, re-solved with its collar held at the level's solution, must reproduce that solution where
// nothing was refined, under the loads the level carries there.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "host/core/error.h"
#include "host/mesh/mesh_mapping.h"
#include "host/pattern/pattern_context.h"
#include "host/scene/scene.h"
#include "solvers/conforming/conforming_verification.h"
#include "solvers/conforming/zoom_submodel.h"

namespace cutwork::solvers {
namespace {

/// The plate clamped on one side, its tip load (1 N) spread over the surface within `load_radius`
/// of (0.1, 0, 0).
Scene plate_scene(double load_radius) {
  nlohmann::json doc = builtin_scene_json("plate");
  doc["mesh"]["edge_length"] = 0.01;
  doc["mesh"]["sim_edge_length"] = 0.02;
  doc["loads"][0]["select"]["near"]["radius"] = load_radius;
  return parse_scene(doc, "test:plate");
}

StencilParams circle_at(double x, double y, double radius) {
  StencilParams s;
  s.position = Vec3(x, y, 0);
  s.scale = radius;
  return s;
}

std::vector<StencilParams> hole_of_15mm() { return {circle_at(0.0, 0.0, 0.015)}; }

/// One graded conforming level at L = 4 mm (depth 2), then `zoom` steps.
ConformingOptions one_level(int zoom) {
  ConformingOptions o;
  o.edge_length = 0.004;
  o.levels = 1;
  o.grading_depth = 2;
  o.peak_zoom = zoom;
  return o;
}

/// One graded conforming level (L = 4 mm) of the plate with a hole of 15 mm, solved by verify, and
/// the load case it was solved under.
struct Level {
  Scene scene;
  SceneMeshes meshes;
  ConformingVerification v;
  LoadCase load_case;
  MechanicsSettings mechanics;
  double load_norm = 0;
};

Level solved_level(double load_radius) {
  Level l{plate_scene(load_radius), {}, {}, {}, {}, 0};
  l.meshes = build_scene_meshes(l.scene);
  const LoadCase coarse = resolve_load_case(l.scene, l.meshes.sim);
  const PatternContext ctx(l.scene, l.meshes);
  l.v = verify_conforming(l.scene, l.meshes, coarse, ctx, hole_of_15mm(), one_level(0));
  const double snap = 1e-9 * (l.meshes.base.bbox_max() - l.meshes.base.bbox_min()).norm();
  const std::vector<bool> outer = boundary_vertices_on_boundary_of(l.v.conforming_mesh, l.meshes.base, snap);
  l.load_case = resolve_load_case(l.scene, l.v.conforming_mesh, &outer, &coarse);
  l.mechanics = l.scene.mechanics;  // α = 1: every fill rule is the solid's
  l.mechanics.stiffness = FillStiffness::Linear;
  l.mechanics.filter = FillFilter::None;
  l.load_norm = free_load_norm(l.v.conforming_mesh, l.load_case, l.scene.material);
  return l;
}

/// The largest distance between the submodel's positions and the level's at the same vertices,
/// over the largest displacement of the level.
double relative_mismatch(const ZoomPatch& patch, const RowMatX3d& positions, const SurfaceMesh& level,
                         const RowMatX3d& u) {
  double worst = 0;
  for (size_t i = 0; i < patch.level_vertex.size(); ++i) {
    const int v = patch.level_vertex[i];
    worst = std::max(worst, (positions.row(Eigen::Index(i)) - level.vertices().row(v) - u.row(v)).norm());
  }
  return worst / u.rowwise().norm().maxCoeff();
}

// A patch of 30 mm about the hole's rim peak, re-solved unrefined: started from the level's
// solution it stays there (the collar and the element patches are exact), started with its free
// vertices at rest it returns there to round-off, and the rim peak is the level's.
TEST(ZoomSubmodel, AnUnrefinedPatchReproducesTheLevel) {
  const Level l = solved_level(0.005);
  const SurfaceMesh& level = l.v.conforming_mesh;
  const RowMatX3d& u = l.v.conforming_displacement;
  const Vec3 peak = l.v.levels.back().rim_peak_position;
  const ZoomPatch hole = zoom_patch(level, {peak}, 0.03);
  const int collar = int(std::count(hole.collar.begin(), hole.collar.end(), true));
  EXPECT_GT(collar, 0);
  EXPECT_LT(collar, hole.mesh.num_faces());
  const LevelLoads loads = level_loads(l.scene, l.meshes, level, l.load_case);
  const LoadCase lc = submodel_load_case(l.scene, l.meshes, loads, hole.mesh);
  const SubmodelSolution s = solve_submodel(hole, hole.mesh, u, lc, l.scene.material, l.mechanics, {}, l.load_norm, {});
  const double mismatch = relative_mismatch(hole, s.positions, level, u);
  EXPECT_LT(mismatch, 1e-9);
  // The free vertices started at rest: Newton brings them to the level's solution.
  RowMatX3d u0 = u;
  std::vector<char> held(size_t(level.num_vertices()), 0);
  for (int f = 0; f < hole.mesh.num_faces(); ++f)
    if (hole.collar[size_t(f)])
      for (int k = 0; k < 3; ++k) held[size_t(hole.level_vertex[size_t(hole.mesh.faces()(f, k))])] = 1;
  for (const int v : hole.level_vertex)
    if (!held[size_t(v)]) u0.row(v).setZero();
  const SubmodelSolution z = solve_submodel(hole, hole.mesh, u0, lc, l.scene.material, l.mechanics, {}, l.load_norm, {});
  EXPECT_GT(z.newton_iterations, 0);
  const double from_rest = relative_mismatch(hole, z.positions, level, u);
  EXPECT_LT(from_rest, 1e-9);
  // The rim peak.
  const ShellModel level_model(level, l.scene.material, l.load_case, l.mechanics);
  const std::vector<RimPoint> level_rim = recover_rim(level_model, level.vertices() + u, {});
  const double p_level = rim_peak_near(level_rim, {peak}, 0.004).energy_density;
  const double p_patch = rim_peak_near(s.rim, {peak}, 0.004).energy_density;
  EXPECT_NEAR(p_patch / p_level, 1.0, 1e-9);
  RecordProperty("measured", fmt::format("{} faces ({} collar): {:.2g}; from rest ({} Newton iterations) {:.2g}; rim "
                                         "peak {:.6g} / {:.6g}",
                                         hole.mesh.num_faces(), collar, mismatch, z.newton_iterations, from_rest,
                                         p_patch, p_level));
}

// The tip load spread within 20 mm of (0.1, 0, 0), and a patch of 30 mm about (0.1, 0.03, 0) that
// holds part of that region, free vertices in it. Under the load the level carries there, the patch
// stays at the level's solution; with the whole 1 N on the patch's part of the region (the load
// resolved on the patch alone) it moves away from it.
TEST(ZoomSubmodel, APatchCarriesTheLevelsShareOfALoad) {
  const Level l = solved_level(0.02);
  const SurfaceMesh& level = l.v.conforming_mesh;
  const RowMatX3d& u = l.v.conforming_displacement;
  const ZoomPatch tip = zoom_patch(level, {Vec3(0.1, 0.03, 0)}, 0.03);
  const LevelLoads loads = level_loads(l.scene, l.meshes, level, l.load_case);
  LoadCase lc = submodel_load_case(l.scene, l.meshes, loads, tip.mesh);
  const double on_patch = -lc.forces.col(2).sum();
  EXPECT_GT(on_patch, 0.1);
  EXPECT_LT(on_patch, 0.9);
  const SubmodelSolution s = solve_submodel(tip, tip.mesh, u, lc, l.scene.material, l.mechanics, {}, l.load_norm, {});
  const double mismatch = relative_mismatch(tip, s.positions, level, u);
  EXPECT_LT(mismatch, 1e-9);
  Scene load_only = l.scene;
  load_only.supports.clear();
  lc.forces = resolve_load_case(load_only, tip.mesh).forces;
  const SubmodelSolution n = solve_submodel(tip, tip.mesh, u, lc, l.scene.material, l.mechanics, {}, l.load_norm, {});
  const double naive = relative_mismatch(tip, n.positions, level, u);
  EXPECT_GT(naive, 1e-6);  // measured 5.4e-5
  RecordProperty("measured", fmt::format("{} faces, {:.3g} N of 1 N on it: {:.2g}; with the whole load {:.2g}",
                                         tip.mesh.num_faces(), on_patch, mismatch, naive));
}

// A load on the n nearest vertices selects by the mesh: the submodel refuses it, and verify re-solves
// the whole shell on each zoom step instead, with a note.
TEST(ZoomSubmodel, RefusesALoadOnTheNearestVertices) {
  nlohmann::json doc = builtin_scene_json("plate");
  doc["mesh"]["edge_length"] = 0.01;
  doc["mesh"]["sim_edge_length"] = 0.02;
  doc["loads"] = nlohmann::json::array(
      {{{"type", "point"}, {"force", {0, 0, -1}}, {"select", {{"entity", "vertices"}, {"near", {{"point", {0.1, 0, 0}}, {"radius", 0.05}}}, {"nearest", 3}}}}});
  const Scene scene = parse_scene(doc, "test:plate");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  EXPECT_THROW(level_loads(scene, meshes, meshes.sim, lc), InputError);
  // verify then says so and re-solves the whole shell on each step.
  const PatternContext ctx(scene, meshes);
  const ConformingVerification v = verify_conforming(scene, meshes, lc, ctx, hole_of_15mm(), one_level(1));
  ASSERT_EQ(v.zoom.steps.size(), 2u);
  EXPECT_EQ(v.zoom.submodel_faces, 0);
  EXPECT_TRUE(std::isfinite(v.zoom.steps[1].compliance));  // the whole shell's
  EXPECT_TRUE(std::any_of(v.notes.begin(), v.notes.end(), [](const std::string& n) {
    return n.find("the peak zoom re-solves the whole shell on each step") != std::string::npos &&
           n.find("nearest") != std::string::npos;
  }));
}

}  // namespace
}  // namespace cutwork::solvers
