#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/conforming/conforming_verification.h"

#include <cmath>
#include <limits>

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
               RunQuantities& q, Eigen::VectorXd& W, RowMatX3d* u) {
  Stopwatch sw;
  EquilibriumSolver solver(model, settings);
  const EquilibriumStats& stats = solver.solve(alpha);
  if (!stats.stable)
    throw SolveError(fmt::format("the {}-triangle shell's equilibrium is unstable (it buckles); the comparison "
                                 "needs a stable equilibrium",
                                 model.num_faces()));
  const EquilibriumSummary s = summarize_equilibrium(model, solver.positions(), alpha);
  static_cast<EquilibriumScalars&>(q) = s;
  q.vertices = model.num_vertices();
  q.faces = model.num_faces();
  q.dofs = model.num_dofs();
  q.material_area = alpha.dot(model.mesh().face_areas());
  q.load_total = model.external_forces(alpha).colwise().sum().transpose();
  q.newton_iterations = stats.newton_iterations;
  W = s.energy_density;
  if (u) *u = solver.displacements();
  q.seconds = sw.seconds();
}

/// The base mesh cut along every stencil outline and remeshed at `edge_length`.
SurfaceMesh conforming_mesh(const PatternContext& ctx, std::span<const StencilParams> stencils, double edge_length,
                            int iterations) {
  const CutSurface cut = cut_stencils(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), stencils);
  if (cut.faces.rows() == 0) throw InputError("the stencils cut the whole surface away: nothing to verify");
  RemeshOptions ro;
  ro.target_edge_length = edge_length;
  ro.iterations = iterations;
  RemeshedMesh r = remesh_isotropic(cut.vertices, cut.faces, ro);
  return SurfaceMesh(std::move(r.vertices), std::move(r.faces),
                     fmt::format("conforming mesh (edge length {:.4g} m)", edge_length));
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

}  // namespace

Eigen::VectorXd design_fill_ratios(const PatternContext& ctx, const SceneMeshes& meshes,
                                   std::span<const StencilParams> stencils, FillRatioOptions fill) {
  if (stencils.empty()) return Eigen::VectorXd::Ones(meshes.sim.num_faces());
  fill.derivatives = false;
  const FaceBvh sim_bvh(meshes.sim);
  FillRatioEvaluator eval(ctx.surface().bvh(), sim_bvh, ctx.shapes(), &ctx.surface().field(), fill);
  eval.evaluate(stencils);
  return eval.alpha();
}

ConformingVerification verify_conforming(const Scene& scene, const SceneMeshes& meshes, const LoadCase& load_case,
                                         const PatternContext& ctx, std::span<const StencilParams> stencils,
                                         const ConformingOptions& options, FillRatioOptions fill) {
  if (!(options.edge_length > 0) || !std::isfinite(options.edge_length))
    throw InputError(fmt::format("conforming edge length {} is not a positive length (m)", options.edge_length));
  if (options.levels < 1 || options.levels > 6)
    throw InputError(fmt::format("conforming levels {} out of range [1, 6]", options.levels));
  ConformingVerification v;
  NewtonSettings settings = options.newton;
  settings.log = [&v](const std::string& line) { v.notes.push_back(line); };

  // 1. The coarse fill-ratio run.
  v.alpha = design_fill_ratios(ctx, meshes, stencils, fill);
  // The conforming runs are at α = 1, where every fill rule is the solid.
  const MechanicsSettings mechanics = resolve_fill_stiffness(scene.mechanics, ctx.shapes(), scene.material);
  {
    const ShellModel coarse(meshes.sim, scene.material, load_case, mechanics);
    solve_run(coarse, v.alpha, settings, v.coarse, v.coarse_W, nullptr);
    v.coarse.edge_length = meshes.sim.mean_edge_length();
  }

  // 2. Conforming runs, coarsest first; the finest is kept for the comparison.
  for (int level = 0; level < options.levels; ++level) {
    const double L = options.edge_length / double(1 << level);
    SurfaceMesh mesh = conforming_mesh(ctx, stencils, L, options.remesh_iterations);
    RunQuantities q;
    Eigen::VectorXd W;
    RowMatX3d u;
    {
      // Boundary selectors mean the surface's boundary, not the rims of the holes (tolerance: the
      // cut's snapping distance is 1e-9 of the longest edge; remeshing keeps boundary vertices on
      // the cut's boundary edges to round-off).
      const std::vector<bool> outer =
          boundary_vertices_on_boundary_of(mesh, meshes.base, 1e-9 * (meshes.base.bbox_max() - meshes.base.bbox_min()).norm());
      const LoadCase lc = resolve_load_case(scene, mesh, &outer);
      const ShellModel model(mesh, scene.material, lc, mechanics);
      solve_run(model, Eigen::VectorXd::Ones(mesh.num_faces()), settings, q, W, &u);
    }
    q.edge_length = L;
    v.levels.push_back(q);
    if (level + 1 == options.levels) {
      v.conforming_W = std::move(W);
      v.conforming_displacement = std::move(u);
      v.conforming_mesh = std::move(mesh);
    }
  }

  // 3. Comparison against the finest level.
  const RunQuantities& f = v.levels.back();
  v.compliance_ratio = ratio(v.coarse.compliance, f.compliance);
  v.strain_energy_ratio = ratio(v.coarse.strain_energy, f.strain_energy);
  v.max_displacement_ratio = ratio(v.coarse.max_displacement, f.max_displacement);
  v.W_max_ratio = ratio(v.coarse.W_max, f.W_max);
  compare_energy_densities(meshes.sim, v);
  const double load_gap = (v.coarse.load_total - f.load_total).norm();
  if (load_gap > 0.01 * f.load_total.norm())
    v.notes.push_back(fmt::format("the loads differ: {:.4g} N in total on the coarse mesh, {:.4g} N on the "
                                  "conforming one (area and edge loads over holes act on the coarse filler only)",
                                  v.coarse.load_total.norm(), f.load_total.norm()));
  return v;
}

}  // namespace cutwork::solvers
