#include "solvers/report/simulate_report.h"

#include <cmath>

#include "solvers/objective/peak_energy_density.h"
#include "solvers/report/run_report.h"

namespace cutwork::solvers {

nlohmann::json simulate_report(const Scene& scene, const SceneMeshes& meshes, const ShellModel& model,
                               const EquilibriumSolver& solver, const EquilibriumStats& stats,
                               const EquilibriumSummary& summary, const FillRatioSource& fill,
                               const Timings& timings, const nlohmann::json& device) {
  nlohmann::json report = base_report(scene, meshes, timings, &model.mechanics());
  if (!device.is_null()) report["device"] = device;
  report["equilibrium"] = {
      {"max_displacement", summary.max_displacement},
      {"max_displacement_vertex", summary.max_displacement_vertex},
      {"strain_energy", summary.strain_energy},
      {"compliance", summary.compliance},
      {"W_max", summary.W_max},
      {"W_max_face", summary.W_max_face},
      {"W_peak_max", number_or_null(summary.W_peak_max)},
      {"W_peak_max_face", summary.W_peak_max_face},
      // ρ of the stress and the moment at that face (−1 pure shear, 0 uniaxial, 1 equibiaxial).
      {"W_peak_biaxiality", {{"membrane", number_or_null(summary.W_peak_membrane_biaxiality)},
                             {"bending", number_or_null(summary.W_peak_bending_biaxiality)}}},
      // ρ/h of the thick-plate transition, and W_peak with Kirchhoff's factors (null where it does
      // not apply).
      {"W_peak_thick_scale", summary.W_peak_thick_scale},
      {"W_peak_kirchhoff_max", number_or_null(summary.W_peak_kirchhoff_max)},
      {"W_peak_rule", std::isfinite(summary.W_peak_max)
                          ? nlohmann::json(kPeakEnergyDensityRule)
                          : nlohmann::json(kPeakEnergyDensityAbsent)},
      {"newton_iterations", stats.newton_iterations},
      {"residual", stats.residual},
      {"converged", stats.converged},
      {"stop", stats.stop},
      {"stable", stats.stable},
      {"load_norm", stats.load_norm},
      {"factorizations", stats.factorizations},
      {"shifted_factorizations", stats.shifted_factorizations},
      {"units", {{"max_displacement", "m"}, {"strain_energy", "J"}, {"compliance", "J"}, {"W_max", "J/m^2"},
                 {"W_peak_max", "J/m^2"}, {"load_norm", "N"}, {"residual", "force residual / load norm"}}}};
  const ShellStiffness& k = model.stiffness();
  report["material"] = {{"youngs_modulus", scene.material.youngs_modulus},
                        {"poisson_ratio", scene.material.poisson_ratio},
                        {"thickness", scene.material.thickness},
                        {"density", scene.material.density},
                        {"bending_stiffness", k.bending}};
  int fixed = 0, clamped = 0, held = 0;
  const auto symmetry_planes_json = [](const LoadCase& lc) {
    nlohmann::json planes = nlohmann::json::object();  // {"x": 0} for the plane x = 0
    for (int a = 0; a < 3; ++a)
      if (std::isfinite(lc.symmetry_planes[a])) planes[std::string(1, char('x' + a))] = lc.symmetry_planes[a];
    return planes;
  };
  for (int v = 0; v < model.num_vertices(); ++v) {
    fixed += model.fixed()[v] ? 1 : 0;
    clamped += model.load_case().clamped[v] ? 1 : 0;
    held += !model.fixed()[v] && model.load_case().held_axes[size_t(v)] != 0 ? 1 : 0;
  }
  const CholmodSolver& chol = solver.linear_solver();
  report["solver"] = {{"dofs", model.num_dofs()},
                      {"fixed_vertices", fixed},
                      {"clamped_vertices", clamped},
                      {"held_vertices", held},
                      {"symmetry_planes", symmetry_planes_json(model.load_case())},
                      {"membranes", model.num_faces()},
                      {"bending", scene.mechanics.bending == BendingModel::Hinge ? "hinge" : "shape_operator"},
                      {"stiffness", model.fill_stiffness().linear() ? "linear" : "homogenised"},
                      {"bends", model.bends().size()},
                      {"hinges", model.hinges().size()},
                      {"clamp_hinges", model.clamp_hinges().size()},
                      {"matrix_nonzeros", model.assembly().num_nonzeros()},
                      {"factor_nonzeros", chol.factor_nonzeros()},
                      {"ordering", chol.ordering()},
                      {"supernodal", chol.supernodal()},
                      {"assembly_colours", model.assembly().colours().size()}};
  const Eigen::VectorXd& A = meshes.sim.face_areas();
  const Eigen::VectorXd& alpha = *fill.alpha;
  report["fill_ratio"] = {{"source", fill.source},
                          {"stencils", fill.stencils},
                          {"min", alpha.minCoeff()},
                          {"mean", alpha.mean()},
                          {"material_fraction", (fill.face_alpha ? *fill.face_alpha : alpha).dot(A) / A.sum()}};
  return report;
}

}  // namespace cutwork::solvers
