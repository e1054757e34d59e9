#pragma once
/// A design's report and its output folder, shared by `cutwork design`, `cutwork sweep` and the
/// end-to-end benchmarks (see run_report.h for why this room builds JSON).
///
/// The standard outputs of a design, written by write_design_outputs into one folder:
///   stencils.json  every stencil (host/pattern/stencils_json.h)
///   fields.ply     the simulation mesh with per-face alpha, W (final) and W_pattern
///   cut.obj        the base surface with every stencil outline cut out
///   fields.vtu, stencils.vtp, cut_solid.stl, cut_solid.3mf, render_*.png
///                  the designer's files (host/export/design_files.h), when add_design_files ran
///   report.json    design_report below; written last, so its presence says the set is complete
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/core/timer.h"
#include "host/cut/cut_surface.h"
#include "host/export/design_files.h"
#include "host/scene/scene.h"
#include "solvers/optimize/design_pipeline.h"

namespace cutwork::solvers {

/// What a run knows besides the design itself.
struct DesignRunInfo {
  Timings timings;                 ///< stages before run_design (scene, meshes, device, ...)
  nlohmann::json device = nullptr; ///< report.json's device {kind, name, driver}; null: left out
  std::vector<std::string> notes;  ///< the report's notes (automatic choices, adjustments)
  /// Re-solve the uncut shell and the final design at half the simulation edge length and report
  /// how far from converged the numbers are (report.json `discretisation`,
  /// solvers/conforming/discretisation_estimate.h); a note says when they are not.
  bool discretisation_estimate = true;
  /// Called before the estimate builds a level past the ones it always solves (h/8, only where
  /// those have not settled; DiscretisationOptions::before_extra_level). Optional.
  std::function<void(int level, size_t faces)> before_extra_level;
};

/// A finished design, computed in full and ready to be written. It refers to the scene's meshes,
/// the pattern context and the design result it was made from, which must outlive it.
struct DesignOutputs {
  const SceneMeshes* meshes = nullptr;
  const PatternContext* ctx = nullptr;
  const DesignResult* result = nullptr;
  CutSurface cut;          ///< the base mesh with the final stencils cut out, as the scene's tool
                           ///< cuts them (fabrication.tool_radius; cut_with_tool)
  nlohmann::json report;   ///< report.json
  /// The largest ligament peak estimate (J/m², solvers/objective/ligament_peak.h; NaN without
  /// concentration factors or narrow ligaments): report.json's structure.ligaments.W_ligament_max.
  double W_ligament_max = std::numeric_limits<double>::quiet_NaN();
  std::optional<DesignFiles> files;  ///< the designer's files (add_design_files), written before report.json
};

/// Cuts the final stencils out of the base mesh (timed as "cut") and builds the report: the
/// design's own timings are appended to `info.timings`, then "cut" and "total" (`since_start`,
/// the run's clock). Throws what cut_stencils throws.
DesignOutputs finish_design(const Scene& scene, const SceneMeshes& meshes, const PatternContext& ctx,
                            const DesignResult& result, DesignRunInfo info, const Stopwatch& since_start);

/// Per-vertex displacement (#V×3, m) of the simulation mesh in equilibrium with fill ratios `alpha`
/// (a fresh Newton solve with the scene's material and mechanics, the curve weighted by `stencils`;
/// the pipeline keeps summaries).
RowMatX3d equilibrium_displacement(const Scene& scene, const SceneMeshes& meshes, const LoadCase& load_case,
                                   const Eigen::VectorXd& alpha, std::span<const StencilParams> stencils = {});

/// The inputs of a design's files: final fields (α, W, W of the pattern design, displacement), the
/// stencils' outlines, the cut surface, β, the thickness and the printable minimum.
DesignFileInputs design_file_inputs(const Scene& scene, const SceneMeshes& meshes, const LoadCase& load_case,
                                    const PatternContext& ctx, const DesignResult& result, const CutSurface& cut);

/// Computes the designer's files of a finished design (prepare_design_files) into `outputs.files`,
/// and records their `fabrication` report and time ("design_files") in `outputs.report`.
void add_design_files(DesignOutputs& outputs, const Scene& scene, const LoadCase& load_case,
                      const DesignFileOptions& options);

/// The file names write_design_outputs writes for `outputs`, in order (report.json last).
std::vector<std::string> design_output_names(const DesignOutputs& outputs);

/// report.json of a design: base_report, device, stencils {count, initial, removed,
/// inserted_by_hole_filling, type_changes, by_type}, phases [{name, iterations, evaluations,
/// rounds, seconds, J/S/P at start and end, stop_reason, objective}], pattern, structure
/// {objective, w_S, beta, W_max/compliance/material_fraction/max_displacement of the designs,
/// overlaps, units, ...}, equilibrium (the final design's), designs {uncut, pattern, final},
/// cut, timings.stages, discretisation {uncut, final, converged, tolerance} (when estimated), notes.
nlohmann::json design_report(const Scene& scene, const SceneMeshes& meshes, const PatternContext& ctx,
                             const DesignResult& result, const CutSurface& cut, const DesignRunInfo& info);

/// One design's equilibrium as the report states it (stencils, W_max, compliance, ...).
nlohmann::json design_state_json(const DesignState& state);

/// Writes the standard outputs (file comment) where `place` puts them — an OutputSet's staging, to
/// be published as one set (host/core/output_set.h) — every file atomically, report.json last.
/// Throws InputError naming a file that cannot be written.
void write_design_outputs(const FilePlacer& place, const DesignOutputs& outputs);

/// One whole design of `scene` into `dir`, as `cutwork design` makes it: meshes, supports and
/// loads, pattern context, run_design with `options`, finish_design, add_design_files with
/// `file_options`, write_design_outputs into an OutputSet on `dir` published as one set.
/// `on_meshes` (optional) is called once the meshes exist, before a file's "auto" simulation mesh
/// is chosen (SceneMeshes::sim_choice_pending) and the design starts (the sweep reserves memory
/// there: estimate_design_memory covers what the choice may take). Returns report.json. Throws what the steps throw; writes nothing
/// unless the design succeeds.
nlohmann::json design_into_folder(const Scene& scene, const std::filesystem::path& dir, const DesignOptions& options,
                                  DesignRunInfo info = {},
                                  const std::function<void(const SceneMeshes&)>& on_meshes = {},
                                  const DesignFileOptions& file_options = {});

}  // namespace cutwork::solvers
