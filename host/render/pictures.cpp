#include "host/render/pictures.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "host/core/atomic_file.h"
#include "host/core/error.h"

namespace cutwork::render {
namespace {

Rgb mix(const Rgb& a, const Rgb& b, double t) {
  return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}

/// Piecewise-linear colour ramp through `stops` (evenly spaced) at t ∈ [0, 1].
template <size_t N>
Rgb ramp(const Rgb (&stops)[N], double t) {
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * double(N - 1);
  const size_t i = std::min(size_t(t), N - 2);
  return mix(stops[i], stops[i + 1], t - double(i));
}

using CairoSurface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using Cairo = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

double top_of_scale(const Eigen::VectorXd& W, double beta) {
  const double w_max = W.size() > 0 ? W.maxCoeff() : 0.0;
  return std::isfinite(beta) ? std::max(w_max, beta) : w_max;
}

void set_colour(cairo_t* cr, const Rgb& c) { cairo_set_source_rgb(cr, c.r, c.g, c.b); }

void text(cairo_t* cr, double x, double y, const std::string& s, double size, bool bold = false) {
  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_move_to(cr, x, y);
  cairo_show_text(cr, s.c_str());
}

/// The vertical colour bar in the box (x, y, w, h) with labels to its right.
void draw_colour_bar(cairo_t* cr, Field field, const DesignFields& f, double x, double y, double w, double h,
                     double font) {
  const bool energy = field == Field::EnergyDensity;
  const double beta = f.beta;
  const double top = energy ? top_of_scale(f.energy_density, beta) : 1.0;
  const double bar_w = std::max(8.0, 0.28 * w);
  set_colour(cr, {0.1, 0.1, 0.1});
  text(cr, x, y - 0.6 * font, energy ? "W (J/m\u00B2)" : "fill ratio \u03B1", font, true);
  for (int row = 0; row < int(h); ++row) {
    const double value = top * (1.0 - (row + 0.5) / h);
    set_colour(cr, energy ? energy_colour(value, beta, top) : fill_colour(value));
    cairo_rectangle(cr, x, y + row, bar_w, 1.0);
    cairo_fill(cr);
  }
  cairo_set_line_width(cr, 1.0);
  set_colour(cr, {0.1, 0.1, 0.1});
  cairo_rectangle(cr, x + 0.5, y + 0.5, bar_w - 1, h - 1);
  cairo_stroke(cr);
  auto tick = [&](double value, const std::string& label) {
    const double ty = y + h * (1.0 - (top > 0 ? value / top : 0.0));
    cairo_move_to(cr, x + bar_w, ty);
    cairo_line_to(cr, x + bar_w + 0.2 * font + 3, ty);
    cairo_stroke(cr);
    text(cr, x + bar_w + 0.3 * font + 4, ty + 0.35 * font, label, 0.9 * font);
  };
  tick(0.0, "0");
  tick(top, fmt::format("{:.3g}", top));
  if (energy && std::isfinite(beta) && beta < top * 0.93 && beta > top * 0.07)
    tick(beta, fmt::format("\u03B2 {:.3g}", beta));
  else if (energy && std::isfinite(beta))
    text(cr, x, y + h + 1.3 * font, fmt::format("\u03B2 = {:.3g}", beta), 0.9 * font);
  else if (!energy)
    tick(0.5, "0.5");
}

/// The triangles and per-face colours one field draws.
struct Coloured {
  const RowMatX3d* vertices;
  const RowMatX3i* faces;
  std::vector<Rgb> colours;
};

Coloured colour_field(const DesignFields& f, Field field) {
  auto need = [&](bool ok, const char* what) {
    if (!ok) throw InputError(fmt::format("render {}: {} is not available", to_string(field), what));
  };
  if (field == Field::Design) {
    need(f.cut_vertices && f.cut_faces, "the cut surface");
    return {f.cut_vertices, f.cut_faces, std::vector<Rgb>(size_t(f.cut_faces->rows()), material_colour())};
  }
  need(f.sim_vertices && f.sim_faces, "the simulation mesh");
  const Eigen::VectorXd& values = field == Field::EnergyDensity ? f.energy_density : f.fill_ratio;
  need(values.size() == f.sim_faces->rows(), field == Field::EnergyDensity ? "the energy density" : "the fill ratio");
  Coloured c{f.sim_vertices, f.sim_faces, std::vector<Rgb>(size_t(values.size()))};
  const double top = top_of_scale(f.energy_density, f.beta);
  for (Eigen::Index i = 0; i < values.size(); ++i)
    c.colours[size_t(i)] = field == Field::EnergyDensity ? energy_colour(values[i], f.beta, top) : fill_colour(values[i]);
  return c;
}

std::string field_title(const DesignFields& f, Field field) {
  switch (field) {
    case Field::EnergyDensity:
      return fmt::format("{}: energy density W, max {:.4g} J/m\u00B2", f.title, f.energy_density.maxCoeff());
    case Field::FillRatio:
      return fmt::format("{}: fill ratio \u03B1, min {:.2f}, mean {:.2f} over the faces", f.title,
                         f.fill_ratio.minCoeff(), f.fill_ratio.mean());
    case Field::Design:
      return fmt::format("{}: {}", f.title, f.fill_ratio.size() > 0 && f.fill_ratio.minCoeff() >= 1 ? "surface (uncut)" : "cut design");
  }
  return f.title;
}

}  // namespace

Rgb energy_colour(double W, double beta, double w_top) {
  static const Rgb stops[] = {{0.17, 0.28, 0.78}, {0.20, 0.72, 0.85}, {0.22, 0.75, 0.25}, {0.98, 0.85, 0.20},
                              {0.85, 0.12, 0.10}};
  const double b = std::isfinite(beta) ? beta : 0.5 * w_top;
  double t = 0.5;
  if (W <= b)
    t = b > 0 ? 0.5 * W / b : 0.5;
  else
    t = w_top > b ? 0.5 + 0.5 * (W - b) / (w_top - b) : 1.0;
  return ramp(stops, t);
}

Rgb fill_colour(double alpha) {
  static const Rgb stops[] = {{0.27, 0.00, 0.33}, {0.23, 0.32, 0.55}, {0.13, 0.57, 0.55}, {0.37, 0.79, 0.38},
                              {0.99, 0.91, 0.14}};
  return ramp(stops, alpha);
}

Rgb material_colour() { return {0.93, 0.90, 0.84}; }

std::string_view to_string(Field field) {
  switch (field) {
    case Field::EnergyDensity:
      return "W";
    case Field::FillRatio:
      return "alpha";
    case Field::Design:
      return "design";
  }
  return "W";
}

Field parse_field(std::string_view text) {
  for (Field f : {Field::EnergyDensity, Field::FillRatio, Field::Design})
    if (text == to_string(f)) return f;
  throw InputError(fmt::format("unknown field '{}': expected W, alpha or design", text));
}

Image draw_picture(const DesignFields& f, Field field, const PictureOptions& o) {
  if (o.width < 64 || o.height < 48)
    throw InputError(fmt::format("render: picture size {}x{} is below 64x48", o.width, o.height));
  if (o.views.empty()) throw InputError("render: no views to draw");
  const Coloured c = colour_field(f, field);
  Eigen::AlignedBox3d frame;
  for (Eigen::Index v = 0; v < c.vertices->rows(); ++v) frame.extend(c.vertices->row(v).transpose());
  std::vector<View> views;
  for (View v : o.views) {
    const Eigen::Vector2d e = projected_extent(v, frame);
    if (!o.skip_edge_on_views || std::min(e.x(), e.y()) >= 0.02 * std::max(e.x(), e.y())) views.push_back(v);
  }
  if (views.empty()) views = o.views;
  const double font = std::clamp(0.04 * o.height, 8.0, 18.0);
  const int title_h = int(std::ceil(1.8 * font));
  const int label_h = int(std::ceil(1.5 * font));
  const int bar_w = field == Field::Design ? 0 : std::max(60, int(0.12 * o.width));
  const int panel_w = std::max(1, (o.width - bar_w) / int(views.size()));
  const int panel_h = std::max(1, o.height - title_h - label_h);

  CairoSurface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, o.width, o.height), &cairo_surface_destroy);
  Cairo cr(cairo_create(surface.get()), &cairo_destroy);
  cairo_set_source_rgb(cr.get(), 1, 1, 1);
  cairo_paint(cr.get());
  for (size_t i = 0; i < views.size(); ++i) {
    ViewSetup setup;
    setup.view = views[i];
    setup.frame = frame;
    Image panel = o.rasterizer.rasterize(*c.vertices, *c.faces, c.colours, setup, panel_w, panel_h);
    CairoSurface ps(cairo_image_surface_create_for_data(reinterpret_cast<unsigned char*>(panel.pixels.data()),
                                                        CAIRO_FORMAT_RGB24, panel_w, panel_h, panel_w * 4),
                    &cairo_surface_destroy);
    const double px = double(i) * panel_w;
    cairo_set_source_surface(cr.get(), ps.get(), px, title_h);
    cairo_paint(cr.get());
    cairo_set_source_rgb(cr.get(), 0.35, 0.35, 0.35);
    text(cr.get(), px + 0.5 * font, title_h + panel_h + 1.1 * font, std::string(to_string(views[i])) + " view",
         0.9 * font);
  }
  cairo_set_source_rgb(cr.get(), 0.1, 0.1, 0.1);
  text(cr.get(), 0.5 * font, 1.3 * font, field_title(f, field), font, true);
  if (bar_w > 0)
    draw_colour_bar(cr.get(), field, f, o.width - bar_w + 0.1 * bar_w, title_h + 2.0 * font, bar_w * 0.9,
                    std::max(10.0, panel_h - 3.5 * font), font);
  cairo_surface_flush(surface.get());
  Image out{o.width, o.height, std::vector<uint32_t>(size_t(o.width) * size_t(o.height))};
  const unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  for (int y = 0; y < o.height; ++y)
    for (int x = 0; x < o.width; ++x)
      out.pixels[size_t(y) * size_t(o.width) + size_t(x)] =
          0xFF000000u | reinterpret_cast<const uint32_t*>(data + size_t(y) * size_t(stride))[x];
  return out;
}

std::string encode_png(const Image& image) {
  std::vector<uint32_t> copy = image.pixels;
  CairoSurface s(cairo_image_surface_create_for_data(reinterpret_cast<unsigned char*>(copy.data()), CAIRO_FORMAT_RGB24,
                                                     image.width, image.height, image.width * 4),
                 &cairo_surface_destroy);
  std::string bytes;
  const cairo_status_t status = cairo_surface_write_to_png_stream(
      s.get(),
      [](void* closure, const unsigned char* data, unsigned int length) {
        static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
        return CAIRO_STATUS_SUCCESS;
      },
      &bytes);
  if (status != CAIRO_STATUS_SUCCESS)
    throw InputError(std::string("PNG encoding failed: ") + cairo_status_to_string(status));
  return bytes;
}

Image read_png(const std::filesystem::path& path) {
  CairoSurface s(cairo_image_surface_create_from_png(path.c_str()), &cairo_surface_destroy);
  if (cairo_surface_status(s.get()) != CAIRO_STATUS_SUCCESS)
    throw InputError(path.string() + ": " + cairo_status_to_string(cairo_surface_status(s.get())));
  cairo_surface_flush(s.get());
  Image out{cairo_image_surface_get_width(s.get()), cairo_image_surface_get_height(s.get()), {}};
  out.pixels.resize(size_t(out.width) * size_t(out.height));
  const unsigned char* data = cairo_image_surface_get_data(s.get());
  const int stride = cairo_image_surface_get_stride(s.get());
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      out.pixels[size_t(y) * size_t(out.width) + size_t(x)] =
          0xFF000000u | reinterpret_cast<const uint32_t*>(data + size_t(y) * size_t(stride))[x];
  return out;
}

std::vector<std::filesystem::path> write_pictures(const std::filesystem::path& dir, const DesignFields& fields,
                                                  const std::vector<Field>& fields_to_draw,
                                                  const PictureOptions& options) {
  // Draw everything first: a failure leaves no picture behind.
  std::vector<std::pair<std::filesystem::path, std::string>> files;
  for (Field field : fields_to_draw) {
    const bool available = field == Field::Design ? fields.cut_vertices != nullptr
                           : field == Field::EnergyDensity ? fields.energy_density.size() > 0
                                                           : fields.fill_ratio.size() > 0;
    if (!available) continue;
    files.emplace_back(dir / fmt::format("render_{}.png", to_string(field)),
                       encode_png(draw_picture(fields, field, options)));
  }
  std::vector<std::filesystem::path> written;
  for (const auto& [path, bytes] : files) {
    write_file_atomic(path, bytes);
    written.push_back(path);
  }
  return written;
}

}  // namespace cutwork::render
