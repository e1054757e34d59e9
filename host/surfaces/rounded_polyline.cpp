#include "host/surfaces/rounded_polyline.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cutwork::shapes_detail {

namespace {

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

/// Signed turning angle at interior corner i (positive = left turn).
double turning_angle(const std::vector<Vec2>& corners, std::size_t i) {
  const Vec2 d_in = (corners[i] - corners[i - 1]).normalized();
  const Vec2 d_out = (corners[i + 1] - corners[i]).normalized();
  return std::atan2(cross2(d_in, d_out), d_in.dot(d_out));
}

}  // namespace

double RoundedPolyline::max_radius(const std::vector<Vec2>& corners) {
  const std::size_t n = corners.size();
  auto consumed_per_radius = [&](std::size_t i) {
    return (i == 0 || i + 1 >= n) ? 0.0 : std::tan(0.5 * std::abs(turning_angle(corners, i)));
  };
  double limit = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double k = consumed_per_radius(i) + consumed_per_radius(i + 1);
    if (k > 0) limit = std::min(limit, (corners[i + 1] - corners[i]).norm() / k);
  }
  return limit;
}

RoundedPolyline::RoundedPolyline(const std::vector<Vec2>& corners, double radius) {
  const std::size_t n = corners.size();
  Vec2 current = corners.front();
  auto add_line = [&](const Vec2& to) {
    const double length = (to - current).norm();
    // A segment fully consumed by its two fillets leaves a zero-length piece: skip it.
    if (length > 1e-14) {
      Piece line;
      line.begin = m_length;
      line.length = length;
      line.start = current;
      line.end = to;
      line.direction = (to - current) / length;
      m_pieces.push_back(line);
      m_length += length;
    }
    current = to;
  };
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double delta = turning_angle(corners, i);
    const double cut = radius * std::tan(0.5 * std::abs(delta));
    if (radius <= 0 || cut <= 1e-14) continue;  // straight continuation: nothing to round
    const Vec2 d_in = (corners[i] - corners[i - 1]).normalized();
    const Vec2 d_out = (corners[i + 1] - corners[i]).normalized();
    const Vec2 arc_start = corners[i] - cut * d_in;
    const Vec2 arc_end = corners[i] + cut * d_out;
    add_line(arc_start);
    Piece arc;
    arc.arc = true;
    arc.begin = m_length;
    arc.length = radius * std::abs(delta);
    arc.turn = delta > 0 ? 1.0 : -1.0;
    arc.radius = radius;
    arc.centre = arc_start + arc.turn * radius * Vec2(-d_in.y(), d_in.x());
    arc.angle0 = std::atan2(arc_start.y() - arc.centre.y(), arc_start.x() - arc.centre.x());
    arc.start = arc_start;
    arc.end = arc_end;
    m_pieces.push_back(arc);
    m_length += arc.length;
    current = arc_end;
  }
  add_line(corners.back());
}

const RoundedPolyline::Piece& RoundedPolyline::piece_at(double s) const {
  // Last piece whose begin ≤ s (pieces are sorted by begin).
  auto it = std::upper_bound(m_pieces.begin(), m_pieces.end(), s,
                             [](double value, const Piece& p) { return value < p.begin; });
  return it == m_pieces.begin() ? m_pieces.front() : *(it - 1);
}

Vec2 RoundedPolyline::point(double s) const {
  // The ends exactly, whatever rounding the piece lengths accumulated (feet on z = 0).
  if (s <= 0) return m_pieces.front().start;
  if (s >= m_length) return m_pieces.back().end;
  const Piece& p = piece_at(s);
  const double sigma = std::clamp(s - p.begin, 0.0, p.length);
  if (!p.arc) {
    // Measured from the nearer end so both ends are reproduced exactly (feet on z = 0).
    return sigma <= 0.5 * p.length ? Vec2(p.start + sigma * p.direction)
                                   : Vec2(p.end - (p.length - sigma) * p.direction);
  }
  const double angle = p.angle0 + p.turn * sigma / p.radius;
  return p.centre + p.radius * Vec2(std::cos(angle), std::sin(angle));
}

std::vector<double> RoundedPolyline::breaks() const {
  std::vector<double> out;
  for (const Piece& piece : m_pieces) out.push_back(piece.begin);
  out.push_back(m_length);
  if (out.front() != 0.0) out.insert(out.begin(), 0.0);
  return out;
}

double RoundedPolyline::radius_at(double s) const {
  const Piece& piece = piece_at(s);
  return piece.arc ? piece.radius : INFINITY;
}

Vec2 RoundedPolyline::tangent(double s) const {
  s = std::clamp(s, 0.0, m_length);
  const Piece& p = piece_at(s);
  if (!p.arc) return p.direction;
  const double angle = p.angle0 + p.turn * std::clamp(s - p.begin, 0.0, p.length) / p.radius;
  return p.turn * Vec2(-std::sin(angle), std::cos(angle));
}

}  // namespace cutwork::shapes_detail
