#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/report/run_report.h"

#include <cmath>

namespace cutwork::solvers {

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json timings_json(const Timings& timings) {
  nlohmann::json t = nlohmann::json::object();
  for (const auto& [name, seconds] : timings.entries()) t[name] = seconds;
  return t;
}

nlohmann::json base_report(const Scene& scene, const SceneMeshes& meshes, const Timings& timings) {
  nlohmann::json r;
  r["scene"] = scene.name;
  r["scene_source"] = scene_origin(scene);
  r["mesh"] = {{"vertices", meshes.base.num_vertices()},
               {"triangles", meshes.base.num_faces()},
               {"sim_vertices", meshes.sim.num_vertices()},
               {"sim_triangles", meshes.sim.num_faces()},
               {"sim_is_base", meshes.sim_is_base},
               {"map_max_distance", meshes.map.max_distance}};
  const MechanicsSettings mechanics = scene_mechanics(scene);
  r["mechanics"] = {{"bending", mechanics.bending == BendingModel::Hinge ? "hinge" : "shape_operator"},
                    {"stiffness", mechanics.stiffness == FillStiffness::Homogenised ? "homogenised" : "linear"},
                    {"filter", mechanics.filter == FillFilter::Cell ? "cell" : "none"}};
  if (!mechanics.stiffness_curve.empty()) {
    const FillStiffnessCurve& c = mechanics.stiffness_curve;
    r["mechanics"]["stiffness_curve"] = {{"alpha", c.alpha}, {"membrane_ratio", c.membrane}, {"bending_ratio", c.bending}};
    if (c.split()) {
      nlohmann::json& j = r["mechanics"]["stiffness_curve"];
      j["membrane_bulk_ratio"] = c.membrane_bulk;
      j["membrane_shear_ratio"] = c.membrane_shear;
      j["bending_bulk_ratio"] = c.bending_bulk;
      j["bending_shear_ratio"] = c.bending_shear;
    }
    // The cell problems' concentration factors K = peak / mean energy density (W_peak's; the
    // sample at α = 1 is the dilute limit).
    if (!c.membrane_concentration.empty()) {
      r["mechanics"]["stiffness_curve"]["membrane_concentration"] = c.membrane_concentration;
      r["mechanics"]["stiffness_curve"]["bending_concentration"] = c.bending_concentration;
    }
  }
  r["timings"] = timings_json(timings);
  return r;
}

}  // namespace cutwork::solvers
