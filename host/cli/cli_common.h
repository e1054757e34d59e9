#pragma once
/// Pieces shared by the `cutwork` subcommands that run a pipeline (design, simulate).
#include <memory>
#include <string>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "host/core/timer.h"
#include "host/scene/scene.h"

namespace CLI {
class App;
}

namespace cutwork::cli {

/// Options every pipeline subcommand takes.
struct RunOptions {
  std::string scene = "pavilion";   ///< SCENE file, built-in NAME or MESH file
  std::string out = "out";          ///< output directory
  int threads = 0;                  ///< 0: all hardware threads
  bool quiet = false;
};

/// Adds SCENE, --out, --threads, --quiet to `cmd`, storing into `opts`.
void add_run_options(CLI::App& cmd, RunOptions& opts, const std::string& default_scene);

/// Bounds TBB's parallelism for the lifetime of the returned object (none when threads == 0).
std::unique_ptr<tbb::global_control> limit_threads(int threads);

/// The report fields every pipeline writes: scene, mesh counts, timings.
nlohmann::json base_report(const Scene& scene, const SceneMeshes& meshes, const Timings& timings);
nlohmann::json timings_json(const Timings& timings);

/// Prints a progress/notice line to stderr unless quiet.
void say(const RunOptions& opts, const std::string& line);

}  // namespace cutwork::cli
