#include "host/cli/cli_common.h"

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include <iostream>

#include "host/core/error.h"

namespace cutwork::cli {

void add_run_options(CLI::App& cmd, RunOptions& opts, const std::string& default_scene) {
  opts.scene = default_scene;
  cmd.add_option("SCENE", opts.scene,
                 "scene file (.json), built-in scene name (see `cutwork scenes`) or mesh file "
                 "(.obj .ply .off .stl)")
      ->capture_default_str();
  cmd.add_option("--out,-o", opts.out, "output directory (created if needed)")->capture_default_str();
  cmd.add_option("--threads", opts.threads, "number of CPU threads (0: all)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  cmd.add_flag("--quiet,-q", opts.quiet, "print nothing but errors");
}

std::unique_ptr<tbb::global_control> limit_threads(int threads) {
  if (threads <= 0) return nullptr;
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                               size_t(threads));
}

nlohmann::json timings_json(const Timings& timings) {
  nlohmann::json t = nlohmann::json::object();
  for (const auto& [name, seconds] : timings.entries()) t[name] = seconds;
  return t;
}

nlohmann::json base_report(const Scene& scene, const SceneMeshes& meshes, const Timings& timings) {
  nlohmann::json r;
  r["scene"] = scene.name;
  r["scene_source"] = scene_origin(scene);
  r["mesh"] = {{"vertices", meshes.base.num_vertices()},
               {"triangles", meshes.base.num_faces()},
               {"sim_vertices", meshes.sim.num_vertices()},
               {"sim_triangles", meshes.sim.num_faces()},
               {"sim_is_base", meshes.sim_is_base},
               {"map_max_distance", meshes.map.max_distance}};
  r["timings"] = timings_json(timings);
  return r;
}

void say(const RunOptions& opts, const std::string& line) {
  if (!opts.quiet) std::cerr << line << "\n";
}

}  // namespace cutwork::cli
