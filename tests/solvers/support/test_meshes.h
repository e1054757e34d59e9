#pragma once
/// Flat test meshes built directly from arrays (no scene code): rectangles in the z = 0 plane,
/// counter-clockwise seen from +z (normals +z).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "host/mesh/surface_mesh.h"

namespace cutwork::test {

/// Near-equilateral triangulation of [0, lx] × [0, ly]: nx segments along x on even rows, odd rows
/// shifted by half a segment (with half triangles at the ends), rows spaced as close to √3/2 of
/// the segment as the height allows (ny > 0: exactly ny rows). The mesh on which the hinge model is
/// isotropic; with ly = ny·(√3/2)·lx/nx its inner triangles are exactly equilateral.
inline SurfaceMesh equilateral_rectangle(double lx, double ly, int nx, int ny = 0) {
  const double dx = lx / nx;
  if (ny <= 0) ny = std::max(1, int(std::lround(ly / (dx * std::sqrt(3.0) / 2.0))));
  std::vector<std::vector<int>> rows(ny + 1);
  std::vector<Vec3> verts;
  for (int j = 0; j <= ny; ++j) {
    const double y = ly * j / ny;
    std::vector<double> xs;
    if (j % 2 == 0) {
      for (int i = 0; i <= nx; ++i) xs.push_back(dx * i);
    } else {
      xs.push_back(0);
      for (int i = 0; i < nx; ++i) xs.push_back(dx * (i + 0.5));
      xs.push_back(lx);
    }
    for (double x : xs) {
      rows[j].push_back(int(verts.size()));
      verts.emplace_back(x, y, 0);
    }
  }
  std::vector<Eigen::Vector3i> faces;
  for (int j = 0; j < ny; ++j) {
    const auto& A = rows[j];
    const auto& B = rows[j + 1];
    std::size_t i = 0, k = 0;
    while (i + 1 < A.size() || k + 1 < B.size()) {
      const bool advance_bottom =
          k + 1 >= B.size() || (i + 1 < A.size() && verts[A[i + 1]].x() <= verts[B[k + 1]].x() + 1e-12);
      if (advance_bottom) {
        faces.emplace_back(A[i], A[i + 1], B[k]);
        ++i;
      } else {
        faces.emplace_back(A[i], B[k + 1], B[k]);
        ++k;
      }
    }
  }
  RowMatX3d V(verts.size(), 3);
  for (std::size_t v = 0; v < verts.size(); ++v) V.row(v) = verts[v].transpose();
  RowMatX3i F(faces.size(), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) F.row(f) = faces[f].transpose();
  return SurfaceMesh(V, F, "equilateral rectangle");
}

/// Regular grid of nx × ny squares on [0, lx] × [0, ly], each split along its diagonal from
/// (i, j) to (i+1, j+1) (all diagonals parallel).
inline SurfaceMesh grid_rectangle(double lx, double ly, int nx, int ny) {
  RowMatX3d V((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) V.row(j * (nx + 1) + i) << lx * i / nx, ly * j / ny, 0;
  RowMatX3i F(2 * nx * ny, 3);
  int f = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
      F.row(f++) << a, b, c;
      F.row(f++) << a, c, d;
    }
  return SurfaceMesh(V, F, "grid rectangle");
}

/// Vertex indices whose position satisfies pred.
template <typename Pred>
std::vector<int> select_vertices(const SurfaceMesh& mesh, Pred&& pred) {
  std::vector<int> out;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (pred(mesh.vertices().row(v).transpose())) out.push_back(v);
  return out;
}

/// Lumped uniform pressure p (Pa) along direction `dir` on every face: p A_f / 3 per vertex.
inline RowMatX3d pressure_forces(const SurfaceMesh& mesh, double p, const Vec3& dir) {
  RowMatX3d f = RowMatX3d::Zero(mesh.num_vertices(), 3);
  for (int t = 0; t < mesh.num_faces(); ++t)
    for (int k = 0; k < 3; ++k) f.row(mesh.faces()(t, k)) += (p * mesh.face_areas()[t] / 3.0 * dir).transpose();
  return f;
}

}  // namespace cutwork::test

namespace cutwork::test {

/// A shallow cap: equilateral_rectangle(lx, ly, nx) lifted to z = height·(1 − r²/r_max²), r the
/// distance from the centre — curved, so membrane and bending couple.
inline SurfaceMesh cap(double lx, double ly, int nx, double height) {
  const SurfaceMesh flat = equilateral_rectangle(lx, ly, nx);
  RowMatX3d V = flat.vertices();
  const Vec2 c(lx / 2, ly / 2);
  const double r2max = c.squaredNorm();
  for (int v = 0; v < V.rows(); ++v) {
    const double r2 = (Vec2(V(v, 0), V(v, 1)) - c).squaredNorm();
    V(v, 2) = height * (1 - r2 / r2max);
  }
  return SurfaceMesh(V, flat.faces(), "cap");
}

}  // namespace cutwork::test

namespace cutwork::test {

/// Annulus r_in ≤ r ≤ r_out in the z = 0 plane (a disc when r_in = 0: a centre vertex), meshed in
/// rings of near-equilateral triangles with edge length ≈ h: ring radii evenly spaced, each ring
/// with round(2π r / h) vertices (at least 6), alternate rings staggered by half a step; a disc
/// (r_in = 0) is a hexagonal lattice bent onto rings (6j vertices on ring j). Normals +z.
inline SurfaceMesh annulus(double r_in, double r_out, double h) {
  const int nr = std::max(1, int(std::lround((r_out - r_in) / (h * std::sqrt(3.0) / 2.0))));
  std::vector<Vec3> verts;
  std::vector<std::vector<int>> rings;
  std::vector<double> step, offset;
  for (int j = 0; j <= nr; ++j) {
    const double r = r_in + (r_out - r_in) * j / nr;
    std::vector<int> ring;
    if (r == 0) {
      ring.push_back(int(verts.size()));
      verts.emplace_back(0, 0, 0);
      step.push_back(2 * std::numbers::pi);
      offset.push_back(0);
    } else {
      // A disc is a hexagonal lattice bent onto rings (ring j has 6j vertices, aligned per 60°
      // sector): near-equilateral everywhere, the centre included.
      const int n = r_in == 0 ? 6 * j : std::max(6, int(std::lround(2 * std::numbers::pi * r / h)));
      step.push_back(2 * std::numbers::pi / n);
      offset.push_back(r_in == 0 || j % 2 == 0 ? 0.0 : 0.5 * step.back());
      for (int i = 0; i < n; ++i) {
        const double t = offset.back() + step.back() * i;
        ring.push_back(int(verts.size()));
        verts.emplace_back(r * std::cos(t), r * std::sin(t), 0);
      }
    }
    rings.push_back(ring);
  }
  std::vector<Eigen::Vector3i> faces;
  auto add = [&](int a, int b, int c) {
    const Vec3 n = (verts[b] - verts[a]).cross(verts[c] - verts[a]);
    if (n.z() > 0)
      faces.emplace_back(a, b, c);
    else
      faces.emplace_back(a, c, b);
  };
  for (int j = 0; j < nr; ++j) {
    const auto& A = rings[j];
    const auto& B = rings[j + 1];
    const int na = int(A.size()), nb = int(B.size());
    if (na == 1) {
      for (int k = 0; k < nb; ++k) add(A[0], B[k], B[(k + 1) % nb]);
      continue;
    }
    int i = 0, k = 0;
    while (i < na || k < nb) {
      const double ta = offset[j] + step[j] * (i + 1), tb = offset[j + 1] + step[j + 1] * (k + 1);
      if (k >= nb || (i < na && ta <= tb)) {
        add(A[i % na], A[(i + 1) % na], B[k % nb]);
        ++i;
      } else {
        add(A[i % na], B[(k + 1) % nb], B[k % nb]);
        ++k;
      }
    }
  }
  RowMatX3d V(verts.size(), 3);
  for (std::size_t v = 0; v < verts.size(); ++v) V.row(v) = verts[v].transpose();
  RowMatX3i F(faces.size(), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) F.row(f) = faces[f].transpose();
  return SurfaceMesh(V, F, "annulus");
}

/// The mesh with every interior vertex moved in its plane (z = 0 meshes) by a uniform random
/// offset of up to `amount` times the mean edge length in x and y (fixed seed): an irregular mesh
/// with the same connectivity.
inline SurfaceMesh jittered(const SurfaceMesh& mesh, double amount, unsigned seed) {
  RowMatX3d V = mesh.vertices();
  const double h = mesh.mean_edge_length();
  unsigned state = seed * 2654435761u + 12345u;
  auto uniform = [&] {
    state = state * 1664525u + 1013904223u;
    return double(state >> 8) / double(1u << 24) * 2.0 - 1.0;
  };
  for (int v = 0; v < V.rows(); ++v) {
    const double dx = uniform(), dy = uniform();
    if (mesh.is_boundary_vertex()[v]) continue;
    V(v, 0) += amount * h * dx;
    V(v, 1) += amount * h * dy;
  }
  return SurfaceMesh(V, mesh.faces(), "jittered " + std::string("mesh"));
}

}  // namespace cutwork::test

namespace cutwork::test {

/// A spherical cap of footprint radius 0.3 m rising 0.1 m, its rim on z = 0 (what a user's mesh
/// file of a dome looks like: flat facets, the rim on the ground), on `rings` rings of
/// `sectors` vertices (alternate rings turned half a sector); `resting_on_apex` turns it upside
/// down (a bowl resting on its bottom point).
inline SurfaceMesh spherical_cap(int rings, int sectors, bool resting_on_apex = false) {
  const double R = 0.3, H = 0.1, rho = (R * R + H * H) / (2 * H);
  std::vector<Vec3> v{Vec3(0, 0, H)};
  for (int i = 1; i <= rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const double r = R * i / rings, t = 2 * std::numbers::pi * (j + 0.5 * (i % 2)) / sectors;
      v.emplace_back(r * std::cos(t), r * std::sin(t), std::sqrt(rho * rho - r * r) - (rho - H));
    }
  const auto id = [&](int i, int j) { return i == 0 ? 0 : 1 + (i - 1) * sectors + (j % sectors); };
  std::vector<Eigen::Vector3i> f;
  for (int j = 0; j < sectors; ++j) f.emplace_back(0, id(1, j), id(1, j + 1));
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      f.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      f.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  // Upside down: z mirrored and every face turned, so that the normals still point outwards.
  RowMatX3d V(v.size(), 3);
  for (size_t k = 0; k < v.size(); ++k)
    V.row(Eigen::Index(k)) = Vec3(v[k].x(), v[k].y(), resting_on_apex ? -v[k].z() : v[k].z()).transpose();
  RowMatX3i F(f.size(), 3);
  for (size_t k = 0; k < f.size(); ++k)
    F.row(Eigen::Index(k)) =
        resting_on_apex ? Eigen::RowVector3i(f[k][0], f[k][2], f[k][1]) : Eigen::RowVector3i(f[k].transpose());
  return SurfaceMesh(V, F, "cap");
}

}  // namespace cutwork::test
