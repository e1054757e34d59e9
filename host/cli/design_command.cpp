// `cutwork design [SCENE|NAME|MESH] --out DIR`: the whole pipeline for one design — pattern phase,
// structural phase, and the outputs (solvers/report/design_report.h): report.json, stencils.json,
// fields.ply, cut.obj and the designer's files (host/export/design_files.h).
#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "host/cli/checkpoint.h"
#include "host/cli/cli_common.h"
#include "host/cli/commands.h"
#include "host/cli/outputs.h"
#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/core/json_io.h"
#include "host/pattern/stencils_json.h"
#include "host/scene/work_estimate.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/optimize/design_pipeline.h"
#include "solvers/report/design_report.h"
#include "solvers/report/run_report.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::cli {

namespace {

using nlohmann::json;

struct DesignCommandOptions {
  RunOptions run;
  std::string phases = "pattern,structure";
  std::string device = "auto";
  int iterations = 0;
  OutputOptions outputs;
  bool resume = false;
};

// SIGINT / SIGTERM during a design: remembered here, acted on at the next progress report (the
// optimiser's iterations), where the run can stop cleanly. A second signal ends it at once.
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void on_stop_signal(int signal) {
  g_stop_signal = signal;
  std::signal(signal, SIG_DFL);
}

/// Installs the handlers for the lifetime of a run.
class StopSignals {
 public:
  StopSignals() : m_int(std::signal(SIGINT, on_stop_signal)), m_term(std::signal(SIGTERM, on_stop_signal)) {}
  ~StopSignals() {
    std::signal(SIGINT, m_int);
    std::signal(SIGTERM, m_term);
  }

 private:
  void (*m_int)(int);
  void (*m_term)(int);
};

/// The checkpoint of a run (host/cli/checkpoint.h): removed when the run ends, unless it was
/// interrupted (then it is what --resume continues from).
struct CheckpointFile {
  std::filesystem::path path;
  bool written = false;
  bool keep = false;
  ~CheckpointFile() {
    std::error_code ignore;
    if (!keep) std::filesystem::remove(path, ignore);
  }
  [[noreturn]] void interrupted(const std::string& out) {
    const int signal = g_stop_signal;
    const char* name = signal == SIGINT ? "SIGINT" : "SIGTERM";
    keep = written;
    if (written)
      throw Interrupted(fmt::format("interrupted by {}: the pattern phase is checkpointed in {}; continue with the "
                                    "same command and --resume",
                                    name, path.string()),
                        signal);
    throw Interrupted(fmt::format("interrupted by {} before the first checkpoint (the end of the pattern phase): "
                                  "nothing written into {}",
                                  name, out),
                      signal);
  }
};

/// Test hook (tests/cli/checkpoint_test.cpp): CUTWORK_TEST_SIGNAL_AFTER_CHECKPOINT=KILL or TERM
/// sends that signal to the run itself right after its checkpoint is written — a kill or a stop
/// request at a known moment.
void raise_test_signal_after_checkpoint() {
  const char* hook = std::getenv("CUTWORK_TEST_SIGNAL_AFTER_CHECKPOINT");
  if (!hook) return;
  if (std::string(hook) == "KILL") std::raise(SIGKILL);
  if (std::string(hook) == "TERM") std::raise(SIGTERM);
}

void run_design_command(const DesignCommandOptions& opts) {
  auto threads = limit_threads(opts.run.threads);
  const bool none = opts.phases == "none";
  const bool structure = opts.phases == "pattern,structure" || opts.phases == "all";
  Timings timings;
  Stopwatch total, sw;
  // The output folder is locked from the start (a second run into it fails at once); what this
  // run writes is staged there and published as one set at the end.
  const std::unique_ptr<OutputSet> outputs = open_output_set(opts.run);
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
    write_json_atomic(outputs->stage("report.json"), report);
    outputs->publish();
    for (const auto& n : notes) say(opts.run, "note: " + n);
    say(opts.run, fmt::format("cutwork design: {}: {} triangles ({} simulated), no phases run; wrote {}",
                              scene.name, meshes.base.num_faces(), meshes.sim.num_faces(),
                              (out / "report.json").string()));
    return;
  }

  check_stencil_work(scene, meshes);  // refuse an unbounded pattern before building anything for it
  {
    // The factor's size from CHOLMOD's symbolic analysis, before the design factorises anything.
    const solvers::ShellModel model(meshes.sim, scene.material, load_case, scene.mechanics);
    check_factor_work(scene, meshes, solvers::EquilibriumSolver(model).linear_solver().factor_nonzeros());
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
  // Checkpoint at the end of the pattern phase; --resume continues from it (host/cli/checkpoint.h).
  const StopSignals stop_signals;
  CheckpointFile checkpoint{checkpoint_path(out)};
  const nlohmann::json fingerprint = checkpoint_fingerprint(scene, opts.iterations);
  std::optional<PatternPhaseResult> resumed;
  if (opts.resume) resumed = read_pattern_checkpoint(out, fingerprint);
  if (resumed) {
    checkpoint.written = true;
    dopt.resume_pattern = &*resumed;
    notes.push_back("resumed from the checkpoint of the pattern phase in " + checkpoint.path.string());
  } else if (opts.resume) {
    notes.push_back("--resume: no checkpoint in " + out.string() + ", so the design started from the beginning");
  }
  dopt.pattern_done = [&](const PatternPhaseResult& pattern) {
    if (!structure) return;  // nothing would follow it
    write_pattern_checkpoint(out, fingerprint, pattern);
    checkpoint.written = true;
    raise_test_signal_after_checkpoint();
    if (g_stop_signal) checkpoint.interrupted(opts.run.out);
  };
  dopt.progress = [&](const std::string& phase, const PatternProgress& p) {
    if (g_stop_signal) {
      progress.finish();
      checkpoint.interrupted(opts.run.out);
    }
    progress.update(phase, p);
    return true;
  };
  const solvers::DesignResult r = solvers::run_design(scene, meshes, load_case, ctx, dopt);

  // Everything is computed before anything is written; then staged and published as one set: a
  // failed run leaves the folder as it was.
  progress.stage("cut");
  solvers::DesignRunInfo info{timings, device.report, notes};
  solvers::DesignOutputs design = solvers::finish_design(scene, meshes, ctx, r, std::move(info), total);
  solvers::add_design_files(design, scene, load_case, design_file_options(opts.outputs, &progress));
  progress.finish();
  solvers::write_design_outputs(placer(*outputs), design);
  outputs->publish();
  for (const auto& n : notes) say(opts.run, "note: " + n);
  say(opts.run,
      fmt::format("cutwork design: {}: {} stencils on {} triangles ({} simulated); W_max {:.4g} uncut, {:.4g} "
                  "pattern, {:.4g} final (J/m^2); material left {:.1f}%; wrote {}",
                  scene.name, r.layout.size(), meshes.base.num_faces(), meshes.sim.num_faces(),
                  r.uncut.summary.W_max, r.pattern_design.summary.W_max, r.final_design.summary.W_max,
                  100 * r.final_design.material_fraction, files_written(out, solvers::design_output_names(design))));
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
  cmd->add_flag("--resume", opts->resume,
                 "continue from the checkpoint a killed or interrupted run left in the output directory (written "
                 "when the pattern phase ends; SIGINT/SIGTERM stop a run cleanly, keeping it): the same design as "
                 "an uninterrupted run");
  cmd->callback([opts] { run_design_command(*opts); });
}

}  // namespace cutwork::cli
