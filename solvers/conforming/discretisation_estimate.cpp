#include "solvers/conforming/discretisation_estimate.h"

#include <algorithm>
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
                                               const SurfaceMesh& coarse_mesh, const DiscretisationOptions& options) {
  if (refined.empty()) throw InternalError("estimate_discretisation: no refined mesh");
  DiscretisationEstimate e;
  e.method = refined.front().method;
  e.tolerance = options.tolerance;
  e.support_tolerance = options.support_tolerance;
  {
    const LoadCase lc = resolve_load_case(scene, coarse_mesh);
    e.levels.push_back({coarse_edge_length, coarse_mesh.num_faces(), coarse, support_extent(coarse_mesh, lc.fixed),
                        support_extent(coarse_mesh, lc.clamped)});
  }
  e.support_change = 0;
  for (const RefinedSimulationMesh& r : refined) {
    const Eigen::VectorXd alpha = fill_on(r.mesh);
    const LoadCase lc = resolve_load_case(scene, r.mesh);
    const ShellModel model(r.mesh, scene.material, lc, mechanics);
    EquilibriumSolver solver(model, options.newton);
    solver.solve(alpha);
    e.levels.push_back({r.edge_length, r.mesh.num_faces(), summarize_equilibrium(model, solver.positions(), alpha),
                        support_extent(r.mesh, lc.fixed), support_extent(r.mesh, lc.clamped)});
    e.support_change = std::max({e.support_change, support_extent_change(e.levels.front().fixed, e.levels.back().fixed, coarse_edge_length),
                                 support_extent_change(e.levels.front().clamped, e.levels.back().clamped, coarse_edge_length)});
  }
  e.supports_consistent = e.support_change <= e.support_tolerance;
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
  e.converged = e.estimated_error <= e.tolerance && e.supports_consistent;
  return e;
}

namespace {
std::string extent_words(const SupportExtent& x) {
  std::vector<std::string> parts;
  if (x.length > 0) parts.push_back(fmt::format("{:.4g} m of line", x.length));
  if (x.area > 0) parts.push_back(fmt::format("{:.4g} m² of area", x.area));
  if (x.points > 0) parts.push_back(fmt::format("{} point{}", x.points, x.points == 1 ? "" : "s"));
  if (parts.empty()) return "nothing";
  std::string out = parts.front();
  for (std::size_t k = 1; k < parts.size(); ++k) out += (k + 1 == parts.size() ? " and " : ", ") + parts[k];
  return out;
}
}  // namespace

std::string discretisation_line(const DiscretisationEstimate& e) {
  if (!e.supports_consistent && e.levels.size() >= 2) {
    // Name the level that differs most and the set (fixed or clamped) that differs.
    const DiscretisationLevel& h = e.levels.front();
    const DiscretisationLevel* worst = &e.levels[1];
    bool clamped = false;
    double change = -1;
    for (std::size_t k = 1; k < e.levels.size(); ++k)
      for (bool c : {false, true}) {
        const double d =
            support_extent_change(c ? h.clamped : h.fixed, c ? e.levels[k].clamped : e.levels[k].fixed, h.edge_length);
        if (d > change) change = d, worst = &e.levels[k], clamped = c;
      }
    return fmt::format(
        "NOT converged: the supports hold a different region on each refinement ({} vertices: {} at {:.3g} m, {} at "
        "{:.3g} m, a change of {:.1f}% against a tolerance of {:.0f}%), so the levels are different structures and "
        "their compliances ({:.4g} J, {:.4g} J) say nothing of the mesh's error: the supports' selector depends on "
        "the mesh (a box that catches a surface rising tangentially out of it, or that cuts a support line between "
        "vertices); select the support region exactly (feet on z = 0: \"z\": {{\"below\": 1e-6}})",
        clamped ? "clamped" : "fixed", extent_words(clamped ? h.clamped : h.fixed), h.edge_length,
        extent_words(clamped ? worst->clamped : worst->fixed), worst->edge_length, 100 * change,
        100 * e.support_tolerance, h.quantities.compliance, worst->quantities.compliance);
  }
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

nlohmann::json support_extent_json(const SupportExtent& x) {
  return {{"area", x.area}, {"length", x.length}, {"points", x.points}};
}

nlohmann::json discretisation_json(const DiscretisationEstimate& e) {
  nlohmann::json levels = nlohmann::json::array();
  for (const DiscretisationLevel& l : e.levels)
    levels.push_back({{"edge_length", l.edge_length},
                      {"faces", l.faces},
                      {"compliance", l.quantities.compliance},
                      {"strain_energy", l.quantities.strain_energy},
                      {"W_max", l.quantities.W_max},
                      {"max_displacement", l.quantities.max_displacement},
                      {"supports", {{"fixed", support_extent_json(l.fixed)}, {"clamped", support_extent_json(l.clamped)}}}});
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
          {"support_change", number_or_null(e.support_change)},
          {"support_tolerance", e.support_tolerance},
          {"supports_consistent", e.supports_consistent},
          {"tolerance", e.tolerance},
          {"converged", e.converged},
          {"summary", discretisation_line(e)}};
}

}  // namespace cutwork::solvers
