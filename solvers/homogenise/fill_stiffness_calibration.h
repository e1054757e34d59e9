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
/// Cost: one patch of ~10⁴ triangles cut, remeshed and factorised per shape and sample (about a
/// second each); results are kept in memory for the process, keyed by shape polygon and ν, so a
/// sweep or a benchmark pays once.
#include <vector>

#include "host/scene/load_case.h"
#include "host/scene/scene.h"
#include "host/stencil/stencil_shape.h"
#include "solvers/homogenise/cell_homogenisation.h"

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

}  // namespace cutwork::solvers
