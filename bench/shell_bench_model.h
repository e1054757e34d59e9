#pragma once
/// Shell models of a given size for the solver benchmarks: a clamped, shallow doubly-curved cap
/// (a pavilion roof) under self-weight and a snow-like pressure, built directly from arrays on a
/// near-equilateral grid. Cached per size so that every benchmark of one run sees the same model.
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <memory>
#include <vector>

#include "host/mesh/surface_mesh.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::bench {

struct BenchModel {
  std::unique_ptr<SurfaceMesh> mesh;
  std::unique_ptr<solvers::ShellModel> model;
};

/// About `dofs` free DOFs (3 per free vertex).
inline const BenchModel& bench_model(int dofs) {
  static std::map<int, BenchModel> cache;
  auto it = cache.find(dofs);
  if (it != cache.end()) return it->second;

  const int n = std::max(4, int(std::lround(std::sqrt(dofs / 3.0))));  // vertices per side
  const double L = 4.0, dx = L / n, dy = dx * std::sqrt(3.0) / 2.0;
  const int ny = n;
  std::vector<Vec3> verts;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= n; ++i) verts.emplace_back(dx * (i + (j % 2 ? 0.5 : 0.0)), dy * j, 0.0);
  const double cx = dx * (n + 0.5) / 2, cy = dy * ny / 2, r2max = cx * cx + cy * cy;
  for (Vec3& v : verts) v.z() = 0.8 * (1 - ((v.x() - cx) * (v.x() - cx) + (v.y() - cy) * (v.y() - cy)) / r2max);
  std::vector<Eigen::Vector3i> faces;
  auto id = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < n; ++i) {
      if (j % 2 == 0) {
        faces.emplace_back(id(i, j), id(i + 1, j), id(i, j + 1));
        faces.emplace_back(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
      } else {
        faces.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
        faces.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
      }
    }
  RowMatX3d V(verts.size(), 3);
  for (std::size_t v = 0; v < verts.size(); ++v) V.row(v) = verts[v].transpose();
  RowMatX3i F(faces.size(), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) F.row(f) = faces[f].transpose();

  BenchModel bm;
  bm.mesh = std::make_unique<SurfaceMesh>(V, F, "bench cap");
  const int nv = bm.mesh->num_vertices();
  LoadCase lc;
  lc.fixed = bm.mesh->is_boundary_vertex();
  lc.clamped = lc.fixed;
  lc.forces = RowMatX3d::Zero(nv, 3);
  for (int t = 0; t < bm.mesh->num_faces(); ++t)
    for (int k = 0; k < 3; ++k) lc.forces(F(t, k), 2) -= 200.0 * bm.mesh->face_areas()[t] / 3.0;  // 200 Pa
  lc.gravity = Vec3(0, 0, -9.81);
  Material m;  // PA12, 3 mm
  bm.model = std::make_unique<solvers::ShellModel>(*bm.mesh, m, lc);
  return cache.emplace(dofs, std::move(bm)).first->second;
}

/// Problem sizes: 1e4 and 1e5 DOFs; 1e6 only with CUTWORK_BENCH_LARGE=1 (minutes, several GB).
inline std::vector<int> bench_sizes() {
  std::vector<int> sizes{10000, 100000};
  if (const char* e = std::getenv("CUTWORK_BENCH_LARGE"); e && std::string(e) == "1") sizes.push_back(1000000);
  return sizes;
}

}  // namespace cutwork::bench
