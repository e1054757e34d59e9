#include "host/cli/sweep_runner.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <iostream>
#include <thread>

#include <fmt/format.h>

#include "host/cli/cli_common.h"
#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/core/json_io.h"
#include "host/sweep/memory_budget.h"
#include "host/sweep/pareto_plot.h"
#include "host/pattern/pattern_context.h"
#include "solvers/report/design_memory.h"
#include "solvers/report/design_report.h"

namespace cutwork::cli {

namespace fs = std::filesystem;
using nlohmann::json;

size_t parse_memory_size(const std::string& text, const std::string& what) {
  size_t pos = 0;
  double v = 0;
  try {
    v = std::stod(text, &pos);
  } catch (const std::exception&) {
    pos = 0;
  }
  std::string unit = text.substr(pos);
  if (!unit.empty() && (unit.back() == 'B' || unit.back() == 'b')) unit.pop_back();
  double scale = 0;
  if (unit.empty()) scale = 1;
  else if (unit == "K" || unit == "k") scale = 1024.0;
  else if (unit == "M" || unit == "m") scale = 1024.0 * 1024;
  else if (unit == "G" || unit == "g") scale = 1024.0 * 1024 * 1024;
  else if (unit == "T" || unit == "t") scale = 1024.0 * 1024 * 1024 * 1024;
  if (pos == 0 || scale == 0 || !std::isfinite(v) || v <= 0)
    throw InputError(fmt::format("{}: '{}' is not a memory size (a positive number with K, M, G or T, e.g. 8G)",
                                 what, text));
  return size_t(v * scale);
}

std::vector<std::string> SweepPlan::axis_pointers() const {
  std::vector<std::string> p;
  for (const SweepAxis& a : spec.axes) p.push_back(a.pointer);
  return p;
}

namespace {

json folder_description(const SweepPlan& plan) {
  json variants = json::array();
  for (const SweepVariant& v : plan.variants) variants.push_back({{"id", v.id}, {"values", v.values}});
  return {{"name", plan.spec.name},
          {"sweep", plan.spec.origin},
          {"axes", plan.axis_pointers()},
          {"design", {{"iterations", plan.iterations}, {"phases", plan.spec.phases}}},
          {"variants", variants}};
}

}  // namespace

void SweepPlan::prepare_folder() const {
  const json mine = folder_description(*this);
  const fs::path file = out / "sweep.json";
  std::error_code ec;
  if (fs::exists(file, ec)) {
    const json theirs = read_json_file(file);
    const auto same = [&](const char* key) { return theirs.contains(key) && theirs[key] == mine[key]; };
    if (!same("axes") || !same("design") || !same("variants"))
      throw InputError(fmt::format("{}: holds another sweep (its axes, design settings or variants differ from {}'s); "
                                   "choose another --out or remove it",
                                   out.string(), spec.origin));
    return;
  }
  ensure_directory(out / "variants");
  write_json_atomic(file, mine);
}

std::optional<VariantResult> SweepPlan::marker(size_t i) const {
  const fs::path file = variant_dir(i) / "result.json";
  std::error_code ec;
  if (!fs::exists(file, ec)) return std::nullopt;
  VariantResult r = VariantResult::from_json(read_json_file(file), file.string());
  if (r.id != variants[i].id || r.values != variants[i].values)
    throw InputError(file.string() + ": belongs to another variant than " + variants[i].id);
  return r;
}

void SweepPlan::record(const VariantResult& r) const {
  const auto it = std::find_if(variants.begin(), variants.end(), [&](const SweepVariant& v) { return v.id == r.id; });
  const fs::path dir = variant_dir(size_t(it - variants.begin()));
  ensure_directory(dir);
  write_json_atomic(dir / "result.json", r.to_json());
}

std::vector<size_t> SweepPlan::pending() const {
  std::vector<size_t> p;
  for (size_t i = 0; i < variants.size(); ++i)
    if (!marker(i)) p.push_back(i);
  return p;
}

std::vector<VariantResult> SweepPlan::write_tables() const {
  std::vector<VariantResult> results;
  for (size_t i = 0; i < variants.size(); ++i)
    if (auto m = marker(i)) results.push_back(std::move(*m));
  const ParetoFronts fronts = sweep_pareto_fronts(results);
  write_file_atomic(out / "summary.csv", summary_csv(axis_pointers(), results));
  write_file_atomic(out / "pareto.csv", pareto_csv(axis_pointers(), results, fronts));
  write_pareto_png(out / "pareto.png", spec.name, results, fronts);
  return results;
}

SweepPlan plan_sweep(const SweepOptions& options) {
  SweepPlan plan;
  plan.spec = load_sweep(options.sweep);
  plan.variants = expand_sweep(plan.spec, &plan.scenes);
  // The stencil shapes are validated with the scene (kinds and their parameters).
  for (size_t i = 0; i < plan.variants.size(); ++i) {
    try {
      (void)scene_stencil_library(plan.scenes[i]);
    } catch (const InputError& e) {
      throw InputError(plan.spec.origin + ": variant " + plan.variants[i].id + " (" +
                       describe_values(plan.spec, plan.variants[i].values) + "): " + e.what());
    }
  }
  plan.out = options.out;
  plan.iterations = options.iterations > 0 ? options.iterations : plan.spec.iterations;
  plan.discretisation_estimate = !options.no_discretisation_estimate;
  return plan;
}

namespace {

std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

}  // namespace

VariantResult run_variant(const SweepPlan& plan, size_t i, const std::string& device,
                          const VariantMemoryHooks& memory) {
  const SweepVariant& v = plan.variants[i];
  VariantResult r;
  r.id = v.id;
  r.values = v.values;
  Stopwatch clock;
  try {
    const fs::path dir = plan.variant_dir(i);
    ensure_directory(dir);
    write_json_atomic(dir / "scene.json", v.scene);
    solvers::DesignRunInfo info;
    info.discretisation_estimate = plan.discretisation_estimate;
    if (memory.top_up) info.before_extra_level = [&](int, size_t) { memory.top_up(); };
    solvers::DesignOptions o;
    o.structure = plan.spec.phases == "pattern,structure";
    if (plan.iterations > 0) o.pattern_iterations = o.structure_iterations = plan.iterations;
    Stopwatch sw;
    const DeviceChoice d = choose_device(device);
    info.device = d.report;
    o.fill = d.fill;
    info.timings.add("device", sw.seconds());
    const json report = solvers::design_into_folder(plan.scenes[i], dir, o, std::move(info), [&](const SceneMeshes& m) {
      if (memory.reserve) memory.reserve(solvers::estimate_design_memory(m, plan.discretisation_estimate));
    });
    r.take_report(report);
    r.ok = true;
  } catch (const Error& e) {
    r.reason = one_line(e.what());
  } catch (const std::bad_alloc&) {
    r.reason = "out of memory";
  } catch (const std::exception& e) {
    r.reason = one_line(std::string("internal error: ") + e.what());
  }
  r.seconds = clock.seconds();
  return r;
}

SweepProgress::SweepProgress(bool quiet, size_t total, size_t already_done)
    : m_active(!quiet && isatty(fileno(stdout))), m_total(total), m_done(already_done) {
  std::lock_guard lock(m_mutex);
  draw();
}

SweepProgress::~SweepProgress() { finish(); }

void SweepProgress::started() {
  std::lock_guard lock(m_mutex);
  ++m_running;
  draw();
}

void SweepProgress::finished(bool ok) {
  std::lock_guard lock(m_mutex);
  --m_running;
  ++m_done;
  ++m_done_here;
  m_failed += ok ? 0 : 1;
  draw();
}

void SweepProgress::draw() {
  if (!m_active) return;
  const double t = m_clock.seconds();
  const size_t left = m_total - m_done;
  const std::string eta = m_done_here == 0 ? std::string("-") : fmt::format("{:.0f} s", t / double(m_done_here) * double(left));
  std::cout << fmt::format("\r\x1b[Ksweep: {}/{} variants done, {} failed, {} running; {:.0f} s, ETA {}", m_done,
                           m_total, m_failed, m_running, t, eta)
            << std::flush;
}

void SweepProgress::finish() {
  std::lock_guard lock(m_mutex);
  if (m_active) std::cout << "\r\x1b[K" << std::flush;
  m_active = false;
}


void single_threaded_blas() {
  // CHOLMOD's supernodal factorisation calls BLAS; OpenBLAS keeps its own thread pool, which
  // concurrent variants would oversubscribe, and whose size changes the rounding of the factor.
  // Looked up at run time: Debian may provide BLAS by another library, which needs nothing.
  for (const char* name : {"openblas_set_num_threads", "goto_set_num_threads"})
    if (void* f = dlsym(RTLD_DEFAULT, name)) {
      reinterpret_cast<void (*)(int)>(f)(1);
      return;
    }
}

SweepJobs sweep_jobs(const SweepOptions& options, size_t variants) {
  SweepJobs j;
  j.threads = options.threads > 0 ? options.threads : std::max(1, int(std::thread::hardware_concurrency()));
  j.jobs = std::max(1, std::min({options.jobs > 0 ? options.jobs : j.threads, int(variants)}));
  j.per_job = std::max(1, j.threads / j.jobs);
  return j;
}

size_t run_sweep_local(const SweepPlan& plan, const SweepOptions& options) {
  single_threaded_blas();
  const std::vector<size_t> todo = plan.pending();
  SweepProgress progress(options.quiet, plan.variants.size(), plan.variants.size() - todo.size());
  if (todo.empty()) return 0;
  const auto [T, J, per_job] = sweep_jobs(options, todo.size());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(std::max(T, J * per_job)));
  // The process and one calibration at a time are held once, whatever the variants.
  const size_t total = options.memory.empty() ? 0 : parse_memory_size(options.memory, "--memory");
  const size_t held = solvers::kProcessMemory + solvers::calibration_memory(plan.scenes, per_job);
  if (total > 0 && total <= held && !options.quiet)
    std::cerr << fmt::format("note: --memory {} is not more than the process and one stiffness calibration hold "
                             "({:.2f} GB): the variants run one at a time\n",
                             options.memory, double(held) / 1e9);
  MemoryBudget budget(total, held);
  std::atomic<size_t> next{0};
  std::mutex record_mutex;
  tbb::task_arena outer(J, 1);
  outer.execute([&] {
    tbb::task_group jobs;
    for (int j = 0; j < J; ++j)
      jobs.run([&] {
        tbb::task_arena inner(per_job, 1);
        for (size_t k = next++; k < todo.size(); k = next++) {
          std::optional<MemoryBudget::Claim> claim;
          VariantMemoryHooks hooks;
          hooks.reserve = [&](const solvers::DesignMemory& m) { claim = budget.reserve(m.held, m.on_demand); };
          hooks.top_up = [&] {
            if (claim) budget.top_up(*claim);
          };
          progress.started();
          const VariantResult r = inner.execute([&] { return run_variant(plan, todo[k], options.device, hooks); });
          if (claim) budget.release(*claim);
          {
            std::lock_guard lock(record_mutex);
            plan.record(r);
          }
          progress.finished(r.ok);
        }
      });
    jobs.wait();
  });
  return todo.size();
}

}  // namespace cutwork::cli
