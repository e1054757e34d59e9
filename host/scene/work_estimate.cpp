#include "host/scene/work_estimate.h"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/work_limits.h"
#include "host/field/sizing_field.h"

namespace cutwork {

WorkLimits& work_limits() {
  static WorkLimits limits;
  return limits;
}

double estimate_stencil_count(const PatternSettings& settings, const SurfaceMesh& base) {
  if (settings.count > 0) return settings.count;
  if (!(settings.scale > 0)) return 300;
  // The sizing field shrinks stencils where it is below 1 (a sizing file is read here too).
  const SizingField sizing = SizingField::from_settings(settings, base);
  const double area = base.face_areas().sum();
  const double spacing = (1 + settings.s) * settings.scale;
  return 0.547 * area * sizing.mean_power(base, -2.0) / (std::numbers::pi * spacing * spacing);
}

void check_stencil_work(const Scene& scene, const SceneMeshes& meshes) {
  const double estimate = estimate_stencil_count(scene.pattern, meshes.base);
  const int limit = work_limits().max_stencils;
  if (estimate <= limit) return;
  const double area = meshes.base.face_areas().sum();
  const std::string what =
      scene.pattern.count > 0
          ? fmt::format("/pattern/count: {} stencils", scene.pattern.count)
          : scene.pattern.scale > 0
                ? fmt::format("/pattern/scale: {:g} m gives about {:.3g} stencils on {:.4g} m^2", scene.pattern.scale,
                              estimate, area)
                : fmt::format("/pattern: the automatic scale gives about {:.0f} stencils", estimate);
  throw InputError(fmt::format("{}: {}, more than the limit of {} (raise it with --max-stencils if this is meant)",
                               scene_origin(scene), what, limit));
}

}  // namespace cutwork

namespace cutwork {

double factor_bytes(long factor_nonzeros) { return double(factor_nonzeros) * (sizeof(double) + sizeof(int)); }

void check_factor_work(const Scene& scene, const SceneMeshes& meshes, long factor_nonzeros) {
  const double gb = factor_bytes(factor_nonzeros) / 1e9, limit = work_limits().max_factor_gb;
  if (gb <= limit) return;
  throw InputError(fmt::format("{}: the stiffness factor of the simulation mesh ({} faces) would take about {:.3g} GB "
                               "({} nonzeros, from CHOLMOD's analysis), more than the limit of {:g} GB (raise it with "
                               "--max-factor-gb, or coarsen the simulation mesh: /mesh/sim_edge_length)",
                               scene_origin(scene), meshes.sim.num_faces(), gb, factor_nonzeros, limit));
}

}  // namespace cutwork
