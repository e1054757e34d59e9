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

/// Memory (bytes) of a Cholesky factor with `factor_nonzeros` entries: a double and a row index
/// each (CHOLMOD's supernodal factor stores about that).
double factor_bytes(long factor_nonzeros);

/// Throws InputError("<origin>: the stiffness factor of the simulation mesh (F faces) would take
/// about X GB ..., more than the limit of Y GB (--max-factor-gb)") when factor_bytes exceeds
/// work_limits().max_factor_gb; `factor_nonzeros` comes from CHOLMOD's symbolic analysis.
void check_factor_work(const Scene& scene, const SceneMeshes& meshes, long factor_nonzeros);

}  // namespace cutwork
