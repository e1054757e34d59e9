#include "host/mesh/union_jack_flips.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <numbers>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "host/core/error.h"

namespace cutwork {

namespace {

Vec3 face_normal(const RowMatX3d& V, const std::array<int, 3>& f) {
  const Vec3 a = V.row(f[0]), b = V.row(f[1]), c = V.row(f[2]);
  return (b - a).cross(c - a);
}

}  // namespace

UnionJackFlips flip_union_jack_diagonals(const SurfaceMesh& mesh, double max_dihedral_degrees) {
  UnionJackFlips out;
  out.mesh = mesh;
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  const RowMatX3d& V = mesh.vertices();
  const RowMatX3i& F = mesh.faces();
  std::vector<int> valence(static_cast<std::size_t>(nv), 0);
  for (int e = 0; e < mesh.num_edges(); ++e)
    for (int k = 0; k < 2; ++k) ++valence[std::size_t(mesh.edges()(e, k))];
  const std::vector<bool>& boundary = mesh.is_boundary_vertex();
  auto inner = [&](int v, int n) { return !boundary[std::size_t(v)] && valence[std::size_t(v)] == n; };
  auto opposite = [&](int f, int a, int b) {
    for (int k = 0; k < 3; ++k)
      if (F(f, k) != a && F(f, k) != b) return F(f, k);
    return -1;
  };

  // 1. The pattern's quads: two faces across a diagonal with an inner valence-8 end and an inner
  //    valence-4 opposite vertex (on the border of a union jack the other may lie on the boundary).
  struct Quad {
    int edge, f0, f1;
  };
  std::vector<Quad> quads;
  std::vector<int> quad_of(static_cast<std::size_t>(nf), -1);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const int f0 = mesh.edge_faces()(e, 0), f1 = mesh.edge_faces()(e, 1);
    if (f1 < 0) continue;
    const int a = mesh.edges()(e, 0), b = mesh.edges()(e, 1);
    const int c = opposite(f0, a, b), d = opposite(f1, a, b);
    if (!(inner(a, 8) || inner(b, 8)) || !(inner(c, 4) || inner(d, 4))) continue;
    if (quad_of[std::size_t(f0)] >= 0 || quad_of[std::size_t(f1)] >= 0) continue;  // a face in two: the first
    quad_of[std::size_t(f0)] = quad_of[std::size_t(f1)] = int(quads.size());
    quads.push_back({e, f0, f1});
  }
  out.union_jack_edges = int(quads.size());
  if (quads.empty()) return out;

  // 2. Neighbouring quads (a face of one across an edge from a face of the other) have their
  //    diagonals the other way; 2-colour each connected patch of quads and flip one colour, which
  //    turns every diagonal of the patch the same way (valence 6 inside).
  std::vector<std::vector<int>> next_to(quads.size());
  for (std::size_t q = 0; q < quads.size(); ++q)
    for (const int f : {quads[q].f0, quads[q].f1})
      for (int k = 0; k < 3; ++k) {
        const int e = mesh.face_edges()(f, k);
        const int g = mesh.edge_faces()(e, 0) == f ? mesh.edge_faces()(e, 1) : mesh.edge_faces()(e, 0);
        if (g >= 0 && quad_of[std::size_t(g)] >= 0 && quad_of[std::size_t(g)] != int(q))
          next_to[q].push_back(quad_of[std::size_t(g)]);
      }
  std::vector<int> colour(quads.size(), -1);
  std::vector<int> flip;
  for (std::size_t start = 0; start < quads.size(); ++start) {
    if (colour[start] >= 0) continue;
    std::vector<int> patch = {int(start)}, odd;
    colour[start] = 0;
    for (std::size_t i = 0; i < patch.size(); ++i)
      for (const int n : next_to[std::size_t(patch[i])])
        if (colour[std::size_t(n)] < 0) {
          colour[std::size_t(n)] = 1 - colour[std::size_t(patch[i])];
          patch.push_back(n);
          if (colour[std::size_t(n)] == 1) odd.push_back(n);
        }
    // A lone quad or two is no pattern (an irregular mesh has such places): left as they are.
    if (patch.size() >= kUnionJackMinQuads) flip.insert(flip.end(), odd.begin(), odd.end());
  }

  // 3. The flips: (p, q, c) and (q, p, d) become (c, p, d) and (d, q, c), where the two faces are
  //    nearly coplanar and both new faces face as the old ones did (a convex quad).
  const double cos_limit = std::cos(max_dihedral_degrees * std::numbers::pi / 180);
  RowMatX3i faces = F;
  std::set<std::pair<int, int>> edges;  // as they are after the flips so far
  for (int e = 0; e < mesh.num_edges(); ++e) edges.insert(std::minmax(mesh.edges()(e, 0), mesh.edges()(e, 1)));
  for (const int q : flip) {
    const Quad& quad = quads[std::size_t(q)];
    const int a = mesh.edges()(quad.edge, 0), b = mesh.edges()(quad.edge, 1);
    const int c = opposite(quad.f0, a, b), d = opposite(quad.f1, a, b);
    int p = a, r = b;
    for (int k = 0; k < 3; ++k)
      if (F(quad.f0, k) == c) {
        p = F(quad.f0, (k + 1) % 3);
        r = F(quad.f0, (k + 2) % 3);
      }
    const std::array<int, 3> t0 = {p, r, c}, t1 = {r, p, d}, g0 = {c, p, d}, g1 = {d, r, c};
    const Vec3 n0 = face_normal(V, t0), n1 = face_normal(V, t1);
    if (!(n0.dot(n1) > cos_limit * n0.norm() * n1.norm())) continue;  // a crease: keep its shape
    const Vec3 m0 = face_normal(V, g0), m1 = face_normal(V, g1), mean = n0 + n1;
    const double area = 0.5 * (n0.norm() + n1.norm());
    if (!(m0.dot(mean) > 0.05 * area * mean.norm()) || !(m1.dot(mean) > 0.05 * area * mean.norm())) continue;
    if (edges.count(std::minmax(c, d))) continue;  // the other diagonal is an edge already: no flip
    edges.erase(std::minmax(a, b));
    edges.insert(std::minmax(c, d));
    faces.row(quad.f0) << g0[0], g0[1], g0[2];
    faces.row(quad.f1) << g1[0], g1[1], g1[2];
    ++out.flips;
  }
  if (out.flips == 0) return out;
  try {
    out.mesh = SurfaceMesh(V, faces, "the simulation mesh (union-jack diagonals flipped)");
  } catch (const InputError&) {
    // Not expected (each flip keeps the quad's orientation and makes no edge twice); should a mesh
    // find a way, it is simulated as the file has it rather than refused.
    out.flips = 0;
  }
  return out;
}

}  // namespace cutwork
