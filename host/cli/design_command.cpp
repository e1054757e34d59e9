// `cutwork design [SCENE|NAME|MESH] --out DIR`: the whole pipeline for one design.
#include <CLI/CLI.hpp>

#include "host/cli/cli_common.h"
#include "host/cli/commands.h"
#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/io/json_io.h"

namespace cutwork::cli {

void add_design_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "design", "Design a stenciled shell: build the meshes, resolve supports and loads, and write "
                "DIR/report.json (the pattern and structural phases extend this)");
  auto opts = std::make_shared<RunOptions>();
  auto phases = std::make_shared<std::string>("all");
  add_run_options(*cmd, *opts, "pavilion");
  cmd->add_option("--phases", *phases,
                  "phases to run: all, none, pattern, or pattern,structure (none: meshes, supports and "
                  "loads only)")
      ->check(CLI::IsMember({"all", "none", "pattern", "pattern,structure"}))
      ->capture_default_str();
  cmd->callback([opts, phases] {
    if (*phases == "pattern" || *phases == "pattern,structure")
      throw InputError("--phases " + *phases +
                       ": the pattern and structural phases are not part of this build yet (use all or none)");
    auto threads = limit_threads(opts->threads);
    Timings timings;
    Stopwatch total;
    Stopwatch sw;
    std::string notice;
    const Scene scene = load_scene(opts->scene, &notice);
    if (!notice.empty()) say(*opts, "note: " + notice);
    timings.add("scene", sw.seconds());

    sw.restart();
    const SceneMeshes meshes = build_scene_meshes(scene);
    timings.add("meshes", sw.seconds());

    sw.restart();
    const LoadCase load_case = resolve_load_case(scene, meshes.sim);
    timings.add("load_case", sw.seconds());
    (void)load_case;

    timings.add("total", total.seconds());
    nlohmann::json report = base_report(scene, meshes, timings);
    report["phases"] = nlohmann::json::array();
    // Everything is computed before anything is written: a failed run leaves no partial output.
    ensure_directory(opts->out);
    write_json_atomic(std::filesystem::path(opts->out) / "report.json", report);
    say(*opts, "cutwork design: " + scene.name + ": " + std::to_string(meshes.base.num_faces()) +
                   " triangles (" + std::to_string(meshes.sim.num_faces()) + " simulated); wrote " +
                   (std::filesystem::path(opts->out) / "report.json").string());
  });
}

}  // namespace cutwork::cli
