#pragma once
/// Conforming verification (paper §6, Fig. 4): a design's stencils simulated twice —
///  - coarse: the scene's simulation mesh with fill ratios α (what the optimiser sees, as
///    `cutwork simulate --stencils` runs it);
///  - conforming: the base mesh cut along every stencil outline (host/cut), remeshed to a target
///    edge length L (host/mesh/isotropic_remesh.h), the scene's supports and loads resolved on
///    that mesh again, simulated with α = 1 everywhere —
/// and compared: compliance, strain energy, maximum displacement of the material, energy density
/// per coarse face and W_max.
///
/// Energy density on coarse faces. Every conforming face is assigned to the coarse (simulation)
/// face that holds the closest point of its centroid; the conforming W of (16) is averaged over
/// the faces assigned to each coarse face, weighted by area: W̄_t = Σ_c A_c W_c / Σ_c A_c. Both W_t
/// (coarse, per area of the material left, see solvers/objective/energy_density.h) and W̄_t are
/// energies per area of material, so they compare directly. Coarse faces count as material when
/// α_t > kMaterialFillRatio (solvers/objective/structural_quantities.h) and some conforming area
/// maps onto them; the comparison runs over those faces only.
///
/// Supports and loads are the scene's selectors resolved on the conforming mesh again; selectors of
/// boundary vertices or edges pick only the uncut surface's boundary (not the rims of the holes,
/// which the coarse mesh does not have either).
///
/// Levels: the conforming solve runs at L, L/2, L/4, … until it has converged, `levels` solves
/// have run, or the next level's mesh has more than `max_faces` triangles (a level from the third
/// on is not built when the last growth predicts more, else it is built, then left unsolved; level
/// 0 is solved whatever its size; kBudgetPredictionMargin). With `grading_depth` > 0 every level is graded along the
/// outlines (isotropic_remesh.h): triangles down to L_k/2^depth where a ligament is narrower, or a
/// hole smaller, than `elements_across` triangles of the level-0 size; the regions are the same on
/// every level, so each level's sizes are half the last's everywhere and Richardson's rule below
/// still applies. The comparison uses the finest level and the Richardson-extrapolated compliance
/// (richardson.h): with the last three levels C₁, C₂, C₃ (edge lengths L, L/2, L/4) and
/// d₁ = C₂ − C₁, d₂ = C₃ − C₂ of one sign and shrinking, the observed order is p = log₂(d₁/d₂) and
/// C∞ = C₃ + d₂/(2^p − 1), error bar |C∞ − C₃|; when the differences change sign or grow,
/// C∞ = C_finest and the error bar is the larger of the two; with two levels, p = 1 is assumed
/// (C∞ = 2C₂ − C₁, error bar |d|).
///
/// Converged: at least `min_levels` (3) levels ran, the error bar is within `tolerance` of C∞, and
/// the supports hold the same region on every level (support_extent within 1% of level 0's).
/// Two levels that agree are no proof: where the outline's refinement stiffens what the interior's
/// softens, the two errors cancel. Measured on the plate design: levels from L = 2.4 mm read 8.542,
/// 8.535 and 8.494 mJ (0.09%, then 0.47%), while a family started at 2L converged monotonically
/// (8.413, 8.478, 8.490 mJ, p = 2.4) onto the same 8.49.
/// Loads: self-weight is ρ h g per area of material on both meshes. Area, pressure and edge loads
/// are integrated over their selector's region on each mesh and carry the coarse mesh's totals on
/// the conforming one (resolve_load_case's match_totals): the share of a dead load that falls on a
/// hole is carried by the material left in the region, evenly, while the coarse mesh lumps it to
/// the vertices of the face it falls on. Point loads are totals spread over the surface inside
/// their region on both meshes. The totals of both runs are reported.
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "host/mesh/surface_mesh.h"
#include "host/scene/scene.h"
#include "host/stencil/fill_ratio.h"
#include "host/stencil/frame.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/objective_terms.h"
#include "solvers/objective/structural_quantities.h"
#include "host/pattern/pattern_context.h"
#include "solvers/conforming/rim_recovery.h"
#include "solvers/objective/ligament_peak.h"

namespace cutwork::solvers {

/// The relative change of the conforming peak between two levels under which it counts as settled.
inline constexpr double kPeakTolerance = 0.05;

/// A level from the third on is not built when the last growth predicts more than this × the face
/// budget (the prediction was 0.89–1.17× the built level's size on the built-in designs).
inline constexpr double kBudgetPredictionMargin = 1.25;

/// A level whose edge length is at least this × the base mesh's mean edge coarsens the straight runs
/// of the cut's outline and of the support lines before remeshing
/// (RemeshOptions::coarsen_straight_runs): a boundary that much finer than L along a straight side
/// leaves triangles spanning two collinear boundary edges, zero-area faces no flip repairs (the
/// chair on a 5 mm base, verified at 20.4 mm). Levels from the base's own edge length down, the
/// default, are unchanged.
inline constexpr double kStraightRunCoarsening = 2.0;

/// The peak zoom: about each candidate of the finest level's rim peak (rim_peak_candidates: W at
/// least kPeakZoomFraction of the peak, at most kPeakZoomCentres, 2 radii apart) the rims are halved
/// `peak_zoom` more times within kPeakZoomRadius × the finest level's edge length
/// (GradingOptions::focus, along the outline), and solved again: by default a submodel of the
/// finest level about the centres, its border held at that level's solution (zoom_submodel.h);
/// with zoom_submodel false the whole shell, remeshed from the cut.
inline constexpr double kPeakZoomRadius = 2.0;
inline constexpr double kPeakZoomFraction = 0.6;
inline constexpr int kPeakZoomCentres = 4;

struct ConformingOptions {
  double edge_length = 0;   ///< conforming target edge length L (m) at the coarsest level; > 0
  int levels = 1;           ///< at most this many conforming solves at L, L/2, …; in [1, 6]
  double tolerance = 0;     ///< converged once the error bar / |C∞| ≤ tolerance (0: run every level)
  int min_levels = 3;       ///< the fewest levels that count as converged; in [2, 6]
  int max_faces = 800'000;  ///< solve no level (but the first) with more triangles than this
  int remesh_iterations = 5;
  /// Grading along the outlines (isotropic_remesh.h GradingOptions): each level's mesh is refined
  /// up to this many halvings where the material is narrower, or a hole smaller, than
  /// `elements_across` level-0 triangles; the thresholds scale with the level (feature_scale 2^k),
  /// so every level's sizes are half the last's everywhere. 0: uniform levels.
  int grading_depth = 0;
  double elements_across = 3;
  NewtonSettings newton;    ///< for both solves (log lines are collected in the result's notes)
  /// Zoom steps about the rim peak after the last level (PeakZoom; 0: none); in [0, 6].
  int peak_zoom = 0;
  /// Each zoom step re-solves a submodel of the finest level about the centres, its collar held at
  /// the level's solution (PeakZoom), instead of the whole shell.
  bool zoom_submodel = true;
  /// Each level starts Newton from the last level's displacements carried onto its mesh (the first
  /// from the coarse run's; host/mesh/mesh_mapping.h interpolate_vertex_field), not from rest: the
  /// same equilibrium to Newton's tolerance in fewer iterations (a guess Newton fails from is
  /// dropped for a start from rest, EquilibriumSolver::start_from).
  bool warm_start = true;
  /// The cutter's radius r (m) the conforming outline is cut with (host/stencil/stencil_opening.h):
  /// each stencil becomes the union of the discs of radius r inside it, so its corners that turn
  /// into the material (a star's tips) are arcs of radius r, as a part cut by such a tool has them,
  /// and the rim peak is read on those arcs instead of being left out about a sharp corner. The
  /// corner window is then r/4 (only corners the tool left sharp count). 0: the outlines as drawn,
  /// the rim within the minimum feature of their sharp corners left out.
  double tool_radius = 0;
};

/// One step of the peak zoom. Step 0 is the finest level itself.
struct PeakZoomStep {
  int faces = 0;
  double rim_edge_length = 0;  ///< m: the size the rims have within the zoom's radius, L_K / 2^(depth + step)
  double peak = NAN;           ///< J/m²: the largest non-singular rim W within the radius of a centre
  Vec3 position = Vec3::Constant(NAN);
  /// J/m²: the largest non-singular rim W outside the balls (not refined further); a peak that
  /// moves there is said in the notes.
  double peak_outside = NAN;
  double compliance = NAN;     ///< J: of the whole zoomed mesh (the zoom refines too little to move it); NaN for a submodel
  double seconds = 0, mesh_seconds = 0;
};

/// The conforming rim peak refined where it is: the zoom's steps, their Richardson extrapolation
/// (richardson.h) and the change over the last step against kPeakTolerance. The global mesh (or the
/// submodel's held border) is the finest level's, so the steps converge onto that level's peak with
/// the rims resolved; its own error is the compliance's.
struct PeakZoom {
  std::vector<Vec3> centres;   ///< m
  double radius = 0;           ///< m
  std::vector<PeakZoomStep> steps;
  double extrapolated = NAN, order = NAN, error_bar = NAN;
  double change = NAN;         ///< |P_last − P_before| / P_last
  bool converged = false;      ///< change ≤ kPeakTolerance
  int submodel_faces = 0;      ///< the submodel's patch of the finest level (0: the whole shell was re-solved)
};

/// One equilibrium's scalar quantities (material only, see summarize_equilibrium) and its run.
struct RunQuantities : EquilibriumScalars {
  int vertices = 0, faces = 0, dofs = 0;
  double edge_length = 0;          ///< m (target for a conforming level; mean for the coarse mesh)
  double material_area = 0;        ///< m²: Σ α A (coarse) or Σ A (conforming)
  Vec3 load_total = Vec3::Zero();  ///< N: dead loads plus self-weight, free and supported vertices
  int newton_iterations = 0;
  bool warm_started = false;       ///< Newton started from the last level's (or the coarse run's) solution and converged from it
  double seconds = 0;              ///< the solve and its summary
  double mesh_seconds = 0;         ///< conforming levels: cutting and (graded) remeshing
  /// Mesh quality (conforming levels; NaN for the coarse run): the smallest angle (degrees) and
  /// the fraction of triangles with an angle below 10°.
  double min_angle = NAN;
  double slivers = NAN;
  /// What the scene's supports hold on this level's mesh (conforming levels; host/scene/scene.h).
  SupportExtent fixed_extent, clamped_extent;
  /// The conforming peak (levels only; NaN for the coarse run), rim_recovery.h: the largest
  /// energy density recovered on the free rims — the holes' outlines and the free border — (J/m²;
  /// NaN without a free rim), leaving out the rim points within the minimum feature of a corner
  /// that turns into the material or within the level-0 edge length of a support's end (their field
  /// may be singular), and where it is. `peak` is that rim peak: the ligament peak W_peak estimates. The largest W over
  /// the faces with no boundary vertex (J/m²) is reported beside it: it is no measure of the
  /// ligaments, and next to supports and point loads it does not converge (on the built-in designs
  /// it grew by 27–56% from one level to the next).
  double rim_peak = NAN;
  Vec3 rim_peak_position = Vec3::Constant(NAN);
  int rim_points = 0, singular_rim_points = 0;
  /// What the corner rule left out (J/m²; NaN with no such point), and where: the largest W over
  /// the rim points within the minimum feature of a singular corner. Where the corners are the
  /// stencils' own rounds below the minimum feature (a small flower's petals: 0.42 mm radius on the
  /// bowl), this is where the shell's peak is, unresolved; the cell problems' factors (W_peak) do
  /// not leave those rounds out.
  double corner_peak = NAN;
  Vec3 corner_peak_position = Vec3::Constant(NAN);
  double interior_peak = NAN;
  double peak = NAN;
};

struct ConformingVerification {
  Eigen::VectorXd alpha;               ///< #F_sim fill ratios of the coarse run
  /// The tool the conforming outline was cut with (ConformingOptions::tool_radius resolved, m) and
  /// what it did: stencils whose outline it rounded, that it does not fit in (cut as drawn), that
  /// it cuts in pieces (the largest kept).
  double tool_radius = 0;
  int tool_rounded = 0, tool_too_small = 0, tool_split = 0;
  RunQuantities coarse;
  Eigen::VectorXd coarse_W;            ///< #F_sim, J/m²
  std::vector<RunQuantities> levels;   ///< conforming levels, coarsest first
  // The finest conforming level.
  SurfaceMesh conforming_mesh;
  Eigen::VectorXd conforming_W;        ///< #F_conf, J/m²
  std::vector<RimPoint> conforming_rim;///< the finest level's recovered rim points
  RowMatX3d conforming_displacement;   ///< #V_conf×3, m
  Eigen::VectorXi conforming_to_coarse;///< #F_conf: the coarse face each conforming face maps to
  Eigen::VectorXd W_on_coarse;         ///< #F_sim: W̄_t (NaN where nothing maps)
  std::vector<bool> compared;          ///< #F_sim: material faces that are compared
  // Convergence of the conforming compliance over the levels (see the file comment).
  bool converged = false;              ///< min_levels ran, the error bar is within the tolerance, supports consistent
  /// The largest support_extent_change of a level's fixed or clamped vertices from level 0's (area
  /// against at least the level-0 L × the line's length), and whether it is within
  /// kSupportExtentTolerance: a selector that catches more of a finer mesh (the table's feet selected
  /// with "z below 0.001" took the legs' walls up to 1 mm on a mesh of 1 mm near them) makes the
  /// levels different structures, and their convergence says nothing. Points beside a line or an
  /// area count as one element of area each (support_extent_change).
  double support_change = NAN;
  bool supports_consistent = true;
  std::string stop;                    ///< "tolerance", "levels" (all run) or "budget" (max_faces)
  double last_change = NAN;            ///< |C_k − C_{k−1}| / |C_k| of the last two levels (NaN: one level)
  double extrapolated_compliance = NAN;///< C∞
  double observed_order = NAN;         ///< p (NaN unless three levels converge monotonically)
  double compliance_error_bar = NAN;   ///< |C∞ − C_finest| (see the file comment)
  double relative_error_bar = NAN;     ///< compliance_error_bar / |C∞|
  double compliance_ratio_extrapolated = NAN;  ///< coarse / C∞
  // Comparison (coarse / conforming, finest level).
  double compliance_ratio = 0, strain_energy_ratio = 0, max_displacement_ratio = 0;
  double W_max_ratio = 0;              ///< coarse W_max / conforming W_max (per conforming face)
  double W_max_on_coarse = 0;          ///< max_t W̄_t over compared faces
  /// The peak zoom (empty unless options.peak_zoom > 0 and the finest level has a rim peak).
  PeakZoom zoom;
  /// The conforming peak the comparison uses: the zoom's last step when it ran, else the finest
  /// level's rim peak (RunQuantities::peak).
  double conforming_peak = NAN;
  /// coarse W_peak_max (the rim estimate from the cell problems' concentration factors,
  /// peak_energy_density.h) / conforming_peak; NaN when the mechanics carries no concentration
  /// samples or the shell has no free rim. Where W_peak's thick-plate transition applies (the
  /// stencils against the thickness), the coarse W_peak with Kirchhoff's factors
  /// (EquilibriumScalars::W_peak_kirchhoff_max): the conforming levels are Kirchhoff shells too, and
  /// the ligaments' W_lig and W_estimate below are read from it as well.
  double W_peak_ratio = NAN;
  /// The narrow ligaments of the design and their estimates W_lig (ligament_peak.h), from the coarse
  /// run's W_peak; empty without concentration samples.
  LigamentPeakSummary ligaments;
  /// The coarse estimate of the peak: max(W_peak_max, W_lig max), and it / conforming_peak (and / P∞
  /// below); NaN where W_peak_ratio is.
  double W_estimate = NAN, W_estimate_ratio = NAN, W_estimate_ratio_extrapolated = NAN;
  /// The conforming peak between the last two levels (between the zoom's last two steps when it
  /// ran): |P_k − P_{k−1}| / P_k (NaN with one level), and whether it is within kPeakTolerance. The recovered rim peak converges at first order or
  /// better (rim_recovery.h); the largest face W next to a rim does not (it was 1.3–1.8× Goodier's
  /// closed form on every level), so it is no longer the peak. W_peak_ratio means little while the
  /// change is large.
  double peak_change = NAN;
  bool peak_converged = false;
  /// The conforming peaks over the levels (over the zoom's steps when it ran) extrapolated as the
  /// compliance is (richardson.h; p = 1
  /// assumed with two levels, the slow end): P∞, its observed order and error bar |P∞ − P_finest|,
  /// and coarse W_peak_max / P∞. NaN where a level has no rim peak. Measured on the plate design's
  /// three levels: 1.491, 2.172, 2.335 J/m², p = 2.1, P∞ = 2.39 ± 0.05.
  double peak_extrapolated = NAN, peak_order = NAN, peak_error_bar = NAN;
  double W_peak_ratio_extrapolated = NAN;
  double W_relative_l2 = 0;            ///< √(Σ A_t (W_t − W̄_t)² / Σ A_t W̄_t²) over compared faces
  int worst_face = -1;                 ///< compared face with the largest |W_t − W̄_t|
  double worst_difference = 0;         ///< W_t − W̄_t there (J/m²)
  Vec3 worst_position = Vec3::Zero();  ///< its centroid (m)
  int compared_faces = 0;
  std::vector<std::string> notes;
};

/// Fill ratios (#F of `sim`) of `stencils` placed on the surface `surface` (with `shapes` and the
/// tangent `field`) on the simulation mesh `sim` (CPU kernels unless `fill` says otherwise;
/// derivatives off). Ones without stencils. With `cover`, also the stencils' cover by shape
/// (solvers/objective/shape_cover.h, unfiltered, its corner moments at `corner_radius`; empty
/// without stencils).
Eigen::VectorXd fill_ratios_on_mesh(const FaceBvh& surface, const StencilLibrary& shapes, const TangentField& field,
                                    const SurfaceMesh& sim, std::span<const StencilParams> stencils,
                                    FillRatioOptions fill = {}, ShapeCover* cover = nullptr,
                                    double corner_radius = 0);

/// Fill ratios (#F of `sim`) of `stencils` on a simulation mesh of the scene (its own or a refined
/// one), as the optimiser computes them: the kernels' α, then the scene's cell filter
/// (scene_cell_filter; the identity unless mechanics.filter says otherwise). CPU kernels unless
/// `fill` says otherwise; derivatives off.
Eigen::VectorXd design_fill_ratios(const Scene& scene, const PatternContext& ctx, const SurfaceMesh& sim,
                                   std::span<const StencilParams> stencils, FillRatioOptions fill = {});

/// Runs both simulations and compares them (see the file comment). Throws InputError for bad
/// options or a scene whose supports/loads select nothing on the conforming mesh (e.g. a point
/// load inside a hole), SolveError when either equilibrium fails (a piece cut loose by the stencils
/// has no support, a load beyond capacity).
ConformingVerification verify_conforming(const Scene& scene, const SceneMeshes& meshes, const LoadCase& load_case,
                                         const PatternContext& ctx, std::span<const StencilParams> stencils,
                                         const ConformingOptions& options, FillRatioOptions fill = {});

/// Fills v.extrapolated_compliance, observed_order and compliance_error_bar from v.levels (the rule
/// of the file comment). Exposed for tests.
void extrapolate_compliance(ConformingVerification& v);

}  // namespace cutwork::solvers
