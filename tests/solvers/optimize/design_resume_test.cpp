// Checkpoints inside the phases (solvers/optimize/design_pipeline.h, DesignSnapshot/DesignResume):
// a design stopped at an optimiser boundary — a round's start or inside an L-BFGS-B run, in the
// pattern or the structural phase — and resumed from the state seen there, with a fresh context
// and shell as a new process would have, ends with the uninterrupted design bit for bit. Scenes
// cover packing and exemplars (several match/optimise rounds, type votes), the energy-density,
// adaptive (β updates) and compliance (area restoration) objectives, and hole filling.
// (The JSON round trip of the state is tests/cli/checkpoint_test.cpp's.)
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "solvers/optimize/design_pipeline.h"

namespace cutwork::solvers {
namespace {
using nlohmann::json;

/// The owning copy of a snapshot: what host/cli/checkpoint.cpp writes and reads back.
DesignResume copy_of(const DesignSnapshot& s) {
  DesignResume r;
  r.stage = s.stage;
  r.pattern = s.pattern;
  if (s.structure) r.structure = *s.structure;
  if (s.phase) {
    r.phase.cursor = s.phase->cursor;
    r.phase.rng = s.phase->rng.state();
    r.phase.optimizer = s.phase->optimizer;
    if (s.phase->lbfgsb) r.phase.optimizer.lbfgsb = *s.phase->lbfgsb;
  }
  if (s.shell_stencils) r.shell_stencils = *s.shell_stencils;
  if (s.equilibrium) r.equilibrium = *s.equilibrium;
  return r;
}

struct Stopped {};

struct Run {
  DesignResult result;
  std::map<DesignStage, int> boundaries;  ///< checkpoint calls per stage
  int inside_lbfgsb = 0;                  ///< of which inside an L-BFGS-B run
  std::map<DesignStage, int> last_round_start;  ///< the last boundary at a round's start, per stage
};

/// A design of `scene`; with `stop_at` (stage, n) it stops at the n-th boundary of that stage and
/// returns the state there in `state`; with `resume` it continues from one.
Run design(const Scene& scene, int pattern_iterations, int structure_iterations,
           std::pair<DesignStage, int> stop_at = {DesignStage::Pattern, 0}, DesignResume* state = nullptr,
           const DesignResume* resume = nullptr) {
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  PatternContext ctx(scene, meshes);
  Run run;
  DesignOptions o;
  o.pattern_iterations = pattern_iterations;
  o.structure_iterations = structure_iterations;
  o.resume = resume;
  o.checkpoint = [&](const DesignSnapshot& s) {
    const int n = ++run.boundaries[s.stage];
    if (s.phase && s.phase->lbfgsb) ++run.inside_lbfgsb;
    if (s.phase && !s.phase->lbfgsb) run.last_round_start[s.stage] = n;
    if (state && s.stage == stop_at.first && n == stop_at.second) {
      *state = copy_of(s);
      throw Stopped{};
    }
  };
  run.result = run_design(scene, meshes, lc, ctx, o);
  return run;
}

void expect_same_layout(const StencilLayout& a, const StencilLayout& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].position, b[i].position) << what << " stencil " << i;
    EXPECT_EQ(a[i].scale, b[i].scale) << what << " stencil " << i;
    EXPECT_EQ(a[i].angle, b[i].angle) << what << " stencil " << i;
    EXPECT_EQ(a[i].type, b[i].type) << what << " stencil " << i;
  }
}

/// Stops the design at a third and at two thirds of each phase's boundaries and at its last round
/// start, resumes, compares.
void check_resume(const Scene& scene, int pattern_iterations, int structure_iterations) {
  const Run whole = design(scene, pattern_iterations, structure_iterations);
  ASSERT_TRUE(whole.result.structure) << scene.name;
  EXPECT_GT(whole.inside_lbfgsb, 0) << scene.name;
  std::printf("%s: %zu stencils, %d pattern and %d structural boundaries; holes filled %d + %d, %zu beta(s)\n",
              scene.name.c_str(), whole.result.layout.size(), whole.boundaries.at(DesignStage::Pattern),
              whole.boundaries.at(DesignStage::Structure), whole.result.pattern.inserted_by_hole_filling,
              whole.result.structure->inserted_by_hole_filling, whole.result.structure->beta_history.size());
  for (DesignStage stage : {DesignStage::Pattern, DesignStage::Structure}) {
    const int count = whole.boundaries.at(stage);
    ASSERT_GE(count, 3) << scene.name;
    for (int n : {count / 3, 2 * count / 3, whole.last_round_start.at(stage)}) {
      const std::string what = scene.name + (stage == DesignStage::Pattern ? " pattern " : " structure ") +
                               std::to_string(n) + "/" + std::to_string(count);
      DesignResume state;
      EXPECT_THROW(design(scene, pattern_iterations, structure_iterations, {stage, n}, &state), Stopped) << what;
      std::printf("%-40s outer %d, fill %d, round %d, %s\n", what.c_str(), state.phase.cursor.outer,
                  state.phase.cursor.fill, state.phase.optimizer.round,
                  state.phase.optimizer.lbfgsb ? "inside L-BFGS-B" : "at a round's start");
      const Run resumed = design(scene, pattern_iterations, structure_iterations, {}, nullptr, &state);
      expect_same_layout(whole.result.pattern.layout, resumed.result.pattern.layout, what + ": pattern design");
      expect_same_layout(whole.result.layout, resumed.result.layout, what + ": final design");
      EXPECT_EQ(whole.result.final_design.summary.W_max, resumed.result.final_design.summary.W_max) << what;
      EXPECT_EQ(whole.result.structure->iterations, resumed.result.structure->iterations) << what;
      EXPECT_EQ(whole.result.structure->evaluations, resumed.result.structure->evaluations) << what;
      EXPECT_EQ(whole.result.structure->round_histories, resumed.result.structure->round_histories) << what;
      EXPECT_EQ(whole.result.pattern.round_histories, resumed.result.pattern.round_histories) << what;
    }
  }
}

Scene reduced(const std::string& name, const json& patch = json::object()) {
  json doc = builtin_scene_json(name);
  doc["mesh"]["edge_length"] = std::min(0.4, doc["mesh"]["edge_length"].get<double>() * 1.5);
  doc["mesh"]["sim_edge_length"] = std::min(0.4, doc["mesh"]["sim_edge_length"].get<double>() * 1.5);
  doc["pattern"]["count"] = 60;
  doc.merge_patch(patch);
  return parse_scene(doc, "test:" + name);
}

TEST(DesignResume, PackingWithHoleFillingContinuesBitForBit) {
  json doc = builtin_scene_json("plate");
  doc.merge_patch({{"structure", {{"fill_holes", true}}}});
  check_resume(parse_scene(doc, "test:plate"), 12, 8);
}

TEST(DesignResume, ExemplarRoundsContinueBitForBit) {
  // 45 pattern iterations: three match/optimise rounds of 20 with type votes between them.
  check_resume(reduced("bowl"), 45, 25);
}

TEST(DesignResume, AdaptiveBetaUpdatesContinueBitForBit) {
  check_resume(reduced("pavilion-adaptive", {{"structure", {{"max_rounds", 3}}}}), 20, 6);
}

TEST(DesignResume, ComplianceWithHoleFillingContinuesBitForBit) {
  check_resume(reduced("pavilion-compliance", {{"structure", {{"fill_holes", true}}}}), 20, 8);
}

}  // namespace
}  // namespace cutwork::solvers
