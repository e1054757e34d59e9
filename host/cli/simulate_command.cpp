// `cutwork simulate [SCENE|NAME|MESH] [--stencils FILE] --out DIR`: the static equilibrium of a
// scene's shell under its supports and loads (§5.1), with the quantities the structural objectives
// use, written as DIR/report.json and DIR/fields.ply (per-face α and W on the simulation mesh).
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "host/cli/cli_common.h"
#include "host/cli/commands.h"
#include "host/cli/outputs.h"
#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/cut/cut_surface.h"
#include "host/core/json_io.h"
#include "host/mesh/mesh_io.h"
#include "host/pattern/pattern_context.h"
#include "host/pattern/stencils_json.h"
#include "host/scene/work_estimate.h"
#include "host/stencil/frame.h"
#include "solvers/conforming/conforming_verification.h"
#include "solvers/conforming/discretisation_estimate.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/optimize/stencilled_shell.h"
#include "solvers/report/run_report.h"
#include "solvers/report/simulate_report.h"

namespace cutwork::cli {

namespace {

struct SimulateOptions {
  RunOptions run;
  std::string stencils;
  std::string device = "auto";
  OutputOptions outputs;
  bool no_discretisation_estimate = false;
};

/// What the stenciled shell is built on besides the simulation mesh: the surface the stencils sit
/// on, their shapes and the tangent field. With a design's stencils that is the scene's pattern
/// context (its orientation field measures the stencils' angles). The uncut shell places no
/// stencil, so the scene's shapes on the base mesh with a fixed-axis field stand in, and the
/// orientation field is not solved.
class StencilSurface {
 public:
  StencilSurface(const Scene& scene, const SceneMeshes& meshes, bool with_stencils) {
    if (with_stencils) {
      m_context = std::make_unique<PatternContext>(scene, meshes);
      return;
    }
    m_shapes = std::make_unique<StencilLibrary>(scene_stencil_library(scene));
    m_bvh = std::make_unique<FaceBvh>(meshes.base);
  }
  const FaceBvh& bvh() const { return m_context ? m_context->surface().bvh() : *m_bvh; }
  const StencilLibrary& shapes() const { return m_context ? m_context->shapes() : *m_shapes; }
  const TangentField& field() const {
    return m_context ? static_cast<const TangentField&>(m_context->surface().field()) : m_axis;
  }
  /// The scene's pattern context (null for the uncut shell).
  const PatternContext* context() const { return m_context.get(); }

 private:
  std::unique_ptr<PatternContext> m_context;
  std::unique_ptr<StencilLibrary> m_shapes;
  std::unique_ptr<FaceBvh> m_bvh;
  AxisTangentField m_axis;
};

/// A design's stencils.json for the scene (`surface` holds its pattern context).
StencilsFile read_design_stencils(const StencilSurface& surface, const SceneMeshes& meshes, const std::string& file) {
  const StencilBounds bounds{meshes.base.bbox_min(), meshes.base.bbox_max()};
  return read_stencils_json(file, surface.shapes(), &bounds);
}

/// The design's stencils set on the shell: its fill ratios on the simulation mesh. Returns the
/// stencils (the cut needs them).
std::vector<StencilParams> set_design_stencils(solvers::StencilledShell& shell, StencilsFile sf,
                                               const std::string& file) {
  shell.set_stencils(sf.stencils);
  if (sf.stencils.empty()) return {};
  // The angles are relative to the field's tangent: the scene must give the same field.
  for (size_t i = 0; i < sf.stencils.size(); ++i) {
    const Vec3 stored = sf.axis_x.row(Eigen::Index(i)).transpose();
    if (stored.squaredNorm() == 0) continue;
    const auto& cs = shell.evaluator().clip_stencils()[i];
    const Vec3 axis(cs.axis_x[0], cs.axis_x[1], cs.axis_x[2]);
    if ((axis - stored).norm() > 1e-6)
      throw InputError(fmt::format("{}: /stencils/{}/axis_x: the stencil's axis differs from the one the scene's "
                                   "orientation field gives ({:.3g} apart): this file was made with another scene",
                                   file, i, (axis - stored).norm()));
  }
  return std::move(sf.stencils);
}

void run_simulate(const SimulateOptions& opts) {
  auto threads = limit_threads(opts.run.threads);
  Timings timings;
  Stopwatch total;
  Stopwatch sw;
  const std::unique_ptr<OutputSet> outputs = open_output_set(opts.run);  // locked from the start
  LoadedScene loaded(opts.run, timings);
  const Scene& scene = loaded.scene;
  const SceneMeshes& meshes = loaded.meshes;
  std::vector<std::string>& notes = loaded.notes;  // told once the run has succeeded

  // The uncut shell (every triangle full), or a design's stencils: p → α → x by StencilledShell.
  const bool with_stencils = !opts.stencils.empty();
  sw.restart();
  nlohmann::json device_report = nullptr;
  // --device places the stencils' fill ratios and the pictures; an uncut run without pictures needs none.
  std::optional<DeviceChoice> device;
  FillRatioOptions fill_options;
  if (with_stencils || !opts.outputs.no_render) {
    device = choose_device(opts.device, !opts.outputs.no_render);
    device_report = device->report;
    if (with_stencils) fill_options = device->fill;
  }
  fill_options.derivatives = false;
  const StencilSurface surface(scene, meshes, with_stencils);
  StencilsFile design_file;
  if (with_stencils) design_file = read_design_stencils(surface, meshes, opts.stencils);
  // "lattice": "auto" is read from these stencils, before the stiffness is calibrated on it (and a
  // lattice that follows the field gets the field's axis).
  loaded.scene.mechanics =
      solvers::measured_lattice(scene.mechanics, surface.bvh(), surface.field(), design_file.stencils, notes);
  double fill_seconds = sw.seconds();

  sw.restart();
  solvers::NewtonSettings settings;
  settings.log = [&notes](const std::string& line) { notes.push_back(line); };
  solvers::StencilledShell shell(meshes.sim, surface.bvh(), scene.material, scene.mechanics, loaded.load_case,
                                 surface.shapes(), surface.field(), fill_options, settings);
  if (surface.context()) shell.set_cell_filter(solvers::scene_cell_filter(scene, *surface.context(), meshes.sim));
  const solvers::ShellModel& model = shell.model();
  const double analysis_seconds = shell.solver().analysis_seconds();
  timings.add("model", sw.seconds() - analysis_seconds);
  timings.add("analysis", analysis_seconds);
  check_factor_work(scene, meshes, shell.solver().linear_solver().factor_nonzeros());  // before any factorisation

  std::optional<CutSurface> cut;
  std::vector<StencilParams> stencils;
  if (with_stencils) {
    sw.restart();
    stencils = set_design_stencils(shell, std::move(design_file), opts.stencils);
    if (!stencils.empty())
      cut = cut_with_tool(surface.bvh(), surface.shapes(), surface.field(), stencils,
                          scene.fabrication.tool_radius);  // render_design
    fill_seconds += sw.seconds();
    timings.add("fill_ratios", fill_seconds);
  }
  const Eigen::VectorXd& alpha = shell.alpha();
  sw.restart();
  const solvers::EquilibriumStats& stats = shell.equilibrate();
  timings.add("equilibrium", sw.seconds());
  timings.add("assembly", stats.assembly_seconds);
  timings.add("factorization", stats.factorization_seconds);
  timings.add("solve", stats.solve_seconds);
  timings.add("line_search", stats.line_search_seconds);

  sw.restart();
  const solvers::EquilibriumSummary summary = shell.summary();
  timings.add("quantities", sw.seconds());
  timings.add("total", total.seconds());

  if (!stats.stable)
    throw SolveError(fmt::format(
        "the shell's equilibrium under these loads is unstable (it buckles: the stiffness at equilibrium is not "
        "positive definite after {} Newton iterations); lower the loads or stiffen the shell",
        stats.newton_iterations));

  // How far from converged: the same shell and stencils at half the simulation edge length.
  std::optional<solvers::DiscretisationEstimate> estimate;
  if (!opts.no_discretisation_estimate) {
    sw.restart();
    // The material the simulation mesh's faces carry (α after the cell filter) held on every
    // level, the holes re-cut where the mesh resolves them: the mesh's error, not the fill rule's.
    solvers::SimulationMeshRefinements refined(scene, meshes);
    solvers::FillRatiosOnMesh held = solvers::coarse_fill_ratios_on(meshes.sim, alpha);
    if (surface.context() && !shell.cell_filter().identity())
      held = solvers::coarse_fill_ratios_on(meshes.sim, alpha, shell.cell_filter().resolution(),
                                            [&](const SurfaceMesh& m) {
                                              return solvers::fill_ratios_on_mesh(
                                                  surface.bvh(), surface.shapes(), surface.field(), m,
                                                  stencils, fill_options);
                                            });
    const RowMatX3d displacement = shell.solver().displacements();
    const Eigen::VectorXd* weight = shell.cell_filter().identity() ? nullptr : &shell.cell_filter().blend();
    estimate = solvers::estimate_discretisation(scene, refined, held, model.mechanics(), summary,
                                                solvers::simulation_edge_length(scene, meshes), meshes.sim,
                                                &displacement, solvers::coarse_peak_inputs_on(meshes.sim, weight, shell.cover()),
                                                &summary.peak_energy_density);
    timings.add("discretisation", sw.seconds());
    if (!estimate->converged) notes.push_back(solvers::discretisation_line(*estimate));
    if (const std::string peak = solvers::peak_discretisation_note(*estimate); !peak.empty()) notes.push_back(peak);
  }

  nlohmann::json lattice_order = nullptr;
  if (!stencils.empty()) {
    lattice_order = solvers::lattice_order_json(scene.mechanics, surface.bvh(), surface.field(), stencils, notes);
    solvers::symmetry_plane_notes(model.load_case(), stencils, notes);
  }

  const solvers::FillRatioSource fill{with_stencils ? opts.stencils : std::string("uncut"), shell.num_stencils(),
                                      &alpha, &shell.face_alpha()};
  nlohmann::json report =
      solvers::simulate_report(scene, meshes, model, shell.solver(), stats, summary, fill, timings, device_report);
  if (estimate) report["discretisation"] = solvers::discretisation_json(*estimate);
  // The narrow ligaments W_peak cannot see (solvers/objective/ligament_peak.h).
  double W_ligament_max = NAN;
  if (cut && summary.peak_energy_density.size() == meshes.sim.num_faces()) {
    sw.restart();
    const std::vector<double>& samples = model.mechanics().stiffness_curve.alpha;
    const solvers::LigamentPeakSummary ligaments = solvers::summarize_ligament_peaks(
        *cut, meshes.base, meshes.sim, alpha, summary.peak_energy_density, samples.empty() ? 0.0 : samples.front(),
        scene.material.thickness, model.mechanics().lattice, model.load_case().symmetry_planes);
    W_ligament_max = ligaments.W_max;
    report["ligaments"] = solvers::ligament_peak_json(ligaments, scene.material.thickness);
    report["timings"]["ligaments"] = sw.seconds();
  }
  if (!lattice_order.is_null()) report["lattice_order"] = lattice_order;
  // What the run found worth telling, as design and verify keep it (also printed on stderr).
  report["notes"] = notes;

  // Per-face fields on the simulation mesh: fill ratio, energy density, mean displacement.
  const RowMatX3d u = shell.solver().displacements();
  const Eigen::VectorXd un = u.rowwise().norm();
  Eigen::VectorXd face_u(model.num_faces());
  for (int f = 0; f < model.num_faces(); ++f) {
    const auto& F = meshes.sim.faces();
    face_u[f] = (un[F(f, 0)] + un[F(f, 1)] + un[F(f, 2)]) / 3.0;
  }
  ProgressLine progress(opts.run);
  const DesignFiles files =
      prepare_design_files(simulation_file_inputs(scene, meshes, alpha, summary.energy_density, u, cut ? &*cut : nullptr),
                           design_file_options(opts.outputs, &progress, device ? device->rasterizer : render::Rasterizer{}));
  progress.finish();

  // Staged, then published as one set (report.json last): a failed run leaves the folder as it was.
  const std::filesystem::path out(opts.run.out);
  std::map<std::string, Eigen::VectorXd> face_fields = {{"alpha", alpha}, {"W", summary.energy_density}, {"displacement", face_u}};
  if (summary.peak_energy_density.size() > 0) face_fields["W_peak"] = summary.peak_energy_density;
  write_ply_with_face_fields(outputs->stage("fields.ply"), meshes.sim, face_fields);
  files.write(placer(*outputs));
  write_json_atomic(outputs->stage("report.json"), report);
  outputs->publish();
  std::vector<std::string> written = {"report.json", "fields.ply"};
  for (const std::string& name : files.file_names()) written.push_back(name);
  for (const std::string& note : notes) say(opts.run, "note: " + note);
  say(opts.run, fmt::format("cutwork simulate: {}: {} triangles, {} DOFs; max displacement {:.4g} m, strain "
                            "energy {:.4g} J, compliance {:.4g} J, W_max {:.4g} J/m^2{} ({} Newton iterations); "
                            "wrote {}",
                            scene.name, model.num_faces(), model.num_dofs(), summary.max_displacement,
                            summary.strain_energy, summary.compliance, summary.W_max,
                            std::isfinite(summary.W_peak_max)
                                ? fmt::format(", ligament peak W_peak {:.4g}{}", summary.W_peak_max,
                                              std::isfinite(W_ligament_max)
                                                  ? fmt::format(", narrow ligaments W_lig {:.4g}", W_ligament_max)
                                                  : std::string())
                                : std::string(),
                            stats.newton_iterations, files_written(out, written)));
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "simulate",
      "Solve the static equilibrium of a scene's shell under its supports and loads and write DIR/report.json "
      "(max displacement, strain energy, compliance, W_max, and with --stencils W_peak at the ligaments and W_lig "
      "at the narrow ones and the stencils' lattice order, the discretisation estimate, Newton statistics, timings) and DIR/fields.ply "
      "(per-face alpha, energy density W and displacement on the simulation mesh), DIR/fields.vtu (the same for "
      "ParaView, displacement per vertex) and the pictures render_W.png, render_alpha.png, render_design.png");
  auto opts = std::make_shared<SimulateOptions>();
  add_run_options(*cmd, opts->run, "plate");
  cmd->add_option("--stencils", opts->stencils,
                  "a design's stencils.json (from `cutwork design` on the same scene): simulate the stenciled "
                  "shell (fill ratios) instead of the uncut one");
  add_device_option(*cmd, opts->device);
  add_output_options(*cmd, opts->outputs);
  cmd->add_flag("--no-discretisation-estimate", opts->no_discretisation_estimate,
                "skip the solves at half and a quarter of the simulation edge length (and an eighth where those "
                "have not settled), with the same material, that estimate how far from converged the numbers are "
                "(report.json `discretisation`)");
  cmd->callback([opts] { run_simulate(*opts); });
}

}  // namespace cutwork::cli
