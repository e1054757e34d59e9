#include "solvers/conforming/discretisation_estimate.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <tbb/parallel_for.h>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/core/work_limits.h"
#include "host/mesh/bvh.h"
#include "host/mesh/mesh_mapping.h"
#include "host/pattern/point_grid.h"
#include "host/surfaces/generators.h"

namespace cutwork::solvers {

namespace {
nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

double relative_change(double coarse, double fine) {
  return fine != 0 ? std::abs(coarse - fine) / std::abs(fine) : (coarse == 0 ? 0.0 : INFINITY);
}

/// Sets where the level's W_peak is (W_peak_position, W_peak_at_support) on its mesh.
void locate_peak(DiscretisationLevel& level, const SurfaceMesh& mesh, const std::vector<bool>& supported) {
  const int f = level.quantities.W_peak_max_face;
  if (f < 0 || f >= mesh.num_faces()) return;
  level.W_peak_position = Vec3::Zero();
  for (int k = 0; k < 3; ++k) {
    const int v = mesh.faces()(f, k);
    level.W_peak_position += mesh.vertices().row(v).transpose() / 3.0;
    level.W_peak_at_support = level.W_peak_at_support || supported[std::size_t(v)];
  }
}

}  // namespace

double peak_away_from_supports(const SurfaceMesh& mesh, const Eigen::VectorXd& field, const std::vector<bool>& material,
                               const std::vector<bool>& held, double clearance, int* face) {
  std::vector<int> held_ids;
  for (int v = 0; v < int(held.size()); ++v)
    if (held[size_t(v)]) held_ids.push_back(v);
  RowMatX3d points(Eigen::Index(held_ids.size()), 3);
  for (size_t k = 0; k < held_ids.size(); ++k) points.row(Eigen::Index(k)) = mesh.vertices().row(held_ids[k]);
  const PointGrid grid = held_ids.empty() ? PointGrid() : PointGrid(points, std::max(clearance, 1e-12));
  double best = NAN;
  int best_face = -1;
  std::vector<int> near;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    if (!material[size_t(f)] || (best_face >= 0 && !(field[f] > best))) continue;
    const Vec3 c = (mesh.vertices().row(mesh.faces()(f, 0)) + mesh.vertices().row(mesh.faces()(f, 1)) +
                    mesh.vertices().row(mesh.faces()(f, 2))).transpose() / 3.0;
    if (!held_ids.empty()) {
      grid.in_ball(c, clearance, near);
      if (!near.empty()) continue;
    }
    best = field[f];
    best_face = f;
  }
  if (face) *face = best_face;
  return best;
}

namespace {

/// The estimate of C_h = values[0] from levels that have not settled: (|C_h − C_finest| + the larger
/// of the finest three's differences) / |C_finest|.
double unsettled_error(const std::vector<double>& values) {
  const double c_h = values.front(), c_finest = values.back();
  return (std::abs(c_h - c_finest) + richardson_extrapolate(values).error_bar) / std::abs(c_finest);
}
}  // namespace

double simulation_edge_length(const Scene& scene, const SceneMeshes& meshes) {
  if (scene.mesh.generator.empty()) return meshes.sim.mean_edge_length();
  return scene.mesh.sim_edge_length > 0 ? scene.mesh.sim_edge_length : scene.mesh.edge_length;
}

SimulationMeshRefinements::SimulationMeshRefinements(const Scene& scene, const SceneMeshes& meshes,
                                                     const DiscretisationOptions& options)
    : m_scene(&scene), m_meshes(&meshes), m_options(options) {}

const RefinedSimulationMesh* SimulationMeshRefinements::level(int k) {
  const int most = m_options.refinements + std::max(0, m_options.extra_refinements);
  while (int(m_levels.size()) <= k && !m_exhausted && int(m_levels.size()) < most) {
    const int j = int(m_levels.size());
    const double faces = 4.0 * (m_levels.empty() ? m_meshes->sim.num_faces() : m_levels.back().mesh.num_faces());
    if (j > 0 && faces > m_options.max_faces) {  // (h/2 always: the estimate needs one refinement)
      m_exhausted = true;
      break;
    }
    if (j >= m_options.refinements && m_options.before_extra_level) m_options.before_extra_level(j, size_t(faces));
    RefinedSimulationMesh r;
    if (m_scene->mesh.generator.empty()) {
      r.mesh = midpoint_subdivision(m_levels.empty() ? m_meshes->sim : m_levels.back().mesh);
      r.method = "subdivided";
      r.edge_length = r.mesh.mean_edge_length();
    } else {
      r.edge_length = simulation_edge_length(*m_scene, *m_meshes) / double(2 << j);
      try {
        r.mesh = generate_shape(m_scene->mesh.generator, m_scene->mesh.params, r.edge_length, work_limits().max_faces,
                                fmt::format("sim_edge_length / {} (the discretisation estimate)", 2 << j));
      } catch (const InputError& e) {
        throw InputError(scene_origin(*m_scene) + ": /mesh: " + e.what());
      }
      r.method = "regenerated";
    }
    m_levels.push_back(std::move(r));
  }
  return k < int(m_levels.size()) ? &m_levels[size_t(k)] : nullptr;
}

std::vector<RefinedSimulationMesh> refine_simulation_mesh(const Scene& scene, const SceneMeshes& meshes,
                                                          const DiscretisationOptions& options) {
  SimulationMeshRefinements refinements(scene, meshes, options);
  std::vector<RefinedSimulationMesh> out;
  for (int k = 0; k < options.refinements; ++k)
    if (const RefinedSimulationMesh* r = refinements.level(k)) out.push_back(*r);
  return out;
}

namespace {

/// Per-face fields of `coarse` (#F × k) as continuous fields on another mesh: each coarse vertex
/// the area-weighted mean of its faces' values, interpolated at the closest point of a face's
/// centroid (coarse_fill_ratios_on).
class CoarseFaceFields {
 public:
  CoarseFaceFields(const SurfaceMesh& coarse, const Eigen::MatrixXd& per_face)
      : m_bvh(std::make_shared<const FaceBvh>(coarse)),
        m_faces(coarse.faces()),
        m_at_vertices(Eigen::MatrixXd::Zero(coarse.num_vertices(), per_face.cols())) {
    Eigen::VectorXd area = Eigen::VectorXd::Zero(coarse.num_vertices());
    for (int f = 0; f < coarse.num_faces(); ++f)
      for (int k = 0; k < 3; ++k) {
        m_at_vertices.row(coarse.faces()(f, k)) += coarse.face_areas()[f] * per_face.row(f);
        area[coarse.faces()(f, k)] += coarse.face_areas()[f];
      }
    for (int v = 0; v < coarse.num_vertices(); ++v) m_at_vertices.row(v) /= std::max(area[v], 1e-300);
  }
  /// #F of `fine` × k.
  Eigen::MatrixXd on(const SurfaceMesh& fine) const {
    Eigen::MatrixXd out(fine.num_faces(), m_at_vertices.cols());
    tbb::parallel_for(0, fine.num_faces(), [&](int f) {
      const auto& F = fine.faces();
      const auto& X = fine.vertices();
      const Vec3 centroid = (X.row(F(f, 0)) + X.row(F(f, 1)) + X.row(F(f, 2))).transpose() / 3.0;
      const SurfacePoint p = m_bvh->closest_point(centroid).where;
      for (Eigen::Index c = 0; c < m_at_vertices.cols(); ++c) {
        double value = 0;
        for (int k = 0; k < 3; ++k) value += p.bary[k] * m_at_vertices(m_faces(p.face, k), c);
        out(f, c) = value;
      }
    });
    return out;
  }

 private:
  std::shared_ptr<const FaceBvh> m_bvh;
  RowMatX3i m_faces;
  Eigen::MatrixXd m_at_vertices;  ///< #V × k
};

}  // namespace

FillRatiosOnMesh coarse_fill_ratios_on(const SurfaceMesh& coarse, Eigen::VectorXd alpha, Eigen::VectorXd resolution,
                                       FillRatiosOnMesh own_on) {
  const int nf = coarse.num_faces();
  if (alpha.size() != nf || (own_on && resolution.size() != nf))
    throw InternalError(fmt::format("coarse_fill_ratios_on: {} fill ratios and {} resolutions for {} faces",
                                    alpha.size(), resolution.size(), nf));
  Eigen::MatrixXd fields(nf, own_on ? 2 : 1);
  fields.col(0) = alpha;
  if (own_on) fields.col(1) = resolution;
  auto carried = std::make_shared<const CoarseFaceFields>(coarse, fields);
  return [&coarse, carried, alpha = std::move(alpha), own_on = std::move(own_on)](const SurfaceMesh& fine) {
    if (&fine == &coarse) return alpha;
    const Eigen::MatrixXd on = carried->on(fine);
    if (!own_on) return Eigen::VectorXd(on.col(0));
    const Eigen::VectorXd own = own_on(fine);
    return Eigen::VectorXd(((1 - on.col(1).array()) * on.col(0).array() + on.col(1).array() * own.array()).matrix());
  };
}

PeakInputsOnMesh coarse_peak_inputs_on(const SurfaceMesh& coarse, const Eigen::VectorXd* weight,
                                       const ShapeCover* cover) {
  const int nf = coarse.num_faces();
  PeakInputs given;
  if (weight) given.weight = *weight;
  if (cover) given.cover = *cover;
  const Eigen::Index shapes = given.cover.covered.cols(), corners = given.cover.corner.cols();
  if ((weight && given.weight.size() != nf) || (cover && given.cover.covered.rows() != nf) ||
      (corners > 0 && given.cover.corner.rows() != nf))
    throw InternalError(fmt::format("coarse_peak_inputs_on: {} weights and a cover of {} rows for {} faces",
                                    given.weight.size(), given.cover.covered.rows(), nf));
  Eigen::MatrixXd fields(nf, given.weight.size() + shapes + corners);
  if (weight) fields.col(0) = given.weight;
  const Eigen::Index w = given.weight.size() > 0 ? 1 : 0;
  if (shapes > 0) fields.middleCols(w, shapes) = given.cover.covered;
  if (corners > 0) fields.middleCols(w + shapes, corners) = given.cover.corner;
  auto carried = std::make_shared<const CoarseFaceFields>(coarse, fields);
  return [&coarse, carried, given = std::move(given), w, shapes, corners](const SurfaceMesh& fine) {
    if (&fine == &coarse) return given;
    const Eigen::MatrixXd on = carried->on(fine);
    PeakInputs out;
    if (w > 0) out.weight = on.col(0);
    if (shapes > 0) out.cover.covered = on.middleCols(w, shapes);
    if (corners > 0) out.cover.corner = on.middleCols(w + shapes, corners);
    return out;
  };
}

DiscretisationEstimate estimate_discretisation(const Scene& scene, SimulationMeshRefinements& refined,
                                               const FillRatiosOnMesh& fill_on, const MechanicsSettings& mechanics,
                                               const EquilibriumScalars& coarse, double coarse_edge_length,
                                               const SurfaceMesh& coarse_mesh, const RowMatX3d* coarse_displacement,
                                               const PeakInputsOnMesh& peak_on, const Eigen::VectorXd* coarse_peak) {
  const bool free_peak = peak_on && coarse_peak && coarse_peak->size() == coarse_mesh.num_faces();
  const DiscretisationOptions& options = refined.options();
  DiscretisationEstimate e;
  e.tolerance = options.tolerance;
  e.support_tolerance = options.support_tolerance;
  {
    const LoadCase lc = resolve_load_case(scene, coarse_mesh);
    e.levels.push_back({coarse_edge_length, coarse_mesh.num_faces(), coarse, support_extent(coarse_mesh, supported_vertices(lc)),
                        support_extent(coarse_mesh, lc.clamped)});
    if (peak_on) locate_peak(e.levels.back(), coarse_mesh, support_held_vertices(lc));
    if (free_peak)
      e.levels.back().W_peak_free = peak_away_from_supports(coarse_mesh, *coarse_peak, material_faces(fill_on(coarse_mesh)),
                                                            support_held_vertices(lc), coarse_edge_length);
  }
  e.support_change = 0;
  std::vector<double> compliances{coarse.compliance};
  // Each refined level starts Newton from the last level's displacements carried onto its mesh
  // (the same equilibrium, fewer iterations; EquilibriumSolver::start_from): the first from the
  // coarse run's, where given.
  const bool coarse_given = coarse_displacement && coarse_displacement->rows() == coarse_mesh.num_vertices();
  const SurfaceMesh* previous = coarse_given ? &coarse_mesh : nullptr;
  RowMatX3d previous_u = coarse_given ? *coarse_displacement : RowMatX3d();
  for (int k = 0;; ++k) {
    // Past the levels always solved, one more only while the finest three have not settled and
    // the cautious estimate of unsettled levels cannot tell converged by itself.
    if (k >= options.refinements &&
        (options.solve_another ? !options.solve_another(compliances)
                               : compliances.size() < 3 || richardson_extrapolate(compliances).asymptotic ||
                                     unsettled_error(compliances) <= options.tolerance))
      break;
    const RefinedSimulationMesh* r = refined.level(k);
    if (r == nullptr) break;
    if (k == 0) e.method = r->method;
    const Eigen::VectorXd alpha = fill_on(r->mesh);
    const LoadCase lc = resolve_load_case(scene, r->mesh);
    const ShellModel model(r->mesh, scene.material, lc, mechanics);
    EquilibriumSolver solver(model, options.newton);
    if (previous)
      solver.start_from(r->mesh.vertices() + interpolate_vertex_field(FaceBvh(*previous), previous_u, r->mesh.vertices()));
    const EquilibriumStats& stats = solver.solve(alpha);
    previous = &r->mesh;
    previous_u = solver.displacements();
    const PeakInputs peak = peak_on ? peak_on(r->mesh) : PeakInputs{};
    const EquilibriumSummary summary =
        summarize_equilibrium(model, solver.positions(), alpha, peak.weight.size() ? &peak.weight : nullptr,
                              peak.cover.empty() ? nullptr : &peak.cover);
    e.levels.push_back({r->edge_length, r->mesh.num_faces(), summary, support_extent(r->mesh, supported_vertices(lc)),
                        support_extent(r->mesh, lc.clamped), stats.newton_iterations,
                        stats.warm_started && !stats.cold_restarted});
    if (peak_on) locate_peak(e.levels.back(), r->mesh, support_held_vertices(lc));
    if (free_peak && summary.peak_energy_density.size() == r->mesh.num_faces())
      e.levels.back().W_peak_free = peak_away_from_supports(r->mesh, summary.peak_energy_density, material_faces(alpha),
                                                            support_held_vertices(lc), coarse_edge_length);
    compliances.push_back(e.levels.back().quantities.compliance);
    e.support_change = std::max({e.support_change, support_extent_change(e.levels.front().fixed, e.levels.back().fixed, coarse_edge_length),
                                 support_extent_change(e.levels.front().clamped, e.levels.back().clamped, coarse_edge_length)});
  }
  if (e.levels.size() < 2) throw InternalError("estimate_discretisation: no refined mesh");
  e.supports_consistent = e.support_change <= e.support_tolerance;
  e.compliance = richardson_extrapolate(compliances);
  const double c_h = coarse.compliance;
  if (e.levels.size() >= 3 && !e.compliance.asymptotic) {
    e.rule = "not asymptotic";
    e.estimated_error = unsettled_error(compliances);
  } else {
    e.rule = e.levels.size() >= 3 ? "richardson" : "first order assumed";
    e.estimated_error = relative_change(c_h, e.compliance.extrapolated);
  }
  const EquilibriumScalars& half = e.levels[1].quantities;
  e.compliance_change = relative_change(c_h, half.compliance);
  e.W_max_change = relative_change(coarse.W_max, half.W_max);
  e.W_peak_levels = bool(peak_on);
  if (peak_on && std::isfinite(coarse.W_peak_max) && std::isfinite(half.W_peak_max))
    e.W_peak_change = relative_change(coarse.W_peak_max, half.W_peak_max);
  if (std::isfinite(e.levels[0].W_peak_free) && std::isfinite(e.levels[1].W_peak_free))
    e.W_peak_free_change = relative_change(e.levels[0].W_peak_free, e.levels[1].W_peak_free);
  e.max_displacement_change = relative_change(coarse.max_displacement, half.max_displacement);
  e.converged = e.estimated_error <= e.tolerance && e.supports_consistent;
  return e;
}

namespace {
std::string extent_words(const SupportExtent& x) {
  std::vector<std::string> parts;
  if (x.length > 0) parts.push_back(fmt::format("{:.4g} m of line", x.length));
  if (x.area > 0) parts.push_back(fmt::format("{:.4g} m² of area", x.area));
  if (x.points > 0) parts.push_back(fmt::format("{} point{}", x.points, x.points == 1 ? "" : "s"));
  if (parts.empty()) return "nothing";
  std::string out = parts.front();
  for (std::size_t k = 1; k < parts.size(); ++k) out += (k + 1 == parts.size() ? " and " : ", ") + parts[k];
  return out;
}
}  // namespace

std::string discretisation_line(const DiscretisationEstimate& e) {
  if (!e.supports_consistent && e.levels.size() >= 2) {
    // Name the level that differs most and the set (fixed or clamped) that differs.
    const DiscretisationLevel& h = e.levels.front();
    const DiscretisationLevel* worst = &e.levels[1];
    bool clamped = false;
    double change = -1;
    for (std::size_t k = 1; k < e.levels.size(); ++k)
      for (bool c : {false, true}) {
        const double d =
            support_extent_change(c ? h.clamped : h.fixed, c ? e.levels[k].clamped : e.levels[k].fixed, h.edge_length);
        if (d > change) change = d, worst = &e.levels[k], clamped = c;
      }
    return fmt::format(
        "NOT converged: the supports hold a different region on each refinement ({} vertices: {} at {:.3g} m, {} at "
        "{:.3g} m, a change of {:.1f}% against a tolerance of {:.0f}%), so the levels are different structures and "
        "their compliances ({:.4g} J, {:.4g} J) say nothing of the mesh's error: the supports' selector depends on "
        "the mesh (a box that catches a surface rising tangentially out of it, or that cuts a support line between "
        "vertices); select the support region exactly (feet on z = 0: \"z\": {{\"below\": 1e-6}})",
        clamped ? "clamped" : "fixed", extent_words(clamped ? h.clamped : h.fixed), h.edge_length,
        extent_words(clamped ? worst->clamped : worst->fixed), worst->edge_length, 100 * change,
        100 * e.support_tolerance, h.quantities.compliance, worst->quantities.compliance);
  }
  std::string values;
  for (const DiscretisationLevel& l : e.levels)
    values += fmt::format("{}{:.4g} J at {:.3g} m", values.empty() ? "" : ", ", l.quantities.compliance, l.edge_length);
  return fmt::format(
      "compliance {} ({}{}): estimated discretisation error of the first {:.1f}% (tolerance {:.0f}%){}; W_max changes "
      "by {:.1f}%{} at half the edge length",
      values, e.rule,
      std::isfinite(e.compliance.order) ? fmt::format(", observed order {:.2f}", e.compliance.order) : std::string(),
      100 * e.estimated_error, 100 * e.tolerance,
      e.converged ? ", converged"
      : e.method == "subdivided"
          ? fmt::format(": NOT converged, the simulation mesh is too coarse for these numbers ({} more subdivisions "
                        "of it, mesh.sim_subdivisions, or a finer file, are closer)",
                        e.levels.size() - 1)
          : fmt::format(": NOT converged, the simulation mesh is too coarse for these numbers (a finer "
                        "mesh.sim_edge_length, e.g. {:.3g} m, is closer)",
                        e.levels.back().edge_length),
      100 * e.W_max_change,
      std::isfinite(e.W_peak_change)
          ? fmt::format(", W_peak by {:.1f}%{}", 100 * e.W_peak_change,
                        e.levels.back().W_peak_at_support && std::isfinite(e.W_peak_free_change)
                            ? fmt::format(" (at a support; away from the supports by {:.1f}%)", 100 * e.W_peak_free_change)
                            : std::string())
          : std::string());
}

std::string peak_discretisation_note(const DiscretisationEstimate& e, double tolerance) {
  if (!(e.W_peak_change > tolerance)) return {};
  std::string values;
  for (const DiscretisationLevel& l : e.levels)
    values += fmt::format("{}{:.4g} J/m^2 at {:.3g} m", values.empty() ? "" : ", ", l.quantities.W_peak_max, l.edge_length);
  const DiscretisationLevel& finest = e.levels.back();
  // Away from the supports: the largest W_peak over the faces that touch none, by level.
  const auto free_words = [&]() -> std::string {
    if (!std::isfinite(e.W_peak_free_change)) return {};
    std::string free;
    for (const DiscretisationLevel& l : e.levels)
      free += fmt::format("{}{:.4g}", free.empty() ? "" : ", ", l.W_peak_free);
    const double to_finest = relative_change(e.levels.front().W_peak_free, e.levels.back().W_peak_free);
    return fmt::format("; farther than {:.3g} m (the simulation mesh's edge length) from the supports it changes by "
                       "{:.1f}% at half the edge length and {:.1f}% to the finest level ({} J/m^2){}",
                       e.levels.front().edge_length, 100 * e.W_peak_free_change, 100 * to_finest, free,
                       std::max(e.W_peak_free_change, to_finest) <= tolerance ? ", within the tolerance" : "");
  };
  const std::string where = fmt::format("({:.3g}, {:.3g}, {:.3g})", finest.W_peak_position.x(),
                                        finest.W_peak_position.y(), finest.W_peak_position.z());
  return fmt::format(
      "the ligament peak W_peak is not converged on the simulation mesh: it changes by {:.1f}% at half the edge "
      "length (tolerance {:.0f}%; {}){}",
      100 * e.W_peak_change, 100 * tolerance, values,
      finest.W_peak_at_support
          ? fmt::format("; on the finest level it is at a support, {} m, where the exact energy density may be "
                        "singular (a clamped corner, a point support) and a maximum need not converge{}",
                        where, free_words())
          : fmt::format("; on the finest level at {} m, where the field varies within a triangle (a hole the "
                        "triangles resolve has its rim's peak averaged over its rim faces); cutwork verify reads the "
                        "peak on conforming rims",
                        where));
}

nlohmann::json support_extent_json(const SupportExtent& x) {
  return {{"area", x.area}, {"length", x.length}, {"points", x.points}};
}

nlohmann::json discretisation_json(const DiscretisationEstimate& e) {
  nlohmann::json levels = nlohmann::json::array();
  for (const DiscretisationLevel& l : e.levels)
    levels.push_back({{"edge_length", l.edge_length},
                      {"faces", l.faces},
                      {"compliance", l.quantities.compliance},
                      {"strain_energy", l.quantities.strain_energy},
                      {"W_max", l.quantities.W_max},
                      {"W_peak", e.W_peak_levels ? number_or_null(l.quantities.W_peak_max) : nlohmann::json()},
                      {"W_peak_position", l.W_peak_position.allFinite()
                                              ? nlohmann::json::array({l.W_peak_position.x(), l.W_peak_position.y(),
                                                                       l.W_peak_position.z()})
                                              : nlohmann::json()},
                      {"W_peak_at_support", l.W_peak_at_support},
                      {"W_peak_free", e.W_peak_levels ? number_or_null(l.W_peak_free) : nlohmann::json()},
                      {"max_displacement", l.quantities.max_displacement},
                      {"supports", {{"fixed", support_extent_json(l.fixed)}, {"clamped", support_extent_json(l.clamped)}}},
                      {"newton_iterations", l.newton_iterations >= 0 ? nlohmann::json(l.newton_iterations) : nlohmann::json()},
                      {"warm_started", l.warm_started}});
  return {{"method", e.method},
          {"levels", levels},
          {"compliance_extrapolated", number_or_null(e.compliance.extrapolated)},
          {"observed_order", number_or_null(e.compliance.order)},
          {"compliance_error_bar", number_or_null(e.compliance.error_bar)},
          {"rule", e.rule},
          {"estimated_error", number_or_null(e.estimated_error)},
          {"compliance_change", number_or_null(e.compliance_change)},
          {"W_max_change", number_or_null(e.W_max_change)},
          {"W_peak_change", number_or_null(e.W_peak_change)},
          {"W_peak_free_change", number_or_null(e.W_peak_free_change)},
          {"max_displacement_change", number_or_null(e.max_displacement_change)},
          {"support_change", number_or_null(e.support_change)},
          {"support_tolerance", e.support_tolerance},
          {"supports_consistent", e.supports_consistent},
          {"tolerance", e.tolerance},
          {"converged", e.converged},
          {"summary", discretisation_line(e)}};
}

}  // namespace cutwork::solvers
