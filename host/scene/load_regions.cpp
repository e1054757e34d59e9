#include "host/scene/load_regions.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

namespace cutwork {

namespace {

bool has_ball(const Selector& sel) { return sel.near_point && std::isfinite(sel.near_radius); }

bool inside_region(const Selector& sel, const Vec3& x) {
  for (int k = 0; k < 3; ++k)
    if (!(x[k] > sel.above[k] && x[k] < sel.below[k])) return false;
  return !has_ball(sel) || (x - *sel.near_point).squaredNorm() <= sel.near_radius * sel.near_radius;
}

/// Sutherland–Hodgman: keeps the part of the convex polygon `poly` where sign·(x_k − bound) > 0.
void clip_half_space(std::vector<Vec3>& poly, int k, double bound, double sign) {
  if (poly.empty()) return;
  std::vector<Vec3> out;
  out.reserve(poly.size() + 1);
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec3& p = poly[i];
    const Vec3& q = poly[(i + 1) % poly.size()];
    const double dp = sign * (p[k] - bound), dq = sign * (q[k] - bound);
    if (dp >= 0) out.push_back(p);
    if ((dp >= 0) != (dq >= 0)) {
      const double t = dp / (dp - dq);
      Vec3 x = p + t * (q - p);
      x[k] = bound;  // exactly on the plane
      out.push_back(x);
    }
  }
  if (out.size() < 3) out.clear();
  poly = std::move(out);
}

double cross2(const Vec2& p, const Vec2& q) { return p.x() * q.y() - p.y() * q.x(); }

/// Area and first moment (about the disc's centre, the origin) of triangle(0, p, q) ∩ disc(0, R),
/// signed by the orientation of (p, q): a straight piece inside the disc is the triangle
/// (0, piece), a piece outside it the sector the piece subtends.
void edge_in_disc(const Vec2& p, const Vec2& q, double R, double& area, Vec2& moment) {
  const Vec2 d = q - p;
  const double A = d.squaredNorm();
  if (A == 0) return;
  const double B = 2 * p.dot(d), C = p.squaredNorm() - R * R;
  double cuts[4] = {0, 0, 0, 1};
  int n = 1;
  const double disc = B * B - 4 * A * C;
  if (disc > 0) {
    const double s = std::sqrt(disc);
    // (numerically stable roots)
    const double u = -0.5 * (B + std::copysign(s, B));
    double t1 = u / A, t2 = u != 0 ? C / u : t1;
    if (t1 > t2) std::swap(t1, t2);
    if (t1 > 0 && t1 < 1) cuts[n++] = t1;
    if (t2 > 0 && t2 < 1) cuts[n++] = t2;
  }
  cuts[n++] = 1;
  for (int j = 0; j + 1 < n; ++j) {
    const Vec2 a = p + cuts[j] * d, b = p + cuts[j + 1] * d;
    const Vec2 mid = 0.5 * (a + b);
    if (mid.squaredNorm() <= R * R) {
      const double t = 0.5 * cross2(a, b);
      area += t;
      moment += t * (a + b) / 3.0;
    } else {
      const double theta = std::atan2(cross2(a, b), a.dot(b));
      const double ta = std::atan2(a.y(), a.x()), tb = ta + theta;
      area += 0.5 * R * R * theta;
      moment += (R * R * R / 3.0) * Vec2(std::sin(tb) - std::sin(ta), std::cos(ta) - std::cos(tb));
    }
  }
}

}  // namespace

RegionMoment triangle_in_region(const Vec3& a, const Vec3& b, const Vec3& c, const Selector& sel) {
  RegionMoment m;
  const Vec3 normal = (b - a).cross(c - a);
  const double twice_area = normal.norm();
  if (!(twice_area > 0)) return m;
  // Whole triangle inside (the region is convex): no clipping.
  if (inside_region(sel, a) && inside_region(sel, b) && inside_region(sel, c)) {
    m.measure = 0.5 * twice_area;
    m.first_moment = m.measure * (a + b + c) / 3.0;
    return m;
  }
  std::vector<Vec3> poly{a, b, c};
  for (int k = 0; k < 3; ++k) {
    if (std::isfinite(sel.above[k])) clip_half_space(poly, k, sel.above[k], +1);
    if (std::isfinite(sel.below[k])) clip_half_space(poly, k, sel.below[k], -1);
  }
  if (poly.empty()) return m;
  if (!has_ball(sel)) {
    // Fan from the first corner: areas along the triangle's normal.
    const Vec3 n = normal / twice_area;
    for (size_t i = 1; i + 1 < poly.size(); ++i) {
      const double t = 0.5 * (poly[i] - poly[0]).cross(poly[i + 1] - poly[0]).dot(n);
      m.measure += t;
      m.first_moment += t * (poly[0] + poly[i] + poly[i + 1]) / 3.0;
    }
    return m;
  }
  // The ball cuts the disc of centre o and radius R from the triangle's plane.
  const Vec3 n = normal / twice_area;
  const double dist = (*sel.near_point - a).dot(n);
  const double r = sel.near_radius;
  if (std::abs(dist) >= r) return m;
  const Vec3 o = *sel.near_point - dist * n;
  const double R = std::sqrt(r * r - dist * dist);
  const Vec3 e1 = (b - a).normalized(), e2 = n.cross(e1);
  std::vector<Vec2> q(poly.size());
  for (size_t i = 0; i < poly.size(); ++i) q[i] = Vec2((poly[i] - o).dot(e1), (poly[i] - o).dot(e2));
  double area = 0;
  Vec2 moment = Vec2::Zero();
  for (size_t i = 0; i < q.size(); ++i) edge_in_disc(q[i], q[(i + 1) % q.size()], R, area, moment);
  if (!(area > 0)) return m;
  m.measure = area;
  m.first_moment = area * o + moment.x() * e1 + moment.y() * e2;
  return m;
}

RegionMoment segment_in_region(const Vec3& a, const Vec3& b, const Selector& sel) {
  RegionMoment m;
  const Vec3 d = b - a;
  const double length = d.norm();
  if (!(length > 0)) return m;
  double t0 = 0, t1 = 1;
  for (int k = 0; k < 3 && t0 < t1; ++k) {
    for (int side = 0; side < 2; ++side) {
      const double bound = side == 0 ? sel.above[k] : sel.below[k];
      if (!std::isfinite(bound)) continue;
      const double sign = side == 0 ? 1.0 : -1.0;  // keep sign·(a_k + t d_k − bound) > 0
      const double f0 = sign * (a[k] - bound), slope = sign * d[k];
      if (slope == 0) {
        if (!(f0 > 0)) t1 = t0;
        continue;
      }
      const double t = -f0 / slope;
      if (slope > 0) t0 = std::max(t0, t);
      else t1 = std::min(t1, t);
    }
  }
  if (t0 < t1 && has_ball(sel)) {
    const Vec3 p = a - *sel.near_point;
    const double A = d.squaredNorm(), B = 2 * p.dot(d), C = p.squaredNorm() - sel.near_radius * sel.near_radius;
    const double disc = B * B - 4 * A * C;
    if (disc <= 0) {
      t1 = t0;
    } else {
      const double s = std::sqrt(disc);
      t0 = std::max(t0, (-B - s) / (2 * A));
      t1 = std::min(t1, (-B + s) / (2 * A));
    }
  }
  if (!(t0 < t1)) return m;
  m.measure = length * (t1 - t0);
  m.first_moment = m.measure * (a + 0.5 * (t0 + t1) * d);
  return m;
}

Vec3 triangle_nodal_weights(const Vec3& a, const Vec3& b, const Vec3& c, const RegionMoment& m) {
  if (!(m.measure > 0)) return Vec3::Zero();
  const Vec3 g = m.first_moment / m.measure;
  const Vec3 v0 = b - a, v1 = c - a, v2 = g - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double denom = d00 * d11 - d01 * d01;
  const double lb = (d11 * d20 - d01 * d21) / denom, lc = (d00 * d21 - d01 * d20) / denom;
  return m.measure * Vec3(1 - lb - lc, lb, lc);
}

std::array<double, 2> segment_nodal_weights(const Vec3& a, const Vec3& b, const RegionMoment& m) {
  if (!(m.measure > 0)) return {0, 0};
  const Vec3 d = b - a;
  const double t = (m.first_moment / m.measure - a).dot(d) / d.squaredNorm();
  return {m.measure * (1 - t), m.measure * t};
}

}  // namespace cutwork
