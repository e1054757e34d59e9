#pragma once
/// How far a simulation-mesh answer is from converged: the same shell, with the same material on
/// every face, solved again on the simulation mesh at half and a quarter of its edge length (and
/// an eighth where those have not settled), and the answers extrapolated
/// (solvers/conforming/richardson.h).
///
/// The refined meshes are the scene's generator run again at sim_edge_length / 2, / 4 (and / 8)
/// when the surface is generated (so the geometry is resolved better too), and 1 → 3 midpoint
/// subdivisions of the simulation mesh when it comes from a file (the same flat facets: only the
/// mechanics' error is seen). A refinement whose mesh would exceed `max_faces` triangles is left
/// out (the estimate then rests on two levels). Supports and loads are resolved on each mesh again
/// (loads are integrated over their regions, so their totals are the same). Each refined level
/// after the first starts Newton from the last level's displacements carried onto its mesh
/// (EquilibriumSolver::start_from): the same equilibria, fewer iterations.
///
/// What is held fixed is the material: the fill ratio each face of the simulation mesh carries
/// (the design's α after the cell filter, what the coarse model's stiffness and weight are
/// evaluated at) goes to every refined face whose centroid's closest point lies in that face
/// (`coarse_fill_ratios_on`). The levels are then one structure meshed three times, and their
/// differences are the mesh's error. Computing the stencils' fill ratios on each refined mesh again
/// would change the model with the mesh instead: the cell filter blends to each face's own α where
/// triangles resolve the stencils, so h/2 and h/4 sit in the rule's transition, and the default
/// designs' estimates read 3.0–7.6% where `verify` measured the coarse compliance within 0.1–2.8% of
/// the built shell. How far the homogenised rule itself is from the cut shell is not a mesh error;
/// `cutwork verify` measures it against conforming meshes of the cut surface.
///
/// The estimate, of the compliance C_h at the simulation mesh's edge length h against the
/// extrapolated C∞ (from the finest three levels):
///  - three levels converging monotonically ("richardson"): |C_h − C∞| / |C∞| with the observed
///    order;
///  - levels that have not settled ("not asymptotic": the differences change sign or grow):
///    (|C_h − C_finest| + the larger difference) / |C_finest|, an estimate, no bound. Where that
///    exceeds the tolerance after h/4, one more level, h/8 (`extra_refinements`, within
///    `max_faces`), is solved, and the finest three judged again: the cautious estimate decides
///    alone only where it says converged (an h/8 level of the table or the chair is 64 times the
///    simulation mesh, 160k triangles, and would make their designs 2.5 times slower);
///  - two levels ("first order assumed"): |C_h − C∞| / |C∞| with C∞ = 2C_{h/2} − C_h, i.e.
///    2|C_h − C_{h/2}| / |C∞| — an upper estimate for any order ≥ 1 in the asymptotic range.
/// `converged` says estimated_error ≤ tolerance (default 2%) and the supports are the same region on
/// every level: the extent of the supported vertices (held along any axis) and of the clamped ones (host/scene/scene.h
/// support_extent) may differ by at most support_tolerance (1%) from the coarse mesh's. A selection
/// that fixes more of a finer mesh (a box catching a surface that rises tangentially out of it)
/// makes each level a different structure, whose compliances say nothing of the mesh's error: the
/// pavilion's feet selected by "z below 0.01" were a strip 0.8 m long at 0.35 m and 1.03 m long
/// under 0.03 m, and its compliance fell 35% under refinement for that reason alone. W_max's change from h to h/2 is
/// reported beside it; it need not converge at all where the exact energy density is singular
/// (point supports, re-entrant clamped corners).
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "host/mesh/surface_mesh.h"
#include "host/scene/scene.h"
#include "solvers/conforming/richardson.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/structural_quantities.h"

namespace cutwork::solvers {

inline constexpr double kDiscretisationTolerance = 0.02;

struct DiscretisationOptions {
  int refinements = 2;         ///< h/2, h/4, always solved (1: h/2 only)
  int extra_refinements = 1;   ///< h/8, solved only where the levels before it have not settled
                               ///< and their cautious estimate exceeds the tolerance
  int max_faces = 250'000;     ///< leave out a refinement with more triangles than this
  double tolerance = kDiscretisationTolerance;
  double support_tolerance = kSupportExtentTolerance;  ///< largest relative change of the supports' extent
  NewtonSettings newton;
  /// Called with the refinement's index (2: h/8) and its predicted triangles before an extra level
  /// (past `refinements`) is built, once per level (SimulationMeshRefinements::level): a sweep takes
  /// the level's memory from its budget there (host/sweep/memory_budget.h). Optional.
  std::function<void(int level, size_t faces)> before_extra_level;
  /// Replaces the rule for levels past `refinements` (one more only while the finest three have
  /// not settled and their cautious estimate exceeds the tolerance): called with the compliances
  /// so far (h first), true solves one more (within extra_refinements and max_faces). Optional.
  std::function<bool(const std::vector<double>& compliances)> solve_another;
};

/// The simulation mesh at a refined edge length, and how it was made ("regenerated" or
/// "subdivided").
struct RefinedSimulationMesh {
  SurfaceMesh mesh;
  std::string method;
  double edge_length = 0;  ///< target (regenerated) or mean (subdivided) edge length, m
};

/// The refinements of the scene's simulation mesh at h/2, h/4, …, each made on first use and
/// kept, so that the uncut shell's estimate and the design's share them. The scene and its meshes
/// must outlive it.
class SimulationMeshRefinements {
 public:
  SimulationMeshRefinements(const Scene& scene, const SceneMeshes& meshes, const DiscretisationOptions& options = {});
  /// Refinement k (0: h/2, 1: h/4, …), or nullptr past refinements + extra_refinements of them or
  /// where its mesh would exceed max_faces (h/2 is always made: the estimate needs one).
  const RefinedSimulationMesh* level(int k);
  const DiscretisationOptions& options() const { return m_options; }

 private:
  const Scene* m_scene;
  const SceneMeshes* m_meshes;
  DiscretisationOptions m_options;
  std::deque<RefinedSimulationMesh> m_levels;  ///< stable addresses
  bool m_exhausted = false;                    ///< the next level would exceed the budget
};

/// The refinements of the scene's simulation mesh at h/2, h/4, … (options.refinements of them,
/// fewer where the next would exceed options.max_faces; at least h/2 unless it alone does).
std::vector<RefinedSimulationMesh> refine_simulation_mesh(const Scene& scene, const SceneMeshes& meshes,
                                                          const DiscretisationOptions& options = {});

/// The edge length the simulation mesh of `scene` was made at: sim_edge_length, else edge_length
/// for generated surfaces; the mean edge length of the mesh for files.
double simulation_edge_length(const Scene& scene, const SceneMeshes& meshes);

struct DiscretisationLevel {
  double edge_length = 0;  ///< m
  int faces = 0;
  EquilibriumScalars quantities;  ///< of the material
  SupportExtent fixed, clamped;   ///< what the scene's supports hold on this level's mesh (fixed: along any axis)
  /// The level's Newton iterations and whether they started from the last level's solution (not
  /// from rest); −1 and false for h, which is solved elsewhere.
  int newton_iterations = -1;
  bool warm_started = false;
  /// Where W_peak is on this level (the centroid of its face, m; NaN where not read) and whether
  /// that face touches a vertex a support holds along any axis (support_held_vertices: a symmetry
  /// plane is no support here): at a clamped corner or a point support the exact energy density may
  /// be singular, and a maximum there need not converge (W_peak_free leaves that region out).
  Vec3 W_peak_position = Vec3::Constant(NAN);
  bool W_peak_at_support = false;
  /// W_peak away from the supports (peak_away_from_supports with the clearance h, the judged run's
  /// edge length: one region on every level); NaN where not read or where no face is that far.
  double W_peak_free = NAN;
};

struct DiscretisationEstimate {
  std::string method;                       ///< how the refined meshes were made
  std::vector<DiscretisationLevel> levels;  ///< h (the run being judged), h/2, h/4
  Richardson compliance;                    ///< over the levels' compliances
  std::string rule;                         ///< "richardson", "not asymptotic", "first order assumed"
  double estimated_error = NAN;             ///< of C_h (see the file comment)
  double compliance_change = NAN;           ///< |C_h − C_{h/2}| / |C_{h/2}|
  double W_max_change = NAN;                ///< |W_h − W_{h/2}| / W_{h/2}
  /// |W_peak,h − W_peak,h/2| / W_peak,h/2 (the ligament peak, read with the coarse run's factors on
  /// every level); NaN without peak inputs or concentration factors.
  double W_peak_change = NAN;
  /// The same for W_peak away from the supports (DiscretisationLevel::W_peak_free).
  double W_peak_free_change = NAN;
  bool W_peak_levels = false;               ///< the levels' W_peak was read (peak inputs given)
  double max_displacement_change = NAN;     ///< the same for the largest displacement
  double support_change = NAN;              ///< largest support_extent_change of a level from h
  double tolerance = kDiscretisationTolerance;
  double support_tolerance = kSupportExtentTolerance;
  bool supports_consistent = false;         ///< support_change ≤ support_tolerance
  bool converged = false;                   ///< estimated_error ≤ tolerance and supports_consistent
};

/// The fill ratios a (refined) simulation mesh is solved with: #F of the mesh.
using FillRatiosOnMesh = std::function<Eigen::VectorXd(const SurfaceMesh&)>;

/// The coarse run's material on a refined mesh. `alpha` (#F of `coarse`) is what the coarse
/// model's stiffness is evaluated at (the cell filter applied); a refined face takes it as a
/// continuous field: each coarse vertex the area-weighted mean of its faces', interpolated at the
/// closest point of the refined face's centroid (on `coarse` itself, `alpha`). A field held face
/// by face instead (each refined face its coarse face's value) is a staircase wherever the refined
/// mesh does not nest in the coarse one, and its own convergence (first order or slower) swamps
/// the mechanics': the bowl's default design read 0.70 as its observed order, 2.8% (1.9 and 1.7%
/// held continuously).
///
/// Where the coarse triangles resolve the stencils, the fill ratio is not a porosity but the holes
/// themselves (cell_filter.h: b_t = 0 where four or more triangles span a stencil's 4A/P), and a finer
/// mesh resolves them better: with `own_on` (the stencils' own fill ratios on a mesh) and
/// `resolution` (#F of `coarse`, CellFilter::resolution()), a refined face takes
/// (1 − r) held + r own, r the resolution interpolated as above. Held alone, the built-in sheet's
/// one hole (eight triangles across) blurred over a coarse triangle and read 3.5% softer under
/// refinement, not converged; it is within 1.4% of the built sheet (verify).
/// `coarse` must outlive the function.
FillRatiosOnMesh coarse_fill_ratios_on(const SurfaceMesh& coarse, Eigen::VectorXd alpha,
                                       Eigen::VectorXd resolution = {}, FillRatiosOnMesh own_on = {});

/// What W_peak reads on a mesh besides its fill ratios (summarize_equilibrium's concentration
/// weight and the stencils' cover by shape), #F of the mesh each; an empty member is not given.
struct PeakInputs {
  Eigen::VectorXd weight;
  ShapeCover cover;
};
using PeakInputsOnMesh = std::function<PeakInputs(const SurfaceMesh&)>;

/// The coarse run's W_peak inputs (`weight`, `cover`: #F of `coarse`, either null) on a refined mesh,
/// carried as coarse_fill_ratios_on carries α (each a continuous field: vertex means of the faces',
/// interpolated at the closest point of a refined face's centroid); on `coarse` itself, the inputs.
/// So every level reads its W with the factors the coarse run read there, and the levels' W_peak
/// differ by the mesh's error of W where the factors apply (a lattice of holes smaller than the
/// triangles), and by how well the rim is resolved where they do not (a hole the triangles resolve,
/// weight 0). `coarse` must outlive the function.
PeakInputsOnMesh coarse_peak_inputs_on(const SurfaceMesh& coarse, const Eigen::VectorXd* weight,
                                       const ShapeCover* cover);

/// Solves the scene's shell on the refinements (h/2 and h/4; h/8 where those have not settled and
/// the budget allows) with the fill ratios `fill_on` gives and `mechanics` (resolved as for the
/// coarse run, its filter already in the fill ratios), and judges the coarse run's `coarse`
/// quantities (on `coarse_mesh`, the simulation mesh, of edge length `coarse_edge_length`). With
/// `coarse_displacement` (#V of coarse_mesh × 3, m: the coarse run's equilibrium) the first refined
/// level's Newton starts from it carried onto its mesh, and each later level from the last one's.
/// With `peak_on` (the W_peak inputs the coarse run read, coarse_peak_inputs_on) each level's W_peak
/// is read with them and its change from h to h/2 judged (W_peak_change); without it the levels'
/// W_peak is not reported. With `coarse_peak` too (the coarse run's W_peak field, #F of coarse_mesh)
/// W_peak away from the supports is read on every level (W_peak_free, W_peak_free_change). Throws what the equilibrium throws (SolveError).
DiscretisationEstimate estimate_discretisation(const Scene& scene, SimulationMeshRefinements& refined,
                                               const FillRatiosOnMesh& fill_on, const MechanicsSettings& mechanics,
                                               const EquilibriumScalars& coarse, double coarse_edge_length,
                                               const SurfaceMesh& coarse_mesh,
                                               const RowMatX3d* coarse_displacement = nullptr,
                                               const PeakInputsOnMesh& peak_on = {},
                                               const Eigen::VectorXd* coarse_peak = nullptr);

/// The largest of `field` (#F) over the faces of `material` (#F) whose centroid lies farther than
/// `clearance` (m) from every vertex of `held` (#V; support_held_vertices): a maximum away from the
/// supports, where a clamped corner or a point support can make the exact field singular, so that
/// its maximum grows without bound under refinement. Held at one physical clearance — the simulation
/// mesh's edge length h, the region its first ring of triangles covers — the region is the same on
/// every level, and the maximum over it converges where the field is bounded there. NaN (face −1)
/// when no face qualifies. A uniform grid over the held vertices (its brute-force twin in the tests).
double peak_away_from_supports(const SurfaceMesh& mesh, const Eigen::VectorXd& field, const std::vector<bool>& material,
                               const std::vector<bool>& held, double clearance, int* face = nullptr);

/// report.json's `discretisation` object: method, levels [{edge_length, faces, compliance,
/// strain_energy, W_max, W_peak and W_peak_free (away from the supports; null where not read),
/// W_peak_position, W_peak_at_support, max_displacement, supports {fixed, clamped: {area, length, points}},
/// newton_iterations (null for h), warm_started}],
/// support_change, supports_consistent, compliance_extrapolated, observed_order,
/// compliance_error_bar, rule, estimated_error, compliance / W_max / W_peak / W_peak_free / max_displacement changes from h
/// to h/2, tolerance, converged and a one-line `summary` (no times: the report's timings hold
/// them, so that two runs of one design give the same object).
nlohmann::json discretisation_json(const DiscretisationEstimate& e);

/// {"area", "length", "points"} of a support extent (report.json).
nlohmann::json support_extent_json(const SupportExtent& x);

/// One line for a person: the compliance at h and its estimated discretisation error.
std::string discretisation_line(const DiscretisationEstimate& e);

/// The change of W_peak from h to h/2 above which a run says in a note that its ligament peak is
/// not converged on the simulation mesh (the zoom's settled change in cutwork verify is the same 5%).
inline constexpr double kPeakDiscretisationTolerance = 0.05;

/// That note (empty where W_peak_change is within `tolerance` or was not read): the levels' W_peak,
/// and where the finest level's is at a support, W_peak away from the supports by level and whether
/// that is within the tolerance.
std::string peak_discretisation_note(const DiscretisationEstimate& e,
                                     double tolerance = kPeakDiscretisationTolerance);

}  // namespace cutwork::solvers
