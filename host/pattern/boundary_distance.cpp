#include "host/pattern/boundary_distance.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace cutwork {

namespace {

int64_t cell_of(double x, double cell) {
  return int64_t(std::floor(std::clamp(x / cell, -1e15, 1e15)));
}

}  // namespace

uint64_t BoundaryPolylines::key(int64_t x, int64_t y, int64_t z) {
  // 21 bits per axis (wrapping): collisions only merge buckets, never lose segments.
  const uint64_t m = (uint64_t(1) << 21) - 1;
  return (uint64_t(x) & m) | ((uint64_t(y) & m) << 21) | ((uint64_t(z) & m) << 42);
}

BoundaryPolylines::BoundaryPolylines(const SurfaceMesh& mesh, double cell_size, const PatternMirror* mirror)
    : m_cell(cell_size > 0 && std::isfinite(cell_size) ? cell_size : 1.0) {
  // Face normal on the surface side of each directed boundary edge (u -> v as the loop walks).
  const RowMatX3i& faces = mesh.faces();
  std::unordered_map<uint64_t, int> directed_edge_face;
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const uint64_t u = uint64_t(faces(f, k)), v = uint64_t(faces(f, (k + 1) % 3));
      directed_edge_face[(u << 32) | v] = f;
    }
  const RowMatX3d& V = mesh.vertices();
  int loop_index = 0;
  for (const auto& loop : mesh.boundary_loops()) {
    const int first = int(m_segments.size());
    const int n = int(loop.size());
    for (int k = 0; k < n; ++k) {
      const int u = loop[size_t(k)], v = loop[size_t((k + 1) % n)];
      Segment s;
      s.a = V.row(u).transpose();
      s.b = V.row(v).transpose();
      auto it = directed_edge_face.find((uint64_t(u) << 32) | uint64_t(v));
      Vec3 normal = Vec3::UnitZ();
      if (it != directed_edge_face.end()) {
        normal = mesh.face_normals().row(it->second).transpose();
      } else if ((it = directed_edge_face.find((uint64_t(v) << 32) | uint64_t(u))) !=
                 directed_edge_face.end()) {
        // Loop stored against the face orientation: the surface is on the right.
        normal = -mesh.face_normals().row(it->second).transpose();
      }
      s.inward = normal.cross(s.b - s.a).normalized();
      s.loop = loop_index;
      s.prev = first + (k + n - 1) % n;
      s.next = first + (k + 1) % n;
      m_segments.push_back(s);
    }
    ++loop_index;
  }
  if (mirror && mirror->any()) {
    const double tol = 1e-6 * (mesh.bbox_max() - mesh.bbox_min()).norm();
    std::vector<int> renumber(m_segments.size(), -1);
    std::vector<Segment> kept;
    for (size_t i = 0; i < m_segments.size(); ++i) {
      const Segment& s = m_segments[i];
      bool on_plane = false;
      for (int a = 0; a < 3; ++a)
        on_plane = on_plane || (mirror->has_plane(a) && std::abs(s.a[a] - mirror->planes()[a]) <= tol &&
                                std::abs(s.b[a] - mirror->planes()[a]) <= tol);
      if (on_plane) continue;
      renumber[i] = int(kept.size());
      kept.push_back(s);
    }
    for (size_t i = 0; i < kept.size(); ++i) {
      Segment& s = kept[i];
      s.prev = renumber[size_t(s.prev)] >= 0 ? renumber[size_t(s.prev)] : int(i);
      s.next = renumber[size_t(s.next)] >= 0 ? renumber[size_t(s.next)] : int(i);
    }
    m_segments = std::move(kept);
  }
  for (int i = 0; i < int(m_segments.size()); ++i) {
    const Segment& s = m_segments[size_t(i)];
    const Vec3 lo = s.a.cwiseMin(s.b), hi = s.a.cwiseMax(s.b);
    for (int64_t z = cell_of(lo.z(), m_cell); z <= cell_of(hi.z(), m_cell); ++z)
      for (int64_t y = cell_of(lo.y(), m_cell); y <= cell_of(hi.y(), m_cell); ++y)
        for (int64_t x = cell_of(lo.x(), m_cell); x <= cell_of(hi.x(), m_cell); ++x)
          m_buckets[key(x, y, z)].push_back(i);
  }
}

BoundaryPoint BoundaryPolylines::evaluate(int segment, const Vec3& p) const {
  const Segment& s = m_segments[size_t(segment)];
  const Vec3 ab = s.b - s.a;
  const double len2 = ab.squaredNorm();
  double t = len2 > 0 ? (p - s.a).dot(ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  BoundaryPoint out;
  out.segment = segment;
  out.point = t == 1.0 ? s.b : Vec3(s.a + t * ab);
  // At a polyline vertex the inward direction is the mean of the two segments' directions.
  if (t == 0.0)
    out.inward = (s.inward + m_segments[size_t(s.prev)].inward).normalized();
  else if (t == 1.0)
    out.inward = (s.inward + m_segments[size_t(s.next)].inward).normalized();
  else
    out.inward = s.inward;
  const Vec3 d = p - out.point;
  out.distance = d.norm();
  const double sign = d.dot(out.inward) >= 0 ? 1.0 : -1.0;
  out.signed_distance = sign * out.distance;
  out.gradient = out.distance > 0 ? Vec3(sign * d / out.distance) : Vec3::Zero();
  return out;
}

std::optional<BoundaryPoint> BoundaryPolylines::nearest(const Vec3& p, double max_distance) const {
  if (m_segments.empty()) return std::nullopt;
  const double r = max_distance;
  double cells = 1;
  for (int k = 0; k < 3; ++k) cells *= double(cell_of(p[k] + r, m_cell) - cell_of(p[k] - r, m_cell) + 1);
  if (!std::isfinite(r) || cells > double(m_segments.size()) + 27) return nearest_brute_force(p, max_distance);

  std::vector<int> candidates;
  for (int64_t z = cell_of(p.z() - r, m_cell); z <= cell_of(p.z() + r, m_cell); ++z)
    for (int64_t y = cell_of(p.y() - r, m_cell); y <= cell_of(p.y() + r, m_cell); ++y)
      for (int64_t x = cell_of(p.x() - r, m_cell); x <= cell_of(p.x() + r, m_cell); ++x) {
        auto it = m_buckets.find(key(x, y, z));
        if (it != m_buckets.end()) candidates.insert(candidates.end(), it->second.begin(), it->second.end());
      }
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  std::optional<BoundaryPoint> best;
  for (int i : candidates) {
    BoundaryPoint bp = evaluate(i, p);
    if (bp.distance <= max_distance && (!best || bp.distance < best->distance)) best = bp;
  }
  return best;
}

std::optional<BoundaryPoint> BoundaryPolylines::nearest_brute_force(const Vec3& p,
                                                                    double max_distance) const {
  std::optional<BoundaryPoint> best;
  for (int i = 0; i < int(m_segments.size()); ++i) {
    BoundaryPoint bp = evaluate(i, p);
    if (bp.distance <= max_distance && (!best || bp.distance < best->distance)) best = bp;
  }
  return best;
}

}  // namespace cutwork
