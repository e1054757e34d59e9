#pragma once
/// The homogenised fill stiffness rule of a design (mechanics.stiffness = "homogenised"): the
/// ratios r_m(α), r_b(α) of fill_stiffness_map.h calibrated by cell homogenisation
/// (cell_homogenisation.h) for the design's stencil shapes and material.
///
/// Samples: α on a fixed grid (calibration_grid), and at the lowest fill ratio each shape reaches
/// in the lattice (1 − max_hole_fraction) where that lies inside the grid (calibration_samples).
/// Below its lowest no lattice of the shape exists: its ratios continue the secant of its lowest
/// two samples for one grid interval, then are held (calibrate_shape; the map holds r constant
/// below its first sample too). The lowest is a sample of its own so that the curve follows the
/// cells from there: with the grid alone the lowest cell's ratios sat at the grid point below it
/// (0.6 for the default star, whose lowest is 0.656 on the hexagonal lattice) and the cubic rose
/// from there, 1.6–8.1% above the star's cells at α 0.67, and the perforated-lattice suite's stars
/// at α 0.67 read 4% too stiff at one and two diameters (0.959 / 0.973; 0.991 / 1.001 now). Held
/// flat from the lowest instead, the cubic would start with zero slope there and lag the cells by
/// 2–6%. With several shapes the ratios are
/// averaged with the shapes' shares of the design's stencils by count (shape_weights; a face's
/// fill ratio does not say which shape cut it, the design's mix does on average). Equal weights
/// made the chair (396 stars, 28 circles) 3.8% too stiff: its circles' ratios, higher than the
/// stars' at every α, counted as much as its stars'; by count that design's stencils read 0.996
/// of its converged conforming compliance (0.9998 with the stars' curve alone). Counts, not areas: they do not change while
/// the stencils move and grow, so the rule stays fixed within a minimisation and its gradient
/// exact; a design of a few large holes among many small ones of another shape is weighted
/// towards the small ones. Ratios depend on the shapes and on ν only (not on E, h, or the design's
/// scale).
///
/// With a tool (MechanicsSettings::tool_radius > 0) the shapes' factors are those of the holes the
/// tool cuts, at the tool nodes (FillStiffnessCurve::tool_cut); the ratios stay the drawn holes'.
///
/// Concentration factors K (cell_homogenisation.h) ride on the same cell solves: per sample, the
/// largest over the shapes of positive weight (what a face's fill ratio alone can say), and each
/// such shape's own (shape_concentration: W_peak mixes them per face by the shapes' covered
/// fractions where it has those); below a shape's lowest fill ratio held like the ratios; the α = 1 sample holds the last cut sample's K (the dilute
/// side held constant; an uncut face's K = 1 is the consumer's rule, peak_energy_density.h).
///
/// Cost: one cell of 10³–2·10⁴ triangles cut, remeshed and factorised per shape and sample (0.1–1 s
/// each, serial; bench/homogenise_benchmark.cpp), with a tool also one of 3–5·10⁴ per sample and
/// tool node (about 2 s). A shape's cells run side by side, each alone in an arena of one thread,
/// and read to the last bit as they do one after the other (the default star's calibration by the
/// tool: 28.4 s on one thread, 14.7 s on two, BM_ToolCalibration; peak resident memory 447 MB and
/// 791 MB: about 350 MB per tool cell at once, up to the thread budget's multiple of it; a sweep
/// sets one calibration's memory aside, solvers/report/design_memory.h). Results are kept in
/// memory for the process, keyed by shape polygon, ν, the cell options and the samples, so a sweep
/// or a benchmark pays once. One calibration runs at a time in a process (a lock around the
/// computation and the cache): concurrent callers wait for the curve instead of computing it again.
#include <span>
#include <vector>

#include "host/scene/load_case.h"
#include "host/mesh/surface_mesh.h"
#include "host/scene/scene.h"
#include "host/stencil/frame.h"
#include "host/stencil/stencil_shape.h"
#include "solvers/homogenise/cell_homogenisation.h"
#include "solvers/shell/cell_filter.h"

namespace cutwork {
class PatternContext;
}

namespace cutwork::solvers {

/// The fixed fill ratios sampled (the last, α = 1, is the solid: ratios 1).
const std::vector<double>& calibration_grid();

/// The fill ratios a curve of `shapes` is sampled at: calibration_grid() and each shape's lowest
/// fill ratio on `lattice` (1 − max_hole_fraction(shape, 0.1, lattice)) where it lies between the
/// grid's first point and 1; strictly increasing, the last 1.
/// Shapes of weight 0 (`weights` indexed by type; empty: every shape) are left out.
std::vector<double> calibration_samples(const StencilLibrary& shapes, CellLattice lattice,
                                        const std::vector<double>& weights = {});

/// Each shape's share of `stencils` by count (#shapes, indexed by type, summing to 1); equal
/// shares where `stencils` is empty. Throws InputError for a stencil whose type is not a shape.
std::vector<double> shape_weights(const StencilLibrary& shapes, std::span<const StencilParams> stencils);

/// Calibrates the curve for `shapes` (≥ 1) and `material`'s ν, the shapes' ratios averaged with
/// `weights` (#shapes, ≥ 0, normalised here; empty: equal; a shape of weight 0 is not calibrated).
/// With `tool_cut` the shapes' factors by corner are the tool's (FillStiffnessCurve::tool_cut: per
/// distinct cell a cell of the opened hole at each tool node a shape has a corner sharp at, ~1–2 s
/// each; the ratios are the drawn holes'). Thread-safe; memoised per shape.
FillStiffnessCurve calibrate_fill_stiffness(const StencilLibrary& shapes, const Material& material,
                                            const CellOptions& options = {}, std::vector<double> weights = {},
                                            bool tool_cut = false);

/// The scene's mechanics, calibrated for its stencil shapes and material (what every shell model of
/// the scene is built with), the shapes weighted by their share of `stencils` (shape_weights;
/// equal without stencils, where α = 1 and the weights do not matter).
MechanicsSettings scene_mechanics(const Scene& scene, std::span<const StencilParams> stencils = {});

/// scene_mechanics for a shell without stencils (every face whole: the checks before a run, the
/// simulation mesh's choice). The square lattice's anisotropy vanishes at α = 1, so a lattice that
/// follows the orientation field needs no field there (its axis function, not attached before the
/// pattern context exists, is not asked for).
MechanicsSettings uncut_scene_mechanics(const Scene& scene);

/// `mechanics` with its lattice read from `stencils` (at their frames on `bvh` with `field`) where
/// the scene left it to them (lattice_source Auto; host/pattern/lattice_order.h measure_lattice):
/// square along the measured axis, square along the orientation field (turned by a measured
/// angle) where the lattice turns with it, or hexagonal; lattice_source then Stencils. A stated
/// lattice, and an Auto one without stencils, keep what they say. Where the lattice follows the
/// field (stated "lattice_axis": "field" or so read), the axis function is attached
/// (attach_lattice_field: `bvh` and `field` must outlive the settings' use). Appends a note where
/// the stencils form a square lattice that neither one axis nor the field fits (the isotropic
/// calibration is kept). Call before the stiffness is calibrated (resolve_fill_stiffness), which
/// the lattice decides.
MechanicsSettings measured_lattice(const MechanicsSettings& mechanics, const FaceBvh& bvh, const TangentField& field,
                                   std::span<const StencilParams> stencils, std::vector<std::string>& notes);

/// `mechanics` with its stiffness_curve filled in when its rule is Homogenised (unchanged when
/// Linear or already filled), the shapes weighted by their share of `stencils` (shape_weights).
MechanicsSettings resolve_fill_stiffness(const MechanicsSettings& mechanics, const StencilLibrary& shapes,
                                         const Material& material, std::span<const StencilParams> stencils = {});

/// The fill-ratio filter of the scene's mechanics (mechanics.filter) on `sim`: the identity for
/// "none"; for "cell", cell_filter.h's filter with spacing a = 2 (1 + s) ℓ σ at each face (ℓ the
/// context's unit, s the collision safety factor, σ the sizing field at the closest point of the
/// face's centroid on the base surface: the centre distance of two nominal stencils that touch
/// with their safety margins) and the blend measured against the hydraulic diameter
/// d = 2 ℓ σ · min over the library's shapes of (4A/P)/2 (4A/P in reference units, where the
/// bounding diameter is 2): the narrowest shape decides when the triangles resolve the pattern.
/// Faces with a clamped vertex (the scene's supports on `sim`) keep their own α and no other
/// face's cell counts them (cell_filter.h).
/// Built from the scene alone, not from the stencils, so it is fixed while they move.
CellFilter scene_cell_filter(const Scene& scene, const PatternContext& ctx, const SurfaceMesh& sim);

}  // namespace cutwork::solvers
