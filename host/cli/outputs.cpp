#include "host/cli/outputs.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <tuple>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/export/stencil_outlines.h"
#include "solvers/equilibrium/equilibrium_solver.h"

namespace cutwork::cli {

void add_output_options(CLI::App& cmd, OutputOptions& opts) {
  cmd.add_flag("--no-render", opts.no_render, "write no pictures (render_W.png, render_alpha.png, render_design.png)");
  cmd.add_option("--render-size", opts.render_size, "size of each picture in pixels, WxH")
      ->check(CLI::Validator(
          [](std::string& text) {
            try {
              parse_size(text, "size");
              return std::string();
            } catch (const InputError& e) {
              return std::string(e.what());
            }
          },
          "WxH", "picture size"))
      ->capture_default_str();
}

std::pair<int, int> parse_size(const std::string& text, const std::string& option) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 64 ||
      w > 8192 || h < 48 || h > 8192)
    throw InputError(fmt::format("{} '{}': expected WxH with W in [64, 8192] and H in [48, 8192], e.g. 1200x420",
                                 option, text));
  return {w, h};
}

DesignFileOptions design_file_options(const OutputOptions& opts, ProgressLine* progress,
                                      const render::Rasterizer& rasterizer) {
  DesignFileOptions o;
  o.render = !opts.no_render;
  std::tie(o.pictures.width, o.pictures.height) = parse_size(opts.render_size, "--render-size");
  o.pictures.rasterizer = rasterizer;
  if (progress != nullptr) o.progress = [progress](const std::string& s) { progress->stage(s); };
  return o;
}

DesignFileInputs simulation_file_inputs(const Scene& scene, const SceneMeshes& meshes, const Eigen::VectorXd& alpha,
                                        const Eigen::VectorXd& energy_density, const RowMatX3d& displacement,
                                        const CutSurface* cut) {
  DesignFileInputs in;
  in.title = scene.name;
  in.base = &meshes.base;
  in.sim = &meshes.sim;
  in.sim_fields.face = {{"alpha", alpha}, {"W", energy_density}};
  in.sim_fields.vertex = {{"displacement", displacement}};
  in.cut = cut;
  in.fabrication = false;
  in.thickness = scene.material.thickness;
  in.min_feature = scene.fabrication.min_feature;
  return in;
}

std::string files_written(const std::filesystem::path& dir, const std::vector<std::string>& names) {
  return fmt::format("{}/{{{}}}", dir.string(), fmt::join(names, ", "));
}

}  // namespace cutwork::cli
