#pragma once
/// The CLI side of the designer's files (host/export/design_files.h): the options every
/// pipeline command takes for them, the final design's displacement, and the summary of the
/// files written.
#include <filesystem>
#include <string>
#include <vector>

#include "host/cli/cli_common.h"
#include "host/export/design_files.h"
#include "solvers/optimize/design_pipeline.h"

namespace cutwork::cli {

/// `--no-render`, `--render-size WxH`.
struct OutputOptions {
  bool no_render = false;
  std::string render_size = "1200x420";
};
void add_output_options(CLI::App& cmd, OutputOptions& opts);

/// "WxH" → (W, H); throws InputError naming the option for anything else or sizes outside
/// [64, 8192] × [48, 8192].
std::pair<int, int> parse_size(const std::string& text, const std::string& option);

/// DesignFileOptions from the command line; stages are shown on `progress` when not null; the
/// pictures are drawn by `rasterizer` (DeviceChoice::rasterizer: the --device's twin).
DesignFileOptions design_file_options(const OutputOptions& opts, ProgressLine* progress,
                                      const render::Rasterizer& rasterizer);

/// The inputs of a simulation's files: fields.vtu (α, W, displacement) and the pictures (the
/// design picture shows `cut`, the design's stencils cut out, or the base surface when null).
DesignFileInputs simulation_file_inputs(const Scene& scene, const SceneMeshes& meshes, const Eigen::VectorXd& alpha,
                                        const Eigen::VectorXd& energy_density, const RowMatX3d& displacement,
                                        const CutSurface* cut);

/// "DIR/{a, b, c}": the files written into `dir`, for the final summary line.
std::string files_written(const std::filesystem::path& dir, const std::vector<std::string>& names);

}  // namespace cutwork::cli
