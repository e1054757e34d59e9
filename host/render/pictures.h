#pragma once
/// The pictures a designer looks at: render_W.png (energy density), render_alpha.png (fill
/// ratio) and render_design.png (the cut surface), each a row of standard views with a title
/// and, for the fields, a labelled colour bar. The views are drawn by PictureOptions::rasterizer
/// (rasterizer.h: the CPU twin, or the Vulkan twin offscreen on the --device's context); labels,
/// colour bars and PNG encoding by cairo. Headless: no window system.
///
/// Energy density follows the paper's figures (Figs. 6, 7): densities around the threshold β
/// are green, higher red, lower blue. The map is blue → cyan → green (at β) → yellow → red,
/// linear in W on [0, β] and on [β, W_top], W_top the field's maximum (at least β); without a
/// threshold (a simulation, a pattern-only design) green sits at W_top / 2. The colour bar
/// marks β and gives W in J/m². The fill ratio α runs from dark violet (0, all cut away)
/// through teal to yellow (1, solid).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "host/core/types.h"
#include "host/render/rasterizer.h"

namespace cutwork::render {

/// The energy-density colour of W for threshold beta (NaN: none) and top of scale w_top.
Rgb energy_colour(double W, double beta, double w_top);
/// The fill-ratio colour of alpha ∈ [0, 1].
Rgb fill_colour(double alpha);
/// The colour of the cut design's material (warm white, like sintered PA12).
Rgb material_colour();

enum class Field { EnergyDensity, FillRatio, Design };
/// "W", "alpha", "design"; file names render_<name>.png.
std::string_view to_string(Field field);
/// Accepts "W", "alpha", "design"; anything else throws InputError.
Field parse_field(std::string_view text);

/// What to draw.
struct PictureOptions {
  int width = 1200, height = 420;  ///< pixels of the whole picture
  std::vector<View> views = {View::Iso, View::Front, View::Top};
  /// Leave out views in which the surface is seen edge-on (its box's projected height or width
  /// below 2% of the other), e.g. a flat plate from the front — unless that leaves none.
  bool skip_edge_on_views = true;
  /// Which twin draws the views: the CPU twin by default; Rasterizer::for_backend(backend) for
  /// the one `--device` resolved to.
  Rasterizer rasterizer;
};

/// A design's (or a simulation's) fields to draw.
struct DesignFields {
  const RowMatX3d* sim_vertices = nullptr;  ///< the simulation mesh, #V×3
  const RowMatX3i* sim_faces = nullptr;     ///< #F×3
  Eigen::VectorXd energy_density;           ///< #F, W (J/m²); empty: no render_W
  Eigen::VectorXd fill_ratio;               ///< #F, α; empty: no render_alpha
  double beta = std::numeric_limits<double>::quiet_NaN();  ///< threshold β (J/m²), NaN: none
  const RowMatX3d* cut_vertices = nullptr;  ///< the cut surface; null: no render_design
  const RowMatX3i* cut_faces = nullptr;
  std::string title;                        ///< e.g. the scene's name
};

/// Draws one field's picture (a row of views, title, colour bar) into an image. Throws
/// InputError when the field is not available in `fields` or the size is below 64×48.
Image draw_picture(const DesignFields& fields, Field field, const PictureOptions& options);

/// PNG bytes of `image` (cairo).
std::string encode_png(const Image& image);
/// Decodes a PNG file (cairo) into an opaque image; throws InputError naming the file.
Image read_png(const std::filesystem::path& path);

/// Writes DIR/render_<field>.png for each of `fields_to_draw` available in `fields` (atomic),
/// returning the paths written.
std::vector<std::filesystem::path> write_pictures(const std::filesystem::path& dir, const DesignFields& fields,
                                                  const std::vector<Field>& fields_to_draw,
                                                  const PictureOptions& options);

}  // namespace cutwork::render
