#include "host/sweep/pareto_plot.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <ostream>
#include <string>

#include <fmt/format.h>

#include "host/core/atomic_file.h"
#include "host/core/error.h"

namespace cutwork {

namespace {

struct Panel {
  double left, top, width, height;  ///< plot area in pixels
  double x0, x1, y0, y1;            ///< data range
  double px(double x) const { return left + (x - x0) / (x1 - x0) * width; }
  double py(double y) const { return top + height - (y - y0) / (y1 - y0) * height; }
};

/// A "nice" tick step (1, 2 or 5 × 10^k) giving about five ticks over [lo, hi].
double tick_step(double lo, double hi) {
  const double raw = (hi - lo) / 5;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

/// [lo, hi] of the values with a 6% margin (a single value gets ±5% of itself, or ±1 at zero).
void padded_range(const std::vector<double>& v, double& lo, double& hi) {
  lo = INFINITY, hi = -INFINITY;
  for (double x : v)
    if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
  if (!std::isfinite(lo)) lo = 0, hi = 1;
  if (hi - lo <= 1e-12 * std::max(std::abs(lo), std::abs(hi))) {
    const double d = lo != 0 ? 0.05 * std::abs(lo) : 1.0;
    lo -= d, hi += d;
  }
  const double m = 0.06 * (hi - lo);
  lo -= m, hi += m;
}

void text_at(cairo_t* cr, const std::string& s, double x, double y, double ax, double ay, double angle = 0) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  cairo_save(cr);
  cairo_translate(cr, x, y);
  cairo_rotate(cr, angle);
  cairo_move_to(cr, -e.x_bearing - ax * e.width, -e.y_bearing - ay * e.height);
  cairo_show_text(cr, s.c_str());
  cairo_restore(cr);
}

/// A tick label with as many decimals as the step needs (so neighbouring ticks differ).
std::string tick_label(double t, double step) {
  if (std::abs(t) < 1e-9 * step) t = 0;
  const double mag = std::max(std::abs(t), step);
  if (mag >= 1e6 || mag < 1e-4) return fmt::format("{:.3g}", t);
  const int decimals = std::max(0, -int(std::floor(std::log10(step) + 1e-9)));
  return fmt::format("{:.{}f}", t, decimals);
}

void draw_axes(cairo_t* cr, const Panel& p, const std::string& xlabel, const std::string& ylabel) {
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 1.2);
  cairo_rectangle(cr, p.left, p.top, p.width, p.height);
  cairo_stroke(cr);
  cairo_set_font_size(cr, 13);
  const double sx = tick_step(p.x0, p.x1), sy = tick_step(p.y0, p.y1);
  for (double t = std::ceil(p.x0 / sx) * sx; t <= p.x1; t += sx) {
    const double x = p.px(t);
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, x, p.top), cairo_line_to(cr, x, p.top + p.height), cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text_at(cr, tick_label(t, sx), x, p.top + p.height + 8, 0.5, 0);
  }
  for (double t = std::ceil(p.y0 / sy) * sy; t <= p.y1; t += sy) {
    const double y = p.py(t);
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, p.left, y), cairo_line_to(cr, p.left + p.width, y), cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text_at(cr, tick_label(t, sy), p.left - 8, y, 1, 0.5);
  }
  cairo_set_font_size(cr, 15);
  text_at(cr, xlabel, p.left + p.width / 2, p.top + p.height + 34, 0.5, 0);
  // The y label, rotated: anchor the text's centre at the left of the tick labels.
  cairo_text_extents_t e;
  cairo_text_extents(cr, ylabel.c_str(), &e);
  cairo_save(cr);
  cairo_translate(cr, p.left - 78, p.top + p.height / 2);
  cairo_rotate(cr, -std::numbers::pi / 2);
  cairo_move_to(cr, -e.width / 2 - e.x_bearing, 0);
  cairo_show_text(cr, ylabel.c_str());
  cairo_restore(cr);
}

void draw_panel(cairo_t* cr, Panel p, const std::vector<VariantResult>& results, const std::vector<size_t>& front,
                bool compliance, const std::string& ylabel) {
  std::vector<double> xs, ys;
  for (const VariantResult& r : results)
    if (r.ok) xs.push_back(100 * r.material_fraction), ys.push_back(compliance ? r.compliance : r.W_max_final);
  padded_range(xs, p.x0, p.x1);
  padded_range(ys, p.y0, p.y1);
  draw_axes(cr, p, "material left (% of the uncut shell's area)", ylabel);
  cairo_save(cr);
  cairo_rectangle(cr, p.left, p.top, p.width, p.height);
  cairo_clip(cr);
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  for (size_t i = 0; i < xs.size(); ++i) {
    cairo_new_sub_path(cr);
    cairo_arc(cr, p.px(xs[i]), p.py(ys[i]), 4, 0, 2 * std::numbers::pi);
  }
  cairo_fill(cr);
  // The front as a staircase: beyond each non-dominated point, nothing is better until the next.
  cairo_set_source_rgb(cr, 0.8, 0.15, 0.1);
  cairo_set_line_width(cr, 1.5);
  double previous_y = 0;
  for (size_t k = 0; k < front.size(); ++k) {
    const VariantResult& r = results[front[k]];
    const double x = p.px(100 * r.material_fraction), y = p.py(compliance ? r.compliance : r.W_max_final);
    if (k == 0) cairo_move_to(cr, x, y);
    else cairo_line_to(cr, x, previous_y), cairo_line_to(cr, x, y);
    previous_y = y;
  }
  cairo_stroke(cr);
  cairo_restore(cr);
  cairo_set_source_rgb(cr, 0.8, 0.15, 0.1);
  cairo_set_font_size(cr, 12);
  for (size_t i : front) {
    const VariantResult& r = results[i];
    const double x = p.px(100 * r.material_fraction), y = p.py(compliance ? r.compliance : r.W_max_final);
    cairo_new_sub_path(cr);
    cairo_arc(cr, x, y, 5.5, 0, 2 * std::numbers::pi);
    cairo_fill(cr);
    // Labels right of their point, or left of it near the right edge.
    const bool right = x < p.left + 0.85 * p.width;
    text_at(cr, r.id, right ? x + 8 : x - 8, y - 6, right ? 0 : 1, 1);
  }
}

cairo_status_t to_stream(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::ostream*>(closure)->write(reinterpret_cast<const char*>(data), std::streamsize(length));
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace

void write_pareto_png(const std::filesystem::path& path, const std::string& title,
                      const std::vector<VariantResult>& results, const ParetoFronts& fronts) {
  const int W = 1400, H = 640;
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, W, H), &cairo_surface_destroy);
  std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cr(cairo_create(surface.get()), &cairo_destroy);
  cairo_set_source_rgb(cr.get(), 1, 1, 1);
  cairo_paint(cr.get());
  cairo_select_font_face(cr.get(), "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_source_rgb(cr.get(), 0, 0, 0);
  cairo_set_font_size(cr.get(), 17);
  int ok = 0;
  for (const VariantResult& r : results) ok += r.ok ? 1 : 0;
  text_at(cr.get(), fmt::format("{}: {} designs ({} failed); non-dominated in red (less material, lower W_max or compliance)",
                                title, ok, int(results.size()) - ok),
          W / 2.0, 18, 0.5, 0);
  draw_panel(cr.get(), {110, 60, 560, 480, 0, 1, 0, 1}, results, fronts.w_max, false, "W_max, final (J/m^2)");
  draw_panel(cr.get(), {810, 60, 560, 480, 0, 1, 0, 1}, results, fronts.compliance, true, "compliance, final (J)");
  cairo_surface_flush(surface.get());
  write_file_atomic(
      path,
      [&](std::ostream& os) {
        if (cairo_surface_write_to_png_stream(surface.get(), to_stream, &os) != CAIRO_STATUS_SUCCESS)
          throw InputError(path.string() + ": cairo could not encode the plot");
      },
      true);
}

}  // namespace cutwork
