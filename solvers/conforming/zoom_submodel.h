#pragma once
/// The peak zoom's submodel (conforming_verification.h PeakZoom, ConformingOptions::zoom_submodel).
///
/// The zoom refines the rims about the candidates of the rim peak a few halvings beyond the finest
/// level. Re-solving the whole shell for each step cost about the finest level's solve and meshing
/// each time (the table's design: 55–70 s a step on 380k–500k triangles), though the refinement
/// changes the field only near the balls (the whole shell's compliance moved by 0.004% over four
/// steps). The submodel re-solves only the finest level's faces about the centres, held on their
/// border at that level's solution: the classical cut-boundary-displacement submodel, which rests on
/// Saint-Venant's principle, the refinement's effect dying out over a few of its own sizes.
///
///  - zoom_patch: the level's faces whose centroids lie within a radius of a centre, and its collar,
///    the faces within two rings of where the patch was cut out. Every vertex of a collar face is
///    held at the level's solution. Two rings make the rest exact: a face next to the cut misses
///    neighbours (its bending element is not the level's), but all of its element's vertices are
///    held, so its energy is a constant; every face of the second ring and inside has all its
///    neighbours in the patch. Tested: the patch re-solved unrefined stays at the level's solution,
///    and returns to it from its free vertices at rest (tests/solvers/conforming).
///  - refine_about (host/mesh/isotropic_remesh.h): the zoom's focus passes on the patch, the collar
///    frozen.
///  - submodel_load_case: the scene's supports and loads on the refined patch, at the densities the
///    level carries.
///  - solve_submodel: the equilibrium from the level's solution interpolated onto the refined patch,
///    the collar's vertices held exactly where the level put them; then the rim recovery.
#include <vector>

#include "host/mesh/surface_mesh.h"
#include "host/scene/load_case.h"
#include "host/scene/scene.h"
#include "solvers/conforming/rim_recovery.h"
#include "solvers/equilibrium/equilibrium_solver.h"

namespace cutwork::solvers {

struct ZoomPatch {
  SurfaceMesh mesh;               ///< the level's faces about the centres (vertices at rest, m)
  std::vector<int> level_vertex;  ///< per patch vertex: its vertex on the level
  std::vector<bool> collar;       ///< per patch face: within two rings of the cut (held)
};

/// The faces of `level` whose centroids lie within `radius` (m) of any of `centres`, and the collar.
ZoomPatch zoom_patch(const SurfaceMesh& level, const std::vector<Vec3>& centres, double radius);

/// What the level's loads are spread over, per scene load: its own measure of the load's region
/// (area or length, or for a total spread over a region the region's), and the measure the level's
/// case carries the total over (level_case.load_measures: the coarse run's, which it matched).
struct LevelLoads {
  std::vector<double> own, matched;
  Vec3 gravity = Vec3::Zero();
};

/// The level's loads (solved under `level_case`), once per zoom. Throws InputError for a load on the
/// n nearest vertices (what it selects depends on the mesh).
LevelLoads level_loads(const Scene& scene, const SceneMeshes& meshes, const SurfaceMesh& level,
                       const LoadCase& level_case);

/// The scene's supports and loads on a submodel `sub` of the level, as they act on the level: per
/// load, the density the level carries (a load per area or length: matched over own; a total spread
/// over a region: the total over the level's measure of the region), so the patch carries the
/// level's share, not the whole load. Supports and loads that select nothing on the patch are left
/// out; self-weight is the level's gravity.
LoadCase submodel_load_case(const Scene& scene, const SceneMeshes& meshes, const LevelLoads& level,
                            const SurfaceMesh& sub);

struct SubmodelSolution {
  RowMatX3d positions;         ///< #V_sub×3 (m), at equilibrium
  std::vector<RimPoint> rim;   ///< recovered with the options given
  int newton_iterations = 0;
};

/// ‖f_ext‖ over the free vertices of a shell on `mesh` under `load_case` (dead loads and lumped
/// self-weight, fill ratios 1): what its Newton solve measured its residual against.
double free_load_norm(const SurfaceMesh& mesh, const LoadCase& load_case, const Material& material);

/// Solves the submodel `sub` (`patch`, refined with its collar frozen) under `load_case`
/// (submodel_load_case), the collar's vertices held where the level's displacements `u` (#V_level×3,
/// m) put them (LoadCase::held_motion), starting from `u` interpolated onto it; then recovers its
/// rim. Newton's residual is measured against `force_scale` (N) where the submodel's own load is
/// smaller: the level's free_load_norm, so that both are converged alike (a patch off the loads
/// has none). Throws SolveError when a collar vertex did not come through the refinement bit for
/// bit, Newton moved one, or the equilibrium is unstable.
SubmodelSolution solve_submodel(const ZoomPatch& patch, const SurfaceMesh& sub, const RowMatX3d& u, LoadCase load_case,
                                const Material& material, const MechanicsSettings& mechanics,
                                NewtonSettings settings, double force_scale, const RimRecoveryOptions& rim_options);

}  // namespace cutwork::solvers
