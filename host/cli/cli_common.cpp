#include "host/cli/cli_common.h"

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include <fmt/format.h>

#include "host/core/work_limits.h"
#include "solvers/conforming/simulation_mesh_choice.h"

namespace cutwork::cli {

void add_run_options(CLI::App& cmd, RunOptions& opts, const std::string& default_scene) {
  opts.scene = default_scene;
  cmd.add_option("SCENE", opts.scene,
                 "scene file (.json), built-in scene name (see `cutwork scenes`) or mesh file "
                 "(.obj .ply .off .stl; simulated on as many midpoint subdivisions of it as the uncut shell needs to "
                 "be within 2% of converged, mesh.sim_subdivisions in a scene)")
      ->capture_default_str();
  cmd.add_option("--out,-o", opts.out, "output directory (created if needed)")->capture_default_str();
  cmd.add_option("--threads", opts.threads, "number of CPU threads for everything the run does: TBB, and the BLAS and OpenMP threads of the factorisations (0: all)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  cmd.add_flag("--quiet,-q", opts.quiet, "print nothing but errors");
  add_limit_options(cmd);
  cmd.add_flag("--wait", opts.wait,
               "when another cutwork run is writing into the output directory, wait for it to finish "
               "(default: fail at once)");
}

void add_limit_options(CLI::App& cmd) {
  WorkLimits& limits = work_limits();
  cmd.add_option("--max-faces", limits.max_faces,
                 "refuse a base or simulation mesh with more faces than this (estimated from the edge length "
                 "for generated meshes, counted for mesh files)")
      ->check(CLI::Range(1, 1'000'000'000))
      ->capture_default_str();
  cmd.add_option("--max-stencils", limits.max_stencils,
                 "refuse a pattern whose estimated stencil count (from pattern.count, or pattern.scale and the "
                 "surface's area) is larger than this")
      ->check(CLI::Range(1, 1'000'000'000))
      ->capture_default_str();
  cmd.add_option("--max-factor-gb", limits.max_factor_gb,
                 "refuse a simulation mesh whose stiffness factor would take more memory than this (GB, from "
                 "CHOLMOD's symbolic analysis before any factorisation)")
      ->check(finite_number())
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
}

CLI::Validator finite_number() {
  return CLI::Validator(
      [](std::string& text) {
        double value = 0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value))
          return "Value " + text + " is not a finite number";
        return std::string();
      },
      "FINITE", "finite number");
}

std::unique_ptr<OutputSet> open_output_set(const RunOptions& opts) {
  return std::make_unique<OutputSet>(opts.out, opts.wait, [&opts] {
    say(opts, "cutwork: waiting for another cutwork run writing into " + opts.out + " to finish");
  });
}

namespace {
std::string& hint_storage() {
  static std::string hint;
  return hint;
}
}  // namespace

void set_solve_error_hint(std::string hint) { hint_storage() = std::move(hint); }
const std::string& solve_error_hint() { return hint_storage(); }

namespace {
template <typename F>
auto timed(Timings& timings, const char* name, F&& f) {
  Stopwatch sw;
  auto value = f();
  timings.add(name, sw.seconds());
  return value;
}
}  // namespace

LoadedScene::LoadedScene(const RunOptions& opts, Timings& timings)
    : scene(timed(timings, "scene",
                  [&] {
                    std::string notice;
                    Scene s = load_scene(opts.scene, &notice);
                    if (!notice.empty()) notes.push_back(notice);
                    return s;
                  })),
      meshes(timed(timings, "meshes",
                   [&] {
                     SceneMeshes m = build_scene_meshes(scene);
                     if (scene.from_plain_mesh) set_solve_error_hint(metres_hint(m.base));
                     for (const std::string& n : model_notes(scene, m)) notes.push_back(n);
                     const std::string note = solvers::choose_simulation_mesh(scene, m);
                     if (!note.empty()) notes.push_back(note);
                     return m;
                   })),
      load_case(timed(timings, "load_case", [&] { return resolve_load_case(scene, meshes.sim); })) {}

std::unique_ptr<tbb::global_control> limit_threads(int threads) {
  if (threads <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               size_t(threads));
}

void say(const RunOptions& opts, const std::string& line) {
  if (!opts.quiet) std::cerr << line << "\n";
}

void add_device_option(CLI::App& cmd, std::string& device) {
  cmd.add_option("--device", device,
                 "where the clip and fill kernels and the pictures' rasteriser run: cpu (TBB), vulkan (a GPU, else Mesa's lavapipe; "
                 "CUTWORK_VK_DEVICE picks one), or auto (a GPU when there is one, else the CPU; a CPU "
                 "implementation of Vulkan such as lavapipe is left to --device vulkan)")
      ->check(CLI::IsMember({"cpu", "vulkan", "auto"}, CLI::ignore_case))
      ->capture_default_str();
}

DeviceChoice choose_device(const std::string& device, bool pictures) {
  DeviceChoice c;
  c.backend = select_compute_backend(parse_device_request(device), &std::cerr);
  c.fill = FillRatioOptions::for_backend(c.backend);
  c.rasterizer = render::Rasterizer::for_backend(c.backend);
  c.report = {{"kind", std::string(c.backend.kind_name())}, {"name", c.backend.name}, {"driver", c.backend.driver},
              {"requested", device}, {"reason", c.backend.reason},
              {"render", pictures ? std::string(c.rasterizer.kind_name()) : std::string("none")}};
  if (!c.backend.fallback_reason.empty()) c.report["fallback_reason"] = c.backend.fallback_reason;
  return c;
}

ProgressLine::ProgressLine(const RunOptions& opts)
    : m_active(!opts.quiet && isatty(fileno(stdout))), m_log(!opts.quiet && !m_active) {
  // CUTWORK_PROGRESS_SECONDS changes the interval of the plain lines (tests use 0: every update).
  if (const char* s = std::getenv("CUTWORK_PROGRESS_SECONDS")) m_log_interval = std::max(0.0, std::atof(s));
}

ProgressLine::~ProgressLine() { finish(); }

void ProgressLine::update(const std::string& phase, const solvers::PatternProgress& p) {
  if (m_log) {
    if (m_since_draw.seconds() < m_log_interval) return;
  } else if (!m_active || (m_dirty && m_since_draw.seconds() < 0.1)) {
    return;
  }
  m_since_draw.restart();
  const std::string w = std::isfinite(p.W_max) ? fmt::format("{:.4g} J/m^2", p.W_max) : std::string("-");
  const std::string line =
      p.stage == "initialise"
          ? fmt::format("{:<9} initialised: {} stencils  {:.1f} s", phase, p.stencils, m_clock.seconds())
          : fmt::format("{:<9} round {:>3}  iteration {:>5}  J {:>12.6g}  |grad J| {:>10.3e}  W_max {:<14} "
                        "{} stencils  {:.1f} s",
                        phase, p.round, p.iteration, p.objective, p.gradient_norm, w, p.stencils, m_clock.seconds());
  if (m_log) {
    std::cerr << "cutwork: " << line << "\n" << std::flush;
    return;
  }
  std::cout << "\r\x1b[K" << line << std::flush;
  m_dirty = true;
}

void ProgressLine::stage(const std::string& name) {
  if (!m_active) return;
  m_since_draw.restart();
  std::cout << fmt::format("\r\x1b[K{} …  {:.1f} s", name, m_clock.seconds()) << std::flush;
  m_dirty = true;
}

void ProgressLine::finish() {
  if (m_active && m_dirty) std::cout << "\r\x1b[K" << std::flush;
  m_dirty = false;
}

}  // namespace cutwork::cli
