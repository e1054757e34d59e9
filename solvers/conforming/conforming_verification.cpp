#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/conforming/conforming_verification.h"

#include "solvers/objective/ligament_peak.h"
#include "solvers/objective/peak_energy_density.h"
#include "solvers/objective/shape_cover.h"
#include "solvers/conforming/richardson.h"
#include "solvers/conforming/zoom_submodel.h"

#include <algorithm>
#include <array>
#include <map>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/timer.h"
#include "host/cut/cut_surface.h"
#include "host/mesh/bvh.h"
#include "host/mesh/isotropic_remesh.h"
#include "host/mesh/mesh_mapping.h"
#include "host/stencil/fill_ratio.h"

namespace cutwork::solvers {

namespace {

/// Solves `model` at `alpha` and fills the scalar quantities of `q`; W (#F) into `W`,
/// displacements into `u` when non-null.
void solve_run(const ShellModel& model, const Eigen::VectorXd& alpha, const NewtonSettings& settings,
               RunQuantities& q, Eigen::VectorXd& W, RowMatX3d* u, const Eigen::VectorXd* concentration_weight = nullptr,
               Eigen::VectorXd* W_peak = nullptr, const RowMatX3d* start = nullptr,
               const ShapeCover* cover = nullptr) {
  Stopwatch sw;
  EquilibriumSolver solver(model, settings);
  if (start) solver.start_from(*start);
  const EquilibriumStats& stats = solver.solve(alpha);
  if (!stats.stable)
    throw SolveError(fmt::format("the {}-triangle shell's equilibrium is unstable (it buckles); the comparison "
                                 "needs a stable equilibrium",
                                 model.num_faces()));
  const EquilibriumSummary s = summarize_equilibrium(model, solver.positions(), alpha, concentration_weight, cover);
  static_cast<EquilibriumScalars&>(q) = s;
  q.vertices = model.num_vertices();
  q.faces = model.num_faces();
  q.dofs = model.num_dofs();
  q.material_area = alpha.dot(model.mesh().face_areas());
  q.load_total = model.external_forces(alpha).colwise().sum().transpose();
  q.newton_iterations = stats.newton_iterations;
  q.warm_started = start != nullptr && !stats.cold_restarted;
  W = s.energy_density;
  // The Kirchhoff shell's own W_peak where the thick-plate transition raised it: the conforming
  // levels are Kirchhoff shells, and the ligaments' estimate is compared with their peak.
  if (W_peak) *W_peak = s.peak_energy_density_kirchhoff.size() > 0 ? s.peak_energy_density_kirchhoff : s.peak_energy_density;
  if (u) *u = solver.displacements();
  q.seconds = sw.seconds();
}

/// The base mesh cut along every stencil outline and remeshed at `edge_length`, keeping the cut's
/// `features` (support_lines_on_cut) as lines. On a level at least kStraightRunCoarsening × the
/// base mesh's mean edge (`base_edge`), the straight runs of the outline and of the lines are first
/// coarsened (RemeshOptions::coarsen_straight_runs; they would leave zero-area caps).
SurfaceMesh conforming_mesh(const CutSurface& cut, double base_edge, double edge_length, int iterations,
                            const GradingOptions& grading, const std::vector<std::array<int, 2>>& features) {
  RemeshOptions ro;
  ro.target_edge_length = edge_length;
  ro.iterations = iterations;
  ro.grading = grading;
  ro.feature_edges = features;
  ro.coarsen_straight_runs = edge_length >= kStraightRunCoarsening * base_edge;
  RemeshedMesh r = remesh_isotropic(cut.vertices, cut.faces, ro);
  return SurfaceMesh(std::move(r.vertices), std::move(r.faces),
                     fmt::format("conforming mesh (edge length {:.4g} m)", edge_length));
}

/// The outlines of the scene's supports on the base mesh (support_outline_edges: a clamped area's
/// border, an interior line support) as edges of the cut (pairs of cut vertices): the pieces of
/// those base edges the stencils leave, each an interior edge of the cut whose ends lie on one
/// outline edge (a base vertex of it, or a vertex the cut made on it, within `snap` m). Every
/// conforming level keeps them (RemeshOptions::feature_edges), so the supports hold the same region
/// on each level instead of one outlined anew by each level's triangles. A scene whose selectors
/// do not resolve on the base mesh gets none (its levels resolve them, and say so, as before).
std::vector<std::array<int, 2>> support_lines_on_cut(const Scene& scene, const SurfaceMesh& base, const CutSurface& cut,
                                                     double snap) {
  std::vector<std::array<int, 2>> out;
  std::vector<int> outline;
  try {
    outline = support_outline_edges(base, resolve_load_case(scene, base).fixed);
  } catch (const InputError&) {
    return out;
  }
  if (outline.empty()) return out;
  // The outline's base edges by base vertex, and the segments.
  std::vector<std::vector<int>> at_vertex(size_t(base.num_vertices()));
  for (int k = 0; k < int(outline.size()); ++k)
    for (int c = 0; c < 2; ++c) at_vertex[size_t(base.edges()(outline[size_t(k)], c))].push_back(k);
  auto on_segment = [&](int k, const Vec3& p) {
    const Vec3 a = base.vertices().row(base.edges()(outline[size_t(k)], 0)).transpose();
    const Vec3 b = base.vertices().row(base.edges()(outline[size_t(k)], 1)).transpose();
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    return (a + t * (b - a) - p).norm() <= snap;
  };
  auto candidates = [&](int v) -> const std::vector<int>* {
    const int s = cut.source_vertex[v];
    return s >= 0 ? &at_vertex[size_t(s)] : nullptr;
  };
  // The cut's interior edges (two faces each).
  std::map<std::pair<int, int>, int> faces_at;
  for (int f = 0; f < cut.faces.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int a = cut.faces(f, c), b = cut.faces(f, (c + 1) % 3);
      ++faces_at[{std::min(a, b), std::max(a, b)}];
    }
  for (const auto& [edge, count] : faces_at) {
    if (count != 2) continue;
    const auto [p, q] = edge;
    const Vec3 xp = cut.vertices.row(p).transpose(), xq = cut.vertices.row(q).transpose();
    const std::vector<int>* cp = candidates(p);
    const std::vector<int>* cq = candidates(q);
    bool along = false;
    if (cp || cq) {
      // One end is a base vertex: the edge lies along one of its outline edges or none.
      for (const std::vector<int>* c : {cp, cq})
        if (c)
          for (int k : *c) along = along || (on_segment(k, xp) && on_segment(k, xq));
    } else {
      for (int k = 0; k < int(outline.size()) && !along; ++k) along = on_segment(k, xp) && on_segment(k, xq);
    }
    if (along) out.push_back({p, q});
  }
  return out;
}

/// W̄ on coarse faces and the comparison fields of `v` (finest level already stored in `v`).
void compare_energy_densities(const SurfaceMesh& sim, ConformingVerification& v) {
  const SurfaceMesh& conf = v.conforming_mesh;
  const FaceBvh bvh(sim);
  const RowMatX3d& X = conf.vertices();
  const RowMatX3i& F = conf.faces();
  v.conforming_to_coarse.resize(conf.num_faces());
  Eigen::VectorXd num = Eigen::VectorXd::Zero(sim.num_faces()), den = num;
  for (int c = 0; c < conf.num_faces(); ++c) {
    const Vec3 centroid = (X.row(F(c, 0)) + X.row(F(c, 1)) + X.row(F(c, 2))).transpose() / 3.0;
    const int t = bvh.closest_point(centroid).where.face;
    v.conforming_to_coarse[c] = t;
    num[t] += conf.face_areas()[c] * v.conforming_W[c];
    den[t] += conf.face_areas()[c];
  }
  const std::vector<bool> material = material_faces(v.alpha);
  v.W_on_coarse.setConstant(sim.num_faces(), std::numeric_limits<double>::quiet_NaN());
  v.compared.assign(size_t(sim.num_faces()), false);
  double err2 = 0, ref2 = 0;
  for (int t = 0; t < sim.num_faces(); ++t) {
    if (den[t] <= 0) continue;
    v.W_on_coarse[t] = num[t] / den[t];
    if (!material[size_t(t)]) continue;
    v.compared[size_t(t)] = true;
    ++v.compared_faces;
    const double d = v.coarse_W[t] - v.W_on_coarse[t];
    err2 += sim.face_areas()[t] * d * d;
    ref2 += sim.face_areas()[t] * v.W_on_coarse[t] * v.W_on_coarse[t];
    v.W_max_on_coarse = std::max(v.W_max_on_coarse, v.W_on_coarse[t]);
    if (v.worst_face < 0 || std::abs(d) > std::abs(v.worst_difference)) {
      v.worst_face = t;
      v.worst_difference = d;
    }
  }
  v.W_relative_l2 = ref2 > 0 ? std::sqrt(err2 / ref2) : 0.0;
  if (v.worst_face >= 0) {
    const RowMatX3i& G = sim.faces();
    const int t = v.worst_face;
    v.worst_position =
        (sim.vertices().row(G(t, 0)) + sim.vertices().row(G(t, 1)) + sim.vertices().row(G(t, 2))).transpose() / 3.0;
  }
}

double ratio(double a, double b) { return b != 0 ? a / b : std::numeric_limits<double>::quiet_NaN(); }

/// Removes the connected pieces of `mesh` without a supported vertex in `lc` (held along any axis); true when it did (the
/// caller resolves the load case again). Adds a note naming their count and area.
bool drop_unsupported_pieces(SurfaceMesh& mesh, const LoadCase& lc, double L, std::vector<std::string>& notes) {
  if (mesh.num_components() < 2) return false;
  const std::vector<int> piece = face_components(mesh);
  std::vector<bool> supported(size_t(mesh.num_components()), false);
  const std::vector<bool> held = supported_vertices(lc);  // along any axis
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (held[size_t(mesh.faces()(f, k))]) supported[size_t(piece[size_t(f)])] = true;
  int loose = 0, kept_faces = 0;
  double loose_area = 0;
  for (bool s : supported) loose += !s;
  if (loose == 0 || loose == int(supported.size())) return false;  // none loose, or nothing held at all
  RowMatX3i kept(mesh.num_faces(), 3);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (supported[size_t(piece[size_t(f)])]) kept.row(kept_faces++) = mesh.faces().row(f);
    else loose_area += mesh.face_areas()[f];
  }
  // Only the referenced vertices, renumbered.
  std::vector<int> index(size_t(mesh.num_vertices()), -1);
  int nv = 0;
  for (int f = 0; f < kept_faces; ++f)
    for (int k = 0; k < 3; ++k)
      if (index[size_t(kept(f, k))] < 0) index[size_t(kept(f, k))] = nv++;
  RowMatX3d V(nv, 3);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (index[size_t(v)] >= 0) V.row(index[size_t(v)]) = mesh.vertices().row(v);
  for (int f = 0; f < kept_faces; ++f)
    for (int k = 0; k < 3; ++k) kept(f, k) = index[size_t(kept(f, k))];
  mesh = SurfaceMesh(std::move(V), kept.topRows(kept_faces).eval(),
                     fmt::format("conforming mesh (edge length {:.4g} m)", L));
  notes.push_back(fmt::format("the stencils cut {} piece(s) loose from the supported shell ({:.3g} m^2 in all, at the "
                              "conforming edge length {:.3g} m): they would fall out of the printed part and are "
                              "left out of the conforming solve",
                              loose, loose_area, L));
  return true;
}

/// Richardson's rule (richardson.h) over value(item) of each item, coarsest first.
template <class Items, class Value>
Richardson richardson_over(const Items& items, Value value) {
  std::vector<double> values;
  for (const auto& item : items) values.push_back(value(item));
  return richardson_extrapolate(values);
}

/// One conforming solve and what is read from it.
struct LevelSolve {
  RunQuantities q;
  Eigen::VectorXd W;          ///< #F, J/m²
  RowMatX3d u;                ///< #V×3, m
  std::vector<RimPoint> rim;  ///< the recovered rim
  LoadCase load_case;         ///< the supports and loads it was solved under
};

/// A solved mesh a level's Newton starts from (solve_conforming_level): its displacements.
struct PreviousLevel {
  const SurfaceMesh* mesh = nullptr;
  const RowMatX3d* u = nullptr;
};

/// Solves the conforming `mesh` (pieces the stencils cut loose are dropped from it first) under the
/// scene's supports and loads, and recovers its rim with `rim_options`; q gets the run's scalars,
/// the supports' extent, the rim peak and the interior peak (not the edge length or mesh quality).
/// With `previous` (the last level's mesh and its displacements), Newton starts from those
/// displacements carried onto this mesh (interpolate_vertex_field) instead of from rest.
LevelSolve solve_conforming_level(SurfaceMesh& mesh, double L, const Scene& scene, const SceneMeshes& meshes,
                                  const LoadCase& load_case, const MechanicsSettings& mechanics,
                                  const NewtonSettings& settings, const RimRecoveryOptions& rim_options,
                                  std::vector<std::string>& notes, PreviousLevel previous = {}) {
  LevelSolve run;
  RunQuantities& q = run.q;
  // Boundary selectors mean the surface's boundary, not the rims of the holes (tolerance: the
  // cut's snapping distance is 1e-9 of the longest edge; remeshing keeps boundary vertices on
  // the cut's boundary edges to round-off).
  const double snap = 1e-9 * (meshes.base.bbox_max() - meshes.base.bbox_min()).norm();
  std::vector<bool> outer = boundary_vertices_on_boundary_of(mesh, meshes.base, snap);
  LoadCase lc = resolve_load_case(scene, mesh, &outer, &load_case);
  // Pieces the stencils cut loose (no supported vertex: an island between holes, or one that
  // hangs on the rest by a single vertex) fall out of the printed shell: left out, and said.
  if (drop_unsupported_pieces(mesh, lc, L, notes)) {
    outer = boundary_vertices_on_boundary_of(mesh, meshes.base, snap);
    lc = resolve_load_case(scene, mesh, &outer, &load_case);
  }
  q.fixed_extent = support_extent(mesh, supported_vertices(lc), &outer);
  q.clamped_extent = support_extent(mesh, lc.clamped, &outer);
  const ShellModel model(mesh, scene.material, lc, mechanics);
  RowMatX3d start;
  if (previous.mesh && previous.u && previous.mesh->num_faces() > 0)
    start = mesh.vertices() + interpolate_vertex_field(FaceBvh(*previous.mesh), *previous.u, mesh.vertices());
  solve_run(model, Eigen::VectorXd::Ones(mesh.num_faces()), settings, q, run.W, &run.u, nullptr, nullptr,
            start.rows() > 0 ? &start : nullptr);
  run.load_case = std::move(lc);
  // The peak: recovered on the rims, and over the interior faces.
  Stopwatch recovering;
  run.rim = recover_rim(model, mesh.vertices() + run.u, rim_options);
  const RimPeak rp = rim_peak(run.rim);
  q.rim_points = int(run.rim.size());
  for (const RimPoint& p : run.rim) {
    q.singular_rim_points += p.singular;
    if (p.at_corner && !(q.corner_peak >= p.energy_density)) {
      q.corner_peak = p.energy_density;
      q.corner_peak_position = p.position;
    }
  }
  if (rp.index >= 0) {
    q.rim_peak = rp.energy_density;
    q.rim_peak_position = run.rim[std::size_t(rp.index)].position;
  }
  const std::vector<bool>& boundary = mesh.is_boundary_vertex();
  for (int t = 0; t < mesh.num_faces(); ++t) {
    const auto face = mesh.faces().row(t);
    if (boundary[std::size_t(face(0))] || boundary[std::size_t(face(1))] || boundary[std::size_t(face(2))]) continue;
    if (!(q.interior_peak >= run.W(t))) q.interior_peak = run.W(t);
  }
  q.peak = q.rim_peak;
  q.seconds += recovering.seconds();
  return run;
}

}  // namespace

void extrapolate_compliance(ConformingVerification& v) {
  const Richardson r = richardson_over(v.levels, [](const RunQuantities& q) { return q.compliance; });
  v.extrapolated_compliance = r.extrapolated;
  v.observed_order = r.order;
  v.compliance_error_bar = r.error_bar;
  v.relative_error_bar = r.error_bar / std::abs(r.extrapolated);
}

Eigen::VectorXd fill_ratios_on_mesh(const FaceBvh& surface, const StencilLibrary& shapes, const TangentField& field,
                                    const SurfaceMesh& sim, std::span<const StencilParams> stencils,
                                    FillRatioOptions fill, ShapeCover* cover, double corner_radius) {
  if (stencils.empty()) {
    if (cover) *cover = ShapeCover{};
    return Eigen::VectorXd::Ones(sim.num_faces());
  }
  fill.derivatives = false;
  const FaceBvh sim_bvh(sim);
  FillRatioEvaluator eval(surface, sim_bvh, shapes, &field, fill);
  eval.evaluate(stencils);
  if (cover) *cover = shape_cover(eval, stencils, corner_radius, CellFilter{});
  return eval.alpha();
}

Eigen::VectorXd design_fill_ratios(const Scene& scene, const PatternContext& ctx, const SurfaceMesh& sim,
                                   std::span<const StencilParams> stencils, FillRatioOptions fill) {
  const Eigen::VectorXd alpha =
      fill_ratios_on_mesh(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), sim, stencils, fill);
  if (stencils.empty() || scene.mechanics.filter == FillFilter::None) return alpha;
  return scene_cell_filter(scene, ctx, sim).apply(alpha);
}

ConformingVerification verify_conforming(const Scene& scene, const SceneMeshes& meshes, const LoadCase& load_case,
                                         const PatternContext& ctx, std::span<const StencilParams> stencils,
                                         const ConformingOptions& options, FillRatioOptions fill) {
  if (!(options.edge_length > 0) || !std::isfinite(options.edge_length))
    throw InputError(fmt::format("conforming edge length {} is not a positive length (m)", options.edge_length));
  if (options.levels < 1 || options.levels > 6)
    throw InputError(fmt::format("conforming levels {} out of range [1, 6]", options.levels));
  if (!(options.tolerance >= 0) || !(options.tolerance < 1))
    throw InputError(fmt::format("conforming tolerance {} out of range [0, 1)", options.tolerance));
  if (options.grading_depth < 0 || options.grading_depth > 4)
    throw InputError(fmt::format("conforming grading depth {} out of range [0, 4]", options.grading_depth));
  if (!(options.elements_across >= 1) || !(options.elements_across <= 16))
    throw InputError(fmt::format("conforming elements across a ligament {} out of range [1, 16]", options.elements_across));
  if (options.max_faces < 1) throw InputError(fmt::format("conforming face budget {} is not positive", options.max_faces));
  if (options.peak_zoom < 0 || options.peak_zoom > 6)
    throw InputError(fmt::format("peak zoom {} out of range [0, 6]", options.peak_zoom));
  if (!(options.tool_radius >= 0) || !std::isfinite(options.tool_radius))
    throw InputError(fmt::format("tool radius {} m: expected a finite radius of at least 0", options.tool_radius));
  if (options.min_levels < 2 || options.min_levels > 6)
    throw InputError(fmt::format("conforming minimum levels {} out of range [2, 6]", options.min_levels));
  ConformingVerification v;
  NewtonSettings settings = options.newton;
  settings.log = [&v](const std::string& line) { v.notes.push_back(line); };

  // 1. The coarse fill-ratio run (design_fill_ratios, with the filter kept for its blend).
  const MechanicsSettings mechanics = resolve_fill_stiffness(scene.mechanics, ctx.shapes(), scene.material, stencils);
  // The cover by shape where W_peak reads its factors by shape and by corner (peak_energy_density.h).
  ShapeCover cover;
  const bool by_shape = !stencils.empty() && concentration_by_shape(mechanics, scene.material);
  const Eigen::VectorXd own = fill_ratios_on_mesh(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), meshes.sim,
                                                  stencils, fill, by_shape ? &cover : nullptr,
                                                  mechanics.corner_radius);
  const CellFilter filter = scene_cell_filter(scene, ctx, meshes.sim);
  v.alpha = stencils.empty() ? own : filter.apply(own);
  if (by_shape && !filter.identity()) {
    for (Eigen::Index k = 0; k < cover.covered.cols(); ++k) cover.covered.col(k) = filter.apply(cover.covered.col(k));
    for (Eigen::Index k = 0; k < cover.corner.cols(); ++k) cover.corner.col(k) = filter.apply(cover.corner.col(k));
  }
  // The conforming runs are at α = 1, where every fill rule is the solid.
  Eigen::VectorXd coarse_W_peak;
  RowMatX3d coarse_u;  // the first conforming level starts from it
  {
    const ShellModel coarse(meshes.sim, scene.material, load_case, mechanics);
    // W_peak's factors blend as the cell filter does (peak_energy_density.h).
    solve_run(coarse, v.alpha, settings, v.coarse, v.coarse_W, &coarse_u, filter.identity() ? nullptr : &filter.blend(),
              &coarse_W_peak, nullptr, by_shape ? &cover : nullptr);
    v.coarse.edge_length = meshes.sim.mean_edge_length();
    // The material the stencils leave is measured with the faces' own α, as a design measures it
    // (the filter is not exactly area-conserving near borders, cell_filter.h).
    v.coarse.material_area = own.dot(meshes.sim.face_areas());
  }

  // 2. Conforming runs, coarsest first, until converged, out of levels or over the budget; the
  // finest is kept for the comparison.
  v.stop = "levels";
  Stopwatch cutting;
  // The outline as the tool cuts it (stencil_opening.h): one shape per stencil, opened by the
  // tool's radius over the stencil's scale.
  v.tool_radius = options.tool_radius;
  ToolCutStencils tool_cut;
  const CutSurface cut =
      cut_with_tool(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), stencils, v.tool_radius, &tool_cut);
  v.tool_rounded = tool_cut.rounded;
  v.tool_too_small = tool_cut.too_small;
  v.tool_split = tool_cut.split;
  if (tool_cut.too_small > 0)
    v.notes.push_back(fmt::format("{} stencil(s) too small for the tool of radius {:.3g} m: cut as drawn, their sharp "
                                  "corners under the corner rule",
                                  tool_cut.too_small, v.tool_radius));
  if (tool_cut.split > 0)
    v.notes.push_back(fmt::format("{} stencil(s) with a neck narrower than the tool's diameter {:.3g} m: the tool cuts "
                                  "them in pieces, the largest is cut",
                                  tool_cut.split, 2 * v.tool_radius));
  if (cut.faces.rows() == 0) throw InputError("the stencils cut the whole surface away: nothing to verify");
  // The narrow ligaments W_peak cannot see (ligament_peak.h), from the coarse run's W_peak.
  if (coarse_W_peak.size() == meshes.sim.num_faces()) {
    const std::vector<double>& samples = mechanics.stiffness_curve.alpha;
    v.ligaments = summarize_ligament_peaks(cut, meshes.base, meshes.sim, v.alpha, coarse_W_peak,
                                           samples.empty() ? 0.0 : samples.front(), scene.material.thickness,
                                           mechanics.lattice, scene_symmetry_planes(scene, meshes.sim));
  }
  // The singular corners of the rim recovery from the cut's outline, the same on every level.
  // The rim recovery's singular zones, the same on every level: the minimum feature about the
  // cut's corners that turn into the material, the level-0 edge length about support ends.
  RimRecoveryOptions rim_options;
  // Turns within a quarter of the minimum feature count as one corner: 30° within 0.25 g is a
  // radius below about g/2, sharper than the printed part can be (the bowl's flower petals end in
  // tips of 0.39 mm radius, turning 15° per 0.1 mm segment). Cut by a tool of radius r, the
  // outline's rounds are r or larger, written at 5° per segment: the window is then r/4 (14° of
  // such a round and one segment's 5°, under 30°), so that only corners the tool left sharp count.
  const double corner_window = v.tool_radius > 0 ? 0.25 * v.tool_radius : 0.25 * scene.fabrication.min_feature;
  const std::vector<Vec3> corners = singular_corners(cut.vertices, cut.faces, rim_options.corner_angle, corner_window);
  rim_options.corner_radius = scene.fabrication.min_feature;
  rim_options.support_radius = options.edge_length;
  rim_options.corners = &corners;
  // The supports' outlines, kept as lines by every level's remeshing.
  const std::vector<std::array<int, 2>> support_lines =
      support_lines_on_cut(scene, meshes.base, cut, 1e-9 * (meshes.base.bbox_max() - meshes.base.bbox_min()).norm());
  const double cut_seconds = cutting.seconds();
  LoadCase finest_case;  // the supports and loads of the finest level solved (the zoom's submodel)
  for (int level = 0; level < options.levels; ++level) {
    const double L = options.edge_length / double(1 << level);
    // Each level's mesh is built first (a prediction from the last level's size was off by
    // 1.4–1.7×) and solved only when it is within the budget (always at level 0, said when over).
    GradingOptions grading;
    grading.depth = options.grading_depth;
    grading.elements_across = options.elements_across;
    grading.feature_scale = double(1 << level);
    // From the third level on, the last growth predicts the size: measured 0.89× the built level on
    // the plate design, 1.17× on the chair's. A level predicted over 1.25× the budget is not built
    // (on the plate design, the refused level took 100 s to mesh).
    if (level >= 2) {
      const double growth = double(v.levels[size_t(level) - 1].faces) / double(v.levels[size_t(level) - 2].faces);
      const double predicted = growth * double(v.levels[size_t(level) - 1].faces);
      if (predicted > kBudgetPredictionMargin * double(options.max_faces)) {
        v.stop = "budget";
        v.notes.push_back(fmt::format("conforming refinement stopped before L = {:.3g} m: the last growth (×{:.2f}) "
                                      "predicts {:.0f} triangles, over 1.25× the budget of {}",
                                      L, growth, predicted, options.max_faces));
        break;
      }
    }
    Stopwatch meshing;
    SurfaceMesh mesh = conforming_mesh(cut, meshes.base.mean_edge_length(), L, options.remesh_iterations, grading, support_lines);
    const double mesh_seconds = meshing.seconds() + (level == 0 ? cut_seconds : 0.0);
    if (mesh.num_faces() > options.max_faces) {
      if (level > 0) {
        v.stop = "budget";
        v.notes.push_back(fmt::format("conforming refinement stopped before L = {:.3g} m: its {} triangles exceed the "
                                      "budget of {}",
                                      L, mesh.num_faces(), options.max_faces));
        break;
      }
      v.notes.push_back(fmt::format("the coarsest conforming mesh (L = {:.3g} m) has {} triangles, over the budget of "
                                    "{}: solved anyway, as the only level",
                                    L, mesh.num_faces(), options.max_faces));
    }
    PreviousLevel previous;
    if (options.warm_start)
      previous = level > 0 ? PreviousLevel{&v.conforming_mesh, &v.conforming_displacement} : PreviousLevel{&meshes.sim, &coarse_u};
    LevelSolve run =
        solve_conforming_level(mesh, L, scene, meshes, load_case, mechanics, settings, rim_options, v.notes, previous);
    RunQuantities& q = run.q;
    q.edge_length = L;
    q.mesh_seconds = mesh_seconds;
    q.min_angle = min_angle(mesh) * 180.0 / std::numbers::pi;
    q.slivers = fraction_of_faces_below_angle(mesh, 10.0 * std::numbers::pi / 180.0);
    v.levels.push_back(q);
    v.conforming_W = std::move(run.W);
    v.conforming_rim = std::move(run.rim);
    v.conforming_displacement = std::move(run.u);
    finest_case = std::move(run.load_case);
    v.conforming_mesh = std::move(mesh);
    {
      const RunQuantities& first = v.levels.front();
      v.support_change = std::max({level == 0 ? 0.0 : v.support_change,
                                   support_extent_change(first.fixed_extent, q.fixed_extent, options.edge_length),
                                   support_extent_change(first.clamped_extent, q.clamped_extent, options.edge_length)});
      v.supports_consistent = v.support_change <= kSupportExtentTolerance;
    }
    if (level > 0) {
      const double c = v.levels[size_t(level)].compliance, c_prev = v.levels[size_t(level) - 1].compliance;
      v.last_change = std::abs(c - c_prev) / std::abs(c);
      extrapolate_compliance(v);
      if (options.tolerance > 0 && level + 1 >= options.min_levels && v.relative_error_bar <= options.tolerance &&
          v.supports_consistent) {
        v.converged = true;
        v.stop = "tolerance";
        break;
      }
    }
  }
  extrapolate_compliance(v);
  if (!v.supports_consistent) {
    // Name the level and the set that differ most from level 0.
    const RunQuantities& first = v.levels.front();
    size_t worst = 1;
    bool clamped = false;
    double change = -1;
    for (size_t k = 1; k < v.levels.size(); ++k)
      for (bool c : {false, true}) {
        const double d = support_extent_change(c ? first.clamped_extent : first.fixed_extent,
                                               c ? v.levels[k].clamped_extent : v.levels[k].fixed_extent,
                                               options.edge_length);
        if (d > change) change = d, worst = k, clamped = c;
      }
    const SupportExtent& a = clamped ? first.clamped_extent : first.fixed_extent;
    const SupportExtent& b = clamped ? v.levels[worst].clamped_extent : v.levels[worst].fixed_extent;
    v.notes.push_back(fmt::format(
        "the supports hold a different region on each level ({} vertices at L = {:.3g} m: {:.4g} m of line, {:.4g} m² "
        "of area, {} points; at L = {:.3g} m: {:.4g} m, {:.4g} m², {}; a change of {:.1f}%, tolerance {:.0f}%): the "
        "levels are different structures and their convergence says nothing; select the support region exactly "
        "(feet on z = 0: \"z\": {{\"below\": 1e-6}})",
        clamped ? "clamped" : "fixed", first.edge_length, a.length, a.area, a.points, v.levels[worst].edge_length,
        b.length, b.area, b.points, 100 * change, 100 * kSupportExtentTolerance));
  }
  if (options.tolerance > 0 && !v.converged && v.supports_consistent) {
    if (v.levels.size() < 2)
      v.notes.push_back("the conforming compliance is not shown to converge: one level ran");
    else if (int(v.levels.size()) < options.min_levels)
      v.notes.push_back(fmt::format(
          "the conforming compliance is not shown to converge: {} level(s) ran, {} are needed (two levels that "
          "agree can do so by chance); the error bar of {:.2g}% assumes first order",
          v.levels.size(), options.min_levels, 100 * v.relative_error_bar));
    else
      v.notes.push_back(fmt::format(
          "the conforming compliance has not converged: its error bar is {:.2g}% (tolerance {:.2g}%), the last "
          "change {:.2g}%",
          100 * v.relative_error_bar, 100 * options.tolerance, 100 * v.last_change));
  }

  // 2b. The peak zoom about the finest level's rim peak (PeakZoom).
  if (options.peak_zoom > 0 && std::isfinite(v.levels.back().rim_peak)) {
    const int k = int(v.levels.size()) - 1;
    const RunQuantities& finest = v.levels.back();
    const double L = finest.edge_length;
    PeakZoom& z = v.zoom;
    z.radius = kPeakZoomRadius * L;
    z.centres = rim_peak_candidates(v.conforming_rim, kPeakZoomFraction, 2 * z.radius, kPeakZoomCentres);
    auto outside_peak = [&](const std::vector<RimPoint>& rim) {
      double out = NAN;
      for (const RimPoint& p : rim) {
        if (p.singular || !(std::isnan(out) || p.energy_density > out)) continue;
        if (std::all_of(z.centres.begin(), z.centres.end(), [&](const Vec3& c) { return (p.position - c).norm() > z.radius; }))
          out = p.energy_density;
      }
      return out;
    };
    auto record = [&](const std::vector<RimPoint>& rim, PeakZoomStep& step) {
      const RimPeak rp = rim_peak_near(rim, z.centres, z.radius);
      step.peak = rp.energy_density;
      if (rp.index >= 0) step.position = rim[std::size_t(rp.index)].position;
      step.peak_outside = outside_peak(rim);
    };
    PeakZoomStep first;
    first.faces = finest.faces;
    first.rim_edge_length = L / double(1 << options.grading_depth);
    first.compliance = finest.compliance;
    record(v.conforming_rim, first);
    z.steps.push_back(first);
    GradingOptions grading;
    grading.depth = options.grading_depth;
    grading.elements_across = options.elements_across;
    grading.feature_scale = double(1 << k);
    grading.focus = z.centres;
    grading.focus_radius = z.radius;
    // The submodel: the finest level's faces within the widest ball of the last step and a margin
    // of two level-0 edge lengths (the rim recovery's singular zone about a support's end, which
    // the held collar is to it), re-solved with the collar held (zoom_patch).
    std::optional<ZoomPatch> patch;
    std::optional<LevelLoads> finest_loads;
    const double finest_load = free_load_norm(v.conforming_mesh, finest_case, scene.material);
    if (options.zoom_submodel) {
      try {
        finest_loads = level_loads(scene, meshes, v.conforming_mesh, finest_case);
        const double widest = z.radius * (1.0 + 0.5 * double(options.grading_depth + options.peak_zoom - 1));
        patch = zoom_patch(v.conforming_mesh, z.centres, widest + 2 * options.edge_length);
      } catch (const InputError& e) {
        v.notes.push_back(fmt::format("the peak zoom re-solves the whole shell on each step: {}", e.what()));
      }
    }
    for (int step = 1; step <= options.peak_zoom; ++step) {
      grading.focus_depth = step;
      if (patch) {
        try {
          Stopwatch meshing;
          RemeshOptions ro;
          ro.target_edge_length = L;
          ro.iterations = options.remesh_iterations;
          ro.grading = grading;
          RemeshedMesh r =
              refine_about(patch->mesh.vertices(), patch->mesh.faces(), patch->collar, cut.vertices, cut.faces, ro);
          const SurfaceMesh sub(std::move(r.vertices), std::move(r.faces), "peak zoom submodel");
          PeakZoomStep s;
          s.mesh_seconds = meshing.seconds();
          Stopwatch solving;
          const std::vector<RimPoint> rim =
              solve_submodel(*patch, sub, v.conforming_displacement,
                             submodel_load_case(scene, meshes, *finest_loads, sub), scene.material,
                             mechanics, settings, finest_load, rim_options)
                  .rim;
          s.seconds = solving.seconds();
          s.faces = sub.num_faces();
          s.rim_edge_length = L / double(1 << (options.grading_depth + step));
          record(rim, s);
          s.peak_outside = outside_peak(v.conforming_rim);  // the rest is the finest level's
          z.steps.push_back(s);
          z.submodel_faces = patch->mesh.num_faces();
          continue;
        } catch (const Interrupted&) {
          throw;
        } catch (const Error& e) {
          v.notes.push_back(fmt::format("the peak zoom's submodel failed at step {} ({}); the zoom re-solves the whole "
                                        "shell instead",
                                        step, e.what()));
          patch.reset();
          z.steps.resize(1);
          z.submodel_faces = 0;
          step = 0;
          continue;
        }
      }
      Stopwatch meshing;
      SurfaceMesh mesh = conforming_mesh(cut, meshes.base.mean_edge_length(), L, options.remesh_iterations, grading, support_lines);
      const double mesh_seconds = meshing.seconds();
      if (mesh.num_faces() > kBudgetPredictionMargin * options.max_faces) {
        v.notes.push_back(fmt::format("the peak zoom stopped before step {}: its {} triangles exceed 1.25× the budget "
                                      "of {}",
                                      step, mesh.num_faces(), options.max_faces));
        break;
      }
      // From the finest level's solution (the zoom changes the field near its balls only).
      PreviousLevel previous;
      if (options.warm_start) previous = {&v.conforming_mesh, &v.conforming_displacement};
      LevelSolve run =
          solve_conforming_level(mesh, L, scene, meshes, load_case, mechanics, settings, rim_options, v.notes, previous);
      PeakZoomStep s;
      s.faces = mesh.num_faces();
      s.rim_edge_length = L / double(1 << (options.grading_depth + step));
      s.compliance = run.q.compliance;
      s.seconds = run.q.seconds;
      s.mesh_seconds = mesh_seconds;
      record(run.rim, s);
      z.steps.push_back(s);
    }
    if (z.steps.size() >= 2) {
      const Richardson r = richardson_over(z.steps, [](const PeakZoomStep& s) { return s.peak; });
      z.extrapolated = r.extrapolated;
      z.order = r.order;
      z.error_bar = r.error_bar;
      const double before = z.steps[z.steps.size() - 2].peak;
      z.change = std::abs(z.steps.back().peak - before) / z.steps.back().peak;
      z.converged = z.change <= kPeakTolerance;
      const PeakZoomStep& last = z.steps.back();
      if (last.peak_outside > last.peak)
        v.notes.push_back(fmt::format("the peak zoom's last step reads {:.4g} J/m² outside its {} ball(s), more than the "
                                      "{:.4g} J/m² it refined: the peak may be elsewhere",
                                      last.peak_outside, z.centres.size(), last.peak));
    }
  }

  // 3. Comparison against the finest level (the peak: against the zoom when it ran).
  const RunQuantities& f = v.levels.back();
  if (f.corner_peak > f.peak)
    v.notes.push_back(fmt::format(
        "rim points within the minimum feature ({:.3g} m) of corners sharper than it, left out of the conforming peak, "
        "read up to {:.4g} J/m² at ({:.4g}, {:.4g}, {:.4g}) m on the finest level, against its peak {:.4g}: where those "
        "corners are the stencils' own rounds the shell's peak is there, unresolved (W_peak's factors leave them out "
        "too, by the same rule){}",
        scene.fabrication.min_feature, f.corner_peak, f.corner_peak_position.x(), f.corner_peak_position.y(),
        f.corner_peak_position.z(), f.peak,
        v.tool_radius > 0 ? std::string()
                          : std::string("; a part cut with a tool has them rounded: --tool-radius (or the scene's "
                                        "fabrication.tool_radius) reads them so")));
  const bool zoomed = v.zoom.steps.size() >= 2;
  v.conforming_peak = zoomed ? v.zoom.steps.back().peak : f.peak;
  v.compliance_ratio = ratio(v.coarse.compliance, f.compliance);
  v.compliance_ratio_extrapolated = ratio(v.coarse.compliance, v.extrapolated_compliance);
  v.strain_energy_ratio = ratio(v.coarse.strain_energy, f.strain_energy);
  v.max_displacement_ratio = ratio(v.coarse.max_displacement, f.max_displacement);
  v.W_max_ratio = ratio(v.coarse.W_max, f.W_max);
  // Like for like: the coarse W_peak with the cells' Kirchhoff factors against the Kirchhoff shell's
  // rim peak (W_peak_max itself carries the thick-round transition where it applies).
  const double coarse_peak = std::isfinite(v.coarse.W_peak_kirchhoff_max) ? v.coarse.W_peak_kirchhoff_max
                                                                           : v.coarse.W_peak_max;
  if (std::isfinite(coarse_peak)) {
    v.W_peak_ratio = ratio(coarse_peak, v.conforming_peak);
    v.W_estimate = std::isfinite(v.ligaments.W_max) ? std::max(coarse_peak, v.ligaments.W_max) : coarse_peak;
    v.W_estimate_ratio = ratio(v.W_estimate, v.conforming_peak);
  }
  if (zoomed) {
    v.peak_extrapolated = v.zoom.extrapolated;
    v.peak_order = v.zoom.order;
    v.peak_error_bar = v.zoom.error_bar;
  } else {
    if (std::all_of(v.levels.begin(), v.levels.end(), [](const RunQuantities& q) { return std::isfinite(q.peak); })) {
      const Richardson r = richardson_over(v.levels, [](const RunQuantities& q) { return q.peak; });
      v.peak_extrapolated = r.extrapolated;
      v.peak_order = r.order;
      v.peak_error_bar = r.error_bar;
    }
  }
  if (std::isfinite(coarse_peak) && std::isfinite(v.peak_extrapolated)) {
    v.W_peak_ratio_extrapolated = ratio(coarse_peak, v.peak_extrapolated);
    v.W_estimate_ratio_extrapolated = ratio(v.W_estimate, v.peak_extrapolated);
  }
  if (zoomed || v.levels.size() >= 2) {
    const double previous = zoomed ? v.zoom.steps[v.zoom.steps.size() - 2].peak : v.levels[v.levels.size() - 2].peak;
    v.peak_change = std::abs(v.conforming_peak - previous) / v.conforming_peak;
    v.peak_converged = v.peak_change <= kPeakTolerance;
    if (!v.peak_converged)
      v.notes.push_back(fmt::format("the conforming peak energy density has not converged: {:.4g} → {:.4g} J/m² over the "
                                    "last {} ({:.2g}%; settled below {:.2g}%): its comparison with W_peak says little",
                                    previous, v.conforming_peak, zoomed ? "zoom step" : "two levels",
                                    100 * v.peak_change, 100 * kPeakTolerance));
  }
  compare_energy_densities(meshes.sim, v);
  // Dead loads carry the coarse totals by construction (resolve_load_case's match_totals); only
  // self-weight differs, by the difference between Σ α A and the conforming material area.
  const double load_gap = (v.coarse.load_total - f.load_total).norm();
  if (load_gap > 0.01 * f.load_total.norm())
    v.notes.push_back(fmt::format("the loads differ: {:.4g} N in total on the coarse mesh, {:.4g} N on the "
                                  "conforming one (self-weight: the fill ratios' material area differs from "
                                  "the cut mesh's)",
                                  v.coarse.load_total.norm(), f.load_total.norm()));
  return v;
}

}  // namespace cutwork::solvers
