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

namespace cutwork::solvers {

/// `v` when finite, else null (JSON has no NaN or infinity).
nlohmann::json number_or_null(double v);

/// {name: seconds, ...} in the order the timings were recorded.
nlohmann::json timings_json(const Timings& timings);

/// scene, scene_source, mesh {vertices, triangles, sim_vertices, sim_triangles, sim_is_base,
/// map_max_distance}, timings.
nlohmann::json base_report(const Scene& scene, const SceneMeshes& meshes, const Timings& timings);

}  // namespace cutwork::solvers
