#include "host/stencil/stencil_shape.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <sstream>

#include <Eigen/Geometry>

#include "host/core/error.h"
#include "host/core/internal_error.h"

namespace cutwork {
namespace {

constexpr double kPi = std::numbers::pi;

std::string join(const std::vector<std::string>& items) {
  std::string s;
  for (size_t i = 0; i < items.size(); ++i) s += (i ? ", " : "") + items[i];
  return s;
}

std::string format_number(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::string range_text(const StencilParamInfo& p) {
  std::string s = p.integer ? "an integer in " : "a number in ";
  s += p.min_inclusive ? "[" : "(";
  s += format_number(p.min) + ", " + format_number(p.max);
  s += p.max_inclusive ? "]" : ")";
  return s;
}

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
double orient(const Vec2& a, const Vec2& b, const Vec2& c) { return cross(b - a, c - a); }

double signed_area(const std::vector<Vec2>& p) {
  double a = 0;
  for (size_t i = 0, n = p.size(); i < n; ++i) a += cross(p[i], p[(i + 1) % n]);
  return 0.5 * a;
}

bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a.x(), b.x()) <= p.x() && p.x() <= std::max(a.x(), b.x()) &&
         std::min(a.y(), b.y()) <= p.y() && p.y() <= std::max(a.y(), b.y());
}

/// Closed segments [a, b] and [c, d] share at least one point.
bool segments_touch(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
               o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
    return true;
  return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) ||
         (o3 == 0 && on_segment(c, d, a)) || (o4 == 0 && on_segment(c, d, b));
}

bool point_in_polygon(const std::vector<Vec2>& p, const Vec2& q) {
  bool inside = false;
  for (size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) {
    if ((p[i].y() > q.y()) != (p[j].y() > q.y()) &&
        q.x() < (p[j].x() - p[i].x()) * (q.y() - p[i].y()) / (p[j].y() - p[i].y()) + p[i].x())
      inside = !inside;
  }
  return inside;
}

struct Circle {
  Vec2 center = Vec2::Zero();
  double radius = -1;
  bool contains(const Vec2& p) const {
    return (p - center).norm() <= radius * (1 + 1e-14) + 1e-300;
  }
};

Circle circle_from(const Vec2& a, const Vec2& b) { return {0.5 * (a + b), 0.5 * (a - b).norm()}; }

Circle circle_from(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Vec2 ab = b - a, ac = c - a;
  const double d = 2 * cross(ab, ac);
  if (!(std::abs(d) > 1e-12 * ab.norm() * ac.norm())) {
    // (Nearly) collinear: the diametral circle of the farthest pair.
    Circle best = circle_from(a, b);
    for (const Circle& c2 : {circle_from(a, c), circle_from(b, c)})
      if (c2.radius > best.radius) best = c2;
    return best;
  }
  const Vec2 u(ac.y() * ab.squaredNorm() - ab.y() * ac.squaredNorm(),
               ab.x() * ac.squaredNorm() - ac.x() * ab.squaredNorm());
  const Vec2 center = a + u / d;
  return {center, std::max({(center - a).norm(), (center - b).norm(), (center - c).norm()})};
}

/// Minimum enclosing circle (Welzl's algorithm in its iterative form, on a fixed-seed shuffle
/// so that the expected cost is linear and the result deterministic).
Circle min_enclosing_circle(std::vector<Vec2> pts) {
  std::mt19937 rng(12345);
  std::shuffle(pts.begin(), pts.end(), rng);
  Circle c{pts[0], 0};
  for (size_t i = 1; i < pts.size(); ++i) {
    if (c.contains(pts[i])) continue;
    c = {pts[i], 0};
    for (size_t j = 0; j < i; ++j) {
      if (c.contains(pts[j])) continue;
      c = circle_from(pts[i], pts[j]);
      for (size_t k = 0; k < j; ++k) {
        if (!c.contains(pts[k])) c = circle_from(pts[i], pts[j], pts[k]);
      }
    }
  }
  return c;
}

}  // namespace

double segment_distance(const Vec2& a, const Vec2& b, const Vec2& p) {
  const Vec2 e = b - a;
  const double len2 = e.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(e) / len2, 0.0, 1.0) : 0.0;
  return (a + t * e - p).norm();
}

bool point_in_polygon(const std::vector<Vec2>& polygon, const Vec2& p) {
  bool inside = false;
  for (size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

namespace {

/// A shape's area, perimeter and inner radius from its polygon (in the reference frame).
void measure_shape(StencilShape& s) {
  const size_t n = s.polygon.size();
  s.area = signed_area(s.polygon);
  s.perimeter = 0;
  for (size_t i = 0; i < n; ++i) s.perimeter += (s.polygon[(i + 1) % n] - s.polygon[i]).norm();
  s.inner_radius = 0;
  if (point_in_polygon(s.polygon, Vec2::Zero())) {
    double d = 1;
    for (size_t i = 0; i < n; ++i)
      d = std::min(d, segment_distance(s.polygon[i], s.polygon[(i + 1) % n], Vec2::Zero()));
    s.inner_radius = d * (1 - 1e-12);  // conservative: "inside the disk" must imply "inside"
  }
}

/// Validation and normalisation shared by built-in and user polygons.
StencilShape finalize(const std::string& name, const std::string& kind, std::vector<Vec2> pts) {
  const std::string who = "stencil shape '" + name + "'";
  for (const Vec2& p : pts) {
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()))
      throw InputError(who + ": polygon has a non-finite coordinate");
  }
  // Drop exact consecutive duplicates, including a closing copy of the first point.
  std::vector<Vec2> clean;
  for (const Vec2& p : pts) {
    if (clean.empty() || p != clean.back()) clean.push_back(p);
  }
  while (clean.size() > 1 && clean.back() == clean.front()) clean.pop_back();
  const size_t n = clean.size();
  if (n < 3)
    throw InputError(who + ": polygon needs at least 3 distinct points (got " +
                     std::to_string(n) + ")");
  if (n > size_t(kMaxStencilPolygonVertices))
    throw InputError(who + ": polygon has " + std::to_string(n) + " points (at most " +
                     std::to_string(kMaxStencilPolygonVertices) + " are accepted; simplify it)");
  Eigen::AlignedBox2d box;
  for (const Vec2& p : clean) box.extend(p);
  const double area = signed_area(clean);
  if (!(std::abs(area) > 1e-12 * box.sizes().squaredNorm()))
    throw InputError(who + ": polygon has zero area");
  // Simple: non-neighbouring edges share no point; neighbouring edges do not fold back.
  for (size_t i = 0; i < n; ++i) {
    const Vec2 &a = clean[i], &b = clean[(i + 1) % n], &c = clean[(i + 2) % n];
    if (n > 3 && orient(a, b, c) == 0 && (b - a).dot(c - b) < 0)
      throw InputError(who + ": polygon folds back on itself at point " +
                       std::to_string((i + 1) % n) + " (it must be simple)");
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // neighbours through the closing edge
      if (segments_touch(a, b, clean[j], clean[(j + 1) % n]))
        throw InputError(who + ": polygon edges " + std::to_string(i) + " and " +
                         std::to_string(j) + " intersect (the polygon must be simple)");
    }
  }
  if (area < 0) std::reverse(clean.begin(), clean.end());

  const Circle mec = min_enclosing_circle(clean);
  StencilShape s;
  s.name = name;
  s.kind = kind;
  s.polygon.reserve(n);
  for (const Vec2& p : clean) s.polygon.push_back((p - mec.center) / mec.radius);
  // Round-off can leave a vertex a few ulps outside the unit circle; pull it in so that the
  // kernel's bounding-circle exit is exact.
  double rmax = 0;
  for (const Vec2& p : s.polygon) rmax = std::max(rmax, p.norm());
  if (rmax > 1)
    for (Vec2& p : s.polygon) p /= rmax;
  measure_shape(s);
  return s;
}

// ---- built-in kinds ---------------------------------------------------------------------------

StencilParamInfo int_param(const std::string& name, double def, double lo, double hi,
                           const std::string& what) {
  return {name, def, lo, hi, true, true, true, what};
}
StencilParamInfo real_param(const std::string& name, double def, double lo, double hi,
                            bool lo_in, bool hi_in, const std::string& what) {
  return {name, def, lo, hi, lo_in, hi_in, false, what};
}

std::vector<Vec2> regular(int n, double radius, double phase) {
  std::vector<Vec2> p;
  for (int i = 0; i < n; ++i) {
    const double a = phase + 2 * kPi * i / n;
    p.emplace_back(radius * std::cos(a), radius * std::sin(a));
  }
  return p;
}

/// Signed angular difference in (−π, π].
double angle_diff(double a, double b) {
  double d = std::fmod(a - b, 2 * kPi);
  if (d > kPi) d -= 2 * kPi;
  if (d <= -kPi) d += 2 * kPi;
  return d;
}

std::vector<Vec2> build_kind(const std::string& kind, const std::map<std::string, double>& v) {
  auto get = [&](const char* key) { return v.at(key); };
  if (kind == "circle") return regular(int(get("segments")), 1, 0);
  if (kind == "ellipse") {
    const int n = int(get("segments"));
    std::vector<Vec2> p;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * kPi * i / n;
      p.emplace_back(std::cos(a), get("aspect") * std::sin(a));
    }
    return p;
  }
  if (kind == "square") return {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  if (kind == "star") {
    const int n = int(get("points"));
    std::vector<Vec2> p;
    for (int i = 0; i < 2 * n; ++i) {
      const double r = i % 2 == 0 ? 1.0 : get("inner_ratio");
      const double a = kPi / 2 + kPi * i / n;  // first point straight up
      p.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    return p;
  }
  if (kind == "flower") {
    // r(θ) = 1 − d + d |cos(P (θ − π/2) / 2)|: round petals, pointed notches between them.
    const int petals = int(get("petals"));
    const double depth = get("petal_depth");
    const int n = 16 * petals;
    std::vector<Vec2> p;
    for (int i = 0; i < n; ++i) {
      const double a = kPi / 2 + 2 * kPi * i / n;
      const double r = 1 - depth + depth * std::abs(std::cos(petals * (a - kPi / 2) / 2));
      p.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    return p;
  }
  if (kind == "leaf") {
    // A lens: two circular arcs through the tips (±1, 0), half-width w at the middle; the
    // tips lie along the stencil's x axis (its orientation).
    const double w = get("width");
    const int n = int(get("segments"));
    const int half = std::max(2, n / 2);
    std::vector<Vec2> p;
    if (w >= 1) return regular(n, 1, 0);
    const double radius = (1 + w * w) / (2 * w), c = radius - w;
    const double a0 = std::atan2(c, 1.0), a1 = kPi - a0;  // arc from (1,0) to (−1,0)
    for (int i = 0; i < half; ++i) {
      const double a = a0 + (a1 - a0) * i / half;
      p.emplace_back(radius * std::cos(a), radius * std::sin(a) - c);
    }
    for (int i = 0; i < half; ++i) {
      const double a = a0 + (a1 - a0) * i / half;
      p.emplace_back(-radius * std::cos(a), -(radius * std::sin(a) - c));
    }
    return p;
  }
  if (kind == "apple") {
    // A slightly wide round body with a dent at the top (where the stem sits) and a shallow
    // one at the bottom.
    const double dent = get("dent");
    const int n = int(get("segments"));
    std::vector<Vec2> p;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * kPi * i / n;
      const double top = angle_diff(a, kPi / 2) / 0.45, bottom = angle_diff(a, -kPi / 2) / 0.5;
      const double r = 1 - dent * std::exp(-top * top) - 0.25 * dent * std::exp(-bottom * bottom);
      p.emplace_back(1.08 * r * std::cos(a), r * std::sin(a));
    }
    return p;
  }
  if (kind == "heart") {
    const int n = int(get("segments"));
    std::vector<Vec2> p;
    for (int i = 0; i < n; ++i) {
      const double t = 2 * kPi * i / n;
      const double s = std::sin(t);
      p.emplace_back(16 * s * s * s,
                     13 * std::cos(t) - 5 * std::cos(2 * t) - 2 * std::cos(3 * t) -
                         std::cos(4 * t));
    }
    return p;
  }
  if (kind == "cross") {
    const double h = get("arm_width") / 2;
    return {{-h, -1}, {h, -1}, {h, -h}, {1, -h}, {1, h},   {h, h},
            {h, 1},   {-h, 1}, {-h, h}, {-1, h}, {-1, -h}, {-h, -h}};
  }
  throw InternalError("unhandled stencil kind " + kind);
}

}  // namespace

const std::vector<StencilKindInfo>& builtin_stencil_info() {
  static const std::vector<StencilKindInfo> info = {
      {"circle", "regular polygon approximating a circle",
       {int_param("segments", 64, 3, 1024, "number of vertices")}},
      {"ellipse", "ellipse with its major axis along the stencil's orientation",
       {real_param("aspect", 0.6, 0, 1, false, true, "minor / major axis"),
        int_param("segments", 64, 8, 1024, "number of vertices")}},
      {"square", "axis-aligned square (sides parallel to the orientation)", {}},
      {"star", "star with sharp points",
       {int_param("points", 5, 3, 64, "number of points"),
        real_param("inner_ratio", 0.5, 0, 1, false, false,
                   "radius of the inner corners / radius of the points")}},
      {"flower", "round petals with pointed notches between them",
       {int_param("petals", 6, 3, 32, "number of petals"),
        real_param("petal_depth", 0.35, 0, 0.9, true, true,
                   "depth of the notches, fraction of the radius")}},
      {"leaf", "lens with two pointed tips along the orientation",
       {real_param("width", 0.5, 0, 1, false, true, "width / length"),
        int_param("segments", 48, 8, 1024, "number of vertices")}},
      {"apple", "round body with a dent at the top",
       {real_param("dent", 0.25, 0, 0.6, true, true, "depth of the top dent, fraction of radius"),
        int_param("segments", 64, 16, 1024, "number of vertices")}},
      {"heart", "heart (the classic parametric curve)",
       {int_param("segments", 96, 16, 1024, "number of vertices")}},
      {"cross", "plus sign with square arm ends",
       {real_param("arm_width", 0.4, 0, 1, false, false, "arm width / arm span")}},
  };
  return info;
}

const std::vector<std::string>& builtin_stencil_kinds() {
  static const std::vector<std::string> kinds = [] {
    std::vector<std::string> k;
    for (const StencilKindInfo& i : builtin_stencil_info()) k.push_back(i.kind);
    return k;
  }();
  return kinds;
}

StencilShape make_builtin_stencil(const std::string& kind,
                                  const std::map<std::string, double>& params,
                                  const std::string& name) {
  const std::string who = "stencil shape '" + name + "'";
  const auto& all = builtin_stencil_info();
  const auto it = std::find_if(all.begin(), all.end(),
                               [&](const StencilKindInfo& i) { return i.kind == kind; });
  if (it == all.end())
    throw InputError(who + ": unknown kind '" + kind + "' (accepted: " +
                     join(builtin_stencil_kinds()) + ", or a polygon)");
  std::map<std::string, double> values;
  std::vector<std::string> accepted;
  for (const StencilParamInfo& p : it->params) {
    values[p.name] = p.default_value;
    accepted.push_back(p.name);
  }
  for (const auto& entry : params) {
    const std::string& key = entry.first;  // (a plain variable: clang 14 cannot capture a structured binding)
    const double value = entry.second;
    const auto pit = std::find_if(it->params.begin(), it->params.end(),
                                  [&](const StencilParamInfo& p) { return p.name == key; });
    if (pit == it->params.end())
      throw InputError(who + ": kind '" + kind + "' has no parameter '" + key + "' (accepted: " +
                       (accepted.empty() ? std::string("none") : join(accepted)) + ")");
    const bool ok = std::isfinite(value) &&
                    (pit->min_inclusive ? value >= pit->min : value > pit->min) &&
                    (pit->max_inclusive ? value <= pit->max : value < pit->max) &&
                    (!pit->integer || value == std::round(value));
    if (!ok)
      throw InputError(who + ": parameter '" + key + "' = " + format_number(value) +
                       " is out of range (expected " + range_text(*pit) + ")");
    values[key] = value;
  }
  return finalize(name, kind, build_kind(kind, values));
}

StencilShape make_polygon_stencil(const std::string& name, const std::vector<Vec2>& pts) {
  return finalize(name, "polygon", pts);
}

double polygon_signed_area(const std::vector<Vec2>& polygon) { return signed_area(polygon); }

StencilShape shape_in_reference_frame(const std::string& name, const std::string& kind, std::vector<Vec2> polygon) {
  const std::string who = "stencil shape '" + name + "'";
  if (polygon.size() < 3 || polygon.size() > size_t(kMaxStencilPolygonVertices))
    throw InputError(who + ": polygon has " + std::to_string(polygon.size()) + " points (3 to " +
                     std::to_string(kMaxStencilPolygonVertices) + " are accepted)");
  for (const Vec2& p : polygon)
    if (!(p.norm() <= 1 + 1e-12)) throw InputError(who + ": polygon leaves the unit circle of its frame");
  StencilShape s;
  s.name = name;
  s.kind = kind;
  s.polygon = std::move(polygon);
  for (Vec2& p : s.polygon)
    if (p.norm() > 1) p /= p.norm();
  measure_shape(s);
  if (!(s.area > 0)) throw InputError(who + ": polygon is not counter-clockwise or has zero area");
  return s;
}

int StencilLibrary::add(StencilShape shape) {
  if (find(shape.name) >= 0)
    throw InputError("stencil shape '" + shape.name + "': the name is used twice");
  if (shape.polygon.size() < 3)
    throw InputError("stencil shape '" + shape.name + "': no polygon (build it with "
                     "make_builtin_stencil or make_polygon_stencil)");
  shape.type = size();
  kernels::ClipShape cs{};
  cs.polygon_offset = int32_t(m_packed.size() / 2);
  cs.polygon_count = int32_t(shape.polygon.size());
  cs.area = shape.area;
  cs.inner_radius = shape.inner_radius;
  for (const Vec2& p : shape.polygon) {
    m_packed.push_back(p.x());
    m_packed.push_back(p.y());
  }
  m_clip_shapes.push_back(cs);
  m_shapes.push_back(std::move(shape));
  return m_shapes.back().type;
}

int StencilLibrary::find(const std::string& name) const {
  for (const StencilShape& s : m_shapes)
    if (s.name == name) return s.type;
  return -1;
}

}  // namespace cutwork
