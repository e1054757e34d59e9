#include "solvers/conforming/zoom_submodel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/mesh/bvh.h"
#include "host/mesh/mesh_mapping.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

ZoomPatch zoom_patch(const SurfaceMesh& level, const std::vector<Vec3>& centres, double radius) {
  const RowMatX3d& X = level.vertices();
  const RowMatX3i& F = level.faces();
  std::vector<bool> inside(size_t(level.num_faces()), false);
  for (int f = 0; f < level.num_faces(); ++f) {
    const Vec3 c = (X.row(F(f, 0)) + X.row(F(f, 1)) + X.row(F(f, 2))).transpose() / 3.0;
    inside[size_t(f)] = std::any_of(centres.begin(), centres.end(), [&](const Vec3& x) { return (c - x).norm() <= radius; });
  }
  // Vertices on the cut: on a face inside and on one outside.
  std::vector<char> on_inside(size_t(level.num_vertices()), 0), on_outside(size_t(level.num_vertices()), 0);
  for (int f = 0; f < level.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) (inside[size_t(f)] ? on_inside : on_outside)[size_t(F(f, k))] = 1;
  std::vector<char> held(size_t(level.num_vertices()), 0);
  for (size_t v = 0; v < held.size(); ++v) held[v] = on_inside[v] && on_outside[v];
  std::vector<bool> collar(size_t(level.num_faces()), false);
  for (int ring = 0; ring < 2; ++ring) {
    for (int f = 0; f < level.num_faces(); ++f)
      if (inside[size_t(f)] && (held[size_t(F(f, 0))] || held[size_t(F(f, 1))] || held[size_t(F(f, 2))]))
        collar[size_t(f)] = true;
    for (int f = 0; f < level.num_faces(); ++f)
      if (collar[size_t(f)])
        for (int k = 0; k < 3; ++k) held[size_t(F(f, k))] = 1;
  }
  ZoomPatch p;
  std::vector<int> index(size_t(level.num_vertices()), -1);
  std::vector<Eigen::Vector3i> faces;
  for (int f = 0; f < level.num_faces(); ++f) {
    if (!inside[size_t(f)]) continue;
    Eigen::Vector3i face;
    for (int k = 0; k < 3; ++k) {
      int& i = index[size_t(F(f, k))];
      if (i < 0) {
        i = int(p.level_vertex.size());
        p.level_vertex.push_back(F(f, k));
      }
      face[k] = i;
    }
    faces.push_back(face);
    p.collar.push_back(collar[size_t(f)]);
  }
  RowMatX3d V(Eigen::Index(p.level_vertex.size()), 3);
  RowMatX3i G(Eigen::Index(faces.size()), 3);
  for (size_t i = 0; i < p.level_vertex.size(); ++i) V.row(Eigen::Index(i)) = X.row(p.level_vertex[i]);
  for (size_t f = 0; f < faces.size(); ++f) G.row(Eigen::Index(f)) = faces[f].transpose();
  p.mesh = SurfaceMesh(std::move(V), std::move(G), "peak zoom submodel");
  return p;
}

LevelLoads level_loads(const Scene& scene, const SceneMeshes& meshes, const SurfaceMesh& level,
                       const LoadCase& level_case) {
  const double snap = 1e-9 * (meshes.base.bbox_max() - meshes.base.bbox_min()).norm();
  const std::vector<bool> outer = boundary_vertices_on_boundary_of(level, meshes.base, snap);
  LevelLoads out;
  out.own.assign(scene.loads.size(), 0.0);
  out.matched = level_case.load_measures;
  out.gravity = level_case.gravity;
  Scene one = scene;
  one.supports.clear();
  for (size_t i = 0; i < scene.loads.size(); ++i) {
    const LoadSpec& l = scene.loads[i];
    if (l.kind == LoadKind::SelfWeight) continue;
    if (l.select.nearest > 0) throw InputError("the peak zoom's submodel cannot carry a load on the nearest vertices");
    one.loads = {l};
    out.own[i] = resolve_load_case(one, level, &outer).load_measures[0];
  }
  return out;
}

LoadCase submodel_load_case(const Scene& scene, const SceneMeshes& meshes, const LevelLoads& level,
                            const SurfaceMesh& sub) {
  const double snap = 1e-9 * (meshes.base.bbox_max() - meshes.base.bbox_min()).norm();
  const std::vector<bool> outer_sub = boundary_vertices_on_boundary_of(sub, meshes.base, snap);
  LoadCase lc;
  const size_t nv = size_t(sub.num_vertices());
  lc.fixed.assign(nv, false);
  lc.clamped.assign(nv, false);
  lc.held_axes.assign(nv, 0);
  lc.forces = RowMatX3d::Zero(sub.num_vertices(), 3);
  lc.gravity = level.gravity;
  lc.load_measures.assign(scene.loads.size(), 0.0);
  Scene one = scene;
  one.loads.clear();
  for (const auto& support : scene.supports) {
    one.supports = {support};
    try {
      const LoadCase s = resolve_load_case(one, sub, &outer_sub);
      for (size_t v = 0; v < nv; ++v) {
        lc.fixed[v] = lc.fixed[v] || s.fixed[v];
        lc.clamped[v] = lc.clamped[v] || s.clamped[v];
        if (!s.held_axes.empty()) lc.held_axes[v] |= s.held_axes[v];
        if (!s.symmetry_axes.empty()) {  // a symmetry plane the patch reaches
          if (lc.symmetry_axes.empty()) lc.symmetry_axes.assign(nv, 0);
          lc.symmetry_axes[v] |= s.symmetry_axes[v];
        }
      }
      for (int a = 0; a < 3; ++a)
        if (std::isfinite(s.symmetry_planes[a])) lc.symmetry_planes[a] = s.symmetry_planes[a];
    } catch (const InputError&) {
      // selects nothing on the patch
    }
  }
  one.supports.clear();
  for (size_t i = 0; i < scene.loads.size(); ++i) {
    const LoadSpec& l = scene.loads[i];
    if (l.kind == LoadKind::SelfWeight || !(level.own[i] > 0)) continue;
    one.loads = {l};
    LoadCase on_sub;
    try {
      on_sub = resolve_load_case(one, sub, &outer_sub);
    } catch (const InputError&) {
      continue;  // nothing of it on the patch
    }
    const double scale =
        l.kind == LoadKind::Point ? on_sub.load_measures[0] / level.own[i] : level.matched[i] / level.own[i];
    lc.forces += scale * on_sub.forces;
    lc.load_measures[i] = on_sub.load_measures[0];
  }
  return lc;
}

double free_load_norm(const SurfaceMesh& mesh, const LoadCase& load_case, const Material& material) {
  RowMatX3d f = load_case.forces.rows() == mesh.num_vertices() ? load_case.forces : RowMatX3d::Zero(mesh.num_vertices(), 3);
  const Vec3 weight = material.density * material.thickness * load_case.gravity;
  for (int t = 0; t < mesh.num_faces(); ++t)
    for (int k = 0; k < 3; ++k) f.row(mesh.faces()(t, k)) += (mesh.face_areas()[t] / 3.0) * weight.transpose();
  double sum = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (load_case.fixed.empty() || !load_case.fixed[size_t(v)]) sum += f.row(v).squaredNorm();
  return std::sqrt(sum);
}

SubmodelSolution solve_submodel(const ZoomPatch& patch, const SurfaceMesh& sub, const RowMatX3d& u, LoadCase lc,
                                const Material& material, const MechanicsSettings& mechanics,
                                NewtonSettings settings, double force_scale, const RimRecoveryOptions& rim_options) {
  // The collar's vertices, found by position (the refinement leaves them bit for bit).
  std::map<std::array<double, 3>, int> held;
  const RowMatX3d& P = patch.mesh.vertices();
  for (int f = 0; f < patch.mesh.num_faces(); ++f)
    if (patch.collar[size_t(f)])
      for (int k = 0; k < 3; ++k) {
        const int v = patch.mesh.faces()(f, k);
        held[{P(v, 0), P(v, 1), P(v, 2)}] = patch.level_vertex[size_t(v)];
      }
  const RowMatX3d& X = sub.vertices();
  RowMatX3d u_patch(patch.mesh.num_vertices(), 3);
  for (int v = 0; v < patch.mesh.num_vertices(); ++v) u_patch.row(v) = u.row(patch.level_vertex[size_t(v)]);
  const FaceBvh bvh(patch.mesh);
  RowMatX3d x = X + interpolate_vertex_field(bvh, u_patch, X);
  size_t found = 0;
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    const auto it = held.find({X(v, 0), X(v, 1), X(v, 2)});
    if (it != held.end()) {
      ++found;
      lc.fixed[size_t(v)] = true;
      x.row(v) = X.row(v) + u.row(it->second);
    } else if (lc.fixed[size_t(v)]) {  // the scene's own support
      x.row(v) = X.row(v);
    } else if (!lc.held_axes.empty() && lc.held_axes[size_t(v)] != 0) {  // held along some axes
      for (int a = 0; a < 3; ++a)
        if (lc.held_axes[size_t(v)] & (1u << a)) x(v, a) = X(v, a);
    }
  }
  if (found != held.size())
    throw SolveError(fmt::format("the peak zoom's submodel kept {} of its {} collar vertices", found, held.size()));
  lc.held_motion = true;
  settings.force_scale = force_scale;
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(sub.num_faces());
  const ShellModel model(sub, material, lc, mechanics);
  EquilibriumSolver solver(model, settings);
  try {
    solver.restore_equilibrium(x, ones);
  } catch (const SolveError&) {
    // The level's displacements interpolated onto the submodel's finer rims are near its equilibrium
    // but not at it, and under membrane compression the Hessian there need not be positive definite:
    // Newton starts from them as a guess instead (its shifted steps take an indefinite start; the
    // collar stays where the level put it, held_motion, which the check below confirms).
    solver.start_from(x);
  }
  const EquilibriumStats& stats = solver.solve(ones);
  if (!stats.stable) throw SolveError("the peak zoom's submodel is unstable");
  for (Eigen::Index v = 0; v < X.rows(); ++v)
    if (lc.fixed[size_t(v)] && solver.positions().row(v) != x.row(v) && held.count({X(v, 0), X(v, 1), X(v, 2)}))
      throw SolveError("the peak zoom's submodel moved a held vertex");
  SubmodelSolution out;
  out.positions = solver.positions();
  out.rim = recover_rim(model, out.positions, rim_options);
  out.newton_iterations = stats.newton_iterations;
  return out;
}

}  // namespace cutwork::solvers
