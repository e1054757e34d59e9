#include "host/render/rasterizer.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "host/core/error.h"
#if CUTWORK_WITH_VULKAN
#include "host/render/rasterizer_vk.h"
#endif

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

/// a · b summed x, y, z in that order: raster.comp computes the same expression, so the two
/// twins' projections agree to the bit wherever the device's double arithmetic is IEEE.
double dot3(const Vec3& a, const Vec3& b) { return a.x() * b.x() + a.y() * b.y() + a.z() * b.z(); }

/// A triangle in supersampled pixel coordinates with its depth and shaded colour.
struct ScreenTriangle {
  double x[3], y[3], z[3];
  double min_y, max_y;
  uint32_t colour;
};

/// Mirrors setup() in raster.comp line by line; change one twin, change the other.
std::vector<ScreenTriangle> project(const RowMatX3d& V, const RowMatX3i& F, const std::vector<Rgb>& colours,
                                    const Projection& pr) {
  std::vector<ScreenTriangle> tris(size_t(F.rows()));
  tbb::parallel_for(Eigen::Index(0), F.rows(), [&](Eigen::Index f) {
    ScreenTriangle& t = tris[size_t(f)];
    Vec3 p[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = V.row(F(f, k)).transpose();
      const Vec3 d = p[k] - pr.centre;
      t.x[k] = 0.5 * pr.sw + pr.scale * dot3(d, pr.right);
      t.y[k] = 0.5 * pr.sh - pr.scale * dot3(d, pr.up);
      t.z[k] = dot3(d, pr.forward);
    }
    t.min_y = std::min({t.y[0], t.y[1], t.y[2]});
    t.max_y = std::max({t.y[0], t.y[1], t.y[2]});
    const Vec3 a = p[1] - p[0], b = p[2] - p[0];
    const Vec3 n(a.y() * b.z() - a.z() * b.y(), a.z() * b.x() - a.x() * b.z(), a.x() * b.y() - a.y() * b.x());
    const double len = std::sqrt(dot3(n, n));
    const double lambert = len > 0 ? std::abs(dot3(n, pr.light)) / len : 0.0;
    const double shade = 0.35 + 0.65 * lambert;
    const Rgb& c = colours[size_t(f)];
    t.colour = pack({c.r * shade, c.g * shade, c.b * shade});
  });
  return tris;
}

/// Rasterises every triangle into rows [y0, y1) of the supersampled buffers. Mirrors raster()
/// in raster.comp.
void rasterize_band(const std::vector<ScreenTriangle>& tris, int sw, int y0, int y1, std::vector<float>& depth,
                    std::vector<uint32_t>& colour) {
  for (const ScreenTriangle& t : tris) {
    if (t.max_y < y0 || t.min_y >= y1) continue;
    const double area = (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.x[2] - t.x[0]) * (t.y[1] - t.y[0]);
    if (std::abs(area) < 1e-12) continue;
    // The sample box, clamped in double before converting (no integer overflow far off-screen).
    const double xa = std::max(0.0, std::floor(std::min({t.x[0], t.x[1], t.x[2]})));
    const double xb = std::min(double(sw - 1), std::ceil(std::max({t.x[0], t.x[1], t.x[2]})));
    const double ya = std::max(double(y0), std::floor(t.min_y));
    const double yb = std::min(double(y1 - 1), std::ceil(t.max_y));
    if (xa > xb || ya > yb) continue;
    for (int y = int(ya); y <= int(yb); ++y) {
      const double py = y + 0.5;
      for (int x = int(xa); x <= int(xb); ++x) {
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

void check_inputs(const RowMatX3d& V, const RowMatX3i& F, const std::vector<Rgb>& colours, int width, int height) {
  if (width < 1 || height < 1) throw InputError(fmt::format("render: image size {}x{} is empty", width, height));
  if (colours.size() != size_t(F.rows()))
    throw InputError(fmt::format("render: {} colours for {} faces", colours.size(), F.rows()));
  if (!V.allFinite()) throw InputError("render: a vertex coordinate is not finite");
  if (F.size() > 0 && (F.minCoeff() < 0 || F.maxCoeff() >= V.rows()))
    throw InputError(fmt::format("render: a face corner is outside the {} vertices", V.rows()));
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

Projection projection_for(const ViewSetup& setup, int width, int height) {
  const Camera cam = camera_for(setup.view);
  Projection p;
  p.sw = width * kSupersample;
  p.sh = height * kSupersample;
  // Scale: the frame box's projected extent fills `fill` of the picture.
  const Eigen::Vector2d extent = projected_extent(setup.view, setup.frame);
  const double ex = extent.x() / 2, ey = extent.y() / 2;
  p.scale = setup.fill * std::min(p.sw / (2 * std::max(ex, 1e-300)), p.sh / (2 * std::max(ey, 1e-300)));
  p.centre = setup.frame.center();
  p.right = cam.right;
  p.up = cam.up;
  p.forward = cam.forward;
  p.light = cam.light;
  return p;
}

uint32_t pack(const Rgb& c) {
  auto byte = [](double v) { return uint32_t(std::floor(std::clamp(v, 0.0, 1.0) * 255.0 + 0.5)); };
  return 0xFF000000u | (byte(c.r) << 16) | (byte(c.g) << 8) | byte(c.b);
}

Image rasterize(const RowMatX3d& vertices, const RowMatX3i& faces, const std::vector<Rgb>& face_colours,
                const ViewSetup& setup, int width, int height) {
  check_inputs(vertices, faces, face_colours, width, height);
  const Projection pr = projection_for(setup, width, height);
  const int sw = pr.sw, sh = pr.sh;
  const std::vector<ScreenTriangle> tris = project(vertices, faces, face_colours, pr);
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

Rasterizer Rasterizer::for_backend(const ComputeBackend& backend) {
  Rasterizer r;
  if (backend.kind != ComputeBackend::Kind::Vulkan) return r;
#if CUTWORK_WITH_VULKAN
  if (backend.context == nullptr)
    throw DeviceError("render: a Vulkan backend without a context (make it with select_compute_backend)");
  r.m_vk = std::make_shared<RasterizerVk>(backend.context);
  return r;
#else
  throw DeviceError("render: this cutwork was built without Vulkan (CUTWORK_WITH_VULKAN=OFF); use --device cpu");
#endif
}

Image Rasterizer::rasterize(const RowMatX3d& vertices, const RowMatX3i& faces, const std::vector<Rgb>& face_colours,
                            const ViewSetup& setup, int width, int height) const {
#if CUTWORK_WITH_VULKAN
  if (m_vk) {
    check_inputs(vertices, faces, face_colours, width, height);
    return m_vk->rasterize(vertices, faces, face_colours, setup, width, height);
  }
#endif
  return render::rasterize(vertices, faces, face_colours, setup, width, height);
}

}  // namespace cutwork::render
