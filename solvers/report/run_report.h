#pragma once
/// The parts of report.json every pipeline writes (design, simulate, each variant of a sweep).
///
/// solvers/report is the one room of cutwork::solvers that builds JSON: it turns solver results
/// into report objects (nlohmann::json) and writes output folders, so that the CLI, the
/// benchmarks and `cutwork sweep` write exactly the same thing. It never parses JSON, and no
/// solver maths includes it (it sits above solvers/optimize, beside nothing that computes).
#include <nlohmann/json.hpp>

#include "host/core/timer.h"
#include "host/scene/scene.h"
#include "host/stencil/frame.h"
#include "solvers/objective/ligament_peak.h"

namespace cutwork::solvers {

/// `v` when finite, else null (JSON has no NaN or infinity).
nlohmann::json number_or_null(double v);

/// {name: seconds, ...} in the order the timings were recorded.
nlohmann::json timings_json(const Timings& timings);

/// scene, scene_source, mesh {vertices, triangles, sim_vertices, sim_triangles, sim_is_base,
/// map_max_distance}, timings.
/// `mechanics`: the rule the run used (its calibrated curve goes into the report); null: the
/// scene's, calibrated with equal shape weights (scene_mechanics).
nlohmann::json base_report(const Scene& scene, const SceneMeshes& meshes, const Timings& timings,
                           const MechanicsSettings* mechanics = nullptr);

/// The ligament peak estimate (solvers/objective/ligament_peak.h) as report.json's
/// `structure.ligaments` (design) and verify's `peak.ligaments`: the rule, how many ligaments were
/// searched and how many are narrower than the shell is thick, the largest W_lig, and the `worst`
/// ligaments (at most `listed`, largest W_lig first), each with its width, rims' radii, x, the
/// lattice's x at the face read, the factor and where it is.
nlohmann::json ligament_peak_json(const LigamentPeakSummary& summary, double thickness, int listed = 5);

/// The stencils' arrangement (host/pattern/lattice_order.h), measured at their frames on the
/// surface (`bvh`, `field`) from the scene's lattice axis, as report.json's `lattice_order`: the
/// stated lattice, how many stencils were measured, the median |ψ₄| (square) and |ψ₆| (hexagonal)
/// and the square lattice's axes' median angle from the axis the model used (lattice_axis, or the
/// field's at each stencil where the lattice follows the field). Appends a line to `notes` where
/// the arrangement and the lattice used disagree: a square arrangement (|ψ₄| ≥ 0.7, |ψ₆| < 0.5)
/// under the hexagonal calibration where the model could have followed it (measure_lattice reads
/// it as square: one axis or the field fits; a lattice read at a design's pattern end that the
/// structural phase moved into one included), a square lattice used that the stencils do not form
/// (|ψ₄| < 0.5), or its axes more than 10° from the axis used.
nlohmann::json lattice_order_json(const MechanicsSettings& mechanics, const FaceBvh& bvh, const TangentField& field,
                                  std::span<const StencilParams> stencils, std::vector<std::string>& notes);

/// Appends a line to `notes` per symmetry plane of `load_case` (LoadCase::symmetry_planes) that
/// stencils cross (their bounding circles reach over it): the built shell, the modelled half and its
/// mirror image, has each such hole united with its mirror image, which the half's model does not
/// see (it cuts the stencil at the plane).
void symmetry_plane_notes(const LoadCase& load_case, std::span<const StencilParams> stencils,
                          std::vector<std::string>& notes);

}  // namespace cutwork::solvers
