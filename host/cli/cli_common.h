#pragma once
/// Pieces shared by the `cutwork` subcommands that run a pipeline (design, simulate).
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "host/core/output_set.h"
#include "host/core/timer.h"
#include "host/render/rasterizer.h"
#include "host/scene/scene.h"
#include "host/stencil/fill_ratio.h"
#include "host/vulkan/backend.h"
#include "solvers/optimize/pattern_progress.h"

namespace CLI {
class App;
class Validator;
}

namespace cutwork::cli {

/// Options every pipeline subcommand takes.
struct RunOptions {
  std::string scene = "pavilion";   ///< SCENE file, built-in NAME or MESH file
  std::string out = "out";          ///< output directory
  int threads = 0;                  ///< 0: all hardware threads
  bool quiet = false;
  bool wait = false;                ///< --wait: wait for another run writing into `out`
};

/// Adds SCENE, --out, --threads, --quiet, --wait to `cmd`, storing into `opts`.
void add_run_options(CLI::App& cmd, RunOptions& opts, const std::string& default_scene);

/// Adds --max-faces, --max-stencils and --max-factor-gb (host/core/work_limits.h) to `cmd`.
void add_limit_options(CLI::App& cmd);

/// Refuses a value that is not a finite number ("nan", "inf"). CLI11's Range, NonNegativeNumber and
/// PositiveNumber let NaN through (every comparison with it is false): `--edge-length nan` ran a
/// verify, `--max-factor-gb nan` switched the limit off. Put it before those on every real-valued
/// option.
CLI::Validator finite_number();

/// Locks the output folder `--out` and stages the run's outputs there (see host/core/output_set.h);
/// says on stderr when it waits for another run (--wait).
std::unique_ptr<OutputSet> open_output_set(const RunOptions& opts);

/// What every pipeline command starts with: the scene, its meshes and the supports and loads on
/// the simulation mesh, timed into `timings` ("scene", "meshes", "load_case"). `notes` collects
/// what to tell the user once the run has succeeded (a failure prints one line only).
/// Said after a SolveError's line by main (one line still): set where a run knows more of why a
/// solve may fail (a plain mesh read as metres that is likely millimetres: metres_hint).
void set_solve_error_hint(std::string hint);
const std::string& solve_error_hint();

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

/// What `--device` resolved to: the fill-ratio backend, the rasteriser twin that draws the
/// pictures (the same device), and report.json's `device` object.
struct DeviceChoice {
  ComputeBackend backend;
  FillRatioOptions fill;
  render::Rasterizer rasterizer;
  nlohmann::json report;  ///< {kind, name, driver, requested, reason, render ("none": no pictures)}
};
/// Resolves `--device` (see host/vulkan/backend.h). `auto` without a usable Vulkan device warns
/// once on stderr (even with --quiet: it changes what runs) and uses the CPU; `vulkan` without
/// one throws DeviceError. `pictures`: whether the run draws any (the report's `render` is
/// "none" otherwise).
DeviceChoice choose_device(const std::string& device, bool pictures = true);

/// The live progress display of a pipeline: one line on the terminal, rewritten in place
/// (phase, iteration, objective, gradient norm, W_max, elapsed), at most ten updates a second.
/// When stdout is not a terminal (a batch job, a log file), the same line goes to stderr as a
/// plain line once a run has taken 5 s, then at most every 5 s (CUTWORK_PROGRESS_SECONDS sets
/// the interval). Silent with --quiet.
class ProgressLine {
 public:
  explicit ProgressLine(const RunOptions& opts);
  ~ProgressLine();
  void update(const std::string& phase, const solvers::PatternProgress& p);
  /// Shows a stage without iterations ("pattern context", "uncut equilibrium", "cut", "render
  /// W", …) with the elapsed time; always drawn (stages are rare).
  void stage(const std::string& name);
  /// Ends the line (idempotent).
  void finish();

 private:
  bool m_active = false;
  bool m_log = false;  ///< not a terminal: plain lines on stderr
  double m_log_interval = 5.0;  ///< seconds between plain lines
  bool m_dirty = false;
  Stopwatch m_clock, m_since_draw;
};

}  // namespace cutwork::cli
