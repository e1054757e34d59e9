// `cutwork design [SCENE|NAME|MESH] --out DIR`: the whole pipeline for one design — pattern phase,
// structural phase, and the outputs report.json, stencils.json, fields.ply and cut.obj.
#include <CLI/CLI.hpp>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "host/cli/checkpoint.h"
#include "host/cli/cli_common.h"
#include "host/cli/commands.h"
#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/cut/cut_surface.h"
#include "host/io/json_io.h"
#include "host/mesh/mesh_io.h"
#include "host/pattern/stencils_json.h"
#include "host/scene/work_estimate.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/optimize/design_pipeline.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::cli {

namespace {

using nlohmann::json;

struct DesignCommandOptions {
  RunOptions run;
  std::string phases = "pattern,structure";
  std::string device = "auto";
  int iterations = 0;
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

json number_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json state_json(const solvers::DesignState& d) {
  return {{"stencils", d.stencils},
          {"W_max", d.summary.W_max},
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

json phase_json(const std::string& name, int iterations, int evaluations, int rounds, double seconds,
                double J0, double J1, double S0, double S1, double P0, double P1, const std::string& stop) {
  return {{"name", name},          {"iterations", iterations}, {"evaluations", evaluations},
          {"rounds", rounds},      {"seconds", seconds},       {"J_start", number_or_null(J0)},
          {"J_end", number_or_null(J1)}, {"S_start", number_or_null(S0)}, {"S_end", number_or_null(S1)},
          {"P_start", number_or_null(P0)}, {"P_end", number_or_null(P1)}, {"stop_reason", stop}};
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
    json report = base_report(scene, meshes, timings);
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
    const solvers::ShellModel model(meshes.sim, scene.material, load_case);
    check_factor_work(scene, meshes, solvers::EquilibriumSolver(model).linear_solver().factor_nonzeros());
  }
  sw.restart();
  const DeviceChoice device = choose_device(opts.device);
  timings.add("device", sw.seconds());

  sw.restart();
  PatternContext ctx(scene, meshes);
  for (const auto& n : ctx.notes()) notes.push_back(n);
  timings.add("pattern_context", sw.seconds());

  ProgressLine progress(opts.run);
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
  progress.finish();
  for (const auto& [name, seconds] : r.timings.entries()) timings.add(name, seconds);

  // The cut surface: the base mesh with every stencil outline cut out.
  sw.restart();
  const std::vector<StencilParams> final_params = solvers::layout_params(r.layout);
  const CutSurface cut = cut_stencils(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), final_params);
  timings.add("cut", sw.seconds());
  timings.add("total", total.seconds());

  json report = base_report(scene, meshes, timings);
  report["device"] = device.report;
  std::map<std::string, int> per_type;
  for (const auto& s : r.layout) per_type[ctx.shapes()[s.type].name] += 1;
  report["stencils"] = {{"count", r.layout.size()},
                        {"initial", r.pattern.initial_count},
                        {"removed", r.pattern.removed + (r.structure ? r.structure->removed : 0)},
                        {"inserted_by_hole_filling",
                         r.pattern.inserted_by_hole_filling + (r.structure ? r.structure->inserted_by_hole_filling : 0)},
                        {"type_changes", r.pattern.type_changes + (r.structure ? r.structure->type_changes : 0)},
                        {"by_type", per_type}};
  const double w_P = scene.pattern.w_P;
  json phases = json::array();
  phases.push_back(phase_json("pattern", r.pattern.iterations, r.pattern.evaluations, r.pattern.rounds,
                              r.pattern.seconds, w_P * r.pattern.objective_start, w_P * r.pattern.objective_end,
                              NAN, NAN, r.pattern.objective_start, r.pattern.objective_end, r.pattern.stop_reason));
  phases.back()["objective"] = r.pattern.objective;
  if (r.structure) {
    const solvers::StructurePhaseResult& s = *r.structure;
    phases.push_back(phase_json("structure", s.iterations, s.evaluations, s.rounds, s.seconds, s.J_start, s.J_end,
                                s.S_start, s.S_end, s.P_start, s.P_end, s.stop_reason));
    phases.back()["objective"] = s.objective;
  }
  report["phases"] = phases;
  report["pattern"] = {{"objective", r.pattern.objective},
                       {"exemplar", r.pattern.exemplar},
                       {"unit", r.pattern.unit},
                       {"epsilon", r.pattern.epsilon},
                       {"field_symmetry", r.pattern.field_symmetry},
                       {"w_P", w_P}};
  json st = {{"objective", r.structure ? r.structure->objective : "none"},
             {"w_S", scene.structure.w_S},
             {"beta", r.structure ? number_or_null(r.structure->beta) : json(nullptr)},
             {"beta_fraction", r.structure && std::isfinite(r.structure->beta)
                                   ? json(r.structure->beta / r.uncut.summary.W_max)
                                   : json(nullptr)},
             {"W_max_uncut", r.uncut.summary.W_max},
             {"W_max_pattern", r.pattern_design.summary.W_max},
             {"W_max_final", r.final_design.summary.W_max},
             {"compliance_uncut", r.uncut.summary.compliance},
             {"compliance_pattern", r.pattern_design.summary.compliance},
             {"compliance_final", r.final_design.summary.compliance},
             {"material_fraction_pattern", r.pattern_design.material_fraction},
             {"material_fraction_final", r.final_design.material_fraction},
             {"max_displacement_pattern", r.pattern_design.summary.max_displacement},
             {"max_displacement_final", r.final_design.summary.max_displacement},
             {"overlaps", r.final_design.overlaps.pairs + r.final_design.overlaps.boundary},
             {"units", {{"W", "J/m^2"}, {"compliance", "J"}, {"max_displacement", "m"}}}};
  if (r.structure) {
    st["beta_history"] = r.structure->beta_history;
    st["optimisations"] = r.structure->optimisations;
    if (r.structure->objective == "compliance") {
      st["covered_area_target"] = r.structure->covered_area_target;
      st["covered_area_final"] = r.structure->covered_area_final;
      st["max_restoring_change"] = r.structure->max_restoring_change;
    }
  }
  report["structure"] = st;
  report["equilibrium"] = state_json(r.final_design);
  report["designs"] = {{"uncut", state_json(r.uncut)},
                       {"pattern", state_json(r.pattern_design)},
                       {"final", state_json(r.final_design)}};
  report["cut"] = {{"vertices", cut.vertices.rows()},
                   {"triangles", cut.faces.rows()},
                   {"area", cut.area},
                   {"split_triangles", cut.split_faces},
                   {"removed_triangles", cut.removed_faces}};
  const auto& t = r.stage_times;
  report["timings"]["stages"] = {{"fill_seconds", t.fill},         {"fills", t.fills},
                                 {"equilibrium_seconds", t.equilibrium}, {"equilibria", t.equilibria},
                                 {"newton_iterations", t.newton_iterations}, {"adjoint_seconds", t.adjoint},
                                 {"adjoints", t.adjoints},         {"pullback_seconds", t.pullback}};
  report["notes"] = notes;

  // Staged, then published as one set: a failed run leaves the folder as it was.
  write_stencils_json(outputs->stage("stencils.json"), r.layout, ctx.surface(), ctx.shapes());
  write_ply_with_face_fields(outputs->stage("fields.ply"), meshes.sim,
                             {{"alpha", r.final_design.alpha}, {"W", r.final_design.summary.energy_density},
                              {"W_pattern", r.pattern_design.summary.energy_density}});
  write_obj(outputs->stage("cut.obj"), cut.vertices, cut.faces);
  write_json_atomic(outputs->stage("report.json"), report);
  outputs->publish();
  for (const auto& n : notes) say(opts.run, "note: " + n);
  say(opts.run,
      fmt::format("cutwork design: {}: {} stencils on {} triangles ({} simulated); W_max {:.4g} uncut, {:.4g} "
                  "pattern, {:.4g} final (J/m^2); material left {:.1f}%; wrote {}",
                  scene.name, r.layout.size(), meshes.base.num_faces(), meshes.sim.num_faces(),
                  r.uncut.summary.W_max, r.pattern_design.summary.W_max, r.final_design.summary.W_max,
                  100 * r.final_design.material_fraction, out.string()));
}

}  // namespace

void add_design_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "design",
      "Design a stenciled shell: place stencils by the scene's pattern objective, optimise them with its "
      "structural objective, and write DIR/report.json, stencils.json, fields.ply (per-face alpha and W) and "
      "cut.obj (the surface with the stencils cut out)");
  auto opts = std::make_shared<DesignCommandOptions>();
  add_run_options(*cmd, opts->run, "pavilion");
  cmd->add_option("--phases", opts->phases,
                  "phases to run: pattern (initialisation and pattern-only optimisation), pattern,structure "
                  "(then the scene's structural objective), or none (meshes, supports and loads only)")
      ->check(CLI::IsMember({"pattern", "pattern,structure", "all", "none"}))
      ->capture_default_str();
  add_device_option(*cmd, opts->device);
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
