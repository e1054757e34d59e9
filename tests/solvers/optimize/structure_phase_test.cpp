// The structural phase (§5.3–§5.4): the joint objective's gradient end to end against finite
// differences of the whole pipeline, the plate's stability and compliance optimisations, and
// every paper scene at a reduced size.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cstdio>
#include <random>

#include "host/pattern/overlaps.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/objective/peak_energy_density.h"
#include "solvers/optimize/design_pipeline.h"
#include "tests/solvers/support/finite_difference.h"

namespace cutwork::solvers {
namespace {
using nlohmann::json;

Scene scene_from(const std::string& name, const json& patch = json::object()) {
  json doc = builtin_scene_json(name);
  doc.merge_patch(patch);
  return parse_scene(doc, "test:" + name);
}

// ---------------------------------------------------------------- the gradient end to end

/// J(p) = w_S S(α(p), x(α(p))) + w_P P(p) through joint_objective — the function the optimiser
/// minimises — against central differences along random directions in p = (q, s, φ)
/// (the restoration of compliance's area constraint included).
/// `stencils`: the library (null: the plate's circles).
void check_joint_gradient(const char* objective, unsigned seed, const json& mechanics = json::object(),
                          const char* measure = "mean", const json& stencils = nullptr) {
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  // Stencils of 6 mm diameter on 10 mm simulation triangles: no triangle is ever covered
  // entirely, so no fill ratio sits at its clamp 1e-4 (a kink of α, where no derivative exists).
  json patch = {{"pattern", {{"count", 40}, {"scale", 0.003}, {"seed", int(seed)}}},
                {"structure", {{"objective", objective}, {"beta", 0.05}, {"measure", measure}}},
                {"mechanics", mechanics}};
  if (!stencils.is_null()) patch["stencils"] = stencils;
  const Scene scene = scene_from("plate", patch);
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  PatternContext ctx(scene, meshes);
  PatternRng rng(seed);
  StencilLayout layout = ctx.initialize(rng);
  ASSERT_GE(layout.size(), 20u);
  // Turn the stencils (squares would do too; circles are 32-gons, so φ matters a little).
  for (auto& s : layout) s.angle = rng.uniform(-0.3, 0.3);
  NewtonSettings newton;
  newton.residual_tolerance = 1e-12;  // FD of S resolves x(α) to what Newton converged to
  StencilledShell shell(meshes.sim, ctx.surface().bvh(), scene.material, scene.mechanics, lc, ctx.shapes(), ctx.surface().field(), {},
                        newton);
  shell.set_cell_filter(scene_cell_filter(scene, ctx, meshes.sim));
  if (scene.mechanics.filter == FillFilter::Cell) {
    // The filter is at work: every row averages over its neighbours (b = 1 at h/d ≈ 1.7).
    ASSERT_FALSE(shell.cell_filter().identity());
    EXPECT_GT(shell.cell_filter().mean_row_size(), 3);
  }
  shell.set_stencils(layout_params(layout));
  // Several shapes, or one whose factors by corner the thick plate's transition makes vary with the
  // stencils' size (peak_energy_density.h "Thick plates"): W_peak reads each shape's factors by the
  // faces' covered fractions.
  const bool thick = !shell.model().mechanics().stiffness_curve.empty() && scene.mechanics.corner_radius > 0 &&
                     ConcentrationMap::for_mechanics(shell.model().mechanics(), scene.material).thick_scale() > 0;
  EXPECT_EQ(shell.cover() != nullptr, ctx.shapes().size() > 1 || thick);
  // With them the corner rule at the scene's minimum feature (the flowers' notches are corners).
  if (shell.cover()) {
    EXPECT_GT(scene.mechanics.corner_radius, 0);
    EXPECT_EQ(shell.cover()->corner.rows(), meshes.sim.num_faces());
  }
  shell.equilibrate();
  const EquilibriumSummary uncut_like = shell.summary();
  const double w_ref = uncut_like.W_max;
  StructuralTerm term(shell, scene.structure.objective, scene.structure.w_S, scene.structure.beta * w_ref, w_ref,
                      uncut_like.compliance, shell.covered_area(nullptr));
  term.set_measure(scene.structure.measure);
  ctx.energy().rematch(layout);
  const Eigen::VectorXi types = layout_types(layout);
  const std::vector<StencilParams> p0 = layout_params(layout);
  const int S = int(p0.size());
  auto J = [&](const std::vector<StencilParams>& p, Eigen::VectorXd* g) {
    std::vector<StencilParams> q = p;
    return joint_objective(ctx.energy(), &term, scene.pattern.w_P, q, types, g);
  };
  Eigen::VectorXd g;
  const double J0 = J(p0, &g);
  ASSERT_TRUE(std::isfinite(J0));
  ASSERT_EQ(g.size(), 5 * S);
  if (std::string(objective) == "energy_density") {
    EXPECT_GT(term.last_structure(), 0);  // some triangles above β: S is not trivially 0
  }

  std::mt19937 gen(seed);
  std::normal_distribution<double> n01;
  const double l = ctx.unit();
  for (int dir = 0; dir < 4; ++dir) {
    // Direction in natural units: positions and scales by ℓ, angles by 1 rad.
    Eigen::VectorXd d(5 * S);
    for (int k = 0; k < 5 * S; ++k) d[k] = n01(gen) * (k % 5 == 4 ? 1.0 : l);
    auto along = [&](const Eigen::VectorXd& t) {
      std::vector<StencilParams> p = p0;
      for (int i = 0; i < S; ++i) {
        p[size_t(i)].position += t[0] * d.segment<3>(5 * i);
        p[size_t(i)].scale += t[0] * d[5 * i + 3];
        p[size_t(i)].angle += t[0] * d[5 * i + 4];
      }
      return J(p, nullptr);
    };
    const Eigen::VectorXd slope = Eigen::VectorXd::Constant(1, g.dot(d));
    const test::DerivativeCheck c = test::check_gradient(along, Eigen::VectorXd::Zero(1), slope, 1.0);
    EXPECT_LE(c.best, 1e-5) << objective << " seed " << seed << " direction " << dir << " dJ/dt = " << slope[0] << "\n" << c.table();
  }
}

TEST(JointGradient, EnergyDensityMatchesFiniteDifferencesOfTheWholePipeline) {
  check_joint_gradient("energy_density", 3);
}

TEST(JointGradient, ComplianceWithRestoredAreaMatchesFiniteDifferences) { check_joint_gradient("compliance", 4); }

// The cell filter (solvers/shell/cell_filter.h) between the kernels and the shell, with the
// homogenised fill stiffness it is made for: its pull-back Bᵀ in the chain.
TEST(JointGradient, CellFilteredHomogenisedStiffnessMatchesFiniteDifferences) {
  check_joint_gradient("energy_density", 5, {{"stiffness", "homogenised"}, {"filter", "cell"}});
  check_joint_gradient("compliance", 6, {{"stiffness", "homogenised"}, {"filter", "cell"}});
}

// The ligament peak as the measure (structure.measure "peak"): K(ᾱ) and the ratios' α-derivatives
// in the chain, the cell filter's blend weights held fixed.
TEST(JointGradient, PeakMeasureMatchesFiniteDifferences) {
  check_joint_gradient("energy_density", 7, {{"stiffness", "homogenised"}, {"filter", "cell"}}, "peak");
  check_joint_gradient("energy_density", 8, {{"stiffness", "homogenised"}}, "peak");
}

// The peak measure of a design of two shapes (flowers and circles, as the bowl's): the factors by
// shape, mixed per face by the shapes' covered fractions, whose derivatives through the clipping
// (FillRatioEvaluator::pullback_by_shape, through the cell filter's Bᵀ) join the chain. Where a
// flower barely enters a face beside a circle, the smooth maximum turns from the circle's factor to
// the flower's within ~1e-3 of covered fraction (the ramp's slope times 1/p), and central
// differences there are truncation-limited down to where the equilibrium's round-off takes over:
// with seed 9 and the filter, 1 of 12 directions read 6e-5 (5e-6 with p = 4), the other 23 of
// seeds 9 and 10 (12 each) 1.1e-6 or below. Without the by-shape pull-back the same directions read 0.3 to 40.
TEST(JointGradient, PeakMeasureByShapeMatchesFiniteDifferences) {
  const json flowers_and_circles =
      json::array({{{"name", "flower"}, {"kind", "flower"}}, {{"name", "circle"}, {"kind", "circle"}}});
  check_joint_gradient("energy_density", 11, {{"stiffness", "homogenised"}, {"filter", "cell"}}, "peak",
                       flowers_and_circles);
  check_joint_gradient("energy_density", 10, {{"stiffness", "homogenised"}}, "peak", flowers_and_circles);
}

// ---------------------------------------------------------------- the plate (Fig. 5)

DesignResult design(const Scene& scene, int pattern_iterations = -1, int structure_iterations = -1) {
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  PatternContext ctx(scene, meshes);
  DesignOptions o;
  o.pattern_iterations = pattern_iterations;
  o.structure_iterations = structure_iterations;
  return run_design(scene, meshes, lc, ctx, o);
}

// The homogenised curve of a library of several shapes follows the shapes the stencils use
// (shape_weights, by count): a plate whose library holds stars and circles, perforated by stars
// alone, is the plate of a star library with the same stencils, to round-off; with half of them
// circles its curve is the two shapes' mean. Equal weights whatever the stencils (the rule before)
// gave the star-only plate the circles' stiffer ratios for half its curve: the chair (396 stars,
// 28 circles) read 3.8% too stiff against its converged conforming compliance, 0.5% by count.
TEST(StencilledShell, TheHomogenisedCurveFollowsTheShapesTheStencilsUse) {
  const json patch = {{"pattern", {{"count", 30}, {"scale", 0.004}}},
                      {"stencils", json::array({{{"name", "star"}, {"kind", "star"}},
                                                {{"name", "circle"}, {"kind", "circle"}}})}};
  const Scene both = scene_from("plate", patch);
  ASSERT_EQ(both.mechanics.stiffness, FillStiffness::Homogenised);
  json star_patch = patch;
  star_patch["stencils"] = json::array({{{"name", "star"}, {"kind", "star"}}});
  const Scene stars_only = scene_from("plate", star_patch);
  const SceneMeshes meshes = build_scene_meshes(both);
  const LoadCase lc = resolve_load_case(both, meshes.sim);
  PatternContext ctx(both, meshes), star_ctx(stars_only, meshes);
  PatternRng rng(3);
  std::vector<StencilParams> stencils = layout_params(ctx.initialize(rng));
  ASSERT_GE(stencils.size(), 10u);
  for (StencilParams& p : stencils) p.type = 0;  // every one a star
  auto compliance = [&](const Scene& scene, PatternContext& c, std::span<const StencilParams> p,
                        FillStiffnessCurve* curve) {
    StencilledShell shell(meshes.sim, c.surface().bvh(), scene.material, scene.mechanics, lc, c.shapes(),
                          c.surface().field());
    shell.set_cell_filter(scene_cell_filter(scene, c, meshes.sim));
    shell.set_stencils(p);
    shell.equilibrate();
    if (curve) *curve = shell.model().mechanics().stiffness_curve;
    return shell.summary().compliance;
  };
  FillStiffnessCurve curve_both, curve_stars;
  const double c_both = compliance(both, ctx, stencils, &curve_both);
  const double c_stars = compliance(stars_only, star_ctx, stencils, &curve_stars);
  // Equal weights, as before: the model of the two-shape library without stencils' shares.
  const ShellModel equal(meshes.sim, both.material, lc, scene_mechanics(both));
  EquilibriumSolver solver(equal);
  StencilledShell probe(meshes.sim, ctx.surface().bvh(), both.material, both.mechanics, lc, ctx.shapes(),
                        ctx.surface().field());
  probe.set_cell_filter(scene_cell_filter(both, ctx, meshes.sim));
  solver.solve(probe.set_stencils(stencils));
  const double c_equal = summarize_equilibrium(equal, solver.positions(), solver.alpha()).compliance;
  std::printf("stars in a star-and-circle library: compliance %.6g (stars' library %.6g; equal weights %.6g)\n",
              c_both, c_stars, c_equal);
  EXPECT_EQ(curve_both.shape_weights, std::vector<double>({1.0, 0.0}));
  EXPECT_EQ(curve_both.alpha, curve_stars.alpha);
  EXPECT_EQ(curve_both.bending_bulk, curve_stars.bending_bulk);
  EXPECT_NEAR(c_both / c_stars, 1.0, 1e-10);
  EXPECT_LT(c_equal, c_stars * 0.999) << "the circles' ratios are stiffer than the stars'";

  // Half of them circles: the mean of the two shapes' curves on the samples of both.
  for (size_t i = 0; i < stencils.size(); i += 2) stencils[i].type = 1;
  const std::vector<double> w = shape_weights(ctx.shapes(), stencils);
  EXPECT_NEAR(w[0] + w[1], 1.0, 1e-15);
  EXPECT_NEAR(w[1], double((stencils.size() + 1) / 2) / double(stencils.size()), 1e-15);
  FillStiffnessCurve curve_mixed;
  compliance(both, ctx, stencils, &curve_mixed);
  const FillStiffnessCurve expected = calibrate_fill_stiffness(ctx.shapes(), both.material, {}, w);
  ASSERT_EQ(curve_mixed.shape_weights.size(), 2u);
  EXPECT_NEAR(curve_mixed.shape_weights[1], w[1], 1e-15);
  EXPECT_EQ(curve_mixed.alpha, expected.alpha);
  EXPECT_EQ(curve_mixed.membrane_shear, expected.membrane_shear);
  const FillStiffnessCurve circle_alone = calibrate_fill_stiffness(ctx.shapes(), both.material, {}, {0.0, 1.0});
  for (size_t k = 0; k + 1 < expected.alpha.size(); ++k) {
    EXPECT_GT(circle_alone.bending_bulk[k], expected.bending_bulk[k]) << expected.alpha[k];
    EXPECT_GT(expected.bending_bulk[k], curve_stars.bending_bulk[k]) << expected.alpha[k];
  }
}

TEST(StructurePhase, PlateStabilityLowersPeakEnergyDensityByAQuarter) {
  const DesignResult r = design(scene_from("plate"));
  ASSERT_TRUE(r.structure);
  const double before = r.pattern_design.summary.W_max, after = r.final_design.summary.W_max;
  RecordProperty("W_max_pattern", std::to_string(before));
  RecordProperty("W_max_final", std::to_string(after));
  EXPECT_LE(after, 0.75 * before) << "W_max " << before << " -> " << after;
  EXPECT_EQ(r.final_design.overlaps.pairs, 0);
  EXPECT_EQ(r.final_design.overlaps.boundary, 0);
  EXPECT_LT(r.structure->S_end, r.structure->S_start);
  // Stencils squeezed below their scale bound by the overlap resolution are removed: a few.
  EXPECT_GE(r.layout.size(), r.pattern.layout.size() * 98 / 100);
}

/// A design of `scene` with its meshes and pattern context kept, for checks on its surface.
struct DesignWithContext {
  explicit DesignWithContext(const Scene& s)
      : scene(s),
        meshes(build_scene_meshes(scene)),
        lc(resolve_load_case(scene, meshes.sim)),
        ctx(scene, meshes),
        result(run_design(scene, meshes, lc, ctx, DesignOptions{})) {}
  Scene scene;
  SceneMeshes meshes;
  LoadCase lc;
  PatternContext ctx;
  DesignResult result;
};

/// fabrication.min_feature (> 0) is held by the final layout — checked by the overlap test with
/// the gap and measured directly between the enlarged circles — and not by the pattern design's,
/// so that the constraint did work.
void expect_minimum_feature_held(const DesignWithContext& d) {
  const StencilLayout& layout = d.result.layout;
  const double s = d.ctx.settings().s, gap = d.scene.fabrication.min_feature;
  ASSERT_GT(gap, 0);
  EXPECT_FALSE(find_overlaps_brute_force(d.ctx.surface(), layout, s, gap).any());
  EXPECT_TRUE(find_overlaps_brute_force(d.ctx.surface(), d.result.pattern.layout, s, gap).any());
  double narrowest = INFINITY;
  for (size_t i = 0; i < layout.size(); ++i)
    for (size_t j = i + 1; j < layout.size(); ++j)
      narrowest = std::min(narrowest, (layout[i].position - layout[j].position).norm() -
                                          (1 + s) * (layout[i].scale + layout[j].scale));
  EXPECT_GE(narrowest, gap * (1 - 1e-9));
}

// structure.measure "peak" on the homogenised, cell-filtered plate: the ligament peak W_peak (the
// quantity thresholded) falls well below the pattern design's, and fabrication.min_feature holds
// as a hard constraint (overlaps.h's gap).
TEST(StructurePhase, PlatePeakMeasureLowersTheLigamentPeakAndKeepsTheMinimumFeature) {
  const DesignWithContext d(scene_from("plate", {{"mechanics", {{"stiffness", "homogenised"}, {"filter", "cell"}}},
                                                 {"structure", {{"measure", "peak"}}}}));
  const DesignResult& r = d.result;
  ASSERT_TRUE(r.structure);
  const double before = r.pattern_design.summary.W_peak_max, after = r.final_design.summary.W_peak_max;
  RecordProperty("W_peak_max_pattern", std::to_string(before));
  RecordProperty("W_peak_max_final", std::to_string(after));
  ASSERT_TRUE(std::isfinite(before));
  EXPECT_LE(after, 0.25 * before) << "W_peak_max " << before << " -> " << after;
  EXPECT_LT(r.structure->S_end, 0.1 * r.structure->S_start);
  expect_minimum_feature_held(d);
}

TEST(StructurePhase, PlateComplianceDropsAtEqualMaterial) {
  // The paper's setting (no minimum feature): the pattern design's material exactly.
  const DesignResult r = design(scene_from("plate", {{"structure", {{"objective", "compliance"}}},
                                                     {"fabrication", {{"min_feature", 0}}}}));
  ASSERT_TRUE(r.structure);
  const double c0 = r.pattern_design.summary.compliance, c1 = r.final_design.summary.compliance;
  RecordProperty("compliance_pattern", std::to_string(c0));
  RecordProperty("compliance_final", std::to_string(c1));
  EXPECT_LT(c1, c0);
  const double m0 = r.pattern_design.material_fraction, m1 = r.final_design.material_fraction;
  EXPECT_NEAR(m1, m0, 1e-3 * m0) << "material " << m0 << " -> " << m1;
  EXPECT_EQ(r.final_design.overlaps.pairs, 0);
  EXPECT_EQ(r.final_design.overlaps.boundary, 0);
}

// With the default minimum feature (1 mm) the phase starts from the pattern design shrunk to keep
// it, holds that design's stencil area to the end, lowers its compliance, and ends keeping the gap.
TEST(StructurePhase, PlateComplianceHoldsTheMinimumFeatureAndTheStartsMaterial) {
  const DesignWithContext d(scene_from("plate", {{"structure", {{"objective", "compliance"}}}}));
  const DesignResult& r = d.result;
  ASSERT_TRUE(r.structure);
  const StructurePhaseResult& s = *r.structure;
  EXPECT_NEAR(s.covered_area_final, s.covered_area_target, 1e-9 * s.covered_area_target);
  EXPECT_GT(s.covered_area_target, 0);
  EXPECT_TRUE(s.notes.empty()) << s.notes.front();  // the area was restored, not given up
  EXPECT_LT(r.final_design.summary.compliance, s.c_ref) << "the start's compliance " << s.c_ref;
  RecordProperty("material_pattern", std::to_string(r.pattern_design.material_fraction));
  RecordProperty("material_final", std::to_string(r.final_design.material_fraction));
  expect_minimum_feature_held(d);
}

// ---------------------------------------------------------------- the paper's scenes, reduced

TEST(StructurePhase, EveryPaperSceneImprovesAtReducedSize) {
  for (const char* name : {"chair", "table", "bowl", "pavilion", "pavilion-adaptive", "pavilion-compliance"}) {
    json doc = builtin_scene_json(name);
    // Coarser meshes (the pavilion's generator accepts edges up to 0.4 m).
    doc["mesh"]["edge_length"] = std::min(0.4, doc["mesh"]["edge_length"].get<double>() * 1.5);
    doc["mesh"]["sim_edge_length"] = std::min(0.4, doc["mesh"]["sim_edge_length"].get<double>() * 1.5);
    doc["pattern"]["count"] = 60;
    doc["structure"]["max_rounds"] = 3;
    const Scene scene = parse_scene(doc, std::string("test:") + name);
    const DesignResult r = design(scene, 60, 40);
    ASSERT_TRUE(r.structure) << name;
    const StructurePhaseResult& s = *r.structure;
    // J never increases across accepted iterations (within an optimiser run).
    for (const auto& h : s.round_histories)
      for (size_t k = 1; k < h.size(); ++k) EXPECT_LE(h[k], h[k - 1]) << name << " iterate " << k;
    // (Across rounds J may rise: re-matching the DET neighbourhoods admits new neighbours.)
    EXPECT_LT(s.S_end, s.S_start) << name;
    EXPECT_EQ(r.final_design.overlaps.pairs + r.final_design.overlaps.boundary, 0) << name;
    std::printf("%-20s %3zu stencils  J %.5g -> %.5g  S %.5g -> %.5g  W_max %.4g -> %.4g  C %.4g -> %.4g  %.2f s\n",
                name, r.layout.size(), s.J_start, s.J_end, s.S_start, s.S_end, r.pattern_design.summary.W_max,
                r.final_design.summary.W_max, r.pattern_design.summary.compliance, r.final_design.summary.compliance,
                s.seconds);
  }
}

}  // namespace
}  // namespace cutwork::solvers
