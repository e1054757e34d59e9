// `cutwork verify DIR [--edge-length L] [--levels N]`: a finished design (the folder `cutwork design
// --out DIR` wrote) simulated on a conforming mesh — the base surface cut along every stencil
// outline and remeshed — and compared with the coarse fill-ratio simulation (paper §6, Fig. 4).
// Writes DIR/verify/report.json, DIR/verify/fields.ply (coarse mesh: α, coarse and conforming W)
// and DIR/verify/conforming.ply (the conforming mesh: W and displacement per face).
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "host/cli/cli_common.h"
#include "host/cli/commands.h"
#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/core/json_io.h"
#include "host/mesh/mesh_io.h"
#include "host/pattern/stencils_json.h"
#include "solvers/conforming/conforming_verification.h"
#include "solvers/conforming/discretisation_estimate.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/objective/peak_energy_density.h"
#include "solvers/report/run_report.h"

namespace cutwork::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct VerifyOptions {
  std::string dir;
  std::string scene;          ///< overrides the scene the design's report names
  double edge_length = 0;     ///< 0: the base mesh's mean edge length
  int levels = 4;             ///< at most
  double tolerance = 0.01;    ///< converged when the error bar is within it (0: run every level)
  int min_levels = 3;         ///< the fewest levels that count as converged
  int peak_zoom = 4;          ///< zoom steps about the rim peak (0: none)
  bool zoom_whole = false;    ///< re-solve the whole shell on each zoom step, not a submodel
  int max_faces = 800'000;
  int grading_depth = 2;
  double elements_across = 3;
  double tool_radius = -1;    ///< m; < 0: the scene's fabrication.tool_radius
  int threads = 0;
  bool quiet = false;
};

using solvers::number_or_null;

json run_json(const solvers::RunQuantities& q) {
  return {{"vertices", q.vertices},
          {"triangles", q.faces},
          {"dofs", q.dofs},
          {"edge_length", q.edge_length},
          {"compliance", q.compliance},
          {"strain_energy", q.strain_energy},
          {"max_displacement", q.max_displacement},
          {"max_displacement_vertex", q.max_displacement_vertex},
          {"W_max", q.W_max},
          {"W_max_face", q.W_max_face},
          {"W_peak_max", number_or_null(q.W_peak_max)},
          {"W_peak_max_face", q.W_peak_max_face},
          {"W_peak_biaxiality", {{"membrane", number_or_null(q.W_peak_membrane_biaxiality)},
                                 {"bending", number_or_null(q.W_peak_bending_biaxiality)}}},
          {"W_peak_thick_scale", q.W_peak_thick_scale},
          {"W_peak_kirchhoff_max", number_or_null(q.W_peak_kirchhoff_max)},
          {"material_area", q.material_area},
          {"load_total", {q.load_total.x(), q.load_total.y(), q.load_total.z()}},
          {"newton_iterations", q.newton_iterations},
          {"seconds", q.seconds},
          {"mesh_seconds", q.mesh_seconds},
          {"min_angle", number_or_null(q.min_angle)},
          {"triangles_below_10_degrees", number_or_null(q.slivers)}};
}

/// A conforming level: run_json and its peak (rim recovery, conforming_verification.h).
json level_json(const solvers::RunQuantities& q) {
  json j = run_json(q);
  j["warm_started"] = q.warm_started;
  j["peak"] = number_or_null(q.peak);
  j["rim_peak"] = number_or_null(q.rim_peak);
  j["rim_peak_position"] = std::isfinite(q.rim_peak)
                               ? json{q.rim_peak_position.x(), q.rim_peak_position.y(), q.rim_peak_position.z()}
                               : json(nullptr);
  j["rim_points"] = q.rim_points;
  j["singular_rim_points"] = q.singular_rim_points;
  j["corner_peak"] = number_or_null(q.corner_peak);
  j["corner_peak_position"] = std::isfinite(q.corner_peak)
                                  ? json{q.corner_peak_position.x(), q.corner_peak_position.y(), q.corner_peak_position.z()}
                                  : json(nullptr);
  j["interior_peak"] = number_or_null(q.interior_peak);
  j["supports"] = {{"fixed", solvers::support_extent_json(q.fixed_extent)},
                   {"clamped", solvers::support_extent_json(q.clamped_extent)}};
  return j;
}

/// The scene a design folder was made with: --scene, else the one its report.json names.
std::string design_scene(const VerifyOptions& opts, const fs::path& dir, const json& report) {
  if (!opts.scene.empty()) return opts.scene;
  const auto it = report.find("scene_source");
  if (it == report.end() || !it->is_string())
    throw InputError((dir / "report.json").string() + ": no scene_source: not a report of `cutwork design`");
  const std::string source = it->get<std::string>();
  if (source.rfind("builtin:", 0) == 0) return source.substr(8);
  if (!fs::exists(source))
    throw InputError(fmt::format("{}: the design's scene {} cannot be found from here; pass it with --scene",
                                 (dir / "report.json").string(), source));
  return source;
}

json comparison_json(const solvers::ConformingVerification& v, const SurfaceMesh& sim) {
  json c = {{"compliance_ratio", number_or_null(v.compliance_ratio)},
            {"compliance_ratio_extrapolated", number_or_null(v.compliance_ratio_extrapolated)},
            {"strain_energy_ratio", number_or_null(v.strain_energy_ratio)},
            {"max_displacement_ratio", number_or_null(v.max_displacement_ratio)},
            {"W_max_ratio", number_or_null(v.W_max_ratio)},
            {"W_max_conforming_on_coarse", v.W_max_on_coarse},
            {"W_peak_coarse", number_or_null(v.coarse.W_peak_max)},
            {"W_peak_coarse_kirchhoff", number_or_null(std::isfinite(v.coarse.W_peak_kirchhoff_max)
                                                           ? v.coarse.W_peak_kirchhoff_max
                                                           : v.coarse.W_peak_max)},
            {"W_peak_coarse_rule", "W_peak_coarse: the design's estimate of the part's peak (the bending factors raised "
                                   "by the thick-plate transition of the stencils against the thickness); "
                                   "W_peak_coarse_kirchhoff: the "
                                   "same with the cells' Kirchhoff factors, which the ratios compare with the conforming "
                                   "Kirchhoff shell's peak"},
            {"W_peak_conforming", number_or_null(v.conforming_peak)},
            {"W_peak_conforming_rule", "the largest energy density recovered on the free rims (a cubic fit of the "
                                       "positions around each rim vertex, the free-edge conditions, a quadratic "
                                       "smoothing along the rim); rim points within the minimum feature of a corner "
                                       "turning into the material or within the level-0 edge length of a support's "
                                       "end are singular and left out; with the peak zoom, on its last step (the "
                                       "finest level's mesh with the rims about the peak's candidates refined further), "
                                       "and extrapolated over its steps"},
            {"W_peak_ratio", number_or_null(v.W_peak_ratio)},
            {"W_peak_conforming_extrapolated", number_or_null(v.peak_extrapolated)},
            {"W_peak_conforming_error_bar", number_or_null(v.peak_error_bar)},
            {"W_peak_conforming_order", number_or_null(v.peak_order)},
            {"W_peak_ratio_extrapolated", number_or_null(v.W_peak_ratio_extrapolated)},
            {"W_peak_conforming_change", number_or_null(v.peak_change)},
            {"W_peak_conforming_converged", v.peak_converged},
            {"W_peak_conforming_tolerance", solvers::kPeakTolerance},
            {"W_peak_rule", solvers::kPeakEnergyDensityRule},
            {"W_estimate_coarse", number_or_null(v.W_estimate)},
            {"W_estimate_ratio", number_or_null(v.W_estimate_ratio)},
            {"W_estimate_ratio_extrapolated", number_or_null(v.W_estimate_ratio_extrapolated)},
            {"W_estimate_rule", "max(W_peak, W_ligament): the cell factors' peak and the narrow ligaments' (ligaments)"},
            {"W_relative_l2", v.W_relative_l2},
            {"compared_faces", v.compared_faces},
            {"material_fill_ratio", solvers::kMaterialFillRatio}};
  if (v.worst_face >= 0) {
    const int t = v.worst_face;
    c["largest_W_difference"] = {{"face", t},
                                 {"position", {v.worst_position.x(), v.worst_position.y(), v.worst_position.z()}},
                                 {"alpha", v.alpha[t]},
                                 {"W_coarse", v.coarse_W[t]},
                                 {"W_conforming", v.W_on_coarse[t]},
                                 {"difference", v.worst_difference},
                                 {"area", sim.face_areas()[t]}};
  }
  return c;
}

json convergence_json(const solvers::ConformingVerification& v, double tolerance, int min_levels) {
  // |C_{k+1} − C_k| / C_finest between consecutive levels: shrinking when the conforming solve converges.
  const std::vector<solvers::RunQuantities>& levels = v.levels;
  json d = json::array();
  const double c = levels.back().compliance;
  for (size_t k = 1; k < levels.size(); ++k) d.push_back(std::abs(levels[k].compliance - levels[k - 1].compliance) / c);
  return {{"compliance_relative_differences", d},
          {"converged", v.converged},
          {"tolerance", tolerance},
          {"min_levels", min_levels},
          {"rule", fmt::format("converged when at least {} levels ran, the extrapolated compliance's error bar "
                               "is within the tolerance of it and the supports hold the same region on every level",
                               min_levels)},
          {"stop", v.stop},
          {"last_change", number_or_null(v.last_change)},
          {"compliance_finest", c},
          {"compliance_extrapolated", number_or_null(v.extrapolated_compliance)},
          {"compliance_error_bar", number_or_null(v.compliance_error_bar)},
          {"compliance_relative_error_bar", number_or_null(v.relative_error_bar)},
          {"observed_order", number_or_null(v.observed_order)},
          {"support_change", number_or_null(v.support_change)},
          {"support_tolerance", kSupportExtentTolerance},
          {"supports_consistent", v.supports_consistent}};
}

void run_verify(const VerifyOptions& opts) {
  auto threads = limit_threads(opts.threads);
  const fs::path dir(opts.dir);
  if (!fs::is_directory(dir)) throw InputError(dir.string() + ": no such folder (expected a `cutwork design --out` folder)");
  for (const char* file : {"report.json", "stencils.json"})
    if (!fs::is_regular_file(dir / file))
      throw InputError(fmt::format("{}: holds no design ({} missing; write one with `cutwork design --out {}`)",
                                   dir.string(), file, dir.string()));
  const json design_report = read_json_file(dir / "report.json");

  Timings timings;
  Stopwatch total, sw;
  RunOptions run;
  run.scene = design_scene(opts, dir, design_report);
  run.quiet = opts.quiet;
  LoadedScene loaded(run, timings);
  // --tool-radius stands for the scene's tool: the conforming outline and the coarse W_peak's
  // factors (MechanicsSettings::tool_radius) both follow it.
  if (opts.tool_radius >= 0) set_tool_radius(loaded.scene, opts.tool_radius);
  const SceneMeshes& meshes = loaded.meshes;
  if (design_report.contains("mesh") && design_report["mesh"].value("sim_triangles", -1) != meshes.sim.num_faces())
    throw InputError(fmt::format("{}: the design was made on {} simulation triangles, the scene {} gives {}: the "
                                 "scene changed since; pass the design's scene with --scene",
                                 (dir / "report.json").string(), design_report["mesh"].value("sim_triangles", -1),
                                 run.scene, meshes.sim.num_faces()));
  sw.restart();
  const PatternContext ctx(loaded.scene, meshes);
  const StencilsFile sf = read_stencils_json(dir / "stencils.json", ctx.shapes());
  // "lattice": "auto" is read from the stencils, as simulate reads it: the coarse model is the one
  // `cutwork simulate --stencils` runs on this design.
  loaded.scene.mechanics = solvers::measured_lattice(loaded.scene.mechanics, ctx.surface().bvh(),
                                                     ctx.surface().field(), sf.stencils, loaded.notes);
  timings.add("stencils", sw.seconds());

  solvers::ConformingOptions co;
  co.edge_length = opts.edge_length > 0 ? opts.edge_length : meshes.base.mean_edge_length();
  co.levels = opts.levels;
  co.tolerance = opts.tolerance;
  co.min_levels = opts.min_levels;
  co.peak_zoom = opts.peak_zoom;
  co.zoom_submodel = !opts.zoom_whole;
  co.max_faces = opts.max_faces;
  co.grading_depth = opts.grading_depth;
  co.elements_across = opts.elements_across;
  co.tool_radius = loaded.scene.fabrication.tool_radius;
  sw.restart();
  const solvers::ConformingVerification v =
      solvers::verify_conforming(loaded.scene, meshes, loaded.load_case, ctx, sf.stencils, co);
  timings.add("verify", sw.seconds());
  timings.add("total", total.seconds());

  const MechanicsSettings used = solvers::scene_mechanics(loaded.scene, sf.stencils);
  json report = solvers::base_report(loaded.scene, meshes, timings, &used);
  report["design"] = dir.string();
  report["stencils"] = sf.stencils.size();
  report["options"] = {{"edge_length", co.edge_length},
                       {"levels", co.levels},
                       {"tolerance", co.tolerance},
                       {"min_levels", co.min_levels},
                       {"peak_zoom", co.peak_zoom},
                       {"zoom_submodel", co.zoom_submodel},
                       {"max_faces", co.max_faces},
                       {"grading_depth", co.grading_depth},
                       {"elements_across", co.elements_across},
                       {"tool_radius", v.tool_radius}};
  report["tool"] = {{"radius", v.tool_radius},
                    {"rounded", v.tool_rounded},
                    {"too_small", v.tool_too_small},
                    {"split", v.tool_split},
                    {"rule", "the conforming outline is each stencil as a cutter of this radius cuts it: the union of "
                             "the discs of the radius inside it (corners turning into the material become arcs of the "
                             "radius; stencils it does not fit in are cut as drawn); 0: as drawn"}};
  report["coarse"] = run_json(v.coarse);
  json levels = json::array();
  for (const auto& q : v.levels) levels.push_back(level_json(q));
  report["conforming"] = {{"levels", levels}, {"finest", level_json(v.levels.back())}};
  report["convergence"] = convergence_json(v, co.tolerance, co.min_levels);
  if (!v.zoom.steps.empty()) {
    json steps = json::array();
    for (const auto& s : v.zoom.steps)
      steps.push_back({{"triangles", s.faces},
                       {"rim_edge_length", s.rim_edge_length},
                       {"peak", number_or_null(s.peak)},
                       {"position", json{s.position.x(), s.position.y(), s.position.z()}},
                       {"peak_outside", number_or_null(s.peak_outside)},
                       {"compliance", number_or_null(s.compliance)},
                       {"seconds", s.seconds},
                       {"mesh_seconds", s.mesh_seconds}});
    json centres = json::array();
    for (const Vec3& c : v.zoom.centres) centres.push_back({c.x(), c.y(), c.z()});
    report["peak_zoom"] = {{"centres", centres},
                           {"radius", v.zoom.radius},
                           {"submodel_triangles", v.zoom.submodel_faces},
                           {"steps", steps},
                           {"extrapolated", number_or_null(v.zoom.extrapolated)},
                           {"order", number_or_null(v.zoom.order)},
                           {"error_bar", number_or_null(v.zoom.error_bar)},
                           {"change", number_or_null(v.zoom.change)},
                           {"converged", v.zoom.converged}};
  }
  report["converged"] = v.converged;
  report["comparison"] = comparison_json(v, meshes.sim);
  if (std::isfinite(v.coarse.W_peak_max))
    report["ligaments"] = solvers::ligament_peak_json(v.ligaments, loaded.scene.material.thickness);
  std::vector<std::string> notes = loaded.notes;
  notes.insert(notes.end(), v.notes.begin(), v.notes.end());
  report["notes"] = notes;
  report["units"] = {{"compliance", "J"}, {"strain_energy", "J"}, {"max_displacement", "m"}, {"W", "J/m^2"},
                     {"edge_length", "m"}, {"load_total", "N"}, {"material_area", "m^2"},
                     {"min_angle", "degree"}, {"triangles_below_10_degrees", "fraction of the level's triangles"}};

  // Per-face fields: NaN (nothing maps there) written as 0 with compared = 0.
  const int nf = meshes.sim.num_faces();
  Eigen::VectorXd W_conf(nf), compared(nf), diff(nf);
  for (int t = 0; t < nf; ++t) {
    const bool ok = std::isfinite(v.W_on_coarse[t]);
    W_conf[t] = ok ? v.W_on_coarse[t] : 0.0;
    compared[t] = v.compared[size_t(t)] ? 1.0 : 0.0;
    diff[t] = v.compared[size_t(t)] ? v.coarse_W[t] - v.W_on_coarse[t] : 0.0;
  }
  const Eigen::VectorXd conf_u = v.conforming_displacement.rowwise().norm();
  Eigen::VectorXd conf_face_u(v.conforming_mesh.num_faces());
  const RowMatX3i& CF = v.conforming_mesh.faces();
  for (int c = 0; c < v.conforming_mesh.num_faces(); ++c)
    conf_face_u[c] = (conf_u[CF(c, 0)] + conf_u[CF(c, 1)] + conf_u[CF(c, 2)]) / 3.0;
  Eigen::VectorXd coarse_face(v.conforming_mesh.num_faces());
  for (int c = 0; c < v.conforming_mesh.num_faces(); ++c) coarse_face[c] = v.conforming_to_coarse[c];

  // Everything is computed before anything is written; report.json goes last.
  const fs::path out = dir / "verify";
  ensure_directory(out);
  write_ply_with_face_fields(out / "fields.ply", meshes.sim,
                             {{"alpha", v.alpha}, {"W", v.coarse_W}, {"W_conforming", W_conf},
                              {"W_difference", diff}, {"compared", compared}});
  write_ply_with_face_fields(out / "conforming.ply", v.conforming_mesh,
                             {{"W", v.conforming_W}, {"displacement", conf_face_u}, {"coarse_face", coarse_face}});
  write_json_atomic(out / "report.json", report);
  if (!opts.quiet) {
    for (const auto& n : notes) say(run, "note: " + n);
    const std::string convergence =
        v.levels.size() < 2
            ? std::string("one level, convergence not measured")
            : fmt::format("{} after {} levels (error bar {:.2g}%, last change {:.2g}%{}): conforming compliance {:.5g} "
                          "J, extrapolated {:.5g} ± {:.2g} J{}",
                          v.converged ? "converged" : "NOT converged", v.levels.size(), 100 * v.relative_error_bar,
                          100 * v.last_change,
                          v.stop == "budget" ? ", face budget reached" : "", v.levels.back().compliance,
                          v.extrapolated_compliance, v.compliance_error_bar,
                          std::isfinite(v.observed_order) ? fmt::format(" (observed order {:.2f})", v.observed_order)
                                                          : std::string());
    say(run, fmt::format("cutwork verify: {}: {} stencils; coarse {} triangles, conforming {} triangles (L = {:.3g} m{}); "
                         "{}; coarse/conforming compliance {:.4f} (extrapolated {:.4f}), strain energy {:.4f}, "
                         "max displacement {:.4f}, W_max {:.4f}; W relative L2 difference {:.3f}; wrote {}",
                         loaded.scene.name, sf.stencils.size(), v.coarse.faces, v.levels.back().faces,
                         v.levels.back().edge_length,
                         co.grading_depth > 0 ? fmt::format(", graded to L/{} along the outlines", 1 << co.grading_depth)
                                              : std::string(),
                         convergence, v.compliance_ratio, v.compliance_ratio_extrapolated,
                         v.strain_energy_ratio, v.max_displacement_ratio, v.W_max_ratio, v.W_relative_l2,
                         (out / "report.json").string()));
    const bool zoomed = v.zoom.steps.size() >= 2;
    const Vec3 peak_position = zoomed ? v.zoom.steps.back().position : v.levels.back().rim_peak_position;
    const double kirchhoff_peak =
        std::isfinite(v.coarse.W_peak_kirchhoff_max) ? v.coarse.W_peak_kirchhoff_max : v.coarse.W_peak_max;
    if (std::isfinite(v.W_peak_ratio))
      say(run, fmt::format("cutwork verify: peak energy density: coarse W_peak {:.4g} J/m² (W_max {:.4g}{}), conforming "
                           "rim peak {:.4g} J/m² at ({:.4g}, {:.4g}, {:.4g}) m ({}{}){}; "
                           "ratio {:.4f} (extrapolated {:.4f}){}{}",
                           kirchhoff_peak, v.coarse.W_max,
                           std::isfinite(v.ligaments.W_max)
                               ? fmt::format(", narrow ligaments W_lig {:.4g} at a {:.2g} m ligament",
                                             v.ligaments.W_max,
                                             v.ligaments.ligaments[std::size_t(v.ligaments.worst)].width)
                               : std::string(),
                           v.conforming_peak, peak_position.x(),
                           peak_position.y(), peak_position.z(),
                           std::isfinite(v.peak_change)
                               ? fmt::format("{}: {:.2g}% change over the last {}",
                                             v.peak_converged ? "converged" : "NOT converged", 100 * v.peak_change,
                                             zoomed ? fmt::format("of {} zoom steps, rims at {:.2g} m",
                                                                  v.zoom.steps.size() - 1,
                                                                  v.zoom.steps.back().rim_edge_length)
                                                    : std::string("level"))
                               : std::string("one level: convergence unknown"),
                           v.tool_radius > 0 ? fmt::format("; outlines as a tool of radius {:.3g} m cuts them, {} rounded",
                                                           v.tool_radius, v.tool_rounded)
                                             : std::string(),
                           std::isfinite(v.peak_error_bar)
                               ? fmt::format(", extrapolated {:.4g} ± {:.2g}", v.peak_extrapolated, v.peak_error_bar)
                               : std::string(", no error bar"),
                           v.W_peak_ratio, v.W_peak_ratio_extrapolated,
                           v.W_estimate != kirchhoff_peak
                               ? fmt::format("; max(W_peak, W_lig) / conforming {:.4f} (extrapolated {:.4f})",
                                             v.W_estimate_ratio, v.W_estimate_ratio_extrapolated)
                               : std::string(),
                           v.coarse.W_peak_thick_scale > 0
                               ? fmt::format("; both are Kirchhoff shells' peaks: the 3-D part's, its stencils against "
                                             "{:.3g} m of shell, W_peak {:.4g} J/m² ({:.2f}x)",
                                             loaded.scene.material.thickness, v.coarse.W_peak_max,
                                             v.coarse.W_peak_max / kirchhoff_peak)
                               : std::string()));
  }
}

}  // namespace

void add_verify_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "verify",
      "Verify a design on a conforming mesh (paper §6): cut the base surface along every stencil outline of DIR "
      "(a `cutwork design --out DIR` folder), remesh it isotropically, graded along the outlines, simulate it without fill ratios and "
      "compare with the coarse fill-ratio run; writes DIR/verify/report.json (compliance, strain energy, maximum "
      "displacement of the material, W_max, the peak energy density recovered on the rims against the coarse "
      "W_peak and the narrow ligaments' W_lig — both Kirchhoff shells', the coarse W_peak with the cells' Kirchhoff "
      "factors; the design's own W_peak, raised for the stencils against the thickness, is reported beside it — "
      "energy density per coarse face, where they differ most), "
      "DIR/verify/fields.ply (coarse mesh: alpha, W, W_conforming, W_difference) and DIR/verify/conforming.ply");
  auto opts = std::make_shared<VerifyOptions>();
  cmd->add_option("DIR", opts->dir, "a design folder (report.json and stencils.json of `cutwork design`)")
      ->required();
  cmd->add_option("--scene", opts->scene,
                  "the scene the design was made with (default: the one DIR/report.json names)");
  cmd->add_option("--edge-length", opts->edge_length,
                  "target edge length of the conforming mesh at the coarsest level, m (0: the base mesh's mean "
                  "edge length)")
      ->check(finite_number())
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--levels", opts->levels,
                  "at most this many conforming solves at L, L/2, L/4, ... (the comparison uses the finest and the "
                  "Richardson-extrapolated compliance; the report shows the convergence)")
      ->check(CLI::Range(1, 6))
      ->capture_default_str();
  cmd->add_option("--tolerance", opts->tolerance,
                  "stop refining once the Richardson-extrapolated conforming compliance's error bar is within this "
                  "fraction of it, after at least --min-levels levels (report.json `converged`; 0: run every level)")
      ->check(finite_number())
      ->check(CLI::Range(0.0, 0.5))
      ->capture_default_str();
  cmd->add_option("--min-levels", opts->min_levels,
                  "the fewest conforming levels that may count as converged (two that agree can do so by chance; "
                  "three show an order)")
      ->check(CLI::Range(2, 6))
      ->capture_default_str();
  cmd->add_option("--peak-zoom", opts->peak_zoom,
                  "after the last level, refine the rims this many more halvings about the candidates of the rim "
                  "peak (within 2 of the finest level's edge lengths) and solve again (a submodel of the finest level "
                  "about them, its border held at that level's solution), so that the conforming peak is read where "
                  "the rims resolve it; its change over the last step is reported (0: the levels' rim peaks only)")
      ->check(CLI::Range(0, 6))
      ->capture_default_str();
  cmd->add_flag("--zoom-whole", opts->zoom_whole,
                "re-solve the whole shell on each peak zoom step (by default a submodel of the finest level about "
                "the peak is re-solved, its border held at that level's solution)");
  cmd->add_option("--max-faces", opts->max_faces,
                  "solve no conforming level above this many triangles (the first is solved whatever its size; "
                  "about 6 kB of memory each)")
      ->check(CLI::Range(1, 100'000'000))
      ->capture_default_str();
  cmd->add_option("--grading-depth", opts->grading_depth,
                  "refine each conforming level up to this many halvings along the outlines, where the material is "
                  "narrower (or a hole smaller) than --elements-across level-0 triangles (0: uniform)")
      ->check(CLI::Range(0, 4))
      ->capture_default_str();
  cmd->add_option("--elements-across", opts->elements_across,
                  "triangles the grading puts across the narrowest ligament and a hole's diameter")
      ->check(finite_number())
      ->check(CLI::Range(1.0, 16.0))
      ->capture_default_str();
  cmd->add_option("--tool-radius", opts->tool_radius,
                  "radius (m) of the cutter the conforming outline is cut with: each stencil becomes the union of the "
                  "discs of this radius inside it, so the corners that turn into the material (a star's tips) are "
                  "rounded as a part cut with that tool is, and the rim peak is read on them; the coarse W_peak it is "
                  "compared with reads the tool's rounds too (default: the scene's fabrication.tool_radius; 0: the "
                  "outlines as drawn, the rim within fabrication.min_feature of their sharp corners left out)")
      ->check(finite_number())
      ->check(CLI::Range(0.0, 1.0))
      ->check(CLI::Validator(
          [](std::string& text) {
            const double r = std::stod(text);
            return r > 0 && r < kMinToolRadius
                       ? fmt::format("{:g} m is finer than any tool rounds a corner (at least {:g} m; 0: sharp corners)",
                                     r, kMinToolRadius)
                       : std::string();
          },
          "TOOL", "a tool's radius"));
  cmd->add_option("--threads", opts->threads, "number of CPU threads (0: all)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  cmd->add_flag("--quiet,-q", opts->quiet, "print nothing but errors");
  cmd->callback([opts] { run_verify(*opts); });
}

}  // namespace cutwork::cli
