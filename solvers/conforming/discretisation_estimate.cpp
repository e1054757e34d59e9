#include "solvers/conforming/discretisation_estimate.h"

#include <cmath>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/timer.h"
#include "host/core/work_limits.h"
#include "host/surfaces/generators.h"

namespace cutwork::solvers {

namespace {
double relative_change(double coarse, double fine) {
  return fine != 0 ? std::abs(coarse - fine) / std::abs(fine) : (coarse == 0 ? 0.0 : INFINITY);
}
}  // namespace

double simulation_edge_length(const Scene& scene, const SceneMeshes& meshes) {
  if (scene.mesh.generator.empty()) return meshes.sim.mean_edge_length();
  return scene.mesh.sim_edge_length > 0 ? scene.mesh.sim_edge_length : scene.mesh.edge_length;
}

RefinedSimulationMesh refine_simulation_mesh(const Scene& scene, const SceneMeshes& meshes) {
  RefinedSimulationMesh r;
  if (scene.mesh.generator.empty()) {
    r.mesh = midpoint_subdivision(meshes.sim);
    r.method = "subdivided";
    r.edge_length = r.mesh.mean_edge_length();
    return r;
  }
  r.edge_length = 0.5 * simulation_edge_length(scene, meshes);
  try {
    r.mesh = generate_shape(scene.mesh.generator, scene.mesh.params, r.edge_length, work_limits().max_faces,
                            "sim_edge_length / 2 (the discretisation estimate)");
  } catch (const InputError& e) {
    throw InputError(scene_origin(scene) + ": /mesh: " + e.what());
  }
  r.method = "regenerated";
  return r;
}

DiscretisationEstimate estimate_discretisation(const Scene& scene, const RefinedSimulationMesh& refined,
                                               const Eigen::VectorXd& refined_alpha,
                                               const MechanicsSettings& mechanics, const EquilibriumScalars& coarse,
                                               double coarse_edge_length, int coarse_faces,
                                               const NewtonSettings& settings) {
  Stopwatch sw;
  DiscretisationEstimate e;
  e.method = refined.method;
  e.edge_length = coarse_edge_length;
  e.refined_edge_length = refined.edge_length;
  e.faces = coarse_faces;
  e.refined_faces = refined.mesh.num_faces();
  e.coarse = coarse;
  const LoadCase lc = resolve_load_case(scene, refined.mesh);
  const ShellModel model(refined.mesh, scene.material, lc, mechanics);
  EquilibriumSolver solver(model, settings);
  solver.solve(refined_alpha);
  e.refined = summarize_equilibrium(model, solver.positions(), refined_alpha);
  e.compliance_change = relative_change(coarse.compliance, e.refined.compliance);
  e.W_max_change = relative_change(coarse.W_max, e.refined.W_max);
  e.max_displacement_change = relative_change(coarse.max_displacement, e.refined.max_displacement);
  e.estimated_error = 2 * e.compliance_change;
  e.converged = e.estimated_error <= e.tolerance;
  e.seconds = sw.seconds();
  return e;
}

std::string discretisation_line(const DiscretisationEstimate& e) {
  return fmt::format(
      "compliance {:.4g} J at the simulation mesh's edge length {:.3g} m, {:.4g} J at {:.3g} m: estimated "
      "discretisation error {:.1f}% (tolerance {:.0f}%){}; W_max changes by {:.1f}%",
      e.coarse.compliance, e.edge_length, e.refined.compliance, e.refined_edge_length, 100 * e.estimated_error,
      100 * e.tolerance,
      e.converged ? ", converged"
                  : fmt::format(": NOT converged, the simulation mesh is too coarse for these numbers (a finer "
                                "mesh.sim_edge_length, e.g. {:.3g} m, is closer)",
                                e.refined_edge_length),
      100 * e.W_max_change);
}

nlohmann::json discretisation_json(const DiscretisationEstimate& e) {
  auto scalars = [](const EquilibriumScalars& s) {
    return nlohmann::json{{"compliance", s.compliance},
                          {"strain_energy", s.strain_energy},
                          {"W_max", s.W_max},
                          {"max_displacement", s.max_displacement}};
  };
  return {{"method", e.method},
          {"edge_length", e.edge_length},
          {"refined_edge_length", e.refined_edge_length},
          {"faces", e.faces},
          {"refined_faces", e.refined_faces},
          {"at_h", scalars(e.coarse)},
          {"at_h_over_2", scalars(e.refined)},
          {"compliance_change", e.compliance_change},
          {"W_max_change", e.W_max_change},
          {"max_displacement_change", e.max_displacement_change},
          {"estimated_error", e.estimated_error},
          {"estimated_error_rule", "2 |C_h - C_h/2| / |C_h/2| (first-order convergence or better)"},
          {"tolerance", e.tolerance},
          {"converged", e.converged},
          {"summary", discretisation_line(e)}};
}

}  // namespace cutwork::solvers
