#include "host/mesh/surface_mesh.h"

#include <Eigen/Geometry>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>

#include "host/core/error.h"

namespace cutwork {

namespace {

/// Key of the undirected edge {a, b}: both indices packed, smaller one first.
std::uint64_t edge_key(int a, int b) {
  const auto lo = std::uint32_t(std::min(a, b)), hi = std::uint32_t(std::max(a, b));
  return (std::uint64_t(lo) << 32) | hi;
}

/// Key of a face's vertex set (order-free), used to find duplicate faces.
struct TriKey {
  std::array<int, 3> v;
  bool operator==(const TriKey& o) const { return v == o.v; }
};
struct TriKeyHash {
  std::size_t operator()(const TriKey& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (int x : k.v) h = (h ^ std::uint32_t(x)) * 1099511628211ull;
    return std::size_t(h);
  }
};

/// Union-find with path halving, for connected components.
struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

/// A face is "zero area" when twice its area is below this fraction of its longest edge
/// squared: collinear vertices give a cross product of round-off size (~1e-16 l²), and a
/// sliver thinner than 1e-12 of its length cannot carry a meaningful stiffness either.
constexpr double kZeroAreaRelative = 1e-12;

[[noreturn]] void mesh_fail(const std::string& what, const std::string& problem) {
  throw InputError(what + ": " + problem);
}

/// The cheapest and most basic problems first: no faces, a non-finite coordinate, an index out
/// of range, a face that repeats a vertex.
void check_indices(const RowMatX3d& V, const RowMatX3i& F, const std::string& what) {
  const int nv = int(V.rows()), nf = int(F.rows());
  if (nf == 0) mesh_fail(what, "no faces");
  for (int v = 0; v < nv; ++v)
    if (!V.row(v).allFinite()) mesh_fail(what, fmt::format("vertex {} has a non-finite coordinate", v));
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      if (F(f, k) < 0 || F(f, k) >= nv)
        mesh_fail(what, fmt::format("face {} index {} out of range [0,{})", f, F(f, k), nv));
  for (int f = 0; f < nf; ++f) {
    const int a = F(f, 0), b = F(f, 1), c = F(f, 2);
    if (a == b || a == c) mesh_fail(what, fmt::format("face {} repeats vertex {}", f, a));
    if (b == c) mesh_fail(what, fmt::format("face {} repeats vertex {}", f, b));
  }
}

/// Face areas (#F) and unit normals (#F×3); throws for a zero-area face. Returns 2·area·normal
/// per face (#F×3), which the vertex normals reuse.
RowMatX3d face_geometry(const RowMatX3d& V, const RowMatX3i& F, const std::string& what,
                        Eigen::VectorXd& areas, RowMatX3d& normals) {
  const int nf = int(F.rows());
  areas.resize(nf);
  normals.resize(nf, 3);
  RowMatX3d weighted(nf, 3);
  for (int f = 0; f < nf; ++f) {
    const Vec3 a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Vec3 n = (b - a).cross(c - a);
    const double twice_area = n.norm();
    const double longest2 =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if (!(twice_area > kZeroAreaRelative * longest2)) mesh_fail(what, fmt::format("face {} has zero area", f));
    areas[f] = 0.5 * twice_area;
    normals.row(f) = n / twice_area;
    weighted.row(f) = n;
  }
  return weighted;
}

/// Throws for two faces on the same three vertices (in any order).
void check_duplicate_faces(const RowMatX3i& F, const std::string& what) {
  const int nf = int(F.rows());
  std::unordered_map<TriKey, int, TriKeyHash> seen;
  seen.reserve(std::size_t(nf) * 2);
  for (int f = 0; f < nf; ++f) {
    TriKey key{{F(f, 0), F(f, 1), F(f, 2)}};
    std::sort(key.v.begin(), key.v.end());
    auto [it, inserted] = seen.emplace(key, f);
    if (!inserted) mesh_fail(what, fmt::format("faces {} and {} are duplicates", it->second, f));
  }
}

/// Edges (#E×2, lower vertex first), their faces (#E×2, −1 for none) and each face's edges
/// (#F×3, slot k: faces(f,k) → faces(f,k+1)). Edges are numbered in order of first appearance
/// (face-major), so the numbering is deterministic and independent of the hash map's iteration
/// order. Throws for an edge of more than two faces.
void number_edges(const RowMatX3i& F, const std::string& what, RowMatX2i& out_edges,
                  RowMatX2i& out_edge_faces, RowMatX3i& face_edges) {
  const int nf = int(F.rows());
  std::unordered_map<std::uint64_t, int> edge_index;
  edge_index.reserve(std::size_t(nf) * 2);
  std::vector<std::array<int, 2>> edges;
  std::vector<std::array<int, 2>> edge_faces;
  std::vector<int> edge_face_count;
  edges.reserve(std::size_t(nf) * 3 / 2 + 3);
  face_edges.resize(nf, 3);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      auto [it, inserted] = edge_index.emplace(edge_key(a, b), int(edges.size()));
      const int e = it->second;
      if (inserted) {
        edges.push_back({std::min(a, b), std::max(a, b)});
        edge_faces.push_back({f, -1});
        edge_face_count.push_back(1);
      } else {
        if (edge_face_count[e] == 1) edge_faces[e][1] = f;
        ++edge_face_count[e];
      }
      face_edges(f, k) = e;
    }
  }
  const int ne = int(edges.size());
  for (int e = 0; e < ne; ++e) {
    if (edge_face_count[e] <= 2) continue;
    std::string faces_on_edge;  // error path only: a linear scan is fine
    for (int f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k)
        if (face_edges(f, k) == e) faces_on_edge += (faces_on_edge.empty() ? "" : ", ") + std::to_string(f);
    mesh_fail(what, fmt::format("edge ({},{}) is shared by {} faces (non-manifold): faces {}", edges[e][0],
                                edges[e][1], edge_face_count[e], faces_on_edge));
  }

  out_edges.resize(ne, 2);
  out_edge_faces.resize(ne, 2);
  for (int e = 0; e < ne; ++e) {
    out_edges(e, 0) = edges[e][0], out_edges(e, 1) = edges[e][1];
    out_edge_faces(e, 0) = edge_faces[e][0], out_edge_faces(e, 1) = edge_faces[e][1];
  }
}

/// Local slot k of edge e in face f (the edge runs faces(f,k) -> faces(f,k+1)).
int edge_slot(const RowMatX3i& face_edges, int f, int e) {
  for (int k = 0; k < 3; ++k)
    if (face_edges(f, k) == e) return k;
  return -1;  // unreachable: e is an edge of f by construction
}

/// One hinge per interior edge; throws where the two faces of an edge are not oriented
/// consistently.
std::vector<Hinge> make_hinges(const RowMatX3i& F, const RowMatX3i& face_edges, const RowMatX2i& edge_faces,
                               const std::string& what) {
  const int ne = int(edge_faces.rows());
  std::vector<Hinge> hinges;
  hinges.reserve(ne);
  for (int e = 0; e < ne; ++e) {
    const int f0 = edge_faces(e, 0), f1 = edge_faces(e, 1);
    if (f1 < 0) continue;
    const int k0 = edge_slot(face_edges, f0, e), k1 = edge_slot(face_edges, f1, e);
    Hinge h;
    h.edge = e;
    h.face[0] = f0, h.face[1] = f1;
    h.v[0] = F(f0, k0);
    h.v[1] = F(f0, (k0 + 1) % 3);
    h.v[2] = F(f0, (k0 + 2) % 3);
    // A consistently oriented neighbour walks the shared edge the other way: v1 -> v0.
    if (F(f1, k1) != h.v[1])
      mesh_fail(what, fmt::format("faces {} and {} both use edge {}->{} in the same direction (inconsistent "
                                  "orientation; flip one of them)",
                                  f0, f1, h.v[0], h.v[1]));
    h.v[3] = F(f1, (k1 + 2) % 3);
    hinges.push_back(h);
  }
  return hinges;
}

/// Boundary loops: each boundary edge is used by its face as a → b with the surface on the
/// left, so chaining those directed edges gives loops oriented like the faces. At a vertex where
/// several boundary fans meet (a "bowtie") the successor is found by turning around the vertex
/// inside the fan of the incoming edge, which keeps every loop simple. Marks the loops' vertices
/// in `is_boundary_vertex` (#V).
std::vector<std::vector<int>> trace_boundary_loops(const RowMatX3i& F, const RowMatX3i& face_edges,
                                                   const RowMatX2i& edge_faces, int nv,
                                                   std::vector<bool>& is_boundary_vertex) {
  const int nf = int(F.rows()), ne = int(edge_faces.rows());
  std::vector<std::vector<int>> loops;
  is_boundary_vertex.assign(nv, false);
  std::vector<bool> used(ne, false);
  for (int e0 = 0; e0 < ne; ++e0) {
    if (edge_faces(e0, 1) >= 0 || used[e0]) continue;
    std::vector<int> loop;
    int e = e0;
    int f = edge_faces(e, 0);
    int k = edge_slot(face_edges, f, e);
    while (!used[e]) {
      used[e] = true;
      loop.push_back(F(f, k));
      is_boundary_vertex[F(f, k)] = true;
      // The edge leaving b = faces(f, k+1) inside f is slot j = k+1; rotate across interior
      // edges until a boundary edge leaving b is found.
      const int b = F(f, (k + 1) % 3);
      int j = (k + 1) % 3;
      for (int guard = 0; guard <= nf; ++guard) {
        const int ej = face_edges(f, j);
        const int g = edge_faces(ej, 0) == f ? edge_faces(ej, 1) : edge_faces(ej, 0);
        if (g < 0) break;
        f = g;
        j = 0;
        while (F(f, j) != b) ++j;
      }
      e = face_edges(f, j);
      k = j;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

/// Area-weighted vertex normals (#V×3) from 2·area·normal per face (`weighted`); zero for an
/// unreferenced vertex, a face normal where the incident faces cancel out.
RowMatX3d area_weighted_vertex_normals(const RowMatX3i& F, const RowMatX3d& weighted, const RowMatX3d& face_normals, int nv) {
  const int nf = int(F.rows());
  RowMatX3d normals = RowMatX3d::Zero(nv, 3);
  std::vector<int> first_face(nv, -1);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = F(f, k);
      normals.row(v) += weighted.row(f);
      if (first_face[v] < 0) first_face[v] = f;
    }
  for (int v = 0; v < nv; ++v) {
    const double len = normals.row(v).norm();
    if (first_face[v] < 0)
      continue;  // unreferenced: no normal (left zero)
    else if (len > 1e-300)
      normals.row(v) /= len;
    else  // the incident faces cancel out (a pinched apex): fall back to one of them
      normals.row(v) = face_normals.row(first_face[v]);
  }
  return normals;
}

/// Connected components of the faces through interior edges.
std::vector<int> label_components(const RowMatX2i& edge_faces, int nf) {
  DisjointSets sets(nf);
  for (int e = 0; e < int(edge_faces.rows()); ++e)
    if (edge_faces(e, 1) >= 0) sets.unite(edge_faces(e, 0), edge_faces(e, 1));
  std::vector<int> label(size_t(nf), -1), root_label(size_t(nf), -1);
  int next = 0;
  for (int f = 0; f < nf; ++f) {
    int& l = root_label[size_t(sets.find(f))];
    if (l < 0) l = next++;
    label[size_t(f)] = l;
  }
  return label;
}

int count_components(const RowMatX2i& edge_faces, int nf) {
  DisjointSets sets(nf);
  for (int e = 0; e < int(edge_faces.rows()); ++e)
    if (edge_faces(e, 1) >= 0) sets.unite(edge_faces(e, 0), edge_faces(e, 1));
  int components = 0;
  for (int f = 0; f < nf; ++f)
    if (sets.find(f) == f) ++components;
  return components;
}

}  // namespace

SurfaceMesh::SurfaceMesh(RowMatX3d vertices, RowMatX3i faces, const std::string& what)
    : m_vertices(std::move(vertices)), m_faces(std::move(faces)) {
  build(what);
}

void SurfaceMesh::build(const std::string& what) {
  const int nv = num_vertices(), nf = num_faces();
  check_indices(m_vertices, m_faces, what);
  const RowMatX3d weighted = face_geometry(m_vertices, m_faces, what, m_face_areas, m_face_normals);
  check_duplicate_faces(m_faces, what);
  number_edges(m_faces, what, m_edges, m_edge_faces, m_face_edges);
  m_hinges = make_hinges(m_faces, m_face_edges, m_edge_faces, what);
  m_boundary_loops = trace_boundary_loops(m_faces, m_face_edges, m_edge_faces, nv, m_is_boundary_vertex);
  m_vertex_normals = area_weighted_vertex_normals(m_faces, weighted, m_face_normals, nv);
  m_num_components = count_components(m_edge_faces, nf);
}

double SurfaceMesh::mean_edge_length() const {
  if (num_edges() == 0) return 0;
  double sum = 0;
  for (int e = 0; e < num_edges(); ++e)
    sum += (m_vertices.row(m_edges(e, 0)) - m_vertices.row(m_edges(e, 1))).norm();
  return sum / num_edges();
}

Vec3 SurfaceMesh::bbox_min() const {
  if (num_vertices() == 0) return Vec3::Zero();
  return m_vertices.colwise().minCoeff().transpose();
}

Vec3 SurfaceMesh::bbox_max() const {
  if (num_vertices() == 0) return Vec3::Zero();
  return m_vertices.colwise().maxCoeff().transpose();
}

Vec3 SurfaceMesh::point(const SurfacePoint& p) const {
  const auto f = m_faces.row(p.face);
  return p.bary[0] * m_vertices.row(f[0]).transpose() + p.bary[1] * m_vertices.row(f[1]).transpose() +
         p.bary[2] * m_vertices.row(f[2]).transpose();
}

Vec3 SurfaceMesh::phong_normal(const SurfacePoint& p) const {
  const auto f = m_faces.row(p.face);
  const Vec3 n = p.bary[0] * m_vertex_normals.row(f[0]).transpose() +
                 p.bary[1] * m_vertex_normals.row(f[1]).transpose() +
                 p.bary[2] * m_vertex_normals.row(f[2]).transpose();
  const double len = n.norm();
  // Opposite vertex normals can cancel inside a face folded by ~180°; the face normal is then
  // the only meaningful direction.
  if (len < 1e-12) return m_face_normals.row(p.face).transpose();
  return n / len;
}

namespace {
/// The smallest interior angle of face f (radians).
double face_min_angle(const SurfaceMesh& mesh, int f) {
  const auto& V = mesh.vertices();
  const auto& F = mesh.faces();
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const Vec3 a = V.row(F(f, k)), b = V.row(F(f, (k + 1) % 3)), c = V.row(F(f, (k + 2) % 3));
    const Vec3 u = b - a, w = c - a;
    best = std::min(best, std::atan2(u.cross(w).norm(), u.dot(w)));
  }
  return best;
}
}  // namespace

double min_angle(const SurfaceMesh& mesh) {
  double best = std::numeric_limits<double>::infinity();
  for (int f = 0; f < mesh.num_faces(); ++f) best = std::min(best, face_min_angle(mesh, f));
  return best;
}

double fraction_of_faces_below_angle(const SurfaceMesh& mesh, double angle) {
  if (mesh.num_faces() == 0) return 0;
  int below = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) below += face_min_angle(mesh, f) < angle;
  return double(below) / mesh.num_faces();
}

double max_aspect_ratio(const SurfaceMesh& mesh) {
  // longest edge / shortest altitude, scaled by √3/2 so that an equilateral triangle gives 1;
  // with the shortest altitude 2A/l_max this is l_max²·√3 / (4A).
  double worst = 0;
  const auto& V = mesh.vertices();
  const auto& F = mesh.faces();
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const double l2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    worst = std::max(worst, l2 * std::sqrt(3.0) / (4.0 * mesh.face_areas()[f]));
  }
  return worst;
}

SurfaceMesh midpoint_subdivision(const SurfaceMesh& mesh) {
  const int nv = mesh.num_vertices(), ne = mesh.num_edges(), nf = mesh.num_faces();
  RowMatX3d V(nv + ne, 3);
  V.topRows(nv) = mesh.vertices();
  for (int e = 0; e < ne; ++e)
    V.row(nv + e) = 0.5 * (mesh.vertices().row(mesh.edges()(e, 0)) + mesh.vertices().row(mesh.edges()(e, 1)));
  RowMatX3i F(4 * nf, 3);
  for (int f = 0; f < nf; ++f) {
    const int a = mesh.faces()(f, 0), b = mesh.faces()(f, 1), c = mesh.faces()(f, 2);
    // face_edges(f,k) runs from corner k to corner k+1.
    const int ab = nv + mesh.face_edges()(f, 0), bc = nv + mesh.face_edges()(f, 1), ca = nv + mesh.face_edges()(f, 2);
    F.row(4 * f + 0) << a, ab, ca;
    F.row(4 * f + 1) << ab, b, bc;
    F.row(4 * f + 2) << ca, bc, c;
    F.row(4 * f + 3) << ab, bc, ca;
  }
  return SurfaceMesh(std::move(V), std::move(F), "midpoint subdivision");
}

std::vector<int> face_components(const SurfaceMesh& mesh) {
  return label_components(mesh.edge_faces(), mesh.num_faces());
}

}  // namespace cutwork
