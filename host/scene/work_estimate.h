#pragma once
/// Estimates of the work a scene asks for, made before the work is done, and the check of them
/// against the limits in force (host/core/work_limits.h).
#include "host/scene/scene.h"

namespace cutwork {

/// About how many stencils the pattern phase places on `base` for `settings`: the requested
/// `count`; for a fixed `scale` ℓ the Poisson-disk jamming estimate
/// 0.547 · A · mean(sizing⁻²) / (π ((1 + s) ℓ)²) (A: the surface's area, m²); for the automatic
/// scale, 300 (the automatic count).
double estimate_stencil_count(const PatternSettings& settings, const SurfaceMesh& base);

/// Throws InputError("<origin>: /pattern/<key>: ... about N stencils, more than the limit M
/// (--max-stencils)") when the estimate exceeds work_limits().max_stencils.
void check_stencil_work(const Scene& scene, const SceneMeshes& meshes);

}  // namespace cutwork
