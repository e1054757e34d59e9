#pragma once
/// A plain CPU rasteriser for headless pictures: orthographic standard views of a triangle
/// mesh, flat-shaded per face, z-buffered, 2×2 supersampled, TBB-parallel over image bands.
/// The result does not depend on the number of threads (each pixel sees the triangles in face
/// order; the nearest wins, ties to the lower face index).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "host/core/types.h"

namespace cutwork::render {

/// Standard views, z up: `iso` from (+x, −y, +z) above the front right, `front` from −y,
/// `top` from +z (y up in the picture), `side` from +x.
enum class View { Iso, Front, Top, Side };
std::string_view to_string(View view);
/// "iso", "front", "top", "side"; anything else throws InputError naming the accepted values.
View parse_view(std::string_view text);

struct Rgb {
  double r = 0, g = 0, b = 0;  ///< each in [0, 1]
};

/// An opaque image, row-major, each pixel 0xFFRRGGBB (cairo's ARGB32/RGB24 layout).
struct Image {
  int width = 0, height = 0;
  std::vector<uint32_t> pixels;
  uint32_t at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

/// How a view maps the scene to the picture: the scene's box `frame` is centred and scaled to
/// fill `fill` of the picture's smaller relative extent (so the same box gives the same scale
/// for every field of a design).
struct ViewSetup {
  View view = View::Iso;
  Eigen::AlignedBox3d frame;
  double fill = 0.9;
  Rgb background{1, 1, 1};
};

/// The projected extent of `box` in `view`: (width, height) in metres.
Eigen::Vector2d projected_extent(View view, const Eigen::AlignedBox3d& box);

/// Renders triangles `faces` (#F×3) on `vertices` (#V×3, m), face f in colour `face_colours[f]`
/// shaded by |n_f · l| (two-sided; l between the viewer and the zenith), into a width×height
/// image (≥ 1 each). Throws InputError on size mismatches.
Image rasterize(const RowMatX3d& vertices, const RowMatX3i& faces, const std::vector<Rgb>& face_colours,
                const ViewSetup& setup, int width, int height);

}  // namespace cutwork::render
