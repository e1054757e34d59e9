#include "solvers/conforming/simulation_mesh_choice.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

std::vector<double> level_errors(const std::vector<double>& compliances) {
  const Richardson r = richardson_extrapolate(compliances);
  const bool unsettled = compliances.size() >= 3 && !r.asymptotic;
  const double finest = compliances.back();
  std::vector<double> out;
  for (double c : compliances)
    out.push_back(unsettled ? (std::abs(c - finest) + r.error_bar) / std::abs(finest)
                  : r.extrapolated != 0 ? std::abs(c - r.extrapolated) / std::abs(r.extrapolated)
                                        : INFINITY);
  return out;
}

int most_simulation_subdivisions(size_t base_faces, const DiscretisationOptions& options) {
  int most = 0;
  while (most < kMaxSimSubdivisions && double(base_faces) * std::pow(4.0, most + 2) <= double(options.max_faces)) ++most;
  return most;
}

std::string choose_simulation_mesh(const Scene& scene, SceneMeshes& meshes, const DiscretisationOptions& options) {
  if (!meshes.sim_choice_pending) return {};
  meshes.sim_choice_pending = false;
  const std::string what = "mesh.sim_subdivisions auto";
  const int most = most_simulation_subdivisions(size_t(meshes.base.num_faces()), options);
  if (most < 1) {
    meshes.sim_choice = {{"subdivisions", 0},
                         {"summary", fmt::format("the file's mesh: a subdivision would leave its estimate's levels over "
                                                 "{} triangles",
                                                 options.max_faces)}};
    return {};
  }

  // The uncut shell on the file's mesh, with the scene's mechanics (what the run solves first).
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  const MechanicsSettings mechanics = uncut_scene_mechanics(scene);
  const ShellModel model(meshes.sim, scene.material, lc, mechanics);
  EquilibriumSolver solver(model, options.newton);
  const Eigen::VectorXd solid = Eigen::VectorXd::Ones(meshes.sim.num_faces());
  solver.solve(solid);
  const EquilibriumSummary coarse = summarize_equilibrium(model, solver.positions(), solid);
  const RowMatX3d u = solver.displacements();
  // Levels past h/4 while none that may be chosen is within the tolerance, or while the finest three
  // have not settled (their cautious errors would choose a finer mesh than needed: the 1984-facet
  // dome's file mesh reads 3.3% that way and 1.4% with one more level), up to the h/2 of the finest
  // that may be chosen.
  DiscretisationOptions o = options;
  o.refinements = 2;
  o.extra_refinements = std::max(0, most - 1);
  const int choosable = most;
  o.solve_another = [&o, choosable](const std::vector<double>& compliances) {
    if (compliances.size() >= 3 && !richardson_extrapolate(compliances).asymptotic) return true;
    const std::vector<double> e = level_errors(compliances);
    for (int k = 0; k <= std::min(choosable, int(e.size()) - 1); ++k)
      if (e[std::size_t(k)] <= o.tolerance) return false;
    return true;
  };
  DiscretisationEstimate study;
  {
    SimulationMeshRefinements refined(scene, meshes, o);
    const FillRatiosOnMesh ones = [](const SurfaceMesh& m) { return Eigen::VectorXd::Ones(m.num_faces()).eval(); };
    study = estimate_discretisation(scene, refined, ones, mechanics, coarse, simulation_edge_length(scene, meshes),
                                    meshes.sim, &u);
  }
  std::vector<double> compliances;
  for (const DiscretisationLevel& l : study.levels) compliances.push_back(l.quantities.compliance);
  const std::vector<double> errors = level_errors(compliances);

  nlohmann::json levels = nlohmann::json::array();
  for (std::size_t k = 0; k < study.levels.size(); ++k) {
    levels.push_back({{"subdivisions", k},
                      {"triangles", study.levels[k].faces},
                      {"compliance", study.levels[k].quantities.compliance},
                      {"error", std::isfinite(errors[k]) ? nlohmann::json(errors[k]) : nlohmann::json(nullptr)}});
  }
  std::string values;
  for (std::size_t k = 0; k < study.levels.size(); ++k)
    values += fmt::format("{}{:.4g} J ({} triangles, {:.1f}%)", values.empty() ? "" : ", ",
                          study.levels[k].quantities.compliance, study.levels[k].faces, 100 * errors[k]);

  int chosen = 0;
  bool converged = false;
  std::string summary;
  if (!study.supports_consistent) {
    summary = fmt::format("simulating on the file's mesh ({} triangles): the supports hold a different region on each "
                          "subdivision ({:.1f}% apart), so their compliances ({}) cannot say which is converged; "
                          "select the supports exactly (docs/SCENES.md)",
                          meshes.base.num_faces(), 100 * study.support_change, values);
  } else {
    const int last = std::min(most, int(study.levels.size()) - 1);
    chosen = last;
    for (int k = 0; k <= last; ++k)
      if (errors[std::size_t(k)] <= study.tolerance) {
        chosen = k;
        converged = true;
        break;
      }
    const std::string mesh = fmt::format("the file's mesh {}({} triangles)",
                                         chosen == 0   ? std::string()
                                         : chosen == 1 ? std::string("divided once ")
                                                       : fmt::format("divided {} times ", chosen),
                                         study.levels[std::size_t(chosen)].faces);
    const std::string levels_line = fmt::format("tolerance {:.0f}%; {}: {}", 100 * study.tolerance, study.rule, values);
    summary = converged ? fmt::format("simulating on {}: its uncut compliance is within {:.1f}% of the converged "
                                      "{:.4g} J ({})",
                                      mesh, 100 * errors[std::size_t(chosen)], study.compliance.extrapolated,
                                      levels_line)
                        : fmt::format("simulating on {}, the finest whose own estimate fits {} triangles: NOT "
                                      "converged, its uncut compliance is {:.1f}% from the converged {:.4g} J ({}); a "
                                      "finer file is closer",
                                      mesh, options.max_faces, 100 * errors[std::size_t(chosen)],
                                      study.compliance.extrapolated, levels_line);
  }
  if (chosen > 0) use_subdivided_simulation_mesh(meshes, chosen);
  meshes.sim_choice = {{"subdivisions", chosen},
                       {"levels", levels},
                       {"extrapolated", std::isfinite(study.compliance.extrapolated)
                                            ? nlohmann::json(study.compliance.extrapolated)
                                            : nlohmann::json(nullptr)},
                       {"rule", study.rule},
                       {"supports_consistent", study.supports_consistent},
                       {"tolerance", study.tolerance},
                       {"converged", converged},
                       {"summary", summary}};
  return what + ": " + summary;
}

}  // namespace cutwork::solvers
