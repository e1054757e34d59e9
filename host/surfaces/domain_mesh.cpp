#include "host/surfaces/domain_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Dense>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace cutwork::shapes_detail {

namespace {

constexpr double kSqrt3Over2 = 0.86602540378443864676;

/// Triangulates the strip between two rows of vertices (lower row `a`, upper row `b`, both
/// sorted by increasing u and spanning the same u-range) by repeatedly adding the shorter of
/// the two possible diagonals (the Delaunay choice for two parallel rows). Appends CCW faces.
void zip_rows(const std::vector<int>& a, const std::vector<int>& b, const RowMatX2d& uv,
              std::vector<Eigen::Vector3i>& faces) {
  std::size_t i = 0, j = 0;
  while (i + 1 < a.size() || j + 1 < b.size()) {
    bool advance_a;
    if (i + 1 >= a.size()) {
      advance_a = false;
    } else if (j + 1 >= b.size()) {
      advance_a = true;
    } else {
      const double d_a = (uv.row(a[i + 1]) - uv.row(b[j])).squaredNorm();
      const double d_b = (uv.row(a[i]) - uv.row(b[j + 1])).squaredNorm();
      advance_a = d_a <= d_b;
    }
    if (advance_a) {
      faces.emplace_back(a[i], a[i + 1], b[j]);
      ++i;
    } else {
      faces.emplace_back(a[i], b[j + 1], b[j]);
      ++j;
    }
  }
}

RowMatX3i to_matrix(const std::vector<Eigen::Vector3i>& faces) {
  RowMatX3i out(Eigen::Index(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) out.row(Eigen::Index(f)) = faces[f].transpose();
  return out;
}

/// Vertex adjacency of a domain mesh (#V lists each): the neighbours, for boundary vertices
/// their two neighbours along the boundary (the endpoints of boundary edges, i.e. edges used by
/// exactly one face), and the faces around each vertex.
struct DomainAdjacency {
  std::vector<std::vector<int>> neighbours, boundary_neighbours, vertex_faces;
};

DomainAdjacency domain_adjacency(const DomainMesh& mesh) {
  const int n = int(mesh.uv.rows());
  DomainAdjacency adj;
  adj.neighbours.assign(std::size_t(n), std::vector<int>{});
  adj.boundary_neighbours.assign(std::size_t(n), std::vector<int>{});
  adj.vertex_faces.assign(std::size_t(n), std::vector<int>{});
  std::vector<std::pair<int, int>> undirected;
  undirected.reserve(std::size_t(mesh.faces.rows()) * 3);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int a = mesh.faces(f, c), b = mesh.faces(f, (c + 1) % 3);
      undirected.emplace_back(std::min(a, b), std::max(a, b));
      adj.vertex_faces[std::size_t(a)].push_back(int(f));
    }
  }
  std::sort(undirected.begin(), undirected.end());
  for (std::size_t e = 0; e < undirected.size();) {
    std::size_t count = 1;
    while (e + count < undirected.size() && undirected[e + count] == undirected[e]) ++count;
    const auto [a, b] = undirected[e];
    adj.neighbours[std::size_t(a)].push_back(b);
    adj.neighbours[std::size_t(b)].push_back(a);
    if (count == 1) {
      adj.boundary_neighbours[std::size_t(a)].push_back(b);
      adj.boundary_neighbours[std::size_t(b)].push_back(a);
    }
    e += count;
  }
  return adj;
}

/// A greedy colouring (in index order) of the vertices that are not `pinned` (empty or #V): the
/// vertices of one colour are pairwise non-adjacent. Returns the vertices of each colour.
std::vector<std::vector<int>> colour_classes(const std::vector<std::vector<int>>& neighbours,
                                             const std::vector<bool>& pinned) {
  const int n = int(neighbours.size());
  std::vector<int> colour(std::size_t(n), -1);
  std::vector<std::vector<int>> by_colour;
  for (int i = 0; i < n; ++i) {
    if (!pinned.empty() && pinned[std::size_t(i)]) continue;
    std::vector<bool> taken(by_colour.size() + 1, false);
    for (int j : neighbours[std::size_t(i)]) {
      if (colour[std::size_t(j)] >= 0) taken[std::size_t(colour[std::size_t(j)])] = true;
    }
    const int c = int(std::find(taken.begin(), taken.end(), false) - taken.begin());
    colour[std::size_t(i)] = c;
    if (std::size_t(c) == by_colour.size()) by_colour.emplace_back();
    by_colour[std::size_t(c)].push_back(i);
  }
  return by_colour;
}

}  // namespace

double RectangleLattice::num_vertices() const {
  const double even_rows = std::floor(rows / 2) + 1;  // rows 0, 2, 4, ... ≤ rows
  const double odd_rows = rows + 1 - even_rows;
  return even_rows * (columns + 1) + odd_rows * (columns + 2);
}

RectangleLattice plan_rectangle(double width, double height, double h) {
  RectangleLattice plan;
  plan.columns = std::max(1.0, std::round(width / h));
  plan.spacing = width / plan.columns;
  // Rounding the row count up keeps row_spacing ≤ (√3/2)·spacing: the boundary right
  // triangles then have their smallest angle atan(spacing / (2·row_spacing)) ≥ 30°, while the
  // interior isosceles triangles stay within a few degrees of equilateral.
  plan.rows = std::max(1.0, std::ceil(height / (kSqrt3Over2 * plan.spacing) - 1e-9));
  plan.row_spacing = height / plan.rows;
  return plan;
}

RectangleLattice plan_rows(double width, const std::vector<double>& breaks, double h,
                           const std::function<double(double, double)>& max_row_spacing) {
  RectangleLattice plan = plan_rectangle(width, breaks.back(), h);
  const double target = kSqrt3Over2 * plan.spacing;
  std::vector<double> kept{0.0};
  for (std::size_t k = 1; k < breaks.size(); ++k) {
    if (k + 1 == breaks.size()) {
      if (breaks[k] - kept.back() < 0.5 * target && kept.size() > 1) kept.pop_back();
      kept.push_back(breaks[k]);
    } else if (breaks[k] - kept.back() >= 0.5 * target) {
      kept.push_back(breaks[k]);
    }
  }
  plan.row_positions = {0.0};
  plan.row_spacing = 0;
  for (std::size_t k = 1; k < kept.size(); ++k) {
    const double length = kept[k] - kept[k - 1];
    // As many rows as keep the spacing ≤ target (angles ≥ 30° at the sides), more where
    // max_row_spacing asks, but never closer than 0.3 spacing (the base angles of the isosceles
    // triangles stay ≥ atan 0.6 = 31°).
    double n = std::max(1.0, std::ceil(length / target - 1e-9));
    if (max_row_spacing) {
      const double wanted = std::ceil(length / max_row_spacing(kept[k - 1], kept[k]) - 1e-9);
      n = std::max(n, std::min(wanted, std::floor(length / (0.3 * plan.spacing))));
    }
    for (int i = 1; i < int(n); ++i) plan.row_positions.push_back(kept[k - 1] + length * i / n);
    plan.row_positions.push_back(kept[k]);
    plan.row_spacing = std::max(plan.row_spacing, length / n);
  }
  plan.rows = double(plan.row_positions.size() - 1);
  return plan;
}

DomainMesh mesh_rectangle(double width, double height, const RectangleLattice& plan) {
  const int columns = int(plan.columns);
  const int rows = int(plan.rows);
  DomainMesh mesh;
  mesh.uv.resize(Eigen::Index(plan.num_vertices()), 2);
  mesh.on_boundary.assign(std::size_t(mesh.uv.rows()), false);
  std::vector<std::vector<int>> row_vertices(std::size_t(rows) + 1);
  int next = 0;
  auto add = [&](int row, double u, double v) {
    mesh.uv.row(next) << u, v;
    mesh.on_boundary[std::size_t(next)] =
        row == 0 || row == rows || u == 0.0 || u == width;
    row_vertices[std::size_t(row)].push_back(next++);
  };
  for (int j = 0; j <= rows; ++j) {
    // The last row sits exactly on v = height (no accumulated rounding).
    const double v = j == rows ? height
                     : plan.row_positions.empty() ? j * plan.row_spacing
                                                  : plan.row_positions[std::size_t(j)];
    if (j % 2 == 0) {
      for (int i = 0; i <= columns; ++i) add(j, i == columns ? width : i * plan.spacing, v);
    } else {
      add(j, 0.0, v);
      for (int i = 0; i < columns; ++i) add(j, (i + 0.5) * plan.spacing, v);
      add(j, width, v);
    }
  }
  std::vector<Eigen::Vector3i> faces;
  faces.reserve(std::size_t(plan.num_faces()));
  for (int j = 0; j < rows; ++j) {
    zip_rows(row_vertices[std::size_t(j)], row_vertices[std::size_t(j) + 1], mesh.uv, faces);
  }
  mesh.faces = to_matrix(faces);
  return mesh;
}

DomainMesh mesh_hex_disk(int rings) {
  const double pi = std::numbers::pi;
  DomainMesh mesh;
  const int num_vertices = 1 + 3 * rings * (rings + 1);
  mesh.uv.resize(num_vertices, 2);
  mesh.on_boundary.assign(std::size_t(num_vertices), false);
  mesh.uv.row(0) << 0.0, 0.0;
  auto ring_start = [](int k) { return k == 0 ? 0 : 1 + 3 * k * (k - 1); };
  for (int k = 1; k <= rings; ++k) {
    const double radius = double(k) / rings;
    for (int j = 0; j < 6 * k; ++j) {
      const double angle = 2.0 * pi * j / (6.0 * k);
      const int index = ring_start(k) + j;
      mesh.uv.row(index) << radius * std::cos(angle), radius * std::sin(angle);
      mesh.on_boundary[std::size_t(index)] = k == rings;
    }
  }
  // Vertex j of ring k (k ≥ 1); ring 0 is the centre.
  auto vertex = [&](int k, int j) { return k == 0 ? 0 : ring_start(k) + j % (6 * k); };
  std::vector<Eigen::Vector3i> faces;
  faces.reserve(std::size_t(6) * std::size_t(rings) * std::size_t(rings));
  for (int k = 1; k <= rings; ++k) {
    for (int side = 0; side < 6; ++side) {
      // Side `side` of the hexagon: k segments on ring k, k−1 on ring k−1, forming k "up"
      // triangles (an edge on ring k) and k−1 "down" triangles (an edge on ring k−1).
      for (int m = 0; m < k; ++m) {
        const int outer = side * k + m;
        const int inner = side * (k - 1) + m;
        faces.emplace_back(vertex(k, outer), vertex(k, outer + 1), vertex(k - 1, inner));
        if (m + 1 < k) {
          faces.emplace_back(vertex(k - 1, inner), vertex(k, outer + 1),
                             vertex(k - 1, inner + 1));
        }
      }
    }
  }
  mesh.faces = to_matrix(faces);
  return mesh;
}

void relax_on_surface(DomainMesh& mesh, const SurfaceMap& map, int sweeps,
                      const std::function<Vec2(const Vec2&)>& keep_on_boundary,
                      const std::function<Vec2(const Vec2&)>& boundary_tangent,
                      const std::vector<bool>& pinned) {
  // Half a step towards the neighbours' centroid: a full step overshoots on curved surfaces.
  const double step = 0.5;
  const int n = int(mesh.uv.rows());
  const DomainAdjacency adjacency = domain_adjacency(mesh);
  const auto& neighbours = adjacency.neighbours;
  const auto& boundary_neighbours = adjacency.boundary_neighbours;
  const auto& vertex_faces = adjacency.vertex_faces;

  RowMatX3d x(n, 3);
  for (int i = 0; i < n; ++i) x.row(i) = map(mesh.uv.row(i).transpose()).transpose();

  // Quality of the faces around vertex i if i sat at (uv_i, x_i): the smallest angle, as
  // 1 − cos(angle) (monotone in the angle, no acos); −1 if a face would flip in the domain.
  auto quality_at = [&](int i, const Vec2& uv_i, const Vec3& x_i) {
    double worst = 2.0;  // min over angles of (1 - cos angle) ∈ [0, 2]
    for (int f : vertex_faces[std::size_t(i)]) {
      Vec2 p[3];
      Vec3 q[3];
      for (int c = 0; c < 3; ++c) {
        const int v = mesh.faces(f, c);
        p[c] = v == i ? uv_i : Vec2(mesh.uv.row(v).transpose());
        q[c] = v == i ? x_i : Vec3(x.row(v).transpose());
      }
      const double orient =
          (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
      if (!(orient > 0)) return -1.0;
      for (int c = 0; c < 3; ++c) {
        const Vec3 e1 = q[(c + 1) % 3] - q[c], e2 = q[(c + 2) % 3] - q[c];
        worst = std::min(worst, 1.0 - e1.dot(e2) / (e1.norm() * e2.norm()));
      }
    }
    return worst;
  };

  auto relax_vertex = [&](int i) {
    const Vec2 uv = mesh.uv.row(i).transpose();
    const Vec3 xi = x.row(i).transpose();
    // Central-difference Jacobian of the map; the step is small against any shape feature
    // and large against rounding (parameter domains are O(1)).
    const double eps = 1e-6;
    const bool boundary = mesh.on_boundary[std::size_t(i)];
    const auto& ring = boundary ? boundary_neighbours[std::size_t(i)] : neighbours[std::size_t(i)];
    Vec3 target = Vec3::Zero();
    for (int j : ring) target += x.row(j).transpose();
    target /= double(ring.size());
    const Vec3 move = step * (target - xi);
    Vec2 delta;
    if (boundary) {
      const Vec2 t = boundary_tangent(uv);
      const Vec3 dx = (map(uv + eps * t) - map(uv - eps * t)) / (2 * eps);
      delta = t * (dx.dot(move) / dx.squaredNorm());
    } else {
      Eigen::Matrix<double, 3, 2> jac;
      jac.col(0) = (map(uv + Vec2(eps, 0)) - map(uv - Vec2(eps, 0))) / (2 * eps);
      jac.col(1) = (map(uv + Vec2(0, eps)) - map(uv - Vec2(0, eps))) / (2 * eps);
      delta = (jac.transpose() * jac).ldlt().solve(jac.transpose() * move);
    }
    Vec2 next = uv + delta;
    if (boundary) next = keep_on_boundary(next);
    const Vec3 x_next = map(next);
    if (quality_at(i, next, x_next) > quality_at(i, uv, xi)) {
      mesh.uv.row(i) = next.transpose();
      x.row(i) = x_next.transpose();
    }
  };

  // Gauss-Seidel by colour: each colour is relaxed in parallel and every vertex reads only other
  // colours' positions — the result is the same for any number of threads.
  const std::vector<std::vector<int>> by_colour = colour_classes(neighbours, pinned);
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    for (const auto& group : by_colour) {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, group.size(), 256),
                        [&](const tbb::blocked_range<std::size_t>& range) {
                          for (std::size_t k = range.begin(); k != range.end(); ++k) {
                            relax_vertex(group[k]);
                          }
                        });
    }
  }
}

}  // namespace cutwork::shapes_detail
