#pragma once
/// How far a simulation-mesh answer is from converged: the same shell, with the same stencils,
/// solved again on the simulation mesh at half its edge length (one extra equilibrium at about
/// four times the degrees of freedom), and the two answers compared.
///
/// The refined mesh is the scene's generator run again at sim_edge_length / 2 when the surface is
/// generated (so the geometry is resolved better too), and the 1 → 4 midpoint subdivision of the
/// simulation mesh when it comes from a file (the same flat facets: only the mechanics' error is
/// seen). Supports and loads are resolved on it again (loads are integrated over their regions,
/// so their totals are the same); the stencils' fill ratios are computed on it again.
///
/// The estimate: with Δ = |C_h − C_{h/2}| the change of the compliance, the error of C_h against
/// the converged value is Δ·2^p/(2^p − 1) for convergence of order p in h; cutwork reports
/// estimated_error = 2Δ/|C_{h/2}| (p = 1, the slowest order a conforming shell discretisation
/// shows, e.g. at re-entrant clamped corners): an upper estimate for p ≥ 1 in the asymptotic range.
/// `converged` says estimated_error ≤ tolerance (default 2%). W_max's change is reported beside it;
/// it need not converge at all where the exact energy density is singular (point supports,
/// re-entrant clamped corners).
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "host/mesh/surface_mesh.h"
#include "host/scene/scene.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/structural_quantities.h"

namespace cutwork::solvers {

inline constexpr double kDiscretisationTolerance = 0.02;

/// The simulation mesh at half the edge length, and how it was made ("regenerated" or
/// "subdivided").
struct RefinedSimulationMesh {
  SurfaceMesh mesh;
  std::string method;
  double edge_length = 0;  ///< target (regenerated) or mean (subdivided) edge length, m
};
RefinedSimulationMesh refine_simulation_mesh(const Scene& scene, const SceneMeshes& meshes);

struct DiscretisationEstimate {
  std::string method;                   ///< how the refined mesh was made
  double edge_length = 0;               ///< m: the simulation mesh's (target, or mean for files)
  double refined_edge_length = 0;       ///< m
  int faces = 0, refined_faces = 0;
  EquilibriumScalars coarse, refined;   ///< material quantities at h and h/2
  double compliance_change = 0;         ///< |C_h − C_{h/2}| / |C_{h/2}|
  double W_max_change = 0;              ///< |W_h − W_{h/2}| / W_{h/2}
  double max_displacement_change = 0;   ///< the same for the largest displacement
  double estimated_error = 0;           ///< 2 × compliance_change (see the file comment)
  double tolerance = kDiscretisationTolerance;
  bool converged = false;               ///< estimated_error ≤ tolerance
  double seconds = 0;                   ///< the refined solve, fill ratios included
};

/// Solves the scene's shell on `refined` with fill ratios `refined_alpha` (#F of refined.mesh; the
/// stencils' fill ratios there, or ones for the uncut shell) and `mechanics` (resolved as for the
/// coarse run), and compares with the coarse run's `coarse` quantities on `coarse_faces` faces of
/// edge length `coarse_edge_length`. Throws what the equilibrium throws (SolveError).
DiscretisationEstimate estimate_discretisation(const Scene& scene, const RefinedSimulationMesh& refined,
                                               const Eigen::VectorXd& refined_alpha,
                                               const MechanicsSettings& mechanics, const EquilibriumScalars& coarse,
                                               double coarse_edge_length, int coarse_faces,
                                               const NewtonSettings& settings = {});

/// The edge length the simulation mesh of `scene` was made at: sim_edge_length, else edge_length
/// for generated surfaces; the mean edge length of the mesh for files.
double simulation_edge_length(const Scene& scene, const SceneMeshes& meshes);

/// report.json's `discretisation` object: method, edge lengths, faces, compliance / W_max /
/// max_displacement at h and h/2 with their relative changes, estimated_error, tolerance,
/// converged and a one-line `summary` (no times: the report's timings hold them, so that two runs
/// of one design give the same object).
nlohmann::json discretisation_json(const DiscretisationEstimate& e);

/// One line for a person: "compliance 1.234 J at h = 0.35 m, 1.111 J at h/2: estimated
/// discretisation error 22% (tolerance 2%): not converged; ..." .
std::string discretisation_line(const DiscretisationEstimate& e);

}  // namespace cutwork::solvers
