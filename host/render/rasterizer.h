#pragma once
/// The rasteriser for headless pictures: orthographic standard views of a triangle mesh,
/// flat-shaded per face, z-buffered, 2×2 supersampled. Two twins behind one interface
/// (Rasterizer):
///  - the CPU twin (`rasterize`, this file): TBB-parallel over image bands;
///  - the Vulkan twin (`RasterizerVk`, rasterizer_vk.h, shader raster.comp): a compute-shader
///    rasteriser on the project's Vulkan context (any device with a compute queue and
///    shaderFloat64, lavapipe included).
/// Both follow the same rules, so their pictures agree (tests/host/render/rasterizer_vk_test.cpp):
/// the triangle set-up (projection, shading) is the same arithmetic in double in both; a sample
/// at a pixel's centre is covered when all three barycentric weights are ≥ 0; its depth is the
/// interpolated depth rounded to float; the nearest triangle wins, ties to the lower face index.
/// The result therefore does not depend on the number of threads or on GPU scheduling.
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "host/core/types.h"
#include "host/vulkan/backend.h"

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

/// Samples per pixel along x and along y (the image is the box-filtered average).
constexpr int kSupersample = 2;

/// How both twins map the scene into the supersampled image (sw × sh samples): a point p goes
/// to x = sw/2 + scale·(p − centre)·right, y = sh/2 − scale·(p − centre)·up, depth
/// (p − centre)·forward (larger is farther); a face is shaded by 0.35 + 0.65·|n̂ · light|.
struct Projection {
  Vec3 centre, right, up, forward, light;
  double scale = 1;  ///< samples per metre
  int sw = 0, sh = 0;
};
Projection projection_for(const ViewSetup& setup, int width, int height);

/// A colour as 0xFFRRGGBB, each channel ⌊255·clamp(v, 0, 1) + ½⌋ (the shader's formula too).
uint32_t pack(const Rgb& colour);

/// Renders triangles `faces` (#F×3) on `vertices` (#V×3, m), face f in colour `face_colours[f]`
/// shaded by |n_f · l| (two-sided; l between the viewer and the zenith), into a width×height
/// image (≥ 1 each). The CPU twin. Throws InputError on size mismatches, face indices out of
/// range or vertices that are not finite.
Image rasterize(const RowMatX3d& vertices, const RowMatX3i& faces, const std::vector<Rgb>& face_colours,
                const ViewSetup& setup, int width, int height);

class RasterizerVk;

/// The rasteriser twins behind one interface: what draws the pictures' panels. A default
/// Rasterizer is the CPU twin; `for_backend` follows `--device` (host/vulkan/backend.h): the
/// Vulkan twin on the backend's context when it resolved to Vulkan, else the CPU twin. The
/// Vulkan twin builds its pipeline on the first call and keeps it and its device buffers for
/// later calls (copies of a Rasterizer share them). One thread at a time, like the Context.
/// No Vulkan types here: this header compiles with or without CUTWORK_WITH_VULKAN.
class Rasterizer {
 public:
  Rasterizer() = default;
  /// Throws DeviceError for a Vulkan backend without a context, or in a build without Vulkan.
  static Rasterizer for_backend(const ComputeBackend& backend);

  /// "cpu" or "vulkan": which twin draws (report.json's device.render).
  std::string_view kind_name() const { return m_vk ? "vulkan" : "cpu"; }
  bool on_device() const { return m_vk != nullptr; }

  /// The same contract as `rasterize` above, on this twin.
  Image rasterize(const RowMatX3d& vertices, const RowMatX3i& faces, const std::vector<Rgb>& face_colours,
                  const ViewSetup& setup, int width, int height) const;

 private:
  std::shared_ptr<RasterizerVk> m_vk;  ///< null: the CPU twin
};

}  // namespace cutwork::render
