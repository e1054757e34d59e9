// Scaling of the equilibrium with the mesh: the built-in `sheet` scene (1 m, pinned boundary,
// self-weight, h = 2 mm) simulated on its base mesh at about 2e3 / 2e4 / 2e5 faces, Newton from rest
// as `cutwork simulate` runs it, under the process's thread policy (solvers/linear/thread_policy.h).
//
//   BM_Equilibrium_Sheet/<faces>   one equilibrium from rest (the model and CHOLMOD's symbolic
//                                  analysis built once, outside the timing).
// Counters: faces, dofs, newton_iterations, factorizations, krylov_steps and krylov_iterations
// (Newton–Krylov steps and their conjugate-gradient iterations), factor_nonzeros, gflop (one
// factorisation), assembly_s, factorization_s, solve_s (CG included) per equilibrium; the ordering
// as label.
// The 2e5 size takes minutes on two cores; filter it out with --benchmark_filter=Sheet/2000\b etc.
#include <benchmark/benchmark.h>

#include <cmath>

#include "host/scene/scene.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/equilibrium/equilibrium_solver.h"

namespace cutwork {
namespace {

void BM_Equilibrium_Sheet(benchmark::State& state) {
  const double faces = double(state.range(0));
  Scene scene = load_scene("sheet");
  // Near-equilateral triangles of edge e: √3/4 e² each, on the 1 m² sheet.
  scene.mesh.edge_length = std::sqrt(4.0 / (std::sqrt(3.0) * faces));
  scene.mesh.sim_edge_length = 0;
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  const solvers::ShellModel model(meshes.sim, scene.material, lc, solvers::scene_mechanics(scene));
  solvers::EquilibriumSolver solver(model);
  const Eigen::VectorXd alpha = Eigen::VectorXd::Ones(model.num_faces());
  double iterations = 0, factorizations = 0, krylov_steps = 0, krylov_iterations = 0;
  double assembly = 0, factorization = 0, solve = 0;
  for (auto _ : state) {
    solver.reset();
    const solvers::EquilibriumStats& s = solver.solve(alpha);
    iterations += s.newton_iterations;
    factorizations += s.factorizations;
    krylov_steps += s.krylov_steps;
    krylov_iterations += s.krylov_iterations;
    assembly += s.assembly_seconds;
    factorization += s.factorization_seconds;
    solve += s.solve_seconds;
  }
  const double n = double(state.iterations());
  state.counters["faces"] = model.num_faces();
  state.counters["dofs"] = model.num_dofs();
  state.counters["newton_iterations"] = iterations / n;
  state.counters["factorizations"] = factorizations / n;
  state.counters["krylov_steps"] = krylov_steps / n;
  state.counters["krylov_iterations"] = krylov_iterations / n;
  state.counters["assembly_s"] = assembly / n;
  state.counters["factorization_s"] = factorization / n;
  state.counters["solve_s"] = solve / n;
  state.counters["factor_nonzeros"] = double(solver.linear_solver().factor_nonzeros());
  state.counters["gflop"] = solver.linear_solver().factorization_flops() * 1e-9;
  state.SetLabel(solver.linear_solver().ordering());
}
BENCHMARK(BM_Equilibrium_Sheet)->Arg(2000)->Arg(20000)->Arg(200000)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
}  // namespace cutwork
