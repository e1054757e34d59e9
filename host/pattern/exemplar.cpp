#include "host/pattern/exemplar.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/pattern/random.h"
#include "host/scene/json_reader.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork {
using nlohmann::json;

namespace {

bool segments_cross(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  auto orient = [](const Vec2& o, const Vec2& p, const Vec2& q) {
    const double v = (p.x() - o.x()) * (q.y() - o.y()) - (p.y() - o.y()) * (q.x() - o.x());
    return (v > 0) - (v < 0);
  };
  const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (o1 != o2 && o3 != o4) return true;
  auto on = [](const Vec2& p, const Vec2& q, const Vec2& r) {  // r on segment pq (collinear)
    return std::min(p.x(), q.x()) <= r.x() && r.x() <= std::max(p.x(), q.x()) &&
           std::min(p.y(), q.y()) <= r.y() && r.y() <= std::max(p.y(), q.y());
  };
  return (o1 == 0 && on(a, b, c)) || (o2 == 0 && on(a, b, d)) || (o3 == 0 && on(c, d, a)) ||
         (o4 == 0 && on(c, d, b));
}

std::vector<Vec2> unit_square() { return {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)}; }

/// Dart throwing in the unit square: elements of radius in [radius_lo, radius_hi) and type
/// `type` kept at centre distances ≥ gap·(r_i + r_j) from everything placed before and
/// ≥ radius from the square's sides, until `misses` consecutive darts fail or `max_count`
/// elements of this call are placed.
void throw_darts(Exemplar& ex, PatternRng& rng, double radius_lo, double radius_hi, int type,
                 double gap, int misses, bool random_angle, int max_count = 1 << 30) {
  int fails = 0, placed = 0;
  while (fails < misses && placed < max_count) {
    const double r = rng.uniform(radius_lo, radius_hi);
    const Vec2 p(rng.uniform(r, 1 - r), rng.uniform(r, 1 - r));
    const double angle = random_angle ? rng.uniform(0, 2 * std::numbers::pi) : 0.0;
    bool ok = true;
    for (const auto& e : ex.elements)
      if ((e.position - p).norm() < gap * (e.scale + r)) {
        ok = false;
        break;
      }
    if (!ok) {
      ++fails;
      continue;
    }
    fails = 0;
    ++placed;
    ex.elements.push_back({p, r, type, angle});
  }
}

}  // namespace

double Exemplar::size() const {
  Vec2 lo = domain.front(), hi = domain.front();
  for (const Vec2& p : domain) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).maxCoeff();
}

double Exemplar::area() const { return std::abs(polygon_signed_area(domain)); }

double Exemplar::mean_scale() const {
  double s = 0;
  for (const auto& e : elements) s += e.scale;
  return elements.empty() ? 1.0 : s / double(elements.size());
}

bool Exemplar::contains(const Vec2& p) const { return !domain.empty() && point_in_polygon(domain, p); }

double Exemplar::distance_to_boundary(const Vec2& p) const {
  double d = INFINITY;
  for (size_t i = 0; i < domain.size(); ++i)
    d = std::min(d, segment_distance(domain[i], domain[(i + 1) % domain.size()], p));
  return contains(p) ? d : -d;
}

const std::vector<std::string>& builtin_exemplar_names() {
  static const std::vector<std::string> names{"packing", "flowers", "stripes", "circles", "mix"};
  return names;
}

Exemplar builtin_exemplar(const std::string& name) {
  Exemplar ex;
  ex.name = name;
  ex.builtin = true;
  ex.domain = unit_square();
  // Every built-in keeps centre distances ≥ 1.3 (r_i + r_j), so it respects collision safety
  // factors up to s = 0.3 and the optimiser never has to fight the exemplar. Each holds 40–65
  // elements, so that the paper's r_N = 0.3 (Table 2) gives neighbourhoods of 10–20 elements.
  if (name == "packing") {
    // Fig. 2 (1): a blue-noise packing of one shape at one size.
    ex.type_names = {"primary"};
    PatternRng rng(0x9ac1);
    throw_darts(ex, rng, 0.05, 0.05, 0, 1.3, 4000, false);
  } else if (name == "flowers") {
    // Fig. 2 (2): irregularly placed flowers of varied size and rotation, small fillers between.
    ex.type_names = {"primary", "secondary"};
    PatternRng rng(0xf10e);
    throw_darts(ex, rng, 0.06, 0.09, 0, 1.3, 4000, true);
    throw_darts(ex, rng, 0.025, 0.03, 1, 1.3, 4000, true, 12);
  } else if (name == "stripes") {
    // Fig. 2 (3): rows along x, dense along the row (0.1) and sparse across it (0.2).
    ex.type_names = {"primary"};
    ex.symmetry = 2;
    for (int row = 0; row < 5; ++row)
      for (int k = 0; k < 10; ++k)
        ex.elements.push_back({Vec2(0.05 + 0.1 * k, 0.1 + 0.2 * row), 0.035, 0, 0.0});
  } else if (name == "circles") {
    // Fig. 2 (4): a square lattice alternating large and small circles (checkerboard).
    ex.type_names = {"primary", "secondary"};
    ex.symmetry = 4;
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j) {
        const bool big = (i + j) % 2 == 0;
        ex.elements.push_back({Vec2(0.0625 + 0.125 * i, 0.0625 + 0.125 * j), big ? 0.045 : 0.025,
                               big ? 0 : 1, 0.0});
      }
  } else if (name == "mix") {
    // Fig. 2 (5): a heterogeneous mix of three types and sizes.
    ex.type_names = {"primary", "secondary", "tertiary"};
    PatternRng rng(0x3170);
    throw_darts(ex, rng, 0.06, 0.07, 0, 1.3, 4000, true, 22);
    throw_darts(ex, rng, 0.04, 0.045, 1, 1.3, 4000, true, 16);
    throw_darts(ex, rng, 0.025, 0.03, 2, 1.3, 4000, true, 16);
  } else {
    std::string names;
    for (const auto& n : builtin_exemplar_names()) names += (names.empty() ? "" : ", ") + n;
    throw InputError("'" + name + "' is not a built-in exemplar (built-in: " + names + ")");
  }
  return ex;
}

Exemplar parse_exemplar(const json& doc, const std::string& origin, const std::string& path) {
  JsonObjectReader r(doc, origin, path);
  Exemplar ex;
  ex.name = "inline";

  const json* dom = r.child("domain");
  if (!dom) r.fail("domain", "is required: [width, height] or a polygon [[x, y], ...]");
  if (!dom->is_array()) r.fail("domain", "expected [width, height] or a polygon [[x, y], ...]");
  if (dom->size() == 2 && (*dom)[0].is_number() && (*dom)[1].is_number()) {
    const double w = (*dom)[0].get<double>(), h = (*dom)[1].get<double>();
    if (!std::isfinite(w) || !std::isfinite(h) || !(w > 0) || !(h > 0))
      r.fail("domain", fmt::format("width and height must be finite and > 0 (got {}, {})",
                                   format_number(w), format_number(h)));
    ex.domain = {Vec2(0, 0), Vec2(w, 0), Vec2(w, h), Vec2(0, h)};
  } else {
    if (dom->size() < 3)
      r.fail("domain", "a polygon needs at least 3 points [[x, y], ...] (or give [width, height])");
    for (size_t i = 0; i < dom->size(); ++i) {
      const json& p = (*dom)[i];
      const std::string pp = r.path_of("domain") + "/" + std::to_string(i);
      if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number())
        throw InputError(origin + ": " + pp + ": expected a point [x, y]");
      const Vec2 v(p[0].get<double>(), p[1].get<double>());
      if (!v.allFinite()) throw InputError(origin + ": " + pp + ": must be finite");
      ex.domain.push_back(v);
    }
    const size_t n = ex.domain.size();
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i + 1; j < n; ++j) {
        if (j == i + 1 || (i == 0 && j == n - 1)) continue;  // adjacent edges share a corner
        if (segments_cross(ex.domain[i], ex.domain[(i + 1) % n], ex.domain[j], ex.domain[(j + 1) % n]))
          r.fail("domain", fmt::format("the polygon is not simple: edges {} and {} intersect", i, j));
      }
    const double a = polygon_signed_area(ex.domain);
    if (!(std::abs(a) > 0)) r.fail("domain", "the polygon has zero area");
    if (a < 0) std::reverse(ex.domain.begin(), ex.domain.end());
  }

  const json& elems = r.array("elements");
  if (elems.empty()) r.fail("elements", "is required: a non-empty array of elements");
  for (size_t i = 0; i < elems.size(); ++i) {
    const std::string ep = r.path_of("elements") + "/" + std::to_string(i);
    JsonObjectReader e(elems[i], origin, ep);
    ExemplarElement el;
    const json* pos = e.child("position");
    if (!pos) e.fail("position", "is required: [x, y]");
    if (!pos->is_array() || pos->size() != 2 || !(*pos)[0].is_number() || !(*pos)[1].is_number())
      e.fail("position", "expected [x, y]");
    el.position = Vec2((*pos)[0].get<double>(), (*pos)[1].get<double>());
    if (!el.position.allFinite()) e.fail("position", "must be finite");
    if (!ex.contains(el.position))
      e.fail("position", fmt::format("({}, {}) lies outside the exemplar's domain",
                                     format_number(el.position.x()), format_number(el.position.y())));
    el.scale = e.required_number("scale", 0, INFINITY, true);
    const std::string type = e.string("type", "");
    auto it = std::find(ex.type_names.begin(), ex.type_names.end(), type);
    if (it == ex.type_names.end()) {
      el.type = int(ex.type_names.size());
      ex.type_names.push_back(type);
    } else {
      el.type = int(it - ex.type_names.begin());
    }
    el.angle = e.number("angle", 0.0, -INFINITY, INFINITY);
    e.finish();
    ex.elements.push_back(el);
  }
  ex.symmetry = r.integer("symmetry", 0, 0, 12);
  r.finish();
  return ex;
}

std::vector<int> map_exemplar_types(const Exemplar& ex, const std::vector<std::string>& stencils,
                                    const std::string& origin, const std::string& path) {
  if (stencils.empty()) throw InputError(origin + ": the scene defines no stencil shapes");
  std::vector<int> out;
  for (size_t t = 0; t < ex.type_names.size(); ++t) {
    if (ex.builtin) {
      out.push_back(int(t % stencils.size()));
      continue;
    }
    const std::string& name = ex.type_names[t];
    if (name.empty()) {  // no "type": the scene's first stencil
      out.push_back(0);
      continue;
    }
    auto it = std::find(stencils.begin(), stencils.end(), name);
    if (it == stencils.end()) {
      std::string list;
      for (const auto& s : stencils) list += (list.empty() ? "" : ", ") + s;
      size_t first = 0;
      while (first < ex.elements.size() && ex.elements[first].type != int(t)) ++first;
      throw InputError(fmt::format("{}: {}/elements/{}/type: '{}' is not a stencil of this scene "
                                   "(stencils: {})",
                                   origin, path, first, name, list));
    }
    out.push_back(int(it - stencils.begin()));
  }
  return out;
}

json exemplar_to_json(const Exemplar& ex) {
  json dom = json::array();
  for (const Vec2& p : ex.domain) dom.push_back({p.x(), p.y()});
  json elems = json::array();
  for (const auto& e : ex.elements)
    elems.push_back({{"position", {e.position.x(), e.position.y()}},
                     {"scale", e.scale},
                     {"type", ex.type_names[size_t(e.type)]},
                     {"angle", e.angle}});
  return {{"domain", dom}, {"elements", elems}, {"symmetry", ex.symmetry}};
}

}  // namespace cutwork
