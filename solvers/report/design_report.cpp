#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/report/design_report.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "host/core/atomic_file.h"
#include "host/core/output_set.h"
#include "host/export/stencil_outlines.h"
#include "host/core/json_io.h"
#include "host/mesh/mesh_io.h"
#include "host/pattern/stencils_json.h"
#include "solvers/conforming/conforming_verification.h"
#include "solvers/conforming/discretisation_estimate.h"
#include "solvers/conforming/simulation_mesh_choice.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/energy_density_reference.h"
#include "solvers/objective/peak_energy_density.h"
#include "solvers/report/run_report.h"

namespace cutwork::solvers {

namespace {

/// The scene as the design modelled it: its "auto" lattice read from the pattern's layout, a
/// lattice that follows the field with the field's axis function attached (DesignResult::mechanics).
Scene as_designed(const Scene& scene, const DesignResult& r) {
  Scene s = scene;
  if (r.mechanics.lattice_source == LatticeSource::Stencils || r.mechanics.lattice_follows_field) {
    s.mechanics.lattice = r.mechanics.lattice;
    s.mechanics.lattice_axis = r.mechanics.lattice_axis;
    s.mechanics.lattice_source = r.mechanics.lattice_source;
    s.mechanics.lattice_follows_field = r.mechanics.lattice_follows_field;
    s.mechanics.lattice_field_angle = r.mechanics.lattice_field_angle;
    s.mechanics.lattice_axis_at = r.mechanics.lattice_axis_at;
  }
  return s;
}

using nlohmann::json;

json phase_json(const std::string& name, int iterations, int evaluations, int rounds, double seconds,
                double J0, double J1, double S0, double S1, double P0, double P1, const std::string& stop) {
  return {{"name", name},          {"iterations", iterations}, {"evaluations", evaluations},
          {"rounds", rounds},      {"seconds", seconds},       {"J_start", number_or_null(J0)},
          {"J_end", number_or_null(J1)}, {"S_start", number_or_null(S0)}, {"S_end", number_or_null(S1)},
          {"P_start", number_or_null(P0)}, {"P_end", number_or_null(P1)}, {"stop_reason", stop}};
}

json stencils_json(const PatternContext& ctx, const DesignResult& r) {
  std::map<std::string, int> per_type;
  for (const auto& s : r.layout) per_type[ctx.shapes()[s.type].name] += 1;
  const StructurePhaseResult* s = r.structure ? &*r.structure : nullptr;
  return {{"count", r.layout.size()},
          {"initial", r.pattern.initial_count},
          {"removed", r.pattern.removed + (s ? s->removed + s->removed_for_min_feature : 0)},
          {"inserted_by_hole_filling", r.pattern.inserted_by_hole_filling + (s ? s->inserted_by_hole_filling : 0)},
          {"type_changes", r.pattern.type_changes + (s ? s->type_changes : 0)},
          {"by_type", per_type}};
}

json phases_json(const Scene& scene, const DesignResult& r) {
  const double w_P = scene.pattern.w_P;
  json phases = json::array();
  const PatternPhaseResult& p = r.pattern;
  phases.push_back(phase_json("pattern", p.iterations, p.evaluations, p.rounds, p.seconds, w_P * p.objective_start,
                              w_P * p.objective_end, NAN, NAN, p.objective_start, p.objective_end, p.stop_reason));
  phases.back()["objective"] = p.objective;
  if (r.structure) {
    const StructurePhaseResult& s = *r.structure;
    phases.push_back(phase_json("structure", s.iterations, s.evaluations, s.rounds, s.seconds, s.J_start, s.J_end,
                                s.S_start, s.S_end, s.P_start, s.P_end, s.stop_reason));
    phases.back()["objective"] = s.objective;
  }
  return phases;
}

json structure_json(const Scene& scene, const DesignResult& r) {
  const StructurePhaseResult* s = r.structure ? &*r.structure : nullptr;
  json st = {{"objective", s ? s->objective : "none"},
             {"w_S", scene.structure.w_S},
             {"measure", scene.structure.measure == DensityMeasure::Peak ? "peak" : "mean"},
             {"beta", s ? number_or_null(s->beta) : json(nullptr)},
             {"beta_fraction", s && std::isfinite(s->beta) && s->w_ref > 0 ? json(s->beta / s->w_ref) : json(nullptr)},
             {"beta_reference", s ? number_or_null(s->w_ref) : json(nullptr)},
             {"W_max_uncut", r.uncut.summary.W_max},
             {"W_max_pattern", r.pattern_design.summary.W_max},
             {"W_max_final", r.final_design.summary.W_max},
             {"W_peak_max_uncut", number_or_null(r.uncut.summary.W_peak_max)},
             {"W_peak_max_pattern", number_or_null(r.pattern_design.summary.W_peak_max)},
             {"W_peak_max_final", number_or_null(r.final_design.summary.W_peak_max)},
             // ρ/h of the thick-plate transition (peak_energy_density.h), and the final W_peak with
             // the cells' Kirchhoff factors beside it (null where it does not apply).
             {"W_peak_thick_scale", r.final_design.summary.W_peak_thick_scale},
             {"W_peak_kirchhoff_max_final", number_or_null(r.final_design.summary.W_peak_kirchhoff_max)},
             {"W_peak_rule", std::isfinite(r.final_design.summary.W_peak_max) ? kPeakEnergyDensityRule
                                                                              : kPeakEnergyDensityAbsent},
             {"compliance_uncut", r.uncut.summary.compliance},
             {"compliance_pattern", r.pattern_design.summary.compliance},
             {"compliance_final", r.final_design.summary.compliance},
             {"material_fraction_pattern", r.pattern_design.material_fraction},
             {"material_fraction_final", r.final_design.material_fraction},
             {"max_displacement_pattern", r.pattern_design.summary.max_displacement},
             {"max_displacement_final", r.final_design.summary.max_displacement},
             {"overlaps", r.final_design.overlaps.pairs + r.final_design.overlaps.boundary},
             {"units", {{"W", "J/m^2"}, {"compliance", "J"}, {"max_displacement", "m"}}}};
  if (s) {
    st["beta_history"] = s->beta_history;
    st["optimisations"] = s->optimisations;
    if (s->objective == "compliance") {
      st["covered_area_target"] = s->covered_area_target;
      st["covered_area_final"] = s->covered_area_final;
      st["max_restoring_change"] = s->max_restoring_change;
    }
  }
  return st;
}

}  // namespace

json design_state_json(const DesignState& d) {
  return {{"stencils", d.stencils},
          {"W_max", d.summary.W_max},
          {"W_peak_max", number_or_null(d.summary.W_peak_max)},
          {"W_peak_max_face", d.summary.W_peak_max_face},
          {"W_peak_biaxiality", {{"membrane", number_or_null(d.summary.W_peak_membrane_biaxiality)},
                                 {"bending", number_or_null(d.summary.W_peak_bending_biaxiality)}}},
          {"compliance", d.summary.compliance},
          {"strain_energy", d.summary.strain_energy},
          {"max_displacement", d.summary.max_displacement},
          {"material_fraction", d.material_fraction},
          {"newton_iterations", d.stats.newton_iterations},
          {"residual", d.stats.residual},
          {"converged", d.stats.converged},
          {"stop", d.stats.stop},
          {"stable", d.stats.stable}};
}

json design_report(const Scene& scene, const SceneMeshes& meshes, const PatternContext& ctx, const DesignResult& r,
                   const CutSurface& cut, const DesignRunInfo& info) {
  const MechanicsSettings used = scene_mechanics(scene, layout_params(r.layout));
  json report = base_report(scene, meshes, info.timings, &used);
  if (!info.device.is_null()) report["device"] = info.device;
  report["stencils"] = stencils_json(ctx, r);
  report["phases"] = phases_json(scene, r);
  report["pattern"] = {{"objective", r.pattern.objective},
                       {"exemplar", r.pattern.exemplar},
                       {"unit", r.pattern.unit},
                       {"epsilon", r.pattern.epsilon},
                       {"field_symmetry", r.pattern.field_symmetry},
                       {"w_P", scene.pattern.w_P}};
  report["structure"] = structure_json(scene, r);
  // The converging reference of energy_density_reference.h that β is a fraction of (beta_reference).
  if (r.uncut.summary.energy_density.size() == meshes.sim.num_faces()) {
    const Eigen::VectorXd& W = r.uncut.summary.energy_density;
    const std::vector<bool> material = r.uncut.alpha.size() == W.size() ? material_faces(r.uncut.alpha)
                                                                         : std::vector<bool>(size_t(W.size()), true);
    const EnergyDensityQuantile q = energy_density_quantile(W, meshes.sim.face_areas(), material);
    report["structure"]["W_reference_uncut"] = {
        {"rule", "area quantile: the faces of material with W above it cover at most this fraction of the "
                 "material area (solvers/objective/energy_density_reference.h); beta is this fraction of it"},
        {"area_fraction", kReferenceAreaFraction},
        {"W", q.value},
        {"faces_excluded", q.faces_above},
        {"area_excluded", q.area_above},
        {"W_max_over_W", q.value > 0 ? json(r.uncut.summary.W_max / q.value) : json(nullptr)}};
  }
  report["equilibrium"] = design_state_json(r.final_design);
  report["designs"] = {{"uncut", design_state_json(r.uncut)},
                       {"pattern", design_state_json(r.pattern_design)},
                       {"final", design_state_json(r.final_design)}};
  report["cut"] = {{"vertices", cut.vertices.rows()},
                   {"triangles", cut.faces.rows()},
                   {"area", cut.area},
                   {"split_triangles", cut.split_faces},
                   {"removed_triangles", cut.removed_faces},
                   {"tool_radius", scene.fabrication.tool_radius}};
  const auto& t = r.stage_times;
  report["timings"]["stages"] = {{"fill_seconds", t.fill},         {"fills", t.fills},
                                 {"equilibrium_seconds", t.equilibrium}, {"equilibria", t.equilibria},
                                 {"newton_iterations", t.newton_iterations}, {"adjoint_seconds", t.adjoint},
                                 {"adjoints", t.adjoints},         {"pullback_seconds", t.pullback}};
  report["notes"] = info.notes;
  return report;
}

DesignOutputs finish_design(const Scene& given_scene, const SceneMeshes& meshes, const PatternContext& ctx,
                            const DesignResult& result, DesignRunInfo info, const Stopwatch& since_start) {
  const Scene scene = as_designed(given_scene, result);
  info.notes.insert(info.notes.end(), result.notes.begin(), result.notes.end());
  for (const auto& [name, seconds] : result.timings.entries()) info.timings.add(name, seconds);
  if (result.structure)
    for (const std::string& n : result.structure->notes) info.notes.push_back(n);
  DesignOutputs out;
  out.meshes = &meshes;
  out.ctx = &ctx;
  out.result = &result;
  Stopwatch sw;
  const std::vector<StencilParams> final_params = layout_params(result.layout);
  // The holes as the scene's tool cuts them (fabrication.tool_radius; 0: as drawn): what is printed,
  // the solids and the minimum-feature check.
  out.cut = cut_with_tool(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), final_params,
                          scene.fabrication.tool_radius);
  info.timings.add("cut", sw.seconds());
  if (has_symmetry_plane(scene)) symmetry_plane_notes(resolve_load_case(scene, meshes.sim), final_params, info.notes);
  json discretisation = nullptr;
  if (info.discretisation_estimate) {
    sw.restart();
    const MechanicsSettings mechanics =
        resolve_fill_stiffness(scene.mechanics, ctx.shapes(), scene.material, final_params);
    DiscretisationOptions levels;
    levels.before_extra_level = info.before_extra_level;
    SimulationMeshRefinements refined(scene, meshes, levels);
    const double h = simulation_edge_length(scene, meshes);
    const DiscretisationEstimate uncut = estimate_discretisation(
        scene, refined, coarse_fill_ratios_on(meshes.sim, result.uncut.alpha), mechanics, result.uncut.summary, h,
        meshes.sim, &result.uncut.displacement);
    // The final design's material held on every level (the holes re-cut where the simulation
    // mesh resolves them): the mesh's error, not the fill rule's.
    const CellFilter filter = scene_cell_filter(scene, ctx, meshes.sim);
    const FillRatiosOnMesh own_on = [&](const SurfaceMesh& m) {
      return fill_ratios_on_mesh(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), m, final_params);
    };
    const DiscretisationEstimate final_design = estimate_discretisation(
        scene, refined,
        coarse_fill_ratios_on(meshes.sim, result.final_design.alpha, filter.resolution(),
                              filter.identity() ? FillRatiosOnMesh() : own_on),
        mechanics, result.final_design.summary, h, meshes.sim, &result.final_design.displacement,
        coarse_peak_inputs_on(meshes.sim,
                              result.final_design.concentration_weight.size() ? &result.final_design.concentration_weight
                                                                              : nullptr,
                              result.final_design.cover.empty() ? nullptr : &result.final_design.cover),
        &result.final_design.summary.peak_energy_density);
    discretisation = {{"uncut", discretisation_json(uncut)},
                      {"final", discretisation_json(final_design)},
                      {"converged", uncut.converged && final_design.converged},
                      {"tolerance", kDiscretisationTolerance}};
    if (!uncut.converged) info.notes.push_back("uncut shell: " + discretisation_line(uncut));
    if (!final_design.converged) info.notes.push_back("final design: " + discretisation_line(final_design));
    if (const std::string peak = peak_discretisation_note(final_design); !peak.empty())
      info.notes.push_back("final design: " + peak);
    info.timings.add("discretisation", sw.seconds());
  }
  // The ligament peak (solvers/objective/ligament_peak.h): the narrow ligaments W_peak cannot see.
  LigamentPeakSummary ligaments;
  const bool peak = result.final_design.summary.peak_energy_density.size() == meshes.sim.num_faces();
  if (peak) {
    sw.restart();
    const MechanicsSettings mechanics =
        resolve_fill_stiffness(scene.mechanics, ctx.shapes(), scene.material, final_params);
    const std::vector<double>& samples = mechanics.stiffness_curve.alpha;
    ligaments = summarize_ligament_peaks(out.cut, meshes.base, meshes.sim, result.final_design.alpha,
                                         result.final_design.summary.peak_energy_density,
                                         samples.empty() ? 0.0 : samples.front(), scene.material.thickness,
                                         mechanics.lattice, scene_symmetry_planes(scene, meshes.sim));
    out.W_ligament_max = ligaments.W_max;
    if (ligaments.narrower_than_thickness > 0)
      info.notes.push_back(fmt::format(
          "{} of the {} ligaments searched between holes are narrower than the shell is thick ({:.4g} m; the narrowest "
          "{:.3g} m): there the part twists as a beam, not as a plate, and neither W_peak, W_lig nor verify's "
          "Kirchhoff shell describes it (fabrication.min_feature, {:.4g} m, sets how narrow a ligament may be)",
          ligaments.narrower_than_thickness, ligaments.ligaments.size(), scene.material.thickness,
          ligaments.ligaments.front().width, scene.fabrication.min_feature));
    info.timings.add("ligaments", sw.seconds());
  }
  const nlohmann::json lattice_order =
      final_params.empty() ? nlohmann::json(nullptr)
                           : lattice_order_json(scene.mechanics, ctx.surface().bvh(), ctx.surface().field(), final_params,
                                                info.notes);
  info.timings.add("total", since_start.seconds());
  out.report = design_report(scene, meshes, ctx, result, out.cut, info);
  if (!lattice_order.is_null()) out.report["pattern"]["lattice_order"] = lattice_order;
  if (peak) out.report["structure"]["ligaments"] = ligament_peak_json(ligaments, scene.material.thickness);
  if (!discretisation.is_null()) out.report["discretisation"] = discretisation;
  return out;
}

namespace {

/// The per-face fields of a design on the simulation mesh: alpha, W of the final and the pattern
/// design, and W_peak of the final design where the mechanics has concentration factors.
std::map<std::string, Eigen::VectorXd> design_face_fields(const DesignResult& r) {
  std::map<std::string, Eigen::VectorXd> fields = {{"alpha", r.final_design.alpha},
                                                   {"W", r.final_design.summary.energy_density},
                                                   {"W_pattern", r.pattern_design.summary.energy_density}};
  if (r.final_design.summary.peak_energy_density.size() > 0)
    fields["W_peak"] = r.final_design.summary.peak_energy_density;
  return fields;
}

}  // namespace

void write_design_outputs(const FilePlacer& place, const DesignOutputs& o) {
  const DesignResult& r = *o.result;
  write_stencils_json(place("stencils.json"), r.layout, o.ctx->surface(), o.ctx->shapes());
  write_ply_with_face_fields(place("fields.ply"), o.meshes->sim, design_face_fields(r));
  write_obj(place("cut.obj"), o.cut.vertices, o.cut.faces);
  if (o.files) o.files->write(place);
  write_json_atomic(place("report.json"), o.report);
}

std::vector<std::string> design_output_names(const DesignOutputs& o) {
  std::vector<std::string> names = {"stencils.json", "fields.ply", "cut.obj"};
  if (o.files)
    for (const std::string& n : o.files->file_names()) names.push_back(n);
  names.push_back("report.json");
  return names;
}

RowMatX3d equilibrium_displacement(const Scene& scene, const SceneMeshes& meshes, const LoadCase& load_case,
                                   const Eigen::VectorXd& alpha, std::span<const StencilParams> stencils) {
  const ShellModel model(meshes.sim, scene.material, load_case, scene_mechanics(scene, stencils));
  EquilibriumSolver solver(model);
  solver.solve(alpha);
  return solver.displacements();
}

DesignFileInputs design_file_inputs(const Scene& scene, const SceneMeshes& meshes, const LoadCase& load_case,
                                    const PatternContext& ctx, const DesignResult& r, const CutSurface& cut) {
  DesignFileInputs in;
  in.title = scene.name;
  in.base = &meshes.base;
  in.sim = &meshes.sim;
  in.sim_fields.face = design_face_fields(r);
  const std::vector<StencilParams> params = layout_params(r.layout);
  in.sim_fields.vertex = {
      {"displacement", equilibrium_displacement(as_designed(scene, r), meshes, load_case, r.final_design.alpha, params)}};
  if (r.structure && std::isfinite(r.structure->beta)) in.beta = r.structure->beta;
  in.outlines = stencil_outlines(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), params);
  in.outline_types.resize(Eigen::Index(params.size()));
  for (size_t i = 0; i < params.size(); ++i) in.outline_types[Eigen::Index(i)] = params[i].type;
  in.cut = &cut;
  in.thickness = scene.material.thickness;
  in.min_feature = scene.fabrication.min_feature;
  in.symmetry_planes = scene_symmetry_planes(scene, meshes.sim);
  return in;
}

void add_design_files(DesignOutputs& outputs, const Scene& scene, const LoadCase& load_case,
                      const DesignFileOptions& options) {
  Stopwatch sw;
  outputs.files = prepare_design_files(
      design_file_inputs(scene, *outputs.meshes, load_case, *outputs.ctx, *outputs.result, outputs.cut), options);
  outputs.report["fabrication"] = outputs.files->fabrication_report();
  outputs.report["timings"]["design_files"] = sw.seconds();
}

json design_into_folder(const Scene& scene, const std::filesystem::path& dir, const DesignOptions& options,
                        DesignRunInfo info, const std::function<void(const SceneMeshes&)>& on_meshes,
                        const DesignFileOptions& file_options) {
  Stopwatch total, sw;
  SceneMeshes meshes = build_scene_meshes(scene);
  // Before a file's "auto" simulation mesh is chosen: its claim covers the finest it may choose and
  // the levels the choice solves (estimate_design_memory).
  if (on_meshes) on_meshes(meshes);
  for (const std::string& n : model_notes(scene, meshes)) info.notes.push_back(n);
  const std::string choice = choose_simulation_mesh(scene, meshes);
  if (!choice.empty()) info.notes.push_back(choice);
  info.timings.add("meshes", sw.seconds());
  sw.restart();
  const LoadCase load_case = resolve_load_case(scene, meshes.sim);
  info.timings.add("load_case", sw.seconds());
  sw.restart();
  PatternContext ctx(scene, meshes);
  for (const auto& n : ctx.notes()) info.notes.push_back(n);
  info.timings.add("pattern_context", sw.seconds());
  const DesignResult result = run_design(scene, meshes, load_case, ctx, options);
  DesignOutputs outputs = finish_design(scene, meshes, ctx, result, std::move(info), total);
  add_design_files(outputs, scene, load_case, file_options);
  OutputSet set(dir);
  write_design_outputs(placer(set), outputs);
  set.publish();
  return outputs.report;
}

}  // namespace cutwork::solvers
