#pragma once
/// Small hand-made and generated meshes for the host/mesh tests. All faces are CCW seen from
/// outside (closed meshes) or from +z (flat and height-field meshes).
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "host/mesh/surface_mesh.h"

namespace cutwork::test {

struct MeshArrays {
  RowMatX3d vertices;
  RowMatX3i faces;
};

inline MeshArrays from_lists(const std::vector<Vec3>& v, const std::vector<std::array<int, 3>>& f) {
  MeshArrays m;
  m.vertices.resize(int(v.size()), 3);
  for (int i = 0; i < int(v.size()); ++i) m.vertices.row(i) = v[i];
  m.faces.resize(int(f.size()), 3);
  for (int i = 0; i < int(f.size()); ++i) m.faces.row(i) << f[i][0], f[i][1], f[i][2];
  return m;
}

/// Unit square in the z = 0 plane, two triangles sharing the diagonal (0,2).
inline MeshArrays square() {
  return from_lists({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}});
}

/// Tetrahedron with outward normals.
inline MeshArrays tetrahedron() {
  return from_lists({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                    {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}});
}

/// Icosphere of radius 1: the icosahedron with every triangle split into 4, `levels` times.
inline MeshArrays icosphere(int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : v) p.normalize();
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const std::pair<int, int> key(std::min(a, b), std::max(a, b));
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return midpoint[key] = int(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& tri : f) {
      const int a = mid(tri[0], tri[1]), b = mid(tri[1], tri[2]), c = mid(tri[2], tri[0]);
      finer.push_back({tri[0], a, c});
      finer.push_back({tri[1], b, a});
      finer.push_back({tri[2], c, b});
      finer.push_back({a, b, c});
    }
    f = std::move(finer);
  }
  return from_lists(v, f);
}

/// Flat annulus 1 ≤ r ≤ 2 in the z = 0 plane: `around` segments, `rings` + 1 circles.
inline MeshArrays annulus(int around, int rings) {
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> f;
  for (int r = 0; r <= rings; ++r)
    for (int i = 0; i < around; ++i) {
      const double radius = 1.0 + double(r) / rings, angle = 2 * std::numbers::pi * i / around;
      v.push_back({radius * std::cos(angle), radius * std::sin(angle), 0});
    }
  auto id = [&](int r, int i) { return r * around + (i % around); };
  for (int r = 0; r < rings; ++r)
    for (int i = 0; i < around; ++i) {
      f.push_back({id(r, i), id(r + 1, i + 1), id(r, i + 1)});
      f.push_back({id(r, i), id(r + 1, i), id(r + 1, i + 1)});
    }
  return from_lists(v, f);
}

/// n×n-cell grid over [0,1]² lifted to a bumpy height field with jittered interior vertices
/// (fixed seed): a generic open surface with no symmetric ties.
inline MeshArrays bumpy_grid(int n, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.25 / n, 0.25 / n);
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> f;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      double x = double(i) / n, y = double(j) / n;
      if (i > 0 && i < n && j > 0 && j < n) x += jitter(rng), y += jitter(rng);
      const double z = 0.15 * std::sin(3 * x) * std::cos(5 * y) + 0.05 * std::sin(11 * x * y);
      v.push_back({x, y, z});
    }
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      f.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      f.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return from_lists(v, f);
}

inline SurfaceMesh make(const MeshArrays& m, const std::string& what = "test mesh") {
  return SurfaceMesh(m.vertices, m.faces, what);
}

}  // namespace cutwork::test
