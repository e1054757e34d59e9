#pragma once
/// report.json of `cutwork simulate`: one equilibrium of a scene's shell (see run_report.h for
/// why this room builds JSON).
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "host/core/timer.h"
#include "host/scene/scene.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/structural_quantities.h"

namespace cutwork::solvers {

/// Where the fill ratios of a simulation came from.
struct FillRatioSource {
  std::string source = "uncut";    ///< "uncut" or the stencils.json file
  int stencils = 0;
  const Eigen::VectorXd* alpha = nullptr;  ///< #F of the simulation mesh: what the stiffness sees
  /// #F: the faces' own fill ratios, which measure the material left (null: alpha). They differ
  /// from alpha under the cell filter (cell_filter.h), which is not exactly area-conserving.
  const Eigen::VectorXd* face_alpha = nullptr;
};

/// base_report, device (unless null), equilibrium {max_displacement(_vertex), strain_energy,
/// compliance, W_max(_face), Newton statistics, units}, material, solver {dofs, supports,
/// elements, matrix and factor sizes, ordering}, fill_ratio {source, stencils, min, mean,
/// material_fraction}. `solver` must have solved the equilibrium `stats`/`summary` describe.
nlohmann::json simulate_report(const Scene& scene, const SceneMeshes& meshes, const ShellModel& model,
                               const EquilibriumSolver& solver, const EquilibriumStats& stats,
                               const EquilibriumSummary& summary, const FillRatioSource& fill,
                               const Timings& timings, const nlohmann::json& device);

}  // namespace cutwork::solvers
