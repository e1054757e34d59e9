#include "host/render/rasterizer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "host/core/error.h"

namespace cutwork::render {

std::string_view to_string(View view) {
  switch (view) {
    case View::Iso:
      return "iso";
    case View::Front:
      return "front";
    case View::Top:
      return "top";
    case View::Side:
      return "side";
  }
  return "iso";
}

View parse_view(std::string_view text) {
  for (View v : {View::Iso, View::Front, View::Top, View::Side})
    if (text == to_string(v)) return v;
  throw InputError(fmt::format("unknown view '{}': expected iso, front, top or side", text));
}

namespace {

constexpr int kSupersample = 2;

/// Orthonormal camera axes: `right`, `up` span the picture; `forward` points into the scene.
struct Camera {
  Vec3 right, up, forward, light;
};

Camera camera_for(View view) {
  Vec3 forward = Vec3::UnitY(), up_hint = Vec3::UnitZ();
  switch (view) {
    case View::Iso:
      forward = -Vec3(1, -1.2, 0.9).normalized();
      break;
    case View::Front:
      forward = Vec3::UnitY();
      break;
    case View::Top:
      forward = -Vec3::UnitZ();
      up_hint = Vec3::UnitY();
      break;
    case View::Side:
      forward = -Vec3::UnitX();
      break;
  }
  Camera c;
  c.forward = forward;
  c.right = forward.cross(up_hint).normalized();
  c.up = c.right.cross(forward);
  c.light = (-forward + 0.6 * Vec3::UnitZ() + 0.3 * c.right).normalized();
  return c;
}

}  // namespace

Eigen::Vector2d projected_extent(View view, const Eigen::AlignedBox3d& box);

namespace {

/// A triangle in supersampled pixel coordinates with its depth and shaded colour.
struct ScreenTriangle {
  double x[3], y[3], z[3];
  double min_y, max_y;
  uint32_t colour;
};

uint32_t pack(const Rgb& c) {
  auto byte = [](double v) { return uint32_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); };
  return 0xFF000000u | (byte(c.r) << 16) | (byte(c.g) << 8) | byte(c.b);
}

std::vector<ScreenTriangle> project(const RowMatX3d& V, const RowMatX3i& F, const std::vector<Rgb>& colours,
                                    const ViewSetup& setup, const Camera& cam, int sw, int sh) {
  // Scale: the frame box's projected extent fills `fill` of the picture.
  const Vec3 centre = setup.frame.center();
  const Eigen::Vector2d extent = projected_extent(setup.view, setup.frame);
  const double ex = extent.x() / 2, ey = extent.y() / 2;
  const double scale = setup.fill * std::min(sw / (2 * std::max(ex, 1e-300)), sh / (2 * std::max(ey, 1e-300)));
  std::vector<ScreenTriangle> tris(size_t(F.rows()));
  tbb::parallel_for(Eigen::Index(0), F.rows(), [&](Eigen::Index f) {
    ScreenTriangle& t = tris[size_t(f)];
    Vec3 p[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = V.row(F(f, k)).transpose();
      const Vec3 d = p[k] - centre;
      t.x[k] = 0.5 * sw + scale * d.dot(cam.right);
      t.y[k] = 0.5 * sh - scale * d.dot(cam.up);
      t.z[k] = d.dot(cam.forward);
    }
    t.min_y = std::min({t.y[0], t.y[1], t.y[2]});
    t.max_y = std::max({t.y[0], t.y[1], t.y[2]});
    const Vec3 n = (p[1] - p[0]).cross(p[2] - p[0]);
    const double len = n.norm();
    const double lambert = len > 0 ? std::abs(n.dot(cam.light)) / len : 0.0;
    const double shade = 0.35 + 0.65 * lambert;
    const Rgb& c = colours[size_t(f)];
    t.colour = pack({c.r * shade, c.g * shade, c.b * shade});
  });
  return tris;
}

/// Rasterises every triangle into rows [y0, y1) of the supersampled buffers.
void rasterize_band(const std::vector<ScreenTriangle>& tris, int sw, int y0, int y1, std::vector<float>& depth,
                    std::vector<uint32_t>& colour) {
  for (const ScreenTriangle& t : tris) {
    if (t.max_y < y0 || t.min_y >= y1) continue;
    const double area = (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.x[2] - t.x[0]) * (t.y[1] - t.y[0]);
    if (std::abs(area) < 1e-12) continue;
    const int xa = std::max(0, int(std::floor(std::min({t.x[0], t.x[1], t.x[2]}))));
    const int xb = std::min(sw - 1, int(std::ceil(std::max({t.x[0], t.x[1], t.x[2]}))));
    const int ya = std::max(y0, int(std::floor(t.min_y)));
    const int yb = std::min(y1 - 1, int(std::ceil(t.max_y)));
    for (int y = ya; y <= yb; ++y) {
      const double py = y + 0.5;
      for (int x = xa; x <= xb; ++x) {
        const double px = x + 0.5;
        // Barycentric weights from edge functions, signed by the triangle's orientation.
        double w[3];
        for (int k = 0; k < 3; ++k) {
          const int i = (k + 1) % 3, j = (k + 2) % 3;
          w[k] = ((t.x[j] - t.x[i]) * (py - t.y[i]) - (t.y[j] - t.y[i]) * (px - t.x[i])) / area;
        }
        if (w[0] < 0 || w[1] < 0 || w[2] < 0) continue;
        const float z = float(w[0] * t.z[0] + w[1] * t.z[1] + w[2] * t.z[2]);
        const size_t at = size_t(y) * size_t(sw) + size_t(x);
        if (z < depth[at]) {
          depth[at] = z;
          colour[at] = t.colour;
        }
      }
    }
  }
}

}  // namespace

Eigen::Vector2d projected_extent(View view, const Eigen::AlignedBox3d& box) {
  const Camera cam = camera_for(view);
  const Vec3 centre = box.center();
  double ex = 0, ey = 0;
  for (int k = 0; k < 8; ++k) {
    const Vec3 d = box.corner(Eigen::AlignedBox3d::CornerType(k)) - centre;
    ex = std::max(ex, std::abs(d.dot(cam.right)));
    ey = std::max(ey, std::abs(d.dot(cam.up)));
  }
  return {2 * ex, 2 * ey};
}

Image rasterize(const RowMatX3d& vertices, const RowMatX3i& faces, const std::vector<Rgb>& face_colours,
                const ViewSetup& setup, int width, int height) {
  if (width < 1 || height < 1) throw InputError(fmt::format("render: image size {}x{} is empty", width, height));
  if (face_colours.size() != size_t(faces.rows()))
    throw InputError(fmt::format("render: {} colours for {} faces", face_colours.size(), faces.rows()));
  const int sw = width * kSupersample, sh = height * kSupersample;
  const Camera cam = camera_for(setup.view);
  const std::vector<ScreenTriangle> tris = project(vertices, faces, face_colours, setup, cam, sw, sh);
  std::vector<float> depth(size_t(sw) * size_t(sh), std::numeric_limits<float>::infinity());
  std::vector<uint32_t> colour(depth.size(), pack(setup.background));
  constexpr int kBand = 16;
  tbb::parallel_for(0, (sh + kBand - 1) / kBand, [&](int band) {
    rasterize_band(tris, sw, band * kBand, std::min(sh, (band + 1) * kBand), depth, colour);
  });
  Image image{width, height, std::vector<uint32_t>(size_t(width) * size_t(height))};
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      uint32_t sum[3] = {0, 0, 0};
      for (int dy = 0; dy < kSupersample; ++dy)
        for (int dx = 0; dx < kSupersample; ++dx) {
          const uint32_t c = colour[size_t(y * kSupersample + dy) * size_t(sw) + size_t(x * kSupersample + dx)];
          sum[0] += (c >> 16) & 0xFF;
          sum[1] += (c >> 8) & 0xFF;
          sum[2] += c & 0xFF;
        }
      constexpr uint32_t n = kSupersample * kSupersample;
      image.pixels[size_t(y) * size_t(width) + size_t(x)] =
          0xFF000000u | (((sum[0] + n / 2) / n) << 16) | (((sum[1] + n / 2) / n) << 8) | ((sum[2] + n / 2) / n);
    }
  });
  return image;
}

}  // namespace cutwork::render
