#pragma once
/// Pieces shared by the `cutwork` subcommands that run a pipeline (design, simulate).
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "host/core/timer.h"
#include "host/scene/scene.h"
#include "host/stencil/fill_ratio.h"
#include "host/vulkan/backend.h"
#include "solvers/optimize/pattern_phase.h"

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

/// What every pipeline command starts with: the scene, its meshes and the supports and loads on
/// the simulation mesh, timed into `timings` ("scene", "meshes", "load_case"). `notes` collects
/// what to tell the user once the run has succeeded (a failure prints one line only).
struct LoadedScene {
  LoadedScene(const RunOptions& opts, Timings& timings);
  std::vector<std::string> notes;
  Scene scene;
  SceneMeshes meshes;
  LoadCase load_case;
};

/// Bounds TBB's parallelism for the lifetime of the returned object (none when threads == 0). The
/// factorisations' OpenBLAS and OpenMP threads follow the same bound (solvers/linear/thread_policy.h).
std::unique_ptr<tbb::global_control> limit_threads(int threads);

/// Prints a progress/notice line to stderr unless quiet.
void say(const RunOptions& opts, const std::string& line);

/// Adds `--device cpu|vulkan|auto` (stored in `device`).
void add_device_option(CLI::App& cmd, std::string& device);

/// What `--device` resolved to: the fill-ratio backend and report.json's `device` object.
struct DeviceChoice {
  ComputeBackend backend;
  FillRatioOptions fill;
  nlohmann::json report;  ///< {kind, name, driver}
};
/// Resolves `--device` (see host/vulkan/backend.h). `auto` without a usable Vulkan device warns
/// once on stderr (even with --quiet: it changes what runs) and uses the CPU; `vulkan` without
/// one throws DeviceError.
DeviceChoice choose_device(const std::string& device);

/// The live progress display of a pipeline: one line on the terminal, rewritten in place
/// (phase, iteration, objective, gradient norm, W_max, elapsed). Silent with --quiet or when
/// stdout is not a terminal; at most ten updates a second.
class ProgressLine {
 public:
  explicit ProgressLine(const RunOptions& opts);
  ~ProgressLine();
  void update(const std::string& phase, const PatternProgress& p);
  /// Shows a stage without iterations ("pattern context", "uncut equilibrium", "cut", "render
  /// W", …) with the elapsed time; always drawn (stages are rare).
  void stage(const std::string& name);
  /// Ends the line (idempotent).
  void finish();

 private:
  bool m_active = false;
  bool m_dirty = false;
  Stopwatch m_clock, m_since_draw;
};

}  // namespace cutwork::cli
