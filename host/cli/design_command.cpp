// `cutwork design [SCENE|NAME|MESH] --out DIR`: the whole pipeline for one design — pattern phase,
// structural phase, and the outputs (solvers/report/design_report.h): report.json, stencils.json,
// fields.ply, cut.obj and the designer's files (host/export/design_files.h).
#include <CLI/CLI.hpp>

#include <filesystem>
#include <utility>

#include <fmt/format.h>

#include "host/cli/cli_common.h"
#include "host/cli/commands.h"
#include "host/cli/outputs.h"
#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/io/json_io.h"
#include "solvers/optimize/design_pipeline.h"
#include "solvers/report/design_report.h"
#include "solvers/report/run_report.h"

namespace cutwork::cli {

namespace {

using nlohmann::json;

struct DesignCommandOptions {
  RunOptions run;
  std::string phases = "pattern,structure";
  std::string device = "auto";
  int iterations = 0;
  OutputOptions outputs;
};

void run_design_command(const DesignCommandOptions& opts) {
  auto threads = limit_threads(opts.run.threads);
  const bool none = opts.phases == "none";
  const bool structure = opts.phases == "pattern,structure" || opts.phases == "all";
  Timings timings;
  Stopwatch total, sw;
  LoadedScene loaded(opts.run, timings);
  const Scene& scene = loaded.scene;
  const SceneMeshes& meshes = loaded.meshes;
  const LoadCase& load_case = loaded.load_case;
  std::vector<std::string>& notes = loaded.notes;  // told once the run has succeeded

  const std::filesystem::path out(opts.run.out);
  if (none) {
    timings.add("total", total.seconds());
    json report = solvers::base_report(scene, meshes, timings);
    report["phases"] = json::array();
    ensure_directory(out);
    write_json_atomic(out / "report.json", report);
    for (const auto& n : notes) say(opts.run, "note: " + n);
    say(opts.run, fmt::format("cutwork design: {}: {} triangles ({} simulated), no phases run; wrote {}",
                              scene.name, meshes.base.num_faces(), meshes.sim.num_faces(),
                              (out / "report.json").string()));
    return;
  }

  sw.restart();
  const DeviceChoice device = choose_device(opts.device);
  timings.add("device", sw.seconds());

  ProgressLine progress(opts.run);
  sw.restart();
  progress.stage("pattern context");
  PatternContext ctx(scene, meshes);
  for (const auto& n : ctx.notes()) notes.push_back(n);
  timings.add("pattern_context", sw.seconds());

  progress.stage("uncut equilibrium");
  solvers::DesignOptions dopt;
  dopt.structure = structure;
  dopt.fill = device.fill;
  if (opts.iterations > 0) dopt.pattern_iterations = dopt.structure_iterations = opts.iterations;
  dopt.progress = [&](const std::string& phase, const PatternProgress& p) {
    progress.update(phase, p);
    return true;
  };
  const solvers::DesignResult r = solvers::run_design(scene, meshes, load_case, ctx, dopt);

  // Everything is computed before anything is written: a failed run leaves no partial output.
  progress.stage("cut");
  solvers::DesignRunInfo info{timings, device.report, notes};
  solvers::DesignOutputs outputs = solvers::finish_design(scene, meshes, ctx, r, std::move(info), total);
  solvers::add_design_files(outputs, scene, load_case, design_file_options(opts.outputs, &progress));
  progress.finish();
  solvers::write_design_outputs(out, outputs);
  for (const auto& n : notes) say(opts.run, "note: " + n);
  say(opts.run,
      fmt::format("cutwork design: {}: {} stencils on {} triangles ({} simulated); W_max {:.4g} uncut, {:.4g} "
                  "pattern, {:.4g} final (J/m^2); material left {:.1f}%; wrote {}",
                  scene.name, r.layout.size(), meshes.base.num_faces(), meshes.sim.num_faces(),
                  r.uncut.summary.W_max, r.pattern_design.summary.W_max, r.final_design.summary.W_max,
                  100 * r.final_design.material_fraction, files_written(out, solvers::design_output_names(outputs))));
}

}  // namespace

void add_design_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "design",
      "Design a stenciled shell: place stencils by the scene's pattern objective, optimise them with its "
      "structural objective, and write DIR/report.json, stencils.json, fields.ply (per-face alpha and W), "
      "cut.obj (the surface with the stencils cut out), fields.vtu and stencils.vtp (ParaView), cut_solid.stl and "
      "cut_solid.3mf (the cut surface thickened into a printable solid) and the pictures render_W.png, "
      "render_alpha.png, render_design.png");
  auto opts = std::make_shared<DesignCommandOptions>();
  add_run_options(*cmd, opts->run, "pavilion");
  cmd->add_option("--phases", opts->phases,
                  "phases to run: pattern (initialisation and pattern-only optimisation), pattern,structure "
                  "(then the scene's structural objective), or none (meshes, supports and loads only)")
      ->check(CLI::IsMember({"pattern", "pattern,structure", "all", "none"}))
      ->capture_default_str();
  add_device_option(*cmd, opts->device);
  add_output_options(*cmd, opts->outputs);
  cmd->add_option("--iterations", opts->iterations,
                  "L-BFGS-B iterations per phase, overriding the scene's pattern.max_iterations and "
                  "structure.max_iterations (0: the scene's)")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  cmd->callback([opts] { run_design_command(*opts); });
}

}  // namespace cutwork::cli
