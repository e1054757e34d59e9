// `cutwork design [SCENE|NAME|MESH] --out DIR`: the whole pipeline for one design — pattern phase,
// structural phase, and the outputs (solvers/report/design_report.h): report.json, stencils.json,
// fields.ply, cut.obj and the designer's files (host/export/design_files.h).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
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
#include "solvers/homogenise/fill_stiffness_calibration.h"
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
  double checkpoint_every = 60;  ///< seconds between checkpoints inside a phase (0: phase ends only)
  bool no_discretisation_estimate = false;
};

// SIGINT / SIGTERM during a design: remembered here, acted on at the next optimiser boundary (a
// checkpoint is written there and the run stops cleanly). A second signal ends it at once.
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

/// Test hook (tests/cli/checkpoint_test.cpp): CUTWORK_TEST_SIGNAL_AFTER_CHECKPOINT=SIGNAL[@STAGE[:N]]
/// sends SIGNAL (KILL or TERM) to the run itself right after the N-th checkpoint (default 1) written
/// at STAGE (pattern, pattern_end — the default —, structure, structure_end): a kill or a stop
/// request at a known moment.
struct TestSignal {
  int signal = 0;
  std::string stage = "pattern_end";
  int count = 1;
  static TestSignal from_environment() {
    TestSignal t;
    const char* hook = std::getenv("CUTWORK_TEST_SIGNAL_AFTER_CHECKPOINT");
    if (!hook) return t;
    std::string spec = hook;
    const size_t at = spec.find('@');
    const std::string name = spec.substr(0, at);
    t.signal = name == "KILL" ? SIGKILL : name == "TERM" ? SIGTERM : 0;
    if (at != std::string::npos) {
      const std::string where = spec.substr(at + 1);
      const size_t colon = where.find(':');
      t.stage = where.substr(0, colon);
      if (colon != std::string::npos) t.count = std::atoi(where.c_str() + colon + 1);
    }
    return t;
  }
};

/// The checkpoints of a run (host/cli/checkpoint.h): written at optimiser boundaries once
/// `interval` seconds have passed since the last (0: never inside a phase), at each phase end that
/// something follows, and at the next boundary after SIGINT/SIGTERM, which then ends the run.
/// Removed when the run ends, unless it was interrupted (then it is what --resume continues from).
class Checkpointer {
 public:
  Checkpointer(std::filesystem::path dir, nlohmann::json fingerprint, double interval, bool structure)
      : m_dir(std::move(dir)),
        m_path(checkpoint_path(m_dir)),
        m_fingerprint(std::move(fingerprint)),
        m_interval(interval),
        m_structure(structure),
        m_test(TestSignal::from_environment()) {}
  Checkpointer(const Checkpointer&) = delete;
  Checkpointer& operator=(const Checkpointer&) = delete;
  ~Checkpointer() {
    std::error_code ignore;
    if (!m_keep) std::filesystem::remove(m_path, ignore);
  }

  const std::filesystem::path& path() const { return m_path; }
  /// A resumed run: the checkpoint it started from is kept if the run is interrupted again.
  void resumed() { m_written = true; }

  /// The hook of solvers::DesignOptions::checkpoint.
  void operator()(const solvers::DesignSnapshot& state) {
    const bool end = state.stage == solvers::DesignStage::PatternEnd || state.stage == solvers::DesignStage::StructureEnd;
    if (state.stage == solvers::DesignStage::PatternEnd && !m_structure) return;  // nothing would follow it
    const bool due = end || (m_interval > 0 && m_since.seconds() >= m_interval);
    if (!due && !g_stop_signal) return;
    Stopwatch sw;
    m_bytes = std::max(m_bytes, write_checkpoint(m_dir, m_fingerprint, state));
    m_seconds += sw.seconds();
    ++m_count;
    m_written = true;
    m_stage = state.stage;
    m_since.restart();
    raise_test_signal(state.stage);
    if (g_stop_signal) interrupted("");
  }

  /// Ends the run after SIGINT/SIGTERM with one message (exit 130/143).
  [[noreturn]] void interrupted(const std::string& out) {
    const int signal = g_stop_signal;
    const char* name = signal == SIGINT ? "SIGINT" : "SIGTERM";
    m_keep = m_written;
    if (m_written)
      throw Interrupted(fmt::format("interrupted by {}: the design is checkpointed ({}) in {}; continue with the "
                                    "same command and --resume",
                                    name, stage_description(m_stage), m_path.string()),
                        signal);
    throw Interrupted(fmt::format("interrupted by {} before the first checkpoint: nothing written into {}", name, out),
                      signal);
  }

  /// Checkpoints written, their total write time (s) and the largest one's size (bytes).
  int count() const { return m_count; }
  double seconds() const { return m_seconds; }
  std::uintmax_t bytes() const { return m_bytes; }

 private:
  void raise_test_signal(solvers::DesignStage stage) {
    if (!m_test.signal || m_test.stage != stage_key(stage) || ++m_test_seen != m_test.count) return;
    std::raise(m_test.signal);
  }
  static std::string stage_key(solvers::DesignStage stage) {
    switch (stage) {
      case solvers::DesignStage::Pattern: return "pattern";
      case solvers::DesignStage::PatternEnd: return "pattern_end";
      case solvers::DesignStage::Structure: return "structure";
      case solvers::DesignStage::StructureEnd: return "structure_end";
    }
    return "";
  }

  std::filesystem::path m_dir, m_path;
  nlohmann::json m_fingerprint;
  double m_interval;
  bool m_structure;
  TestSignal m_test;
  int m_test_seen = 0;
  Stopwatch m_since;
  bool m_written = false, m_keep = false;
  solvers::DesignStage m_stage = solvers::DesignStage::PatternEnd;
  int m_count = 0;
  double m_seconds = 0;
  std::uintmax_t m_bytes = 0;
};

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
    // Its model calibrates a homogenised stiffness (the cell problems, kept for the run): timed.
    sw.restart();
    const solvers::ShellModel model(meshes.sim, scene.material, load_case, solvers::uncut_scene_mechanics(scene));
    timings.add("calibration", sw.seconds());
    check_factor_work(scene, meshes, solvers::EquilibriumSolver(model).linear_solver().factor_nonzeros());
  }
  sw.restart();
  const DeviceChoice device = choose_device(opts.device, !opts.outputs.no_render);
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
  // Checkpoints inside and at the end of the phases; --resume continues from one (host/cli/checkpoint.h).
  const StopSignals stop_signals;
  Checkpointer checkpoint(out, checkpoint_fingerprint(scene, opts.iterations), opts.checkpoint_every, structure);
  std::optional<solvers::DesignResume> resumed;
  if (opts.resume) resumed = read_checkpoint(out, checkpoint_fingerprint(scene, opts.iterations));
  if (resumed) {
    checkpoint.resumed();
    dopt.resume = &*resumed;
    notes.push_back(fmt::format("resumed from the checkpoint in {} ({})", checkpoint.path().string(),
                                stage_description(resumed->stage)));
  } else if (opts.resume) {
    notes.push_back("--resume: no checkpoint in " + out.string() + ", so the design started from the beginning");
  }
  dopt.checkpoint = [&](const solvers::DesignSnapshot& state) { checkpoint(state); };
  dopt.progress = [&](const std::string& phase, const solvers::PatternProgress& p) {
    progress.update(phase, p);
    return true;
  };
  const solvers::DesignResult r = solvers::run_design(scene, meshes, load_case, ctx, dopt);

  if (g_stop_signal) {
    progress.finish();
    checkpoint.interrupted(opts.run.out);
  }
  if (checkpoint.count() > 0)
    notes.push_back(fmt::format("{} checkpoint(s) written in {:.3f} s, the largest {:.1f} kB", checkpoint.count(),
                                checkpoint.seconds(), checkpoint.bytes() / 1e3));

  // Everything is computed before anything is written; then staged and published as one set: a
  // failed run leaves the folder as it was.
  progress.stage("cut");
  solvers::DesignRunInfo info{timings, device.report, notes, !opts.no_discretisation_estimate, {}};
  solvers::DesignOutputs design = solvers::finish_design(scene, meshes, ctx, r, std::move(info), total);
  solvers::add_design_files(design, scene, load_case, design_file_options(opts.outputs, &progress, device.rasterizer));
  progress.finish();
  solvers::write_design_outputs(placer(*outputs), design);
  outputs->publish();
  // (the report's notes: the run's own and finish_design's, e.g. an unconverged simulation mesh)
  for (const auto& n : design.report["notes"]) say(opts.run, "note: " + n.get<std::string>());
  const nlohmann::json& disc = design.report.value("discretisation", nlohmann::json());
  say(opts.run,
      fmt::format("cutwork design: {}: {} stencils on {} triangles ({} simulated); W_max {:.4g} uncut, {:.4g} "
                  "pattern, {:.4g} final (J/m^2){}; material left {:.1f}%{}; wrote {}",
                  scene.name, r.layout.size(), meshes.base.num_faces(), meshes.sim.num_faces(),
                  r.uncut.summary.W_max, r.pattern_design.summary.W_max, r.final_design.summary.W_max,
                  std::isfinite(r.final_design.summary.W_peak_max)
                      ? fmt::format("; ligament peak W_peak {:.4g} pattern, {:.4g} final{}{}",
                                    r.pattern_design.summary.W_peak_max, r.final_design.summary.W_peak_max,
                                    r.final_design.summary.W_peak_thick_scale > 0
                                        ? fmt::format(" ({:.2f}x Kirchhoff's: the stencils against the thickness)",
                                                      r.final_design.summary.W_peak_max /
                                                          r.final_design.summary.W_peak_kirchhoff_max)
                                        : std::string(),
                                    std::isfinite(design.W_ligament_max)
                                        ? fmt::format(", narrow ligaments W_lig {:.4g}", design.W_ligament_max)
                                        : std::string())
                      : std::string(),
                  100 * r.final_design.material_fraction,
                  disc.is_null() ? std::string()
                                 : fmt::format("; compliance {:.4g} J, estimated discretisation error {:.1f}%{}",
                                               r.final_design.summary.compliance,
                                               100 * disc["final"].value("estimated_error", NAN),
                                               disc["converged"].get<bool>() ? "" : " (not converged)"),
                  files_written(out, solvers::design_output_names(design))));
}

}  // namespace

void add_design_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "design",
      "Design a stenciled shell: place stencils by the scene's pattern objective, optimise them with its "
      "structural objective, and write DIR/report.json (objectives, the structure's W_max, W_peak and the narrow "
      "ligaments' W_lig, the discretisation estimate, the stencils' lattice order, timings), stencils.json, fields.ply (per-face alpha and W), "
      "cut.obj (the surface with the stencils cut out), fields.vtu and stencils.vtp (ParaView), cut_solid.stl and "
      "cut_solid.3mf (the cut surface thickened into a printable solid; for a half on symmetry planes, the whole its "
      "mirror images make) and the pictures render_W.png, "
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
                 "inside the phases every --checkpoint-every seconds and at each phase end; SIGINT/SIGTERM write "
                 "one and stop the run cleanly): the same design as an uninterrupted run");
  cmd->add_option("--checkpoint-every", opts->checkpoint_every,
                  "seconds between checkpoints inside a phase, taken at the first optimiser iteration after the "
                  "interval (0: only at phase ends)")
      ->check(finite_number())
      ->check(CLI::Range(0.0, 1e9))
      ->capture_default_str();
  cmd->add_flag("--no-discretisation-estimate", opts->no_discretisation_estimate,
                "skip the solves at half and a quarter of the simulation edge length (and an eighth where those "
                "have not settled), of the uncut shell and of the final design with its material held, that "
                "estimate how far from converged the numbers are (report.json `discretisation`)");
  cmd->callback([opts] { run_design_command(*opts); });
}

}  // namespace cutwork::cli
