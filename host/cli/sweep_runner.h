#pragma once
/// `cutwork sweep`: runs every variant of a sweep (host/sweep/sweep_spec.h) as a full design
/// into DIR/variants/<id>/, records each one's outcome atomically, and writes the tables.
///
/// DIR/sweep.json          what the folder holds: the sweep's axes and variants (a later run
///                         into DIR must expand to the same, or it is refused)
/// DIR/variants/<id>/      scene.json (the variant's complete scene), the design's standard
///                         outputs (solvers/report/design_report.h), and result.json — the
///                         completion marker, written last and atomically (status ok or failed
///                         with its one-line reason, the summary's numbers). A variant with a
///                         marker is done: a run started again runs only the variants without one.
/// DIR/summary.csv, DIR/pareto.csv, DIR/pareto.png   written once every variant is done.
///
/// Concurrency on one machine (run_sweep_local): J variants at a time, each in its own TBB arena
/// of max(1, T / J) threads, T = --threads (0: all hardware threads), J = --jobs (0: as many as
/// there are variants to run, at most T), within --memory (each variant claims its estimated
/// peak before its design starts, part of it on demand, and waits until the budget admits it:
/// host/sweep/memory_budget.h).
/// BLAS runs single-threaded in every variant (single_threaded_blas), so the summary is the same
/// bit for bit whatever the jobs, threads or ranks.
/// Across machines (run_sweep_mpi, built with CUTWORK_WITH_MPI): see sweep_mpi.h.
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "host/core/timer.h"
#include "host/scene/scene.h"
#include "host/sweep/sweep_results.h"
#include "host/sweep/sweep_spec.h"
#include "solvers/report/design_memory.h"

namespace cutwork::cli {

struct SweepOptions {
  std::string sweep;                 ///< the sweep file
  std::string out = "sweep-out";
  int threads = 0;                   ///< all threads of this process (0: hardware)
  int jobs = 0;                      ///< variants at a time (0: automatic)
  std::string memory;                ///< budget, e.g. 8G (empty: none)
  int iterations = 0;                ///< L-BFGS-B iterations per phase (0: the sweep's, else the scene's)
  std::string device = "cpu";
  bool quiet = false;
  bool list = false;                 ///< print the variants and stop
  bool no_discretisation_estimate = false;  ///< skip each design's discretisation estimate
};

/// Parses a memory size: a number with an optional K, M, G or T (powers of 1024) and an
/// optional B ("512M", "8G", "1.5GB"). Throws InputError naming `what`.
size_t parse_memory_size(const std::string& text, const std::string& what);


/// How a local sweep spreads `variants` variants over the threads (SweepOptions::threads, jobs).
struct SweepJobs {
  int threads = 1;  ///< T: all of this process's (0 in the options: the hardware's)
  int jobs = 1;     ///< J: variants at once (the options' jobs, or T; at most `variants`)
  int per_job = 1;  ///< each variant's arena: max(1, T / J)
};
SweepJobs sweep_jobs(const SweepOptions& options, size_t variants);

/// The sweep, expanded and validated, with its output folder.
struct SweepPlan {
  SweepSpec spec;
  std::vector<SweepVariant> variants;
  std::vector<Scene> scenes;         ///< parsed, one per variant
  std::filesystem::path out;
  int iterations = 0;                ///< resolved: --iterations, else the sweep file's
  bool discretisation_estimate = true;  ///< each design's report.json `discretisation`

  std::filesystem::path variant_dir(size_t i) const { return out / "variants" / variants[i].id; }
  std::vector<std::string> axis_pointers() const;
  /// Creates DIR and writes DIR/sweep.json, or checks that an existing one describes this sweep
  /// (throws InputError otherwise).
  void prepare_folder() const;
  /// The marker of variant i, when it has one.
  std::optional<VariantResult> marker(size_t i) const;
  /// Writes variant i's marker (atomic).
  void record(const VariantResult& r) const;
  /// Indices of the variants without a marker.
  std::vector<size_t> pending() const;
  /// summary.csv, pareto.csv and pareto.png from every variant's marker; returns the results.
  std::vector<VariantResult> write_tables() const;
};

/// Loads, expands and validates the sweep (nothing is written). Throws InputError naming the
/// variant and the scene's JSON path for the first variant that is not a valid scene.
SweepPlan plan_sweep(const SweepOptions& options);

/// What a variant asks of a memory budget (host/sweep/memory_budget.h), both optional.
struct VariantMemoryHooks {
  /// Once the design's meshes exist: what it holds throughout and may ask for more.
  std::function<void(const solvers::DesignMemory&)> reserve;
  /// Before the discretisation estimate builds its extra level (h/8), which asks for the more.
  std::function<void()> top_up;
};

/// Runs one variant into its folder: writes scene.json, designs it (solvers::design_into_folder).
/// Never throws for the variant's own failure: the result says failed, with a one-line reason.
VariantResult run_variant(const SweepPlan& plan, size_t i, const std::string& device,
                          const VariantMemoryHooks& memory = {});

/// The live display on a terminal: variants done / total, failed, running, elapsed and ETA
/// (silent when quiet or stdout is not a terminal). Thread-safe.
class SweepProgress {
 public:
  SweepProgress(bool quiet, size_t total, size_t already_done);
  ~SweepProgress();
  void started();
  void finished(bool ok);
  void finish();

 private:
  void draw();
  bool m_active;
  size_t m_total, m_done, m_failed = 0, m_running = 0, m_done_here = 0;
  Stopwatch m_clock;
  std::mutex m_mutex;
};

/// Limits BLAS (OpenBLAS, when it is the one loaded) to the calling thread: the sweep's
/// parallelism is its variants and their TBB kernels, and a summary must not depend on how the
/// variants were spread over threads, processes or machines (BLAS threads change the rounding).
void single_threaded_blas();

/// Runs the pending variants on this machine (policy in the file comment). Returns the number run.
size_t run_sweep_local(const SweepPlan& plan, const SweepOptions& options);

}  // namespace cutwork::cli
