#include "host/stencil/stencil_opening.h"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Gps_circle_segment_traits_2.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/approximated_offset_2.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <list>
#include <numbers>

#include <fmt/format.h>

#include "host/core/error.h"

namespace cutwork {
namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Traits = CGAL::Gps_circle_segment_traits_2<Kernel>;
using LinearPolygon = CGAL::Polygon_2<Kernel>;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// No corner of the polygon is sharp at r: every vertex where it turns towards its inside (a convex
/// vertex) turns by at most kToolCornerTurn and its fillet of radius r fits within half of each of
/// its edges (its local radius, edge / turn, is at least about r). Such a polygon is a smooth curve
/// written as segments (a flower's petals), which the tool follows; its kinks are the writing's.
bool smooth_at(std::span<const Vec2> p, double r, bool* convex) {
  const size_t n = p.size();
  *convex = true;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = p[i] - p[(i + n - 1) % n], b = p[(i + 1) % n] - p[i];
    const double turn = std::atan2(cross(a, b), a.dot(b));
    if (turn < 0) {
      *convex = false;
      continue;
    }
    if (turn > kToolCornerTurn) return false;
    if (r * std::tan(0.5 * turn) > 0.5 * std::min(a.norm(), b.norm())) return false;
  }
  return true;
}

/// Appends a circular arc's interior points (the ends are the neighbouring curves'), from angle a0
/// turning by d (signed) about c at radius r: on the circle (inscribed), or on the tangents'
/// intersections at radius r / cos(Δ/2) (circumscribed), at most `step` per segment.
void append_arc(std::vector<Vec2>& out, const Vec2& c, double r, double a0, double d, double step, bool circumscribed) {
  const int n = std::max(1, int(std::ceil(std::abs(d) / step)));
  const double delta = d / n;
  if (circumscribed) {
    const double rr = r / std::cos(0.5 * delta);
    for (int k = 0; k < n; ++k) {
      const double a = a0 + (k + 0.5) * delta;
      out.emplace_back(c.x() + rr * std::cos(a), c.y() + rr * std::sin(a));
    }
  } else {
    for (int k = 1; k < n; ++k) {
      const double a = a0 + k * delta;
      out.emplace_back(c.x() + r * std::cos(a), c.y() + r * std::sin(a));
    }
  }
}

/// The smallest distance between two edges of the polygon that share no vertex (brute force, n²/2
/// pairs; each pair's distance is the least of its four vertex-to-edge distances, since
/// two edges of a simple polygon do not cross).
double narrowest_neck(std::span<const Vec2> p) {
  const size_t n = p.size();
  double d = INFINITY;
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent across the wrap
      const Vec2 &a = p[i], &b = p[(i + 1) % n], &c = p[j], &e = p[(j + 1) % n];
      d = std::min({d, segment_distance(a, b, c), segment_distance(a, b, e), segment_distance(c, e, a),
                    segment_distance(c, e, b)});
    }
  return d;
}

/// A polygon of line segments and circular arcs as a polyline (see append_arc), points closer than
/// `merge` to the last kept one dropped.
std::vector<Vec2> linearise(const Traits::Polygon_2& g, double step, bool circumscribed, double merge) {
  std::vector<Vec2> out;
  for (auto c = g.curves_begin(); c != g.curves_end(); ++c) {
    const Vec2 s(CGAL::to_double(c->source().x()), CGAL::to_double(c->source().y()));
    out.push_back(s);
    if (!c->is_circular()) continue;
    const Vec2 t(CGAL::to_double(c->target().x()), CGAL::to_double(c->target().y()));
    const auto& circle = c->supporting_circle();
    const Vec2 centre(CGAL::to_double(circle.center().x()), CGAL::to_double(circle.center().y()));
    const double r = std::sqrt(CGAL::to_double(circle.squared_radius()));
    const double a0 = std::atan2(s.y() - centre.y(), s.x() - centre.x());
    const double a1 = std::atan2(t.y() - centre.y(), t.x() - centre.x());
    double d = a1 - a0;
    if (c->orientation() == CGAL::COUNTERCLOCKWISE) {
      while (d <= 0) d += 2 * std::numbers::pi;
    } else {
      while (d >= 0) d -= 2 * std::numbers::pi;
    }
    append_arc(out, centre, r, a0, d, step, circumscribed);
  }
  std::vector<Vec2> clean;
  for (const Vec2& p : out)
    if (clean.empty() || (p - clean.back()).norm() > merge) clean.push_back(p);
  while (clean.size() > 1 && (clean.back() - clean.front()).norm() <= merge) clean.pop_back();
  return clean;
}

LinearPolygon to_cgal(std::span<const Vec2> p) {
  LinearPolygon q;
  for (const Vec2& v : p) q.push_back(Kernel::Point_2(v.x(), v.y()));
  return q;
}

}  // namespace

bool fillet_polygon(std::span<const Vec2> polygon, double radius, double arc_step, std::vector<Vec2>& out) {
  const size_t n = polygon.size();
  out.clear();
  for (size_t i = 0; i < n; ++i) {
    const Vec2 &p = polygon[(i + n - 1) % n], &v = polygon[i], &q = polygon[(i + 1) % n];
    const Vec2 a = v - p, b = q - v;
    const double turn = std::atan2(cross(a, b), a.dot(b));
    if (turn <= arc_step) {  // a notch (turning away), or a fillet within r (1/cos(step/2) − 1) of v
      out.push_back(v);
      continue;
    }
    const double t = radius * std::tan(0.5 * turn);  // from v to the fillet's tangent points
    if (t > 0.5 * std::min(a.norm(), b.norm())) return false;
    const Vec2 ua = a.normalized(), ub = b.normalized();
    const Vec2 start = v - t * ua, end = v + t * ub, centre = start + radius * Vec2(-ua.y(), ua.x());
    out.push_back(start);
    append_arc(out, centre, radius, std::atan2(start.y() - centre.y(), start.x() - centre.x()), turn, arc_step, false);
    out.push_back(end);
  }
  return narrowest_neck(polygon) >= 2 * radius;
}

OpenedPolygon open_polygon(std::span<const Vec2> polygon, double radius, double arc_step) {
  if (!(radius > 0) || !std::isfinite(radius))
    throw InputError(fmt::format("polygon opening: the radius must be finite and positive (got {})", radius));
  if (polygon.size() < 3) throw InputError("polygon opening: the polygon needs at least 3 points");
  if (!(arc_step > 0) || !(arc_step <= std::numbers::pi / 2))
    throw InputError(fmt::format("polygon opening: the arc step must be in (0, pi/2] (got {})", arc_step));
  OpenedPolygon out;
  bool convex = true;
  const bool smooth = smooth_at(polygon, radius, &convex);
  if (smooth && convex) {  // a disc of radius r rolls freely inside it (Blaschke)
    out.polygon.assign(polygon.begin(), polygon.end());
    out.components = 1;
    out.unchanged = true;
    return out;
  }
  // A tool far smaller than the polygon (under kFilletOpening of its size) whose fillets fit: the
  // fillets themselves. CGAL's offsets there left needles of no width (the default heart opened by
  // 1e-4 of its size had a vertex on another edge; the leaf at 1e-7), which the cut made into holes
  // touching at a point and the solid into a non-manifold one.
  double size = 0;
  for (const Vec2& v : polygon) size = std::max(size, (v - polygon[0]).norm());
  if (radius < kFilletOpening * size && fillet_polygon(polygon, radius, arc_step, out.polygon)) {
    out.components = 1;
    return out;
  }
  out.polygon.clear();
  // Points closer than 1e-3 r are one: CGAL's arcs between nearly coincident points would leave
  // pieces of 1e-8 r, which the cut (host/cut) would make into vertices a few 1e-10 m apart.
  const double eps = 1e-6 * radius, merge = 1e-3 * radius;
  const LinearPolygon p = to_cgal(polygon);
  std::list<Traits::Polygon_2> insets;
  CGAL::approximated_inset_2(p, radius, eps, std::back_inserter(insets));
  double best = 0;
  for (const Traits::Polygon_2& inset : insets) {
    // The inset's arcs (about the notches) circumscribed at π/8 per segment: inside the inset, so
    // the dilation below stays inside the polygon.
    const std::vector<Vec2> eroded = linearise(inset, std::numbers::pi / 8, true, merge);
    if (eroded.size() < 3) continue;
    ++out.components;
    const auto dilated = CGAL::approximated_offset_2(to_cgal(eroded), radius, eps);
    std::vector<Vec2> q = linearise(dilated.outer_boundary(), arc_step, false, merge);
    if (q.size() < 3) continue;
    if (polygon_signed_area(q) < 0) std::reverse(q.begin(), q.end());
    const double a = polygon_signed_area(q);
    if (a > best) {
      best = a;
      out.polygon = std::move(q);
    }
  }
  // Smooth but not convex: the tool follows the drawn outline unless a neck is narrower than 2r
  // (the opening in pieces) or nothing fits.
  if (smooth && out.components == 1) {
    out.polygon.assign(polygon.begin(), polygon.end());
    out.unchanged = true;
  }
  return out;
}

ToolCutStencils tool_cut_stencils(const StencilLibrary& shapes, std::span<const StencilParams> stencils,
                                  double tool_radius) {
  const int n = int(stencils.size());
  for (int i = 0; i < n; ++i) {
    const StencilParams& s = stencils[size_t(i)];
    if (s.type < 0 || s.type >= shapes.size())
      throw InputError(fmt::format("stencil {}: type {} is not one of the {} shapes", i, s.type, shapes.size()));
    if (!(s.scale > 0) || !std::isfinite(s.scale))
      throw InputError(fmt::format("stencil {}: scale {} is not finite and positive", i, s.scale));
  }
  std::vector<OpenedPolygon> cut(static_cast<size_t>(n));
  if (tool_radius > 0) {
    tbb::parallel_for(tbb::blocked_range<int>(0, n), [&](const tbb::blocked_range<int>& range) {
      for (int i = range.begin(); i < range.end(); ++i) {
        const StencilParams& s = stencils[size_t(i)];
        cut[size_t(i)] = open_polygon(shapes[s.type].polygon, tool_radius / s.scale);
      }
    });
  }
  ToolCutStencils out;
  out.stencils.assign(stencils.begin(), stencils.end());
  for (int i = 0; i < n; ++i) {
    const StencilShape& shape = shapes[stencils[size_t(i)].type];
    OpenedPolygon& o = cut[size_t(i)];
    std::vector<Vec2> polygon = shape.polygon;
    if (tool_radius > 0) {
      if (o.polygon.size() < 3) {
        ++out.too_small;
      } else {
        if (o.components > 1) ++out.split;
        if (!o.unchanged) {
          ++out.rounded;
          polygon = std::move(o.polygon);
          for (Vec2& p : polygon)  // inside the drawn polygon up to the offsets' ε
            if (p.norm() > 1) p /= p.norm();
        }
      }
    }
    StencilShape cut_shape = shape_in_reference_frame(fmt::format("{}@{}", shape.name, i), shape.kind, std::move(polygon));
    out.stencils[size_t(i)].type = out.shapes.add(std::move(cut_shape));
  }
  return out;
}

}  // namespace cutwork
