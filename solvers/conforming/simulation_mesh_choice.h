#pragma once
/// The simulation mesh of a scene whose mesh is a file, where `mesh.sim_subdivisions` is "auto"
/// (the default): the coarsest of the file's mesh and its midpoint subdivisions on which the uncut
/// shell's compliance is within the discretisation tolerance (2%) of its converged value.
///
/// A generated scene's simulation mesh has its own edge length, chosen so that its default is
/// converged (docs/DESIGN.md "Discretisation estimate"); a file's mesh is whatever the file holds,
/// and it is also the base mesh, cut and exported as it is. So the file's mesh stays the base, and
/// the shell is simulated on it divided k times at its edges' midpoints: the same flat facets (what
/// is printed from the file), finer. k comes from the uncut shell solved on the file's mesh and its
/// subdivisions (estimate_discretisation: divided once and twice always, then once more while no
/// level that may be chosen is within the tolerance or the finest three have not settled, up to
/// the h/2 of the finest that may be) and
/// is the smallest whose compliance C_k is within the tolerance of the extrapolated C∞ (the finest
/// three levels' Richardson value; where those have not settled, the cautious
/// (|C_k − C_finest| + the finest three's larger difference) / |C_finest|). k is at most the largest
/// whose own estimate (the run's, at its h/2) stays within the estimate's face budget (250,000
/// triangles), and at most kMaxSimSubdivisions. Where no level qualifies, the finest allowed is
/// taken and the note says how far from converged it is. Where the supports hold a different
/// region on each level (a selector that depends on the mesh) the levels are different
/// structures: the file's mesh is kept and the note says why.
///
/// Deterministic: design, simulate, verify and a sweep's variants choose the same mesh for the
/// same scene.
#include <string>
#include <vector>

#include "host/scene/scene.h"
#include "solvers/conforming/discretisation_estimate.h"

namespace cutwork::solvers {

/// Resolves meshes.sim_choice_pending (build_scene_meshes sets it for "auto"): solves the uncut
/// shell on the file's mesh and its subdivisions, makes the chosen one meshes.sim
/// (use_subdivided_simulation_mesh) and records the study in meshes.sim_choice (report.json
/// mesh.sim_choice: subdivisions, levels [{subdivisions, triangles, compliance, error}],
/// extrapolated, rule, tolerance, converged, summary). Returns a one-line note for the run's notes
/// ("" when nothing was pending). Throws what the equilibrium throws (SolveError: a load the uncut
/// shell cannot carry).
std::string choose_simulation_mesh(const Scene& scene, SceneMeshes& meshes, const DiscretisationOptions& options = {});

/// The most subdivisions "auto" may choose for a file's mesh of `base_faces` triangles: the most
/// (≤ kMaxSimSubdivisions) whose run's own estimate can still make its h/2 within
/// options.max_faces; 0 where one subdivision could not (nothing to choose then: no study).
int most_simulation_subdivisions(size_t base_faces, const DiscretisationOptions& options = {});

/// The estimated error of each level's compliance (h first, each level at half the last's edge
/// length) against the converged value: |C_k − C∞| / |C∞| (Richardson over the finest three, or
/// first order assumed with two), or where the finest three have not settled
/// (|C_k − C_finest| + their larger difference) / |C_finest|.
std::vector<double> level_errors(const std::vector<double>& compliances);

}  // namespace cutwork::solvers
