// `cutwork sweep SWEEP.json --out DIR`: batch design-space exploration — every variant of a sweep
// file as a full design, concurrently (TBB) or across MPI ranks; summary and Pareto outputs.
#include <CLI/CLI.hpp>

#include <iostream>

#include <fmt/format.h>

#include "host/cli/commands.h"
#include "host/cli/sweep_mpi.h"
#include "host/cli/sweep_runner.h"
#include "solvers/report/design_memory.h"

namespace cutwork::cli {

namespace {

/// The variants, one line each; with --memory also what each would reserve of it (its meshes are
/// built for that) and what the sweep sets aside once (docs/SWEEP.md "Memory").
void print_variants(const SweepPlan& plan, const SweepOptions& opts) {
  const bool memory = !opts.memory.empty();
  for (size_t i = 0; i < plan.variants.size(); ++i) {
    const SweepVariant& v = plan.variants[i];
    std::cout << v.id << "  " << describe_values(plan.spec, v.values);
    if (memory) {
      const SceneMeshes meshes = build_scene_meshes(plan.scenes[i]);
      const solvers::DesignMemory m = solvers::estimate_design_memory(meshes, plan.discretisation_estimate);
      std::cout << fmt::format("  (reserves {:.0f} MB{}: {} base, {} simulated triangles)", double(m.held) / 1e6,
                               m.on_demand > 0 ? fmt::format(" and {:.0f} MB more if its discretisation estimate "
                                                             "solves h/8", double(m.on_demand) / 1e6)
                                               : std::string(),
                               meshes.base.num_faces(), meshes.sim.num_faces());
    }
    std::cout << "\n";
  }
  if (memory) {
    const SweepJobs jobs = sweep_jobs(opts, plan.variants.size());
    std::cout << fmt::format("set aside once: {:.0f} MB (the process and one stiffness calibration on {} thread(s) "
                             "per variant) of --memory {}\n",
                             double(solvers::kProcessMemory + solvers::calibration_memory(plan.scenes, jobs.per_job)) / 1e6,
                             jobs.per_job, opts.memory);
  }
}

void report_done(const SweepPlan& plan, const SweepOptions& opts, size_t ran, const std::vector<VariantResult>& results) {
  if (opts.quiet) return;
  size_t failed = 0;
  for (const VariantResult& r : results) failed += r.ok ? 0 : 1;
  std::cerr << fmt::format("cutwork sweep: {}: {} variants ({} run now, {} done before), {} failed; wrote {}, "
                           "pareto.csv, pareto.png\n",
                           plan.spec.name, plan.variants.size(), ran, plan.variants.size() - ran, failed,
                           (plan.out / "summary.csv").string());
  for (const VariantResult& r : results)
    if (!r.ok) std::cerr << fmt::format("  {} failed: {}\n", r.id, r.reason);
}

void run_sweep_command(const SweepOptions& opts) {
  if (!opts.memory.empty()) (void)parse_memory_size(opts.memory, "--memory");
  MpiSession mpi;  // a no-op unless built with MPI and started by mpirun with more than one rank
  SweepPlan plan = mpi.guard([&] { return plan_sweep(opts); });
  if (opts.list) {
    if (mpi.rank() == 0) print_variants(plan, opts);
    return;
  }
  if (mpi.size() > 1) {
    try {
      const size_t ran = run_sweep_mpi(mpi, plan, opts);
      if (mpi.rank() == 0) report_done(plan, opts, ran, plan.write_tables());
    } catch (const std::exception& e) {
      if (mpi.failed_collectively()) throw;  // every rank stopped alike: one line from rank 0
      mpi.abort(e.what());
    }
    return;
  }
  plan.prepare_folder();
  const size_t ran = run_sweep_local(plan, opts);
  report_done(plan, opts, ran, plan.write_tables());
}

}  // namespace

void add_sweep_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "sweep",
      "Batch design-space exploration: run every variant of a sweep file (docs/SWEEP.md) as a full design into "
      "DIR/variants/<id>/ and write DIR/summary.csv, DIR/pareto.csv and DIR/pareto.png. Variants run concurrently "
      "(--jobs variants x max(1, threads/jobs) threads each); a run started again runs only what is missing; under "
      "`mpirun -n N` rank 0 hands variants out to all ranks");
  auto opts = std::make_shared<SweepOptions>();
  cmd->add_option("SWEEP", opts->sweep, "sweep file (.json; format: docs/SWEEP.md)")->required();
  cmd->add_option("--out,-o", opts->out, "output directory (created if needed)")->capture_default_str();
  cmd->add_option("--threads", opts->threads, "CPU threads of this process, shared by its variants (0: all)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  cmd->add_option("--jobs,-j", opts->jobs,
                  "variants at a time (0: as many as there are variants to run, at most --threads); each gets "
                  "max(1, threads/jobs) threads. Under MPI every rank runs one variant at a time")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  cmd->add_option("--memory", opts->memory,
                  "peak memory budget of the process, e.g. 8G: the process and one stiffness calibration are set "
                  "aside, and each variant reserves its estimated peak from the rest before its design starts "
                  "(docs/SWEEP.md \"Memory\"; default: no budget)");
  cmd->add_option("--iterations", opts->iterations,
                  "L-BFGS-B iterations per phase for every variant (0: the sweep file's design.iterations, else "
                  "the scene's)")
      ->check(CLI::Range(0, 1000000))
      ->capture_default_str();
  cmd->add_option("--device", opts->device, "where the clip and fill kernels run: cpu, vulkan or auto")
      ->check(CLI::IsMember({"cpu", "vulkan", "auto"}, CLI::ignore_case))
      ->capture_default_str();
  cmd->add_flag("--list", opts->list, "print the variants (id and axis values) and stop; nothing is written (with --memory also what "
                "each would reserve and what is set aside)");
  cmd->add_flag("--no-discretisation-estimate", opts->no_discretisation_estimate,
                "skip each design's solves at half and a quarter of the simulation edge length that say how far "
                "from converged its numbers are (report.json `discretisation`): faster sweeps");
  cmd->add_flag("--quiet,-q", opts->quiet, "print nothing but errors");
  cmd->callback([opts] { run_sweep_command(*opts); });
}

}  // namespace cutwork::cli
