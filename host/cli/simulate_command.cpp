// `cutwork simulate [SCENE|NAME|MESH] [--stencils FILE] --out DIR`: the static equilibrium of a
// scene's shell under its supports and loads (§5.1), with the quantities the structural objectives
// use, written as DIR/report.json and DIR/fields.ply (per-face α and W on the simulation mesh).
#include <CLI/CLI.hpp>

#include <filesystem>
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
#include "host/pattern/stencils_json.h"
#include "host/scene/work_estimate.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/structural_quantities.h"
#include "solvers/report/simulate_report.h"

namespace cutwork::cli {

namespace {

struct SimulateOptions {
  RunOptions run;
  std::string stencils;
  std::string device = "auto";
  OutputOptions outputs;
};

/// Fill ratios of a design's stencils.json on the simulation mesh (the scene supplies the shapes
/// and the orientation field the stencils' angles are measured from).
Eigen::VectorXd stencil_fill_ratios(const Scene& scene, const SceneMeshes& meshes, const std::string& file,
                                    const FillRatioOptions& fill, int* count, std::optional<CutSurface>* cut) {
  const PatternContext ctx(scene, meshes);
  const StencilBounds bounds{meshes.base.bbox_min(), meshes.base.bbox_max()};
  const StencilsFile sf = read_stencils_json(file, ctx.shapes(), &bounds);
  *count = int(sf.stencils.size());
  if (sf.stencils.empty()) return Eigen::VectorXd::Ones(meshes.sim.num_faces());
  FillRatioOptions o = fill;
  o.derivatives = false;
  const FaceBvh sim_bvh(meshes.sim);
  FillRatioEvaluator eval(ctx.surface().bvh(), sim_bvh, ctx.shapes(), &ctx.surface().field(), o);
  eval.evaluate(sf.stencils);
  // The angles are relative to the field's tangent: the scene must give the same field.
  for (size_t i = 0; i < sf.stencils.size(); ++i) {
    const Vec3 stored = sf.axis_x.row(Eigen::Index(i)).transpose();
    if (stored.squaredNorm() == 0) continue;
    const auto& cs = eval.clip_stencils()[i];
    const Vec3 axis(cs.axis_x[0], cs.axis_x[1], cs.axis_x[2]);
    if ((axis - stored).norm() > 1e-6)
      throw InputError(fmt::format("{}: /stencils/{}/axis_x: the stencil's axis differs from the one the scene's "
                                   "orientation field gives ({:.3g} apart): this file was made with another scene",
                                   file, i, (axis - stored).norm()));
  }
  *cut = cut_stencils(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), sf.stencils);  // render_design
  return eval.alpha();
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
  const LoadCase& load_case = loaded.load_case;
  std::vector<std::string>& notes = loaded.notes;  // told once the run has succeeded

  sw.restart();
  const solvers::ShellModel model(meshes.sim, scene.material, load_case, scene.mechanics);
  timings.add("model", sw.seconds());

  solvers::NewtonSettings settings;
  settings.log = [&notes](const std::string& line) { notes.push_back(line); };
  solvers::EquilibriumSolver solver(model, settings);
  timings.add("analysis", solver.analysis_seconds());
  check_factor_work(scene, meshes, solver.linear_solver().factor_nonzeros());  // before any factorisation

  // The uncut shell (every triangle full), or a design's stencils.
  Eigen::VectorXd alpha = Eigen::VectorXd::Ones(model.num_faces());
  int stencil_count = 0;
  nlohmann::json device_report = nullptr;
  std::optional<CutSurface> cut;
  if (!opts.stencils.empty()) {
    sw.restart();
    const DeviceChoice device = choose_device(opts.device);
    device_report = device.report;
    alpha = stencil_fill_ratios(scene, meshes, opts.stencils, device.fill, &stencil_count, &cut);
    timings.add("fill_ratios", sw.seconds());
  }
  sw.restart();
  const solvers::EquilibriumStats& stats = solver.solve(alpha);
  timings.add("equilibrium", sw.seconds());
  timings.add("assembly", stats.assembly_seconds);
  timings.add("factorization", stats.factorization_seconds);
  timings.add("solve", stats.solve_seconds);
  timings.add("line_search", stats.line_search_seconds);

  sw.restart();
  const solvers::EquilibriumSummary summary = solvers::summarize_equilibrium(model, solver.positions(), alpha);
  timings.add("quantities", sw.seconds());
  timings.add("total", total.seconds());

  if (!stats.stable)
    throw SolveError(fmt::format(
        "the shell's equilibrium under these loads is unstable (it buckles: the stiffness at equilibrium is not "
        "positive definite after {} Newton iterations); lower the loads or stiffen the shell",
        stats.newton_iterations));

  const solvers::FillRatioSource fill{opts.stencils.empty() ? std::string("uncut") : opts.stencils, stencil_count,
                                      &alpha};
  const nlohmann::json report =
      solvers::simulate_report(scene, meshes, model, solver, stats, summary, fill, timings, device_report);

  // Per-face fields on the simulation mesh: fill ratio, energy density, mean displacement.
  const RowMatX3d u = solver.displacements();
  const Eigen::VectorXd un = u.rowwise().norm();
  Eigen::VectorXd face_u(model.num_faces());
  for (int f = 0; f < model.num_faces(); ++f) {
    const auto& F = meshes.sim.faces();
    face_u[f] = (un[F(f, 0)] + un[F(f, 1)] + un[F(f, 2)]) / 3.0;
  }
  ProgressLine progress(opts.run);
  const DesignFiles files =
      prepare_design_files(simulation_file_inputs(scene, meshes, alpha, summary.energy_density, u, cut ? &*cut : nullptr),
                           design_file_options(opts.outputs, &progress));
  progress.finish();

  // Staged, then published as one set (report.json last): a failed run leaves the folder as it was.
  const std::filesystem::path out(opts.run.out);
  write_ply_with_face_fields(outputs->stage("fields.ply"), meshes.sim,
                             {{"alpha", alpha}, {"W", summary.energy_density}, {"displacement", face_u}});
  files.write(placer(*outputs));
  write_json_atomic(outputs->stage("report.json"), report);
  outputs->publish();
  std::vector<std::string> written = {"report.json", "fields.ply"};
  for (const std::string& name : files.file_names()) written.push_back(name);
  for (const std::string& note : notes) say(opts.run, "note: " + note);
  say(opts.run, fmt::format("cutwork simulate: {}: {} triangles, {} DOFs; max displacement {:.4g} m, strain "
                            "energy {:.4g} J, compliance {:.4g} J, W_max {:.4g} J/m^2 ({} Newton iterations); "
                            "wrote {}",
                            scene.name, model.num_faces(), model.num_dofs(), summary.max_displacement,
                            summary.strain_energy, summary.compliance, summary.W_max, stats.newton_iterations,
                            files_written(out, written)));
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "simulate",
      "Solve the static equilibrium of a scene's shell under its supports and loads and write DIR/report.json "
      "(max displacement, strain energy, compliance, W_max, Newton statistics, timings) and DIR/fields.ply "
      "(per-face alpha, energy density W and displacement on the simulation mesh), DIR/fields.vtu (the same for "
      "ParaView, displacement per vertex) and the pictures render_W.png, render_alpha.png, render_design.png");
  auto opts = std::make_shared<SimulateOptions>();
  add_run_options(*cmd, opts->run, "plate");
  cmd->add_option("--stencils", opts->stencils,
                  "a design's stencils.json (from `cutwork design` on the same scene): simulate the stenciled "
                  "shell (fill ratios) instead of the uncut one");
  add_device_option(*cmd, opts->device);
  add_output_options(*cmd, opts->outputs);
  cmd->callback([opts] { run_simulate(*opts); });
}

}  // namespace cutwork::cli
