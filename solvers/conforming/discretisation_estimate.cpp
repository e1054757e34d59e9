#include "solvers/conforming/discretisation_estimate.h"

#include <cmath>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/core/work_limits.h"
#include "host/surfaces/generators.h"

namespace cutwork::solvers {

namespace {
nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

double relative_change(double coarse, double fine) {
  return fine != 0 ? std::abs(coarse - fine) / std::abs(fine) : (coarse == 0 ? 0.0 : INFINITY);
}
}  // namespace

double simulation_edge_length(const Scene& scene, const SceneMeshes& meshes) {
  if (scene.mesh.generator.empty()) return meshes.sim.mean_edge_length();
  return scene.mesh.sim_edge_length > 0 ? scene.mesh.sim_edge_length : scene.mesh.edge_length;
}

std::vector<RefinedSimulationMesh> refine_simulation_mesh(const Scene& scene, const SceneMeshes& meshes,
                                                          const DiscretisationOptions& options) {
  std::vector<RefinedSimulationMesh> out;
  double h = simulation_edge_length(scene, meshes);
  double faces = meshes.sim.num_faces();
  for (int k = 0; k < options.refinements; ++k) {
    h *= 0.5;
    faces *= 4;
    if (k > 0 && faces > options.max_faces) break;  // (h/2 always: the estimate needs one refinement)
    RefinedSimulationMesh r;
    if (scene.mesh.generator.empty()) {
      r.mesh = midpoint_subdivision(out.empty() ? meshes.sim : out.back().mesh);
      r.method = "subdivided";
      r.edge_length = r.mesh.mean_edge_length();
    } else {
      r.edge_length = h;
      try {
        r.mesh = generate_shape(scene.mesh.generator, scene.mesh.params, h, work_limits().max_faces,
                                fmt::format("sim_edge_length / {} (the discretisation estimate)", 2 << k));
      } catch (const InputError& e) {
        throw InputError(scene_origin(scene) + ": /mesh: " + e.what());
      }
      r.method = "regenerated";
    }
    faces = r.mesh.num_faces();
    out.push_back(std::move(r));
  }
  return out;
}

DiscretisationEstimate estimate_discretisation(const Scene& scene, const std::vector<RefinedSimulationMesh>& refined,
                                               const FillRatiosOnMesh& fill_on, const MechanicsSettings& mechanics,
                                               const EquilibriumScalars& coarse, double coarse_edge_length,
                                               int coarse_faces, const DiscretisationOptions& options) {
  if (refined.empty()) throw InternalError("estimate_discretisation: no refined mesh");
  DiscretisationEstimate e;
  e.method = refined.front().method;
  e.tolerance = options.tolerance;
  e.levels.push_back({coarse_edge_length, coarse_faces, coarse});
  for (const RefinedSimulationMesh& r : refined) {
    const Eigen::VectorXd alpha = fill_on(r.mesh);
    const LoadCase lc = resolve_load_case(scene, r.mesh);
    const ShellModel model(r.mesh, scene.material, lc, mechanics);
    EquilibriumSolver solver(model, options.newton);
    solver.solve(alpha);
    e.levels.push_back({r.edge_length, r.mesh.num_faces(), summarize_equilibrium(model, solver.positions(), alpha)});
  }
  std::vector<double> compliances;
  for (const DiscretisationLevel& l : e.levels) compliances.push_back(l.quantities.compliance);
  e.compliance = richardson_extrapolate(compliances);
  const double c_h = coarse.compliance, c_finest = compliances.back();
  if (e.levels.size() >= 3 && !e.compliance.asymptotic) {
    e.rule = "not asymptotic";
    e.estimated_error = (std::abs(c_h - c_finest) + e.compliance.error_bar) / std::abs(c_finest);
  } else {
    e.rule = e.levels.size() >= 3 ? "richardson" : "first order assumed";
    e.estimated_error = relative_change(c_h, e.compliance.extrapolated);
  }
  const EquilibriumScalars& half = e.levels[1].quantities;
  e.compliance_change = relative_change(c_h, half.compliance);
  e.W_max_change = relative_change(coarse.W_max, half.W_max);
  e.max_displacement_change = relative_change(coarse.max_displacement, half.max_displacement);
  e.converged = e.estimated_error <= e.tolerance;
  return e;
}

std::string discretisation_line(const DiscretisationEstimate& e) {
  std::string values;
  for (const DiscretisationLevel& l : e.levels)
    values += fmt::format("{}{:.4g} J at {:.3g} m", values.empty() ? "" : ", ", l.quantities.compliance, l.edge_length);
  return fmt::format(
      "compliance {} ({}{}): estimated discretisation error of the first {:.1f}% (tolerance {:.0f}%){}; W_max changes "
      "by {:.1f}% at half the edge length",
      values, e.rule,
      std::isfinite(e.compliance.order) ? fmt::format(", observed order {:.2f}", e.compliance.order) : std::string(),
      100 * e.estimated_error, 100 * e.tolerance,
      e.converged ? ", converged"
                  : fmt::format(": NOT converged, the simulation mesh is too coarse for these numbers (a finer "
                                "mesh.sim_edge_length, e.g. {:.3g} m, is closer)",
                                e.levels.back().edge_length),
      100 * e.W_max_change);
}

nlohmann::json discretisation_json(const DiscretisationEstimate& e) {
  nlohmann::json levels = nlohmann::json::array();
  for (const DiscretisationLevel& l : e.levels)
    levels.push_back({{"edge_length", l.edge_length},
                      {"faces", l.faces},
                      {"compliance", l.quantities.compliance},
                      {"strain_energy", l.quantities.strain_energy},
                      {"W_max", l.quantities.W_max},
                      {"max_displacement", l.quantities.max_displacement}});
  return {{"method", e.method},
          {"levels", levels},
          {"compliance_extrapolated", number_or_null(e.compliance.extrapolated)},
          {"observed_order", number_or_null(e.compliance.order)},
          {"compliance_error_bar", number_or_null(e.compliance.error_bar)},
          {"rule", e.rule},
          {"estimated_error", number_or_null(e.estimated_error)},
          {"compliance_change", number_or_null(e.compliance_change)},
          {"W_max_change", number_or_null(e.W_max_change)},
          {"max_displacement_change", number_or_null(e.max_displacement_change)},
          {"tolerance", e.tolerance},
          {"converged", e.converged},
          {"summary", discretisation_line(e)}};
}

}  // namespace cutwork::solvers
