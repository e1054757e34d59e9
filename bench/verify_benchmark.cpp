// Conforming verification (paper §6, Fig. 4): the coarse fill-ratio simulation against a simulation
// on a mesh that conforms to the stencil outlines (solvers/conforming), as the coarse mesh is refined.
//
//   BM_Verify_Sheet/<k>       Fig. 4: the unit sheet (built-in scene `sheet`: pinned outer boundary,
//                             self-weight) with one circular stencil of radius 0.2 m at its centre;
//                             coarse (base = simulation) edge length h = 0.2 / 2^k m.
//   BM_Verify_Cantilever/<k>  a perforated cantilever: the built-in `plate` (0.2 × 0.1 m, clamped at
//                             x = −0.1, 1 N at the middle of the free end) with a row of three
//                             circular stencils of radius 0.02 m at x = −0.05, 0, 0.05;
//                             h = 0.02 / 2^k m.
//   BM_Verify_Perforated/<k>  the cantilever `plate` perforated by 6 mm circles on a hexagonal
//                             lattice of 16 mm (fill ratio 0.49 there): holes smaller than the
//                             coarse triangles, the case homogenisation is for; h = 0.02 / 2^k m,
//                             conforming 0.0015 m.
//   BM_Verify_Levels/<d>/<w>  the perforated `plate` above (4 mm ligaments) through verify's level
//                             loop: conforming L = 6 mm, at most 4 levels, tolerance 1%, budget
//                             500k triangles, grading depth d (0: uniform levels); w = 1 starts each
//                             level's Newton from the last level's solution (the default), 0 from
//                             rest. Counters: levels, converged, last_change, finest_faces, C_finest
//                             and C_extrapolated (J), error_bar (relative), newton_iterations (all
//                             levels), solve_seconds (the levels' solves alone). Real time: meshing
//                             and every solve.
//   BM_PeakZoom/<s>/<m>       the peak zoom, whole shell (m = 0) or submodel (m = 1); see below.
// Second argument m, the shell model of the coarse run: 0 the paper's (hinge bending, stiffness
// linear in α), 1 shape-operator bending with linear stiffness, 2 shape-operator bending with
// homogenised stiffness (solvers/homogenise). The conforming run uses the same bending model.
// The conforming reference is the same at every k: the base surface cut along the outlines and
// remeshed at a fixed edge length (sheet 0.0125 m, cantilever 0.002 m), α = 1.
// Counters (coarse / conforming unless named): energy_ratio (strain energy, the quantity Fig. 4
// plots), density_ratio (strain energy per area of material), compliance_ratio, W_max_ratio,
// W_l2 (relative L2 difference of W per coarse face), E_coarse and E_conforming (J), coarse_faces,
// conforming_faces. Manual time: the coarse and conforming equilibria together.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <vector>

#include "host/scene/scene.h"
#include "solvers/conforming/conforming_verification.h"

namespace cutwork {
namespace {

struct VerifyCase {
  const char* scene;
  double coarsest;                    ///< h at k = 0 (m)
  double reference;                   ///< conforming edge length (m)
  std::vector<StencilParams> stencils;
};

StencilParams circle_at(double x, double y, double radius) {
  StencilParams s;
  s.position = Vec3(x, y, 0);
  s.scale = radius;
  return s;
}

const char* const kModelNames[] = {"paper (hinge, linear)", "shape operator, linear", "shape operator, homogenised"};

void BM_Verify(benchmark::State& state, const VerifyCase& c) {
  const double h = c.coarsest / double(1 << state.range(0));
  const int model = int(state.range(1));
  nlohmann::json doc = builtin_scene_json(c.scene);
  doc["mesh"]["edge_length"] = h;
  doc["mesh"]["sim_edge_length"] = h;  // simulate on the base mesh, as Fig. 4 does
  doc["mechanics"]["bending"] = model == 0 ? "hinge" : "shape_operator";
  doc["mechanics"]["stiffness"] = model == 2 ? "homogenised" : "linear";
  const Scene scene = parse_scene(doc, std::string("bench:") + c.scene);
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  const PatternContext ctx(scene, meshes);
  solvers::ConformingOptions o;
  o.edge_length = c.reference;
  solvers::ConformingVerification v;
  state.SetLabel(kModelNames[model]);
  for (auto _ : state) {
    v = solvers::verify_conforming(scene, meshes, lc, ctx, c.stencils, o);
    state.SetIterationTime(v.coarse.seconds + v.levels.back().seconds);
  }
  const solvers::RunQuantities& f = v.levels.back();
  state.counters["h"] = h;
  state.counters["coarse_faces"] = v.coarse.faces;
  state.counters["conforming_faces"] = f.faces;
  state.counters["E_coarse"] = v.coarse.strain_energy;
  state.counters["E_conforming"] = f.strain_energy;
  state.counters["energy_ratio"] = v.strain_energy_ratio;
  state.counters["density_ratio"] =
      (v.coarse.strain_energy / v.coarse.material_area) / (f.strain_energy / f.material_area);
  state.counters["compliance_ratio"] = v.compliance_ratio;
  state.counters["max_displacement_ratio"] = v.max_displacement_ratio;
  state.counters["W_max_ratio"] = v.W_max_ratio;
  state.counters["W_l2"] = v.W_relative_l2;
}

const VerifyCase& sheet() {
  static const VerifyCase c{"sheet", 0.2, 0.0125, {circle_at(0, 0, 0.2)}};
  return c;
}

/// The `plate` (0.2 × 0.1 m, clamped at x = −0.1, 1 N at the free end) perforated by circles of
/// radius 6 mm on a hexagonal lattice of spacing 16 mm (fill ratio 0.49 where the lattice runs),
/// kept 4 mm inside the plate.
const VerifyCase& perforated() {
  static const VerifyCase c = [] {
    VerifyCase v{"plate", 0.02, 0.0015, {}};
    const double a = 0.016, r = 0.006;
    for (int n = -8; n <= 8; ++n)
      for (int m = -12; m <= 12; ++m) {
        const double x = (m + 0.5 * n) * a, y = 0.5 * std::sqrt(3.0) * n * a;
        if (std::abs(x) + r < 0.096 && std::abs(y) + r < 0.046) v.stencils.push_back(circle_at(x, y, r));
      }
    return v;
  }();
  return c;
}

const VerifyCase& cantilever() {
  static const VerifyCase c{"plate", 0.02, 0.002,
                            {circle_at(-0.05, 0, 0.02), circle_at(0, 0, 0.02), circle_at(0.05, 0, 0.02)}};
  return c;
}

/// The `plate` scene at base edge 0.01 m and simulation edge 0.02 m, what verify needs of it.
struct PlateForVerify {
  Scene scene;
  SceneMeshes meshes;
  LoadCase lc;
  std::unique_ptr<PatternContext> ctx;
  PlateForVerify() {
    nlohmann::json doc = builtin_scene_json("plate");
    doc["mesh"]["edge_length"] = 0.01;
    doc["mesh"]["sim_edge_length"] = 0.02;
    scene = parse_scene(doc, "bench:plate");
    meshes = build_scene_meshes(scene);
    lc = resolve_load_case(scene, meshes.sim);
    ctx = std::make_unique<PatternContext>(scene, meshes);
  }
};

void BM_Verify_Levels(benchmark::State& state) {
  const VerifyCase& c = perforated();
  const PlateForVerify p;
  const Scene& scene = p.scene;
  const SceneMeshes& meshes = p.meshes;
  const LoadCase& lc = p.lc;
  const PatternContext& ctx = *p.ctx;
  solvers::ConformingOptions o;
  o.edge_length = 0.006;
  o.levels = 4;
  o.tolerance = 0.01;
  o.max_faces = 500'000;
  o.grading_depth = int(state.range(0));
  o.warm_start = state.range(1) != 0;
  solvers::ConformingVerification v;
  for (auto _ : state) v = solvers::verify_conforming(scene, meshes, lc, ctx, c.stencils, o);
  double iterations = 0, solve_seconds = 0;
  for (const solvers::RunQuantities& q : v.levels) iterations += q.newton_iterations, solve_seconds += q.seconds;
  state.counters["newton_iterations"] = iterations;
  state.counters["solve_seconds"] = solve_seconds;
  state.counters["levels"] = double(v.levels.size());
  state.counters["converged"] = v.converged;
  state.counters["last_change"] = v.last_change;
  state.counters["finest_faces"] = v.levels.back().faces;
  state.counters["C_finest"] = v.levels.back().compliance;
  state.counters["C_extrapolated"] = v.extrapolated_compliance;
  state.counters["error_bar"] = v.compliance_error_bar / v.extrapolated_compliance;
}

BENCHMARK(BM_Verify_Levels)
    ->Args({0, 1})
    ->Args({2, 0})
    ->Args({2, 1})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

// BM_PeakZoom/<s>/<m>: the plate clamped on one side with one hole of 15 mm (the test of the peak
// zoom), two graded levels from L = 4 mm, then s zoom steps; m = 0 re-solves the whole shell on
// each step, 1 the submodel of the finest level (solvers/conforming/zoom_submodel.h). Real time:
// the whole verify, levels included (s = 0 is the levels alone). Counters: zoom_seconds (the steps'
// meshing and solving), step_faces (the last step's triangles), patch_faces, peak (the last step's,
// J/m²).
void BM_PeakZoom(benchmark::State& state) {
  const PlateForVerify p;
  const std::vector<StencilParams> stencils{circle_at(0.0, 0.0, 0.015)};
  solvers::ConformingOptions o;
  o.edge_length = 0.004;
  o.levels = 2;
  o.grading_depth = 2;
  o.peak_zoom = int(state.range(0));
  o.zoom_submodel = state.range(1) == 1;
  solvers::ConformingVerification v;
  for (auto _ : state) v = solvers::verify_conforming(p.scene, p.meshes, p.lc, *p.ctx, stencils, o);
  double zoom = 0;
  for (size_t k = 1; k < v.zoom.steps.size(); ++k) zoom += v.zoom.steps[k].seconds + v.zoom.steps[k].mesh_seconds;
  state.counters["zoom_seconds"] = zoom;
  state.counters["step_faces"] = v.zoom.steps.empty() ? 0 : v.zoom.steps.back().faces;
  state.counters["patch_faces"] = v.zoom.submodel_faces;
  state.counters["peak"] = v.zoom.steps.empty() ? v.levels.back().peak : v.zoom.steps.back().peak;
}
BENCHMARK(BM_PeakZoom)
    ->Args({0, 1})
    ->Args({2, 0})
    ->Args({2, 1})
    ->Args({4, 0})
    ->Args({4, 1})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

BENCHMARK_CAPTURE(BM_Verify, Sheet, sheet())
    ->ArgsProduct({{0, 1, 2, 3, 4}, {0, 1, 2}})
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->Name("BM_Verify_Sheet");
BENCHMARK_CAPTURE(BM_Verify, Cantilever, cantilever())
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1, 2}})
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->Name("BM_Verify_Cantilever");
BENCHMARK_CAPTURE(BM_Verify, Perforated, perforated())
    ->ArgsProduct({{0, 1, 2}, {0, 1, 2}})
    ->UseManualTime()
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->Name("BM_Verify_Perforated");

}  // namespace
}  // namespace cutwork
