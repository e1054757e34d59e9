// `cutwork render DIR`: re-draws the pictures of a finished design or simulation from its files
// (fields.vtu, cut.obj, report.json), with other views, fields or sizes.
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "host/cli/cli_common.h"
#include "host/cli/commands.h"
#include "host/cli/outputs.h"
#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/export/vtk_files.h"
#include "host/mesh/mesh_io.h"
#include "host/render/pictures.h"

namespace cutwork::cli {
namespace {
namespace fs = std::filesystem;

struct RenderCommandOptions {
  std::string dir;
  std::string out;  ///< default: DIR
  std::string views = "iso,front,top";
  std::string fields = "all";
  std::string size = "1200x420";
  std::string device = "auto";
  bool quiet = false;
};

std::vector<std::string> split(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

/// β (J/m²) and the scene's name from DIR/report.json, when it has them.
void read_report(const fs::path& file, render::DesignFields& f) {
  if (!fs::exists(file)) return;
  std::ifstream in(file);
  const nlohmann::json report = nlohmann::json::parse(in, nullptr, false);
  if (report.is_discarded()) throw InputError(file.string() + ": not valid JSON");
  if (report.contains("scene") && report["scene"].is_string()) f.title = report["scene"].get<std::string>();
  if (report.contains("structure") && report["structure"].contains("beta") && report["structure"]["beta"].is_number())
    f.beta = report["structure"]["beta"].get<double>();
}

void run_render(const RenderCommandOptions& opts) {
  const fs::path dir(opts.dir);
  const fs::path out = opts.out.empty() ? dir : fs::path(opts.out);
  render::PictureOptions po;
  std::tie(po.width, po.height) = parse_size(opts.size, "--size");
  po.views.clear();
  for (const std::string& v : split(opts.views)) po.views.push_back(render::parse_view(v));
  if (po.views.empty()) throw InputError("--view: no view given");
  std::vector<render::Field> fields;
  for (const std::string& f : split(opts.fields)) {
    if (f == "all")
      fields.insert(fields.end(), {render::Field::EnergyDensity, render::Field::FillRatio, render::Field::Design});
    else
      fields.push_back(render::parse_field(f));
  }

  if (!fs::exists(dir / "fields.vtu"))
    throw InputError(fmt::format("{}: no fields.vtu (is it the --out folder of cutwork design or simulate?)",
                                 dir.string()));
  const VtuContents vtu = read_vtu(dir / "fields.vtu");
  render::DesignFields f;
  f.title = dir.filename().string();
  read_report(dir / "report.json", f);
  f.sim_vertices = &vtu.vertices;
  f.sim_faces = &vtu.faces;
  if (auto it = vtu.fields.face.find("W"); it != vtu.fields.face.end()) f.energy_density = it->second;
  if (auto it = vtu.fields.face.find("alpha"); it != vtu.fields.face.end()) f.fill_ratio = it->second;
  std::optional<SurfaceMesh> cut;
  if (fs::exists(dir / "cut.obj")) cut = read_mesh(dir / "cut.obj");
  const SurfaceMesh* design = cut ? &*cut : nullptr;
  if (design != nullptr) {
    f.cut_vertices = &design->vertices();
    f.cut_faces = &design->faces();
  }
  // A field asked for by name must exist; `all` draws what there is.
  const bool all = opts.fields == "all";
  if (!all)
    for (render::Field field : fields) (void)render::draw_picture(f, field, {64, 48, {render::View::Top}, false, {}});
  const DeviceChoice device = choose_device(opts.device);
  po.rasterizer = device.rasterizer;
  ensure_directory(out);
  const std::vector<fs::path> written = render::write_pictures(out, f, fields, po);
  std::vector<std::string> names;
  for (const fs::path& p : written) names.push_back(p.filename().string());
  if (!opts.quiet)
    std::cerr << "cutwork render: wrote " << files_written(out, names) << " (drawn on " << device.rasterizer.kind_name()
              << (device.rasterizer.on_device() ? ": " + device.backend.name : std::string()) << ")\n";
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "render",
      "Draw the pictures of a finished design or simulation again from DIR/fields.vtu, cut.obj and report.json: "
      "render_W.png (energy density, the paper's colours: green at the threshold beta, red above, blue below), "
      "render_alpha.png (fill ratio) and render_design.png (the cut surface)");
  auto opts = std::make_shared<RenderCommandOptions>();
  cmd->add_option("DIR", opts->dir, "the --out folder of `cutwork design` or `cutwork simulate`")->required();
  cmd->add_option("--out,-o", opts->out, "where to write the pictures (default: DIR)");
  cmd->add_option("--view", opts->views, "comma-separated views, side by side: iso, front, top, side")
      ->capture_default_str();
  cmd->add_option("--field", opts->fields, "comma-separated pictures to draw: W, alpha, design, or all")
      ->capture_default_str();
  cmd->add_option("--size", opts->size, "picture size in pixels, WxH")->capture_default_str();
  add_device_option(*cmd, opts->device);
  cmd->add_flag("--quiet,-q", opts->quiet, "print nothing but errors");
  cmd->callback([opts] { run_render(*opts); });
}

}  // namespace cutwork::cli
