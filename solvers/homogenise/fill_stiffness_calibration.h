#pragma once
/// The homogenised fill stiffness rule of a design (mechanics.stiffness = "homogenised"): the
/// ratios r_m(α), r_b(α) of fill_stiffness_map.h calibrated by cell homogenisation
/// (cell_homogenisation.h) for the design's stencil shapes and material.
///
/// Samples: α on a fixed grid (kCalibrationGrid) down to the lowest fill ratio a shape reaches
/// in the lattice (1 − max_hole_fraction); below that a shape's ratio is held at its lowest sample
/// (the map holds r constant below its first sample too). With several shapes the ratios are
/// averaged with equal weights (a face's fill ratio does not say which shape cut it). Ratios
/// depend on the shapes and on ν only (not on E, h, or the design's scale).
///
/// Concentration factors K (cell_homogenisation.h) ride on the same cell solves: per sample, the
/// largest over the shapes (a face's fill ratio does not say which shape cut it); below a shape's
/// lowest fill ratio held like the ratios; the α = 1 sample holds the last cut sample's K (the dilute
/// side held constant; an uncut face's K = 1 is the consumer's rule, peak_energy_density.h).
///
/// Cost: one cell of 10³–2·10⁴ triangles cut, remeshed and factorised per shape and sample (0.1–1 s
/// each, serial; bench/homogenise_benchmark.cpp); results are kept in memory for the process, keyed
/// by shape polygon, ν and the cell options, so a sweep or a benchmark pays once. One calibration
/// runs at a time in a process (a lock around the computation and the cache): concurrent callers
/// wait for the curve instead of computing it again, and two cells are never factorised at once
/// (that was not reproducible to the last digits, fill_stiffness_calibration.cpp).
#include <vector>

#include "host/scene/load_case.h"
#include "host/mesh/surface_mesh.h"
#include "host/scene/scene.h"
#include "host/stencil/stencil_shape.h"
#include "solvers/homogenise/cell_homogenisation.h"
#include "solvers/shell/cell_filter.h"

namespace cutwork {
class PatternContext;
}

namespace cutwork::solvers {

/// The fill ratios sampled (the last, α = 1, is the solid: ratios 1).
const std::vector<double>& calibration_grid();

/// Calibrates the curve for `shapes` (≥ 1) and `material`'s ν. Thread-safe; memoised.
FillStiffnessCurve calibrate_fill_stiffness(const StencilLibrary& shapes, const Material& material,
                                            const CellOptions& options = {});

/// The scene's mechanics, calibrated for its stencil shapes and material (what every shell model of
/// the scene is built with).
MechanicsSettings scene_mechanics(const Scene& scene);

/// `mechanics` with its stiffness_curve filled in when its rule is Homogenised (unchanged when
/// Linear or already filled).
MechanicsSettings resolve_fill_stiffness(const MechanicsSettings& mechanics, const StencilLibrary& shapes,
                                         const Material& material);

/// The fill-ratio filter of the scene's mechanics (mechanics.filter) on `sim`: the identity for
/// "none"; for "cell", cell_filter.h's filter with the pattern's nominal stencil diameter
/// d = 2 ℓ σ and spacing a = 2 (1 + s) ℓ σ at each face (ℓ the context's unit, s the collision
/// safety factor, σ the sizing field at the closest point of the face's centroid on the base
/// surface): the centre distance of two nominal stencils that touch with their safety margins.
/// Faces with a clamped vertex (the scene's supports on `sim`) keep their own α and no other
/// face's cell counts them (cell_filter.h).
/// Built from the scene alone, not from the stencils, so it is fixed while they move.
CellFilter scene_cell_filter(const Scene& scene, const PatternContext& ctx, const SurfaceMesh& sim);

}  // namespace cutwork::solvers
