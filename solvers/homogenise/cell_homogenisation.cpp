#include "solvers/homogenise/cell_homogenisation.h"

#include <array>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <span>
#include <numbers>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/cut/cut_surface.h"
#include "host/mesh/bvh.h"
#include "host/mesh/isotropic_remesh.h"
#include "host/stencil/frame.h"
#include "host/stencil/stencil_opening.h"
#include "solvers/conforming/rim_recovery.h"
#include "solvers/homogenise/free_edge_strain.h"
#include "solvers/linear/cholmod_solver.h"
#include "solvers/shell/shell_energy.h"

namespace cutwork::solvers {

namespace {

const double kSqrt3 = std::numbers::sqrt3;
/// Number of macroscopic load cases: three membrane strains, three curvatures.
constexpr int kCases = 6;
/// Triangles across the narrowest ligament, at least (homogenise_cell raises the resolution).
constexpr double kLigamentElements = 6;
/// The tiled cell keeps the copies' faces within max(kTileMargin, kTileMarginEdges target edges) of
/// the centre rhombus (lattice coordinates): a bending patch reaches one ring, a rim recovery patch
/// 2.5–5 mean edges.
constexpr double kTileMargin = 0.1, kTileMarginEdges = 10;
/// Amplitude of the unit cases' displacements at which the rim is recovered (spacing 1).
constexpr double kProbe = 1e-6;

Eigen::Matrix3d isotropic_voigt(double factor, double nu) {
  Eigen::Matrix3d C;
  C << 1, nu, 0, nu, 1, 0, 0, 0, 0.5 * (1 - nu);
  return factor * C;
}

/// The macroscopic field of load case k at rest point X: in-plane u = ε̄ X (k < 3), out-of-plane
/// w = ½ Xᵀ κ̄ X (k ≥ 3), unit Voigt component.
Vec3 macro_displacement(int k, const Vec3& X) {
  const double x = X.x(), y = X.y();
  switch (k) {
    case 0: return {x, 0, 0};                   // ε_xx
    case 1: return {0, y, 0};                   // ε_yy
    case 2: return {0.5 * y, 0.5 * x, 0};       // γ_xy
    case 3: return {0, 0, 0.5 * x * x};         // κ_xx
    case 4: return {0, 0, 0.5 * y * y};         // κ_yy
    default: return {0, 0, 0.5 * x * y};        // 2κ_xy
  }
}

/// The lattice at spacing 1: vectors a₁ = (1, 0) and a₂ = (½, √3/2) (hexagonal) or (0, 1) (square),
/// the gross area of one cell (one hole), and the radius of the period cell's inscribed circle (a
/// hole within it stays inside the cell: the rhombus's √3/4, the square's ½).
struct LatticeGeometry {
  Vec3 a1, a2;
  double area, inscribed;
  explicit LatticeGeometry(CellLattice lattice)
      : a1(1, 0, 0),
        a2(lattice == CellLattice::Square ? Vec3(0, 1, 0) : Vec3(0.5, 0.5 * kSqrt3, 0)),
        area(lattice == CellLattice::Square ? 1.0 : 0.5 * kSqrt3),
        inscribed(lattice == CellLattice::Square ? 0.5 : 0.25 * kSqrt3) {}
  /// Lattice coordinates (s, t) of X = s a₁ + t a₂.
  Eigen::Vector2d coordinates(const Vec3& X) const {
    const double t = X.y() / a2.y();
    return {X.x() - a2.x() * t, t};
  }
};

/// The period cell: the parallelogram spanned by a₁, a₂ (the hexagonal lattice's rhombus, the square
/// lattice's unit square), meshed by the regular triangular grid of spacing
/// 1/n, with the stencil cut out at its centre and the result remeshed at 1/n (outlines and the
/// cell's sides kept: opposite sides still carry translated copies of each other's vertices).
/// A regular triangular grid of the lattice parallelogram [i0, i1] a₁ + [j0, j1] a₂ (in spacings),
/// n triangles pairs per spacing; face (i, j, 0/1) of the square (i, j) at 2 ((j − j0) w + (i − i0)) + 0/1,
/// w = n (i1 − i0).
SurfaceMesh lattice_grid(const LatticeGeometry& L, int n, int i0, int i1, int j0, int j1) {
  const int w = n * (i1 - i0), h = n * (j1 - j0);
  RowMatX3d V((w + 1) * (h + 1), 3);
  RowMatX3i F(2 * w * h, 3);
  for (int j = 0; j <= h; ++j)
    for (int i = 0; i <= w; ++i)
      V.row(j * (w + 1) + i) = (double(i + n * i0) / n * L.a1 + double(j + n * j0) / n * L.a2).transpose();
  for (int j = 0, f = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const int v = j * (w + 1) + i;
      F.row(f++) << v, v + 1, v + w + 1;
      F.row(f++) << v + 1, v + w + 2, v + w + 1;
    }
  return SurfaceMesh(V, F, "homogenisation cell");
}

/// The cell's hole: the shape as drawn, or as a tool of radius `tool` (bounding radii) cuts it
/// (CellOptions::tool_radius), with the points of the opened polygon on the tool's rounds.
struct CellHole {
  StencilShape shape;
  std::vector<Vec2> rounds;  ///< reference frame; empty as drawn or where the tool changed nothing
};

CellHole cell_hole(const StencilShape& shape, double tool) {
  CellHole h{shape, {}};
  if (!(tool > 0)) return h;
  const OpenedPolygon opened = open_polygon(shape.polygon, tool);
  // No disc of the tool's radius fits: kept as drawn, as cutwork verify keeps such a stencil
  // (tool_cut_stencils' too_small; the minimum feature check reports it).
  if (opened.unchanged || opened.polygon.empty()) return h;
  h.shape = shape_in_reference_frame(shape.name + "@tool", shape.kind, opened.polygon);
  // The opening's straight pieces lie on the drawn sides (1e-5 τ) and its notches' arcs within
  // 0.02 τ of the drawn notches; a vertex farther than τ/20 from the drawn outline is on a round.
  const std::vector<Vec2>& drawn = shape.polygon;
  for (const Vec2& p : opened.polygon) {
    double d = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < drawn.size(); ++i) {
      const Vec2 a = drawn[i], e = drawn[(i + 1) % drawn.size()] - a;
      const double t = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
      d = std::min(d, (p - a - t * e).norm());
    }
    if (d > 0.05 * tool) h.rounds.push_back(p);
  }
  // No point of the opening farther than τ/20 from the drawn outline (the default flower's petals
  // at τ = 1/4, rounds of about that radius): the drawn cell. Cut, its outline would carry the
  // opening's short segments unrefined (no round to refine about), and the faces beside them read a
  // bending K of 209 against the drawn cell's 5.4.
  if (h.rounds.empty()) h.shape = shape;
  return h;
}

/// The faces about a cell's rounds halved down to the round's radius / `round_edges` (see "The
/// tool's rounds"), the faces with a vertex on the parallelogram's sides frozen; new vertices onto
/// (surface_V, surface_F), the cut before remeshing, whose outline holds the rounds' arcs.
/// The halvings that bring edges of 1/n down to round_radius / round_edges (at most 10).
int round_depth(double round_radius, int n, double round_edges) {
  return std::clamp(int(std::ceil(std::log2(round_edges / (n * round_radius)) - 1e-9)), 0, 10);
}

/// The radius about each round's points within which refine_rounds grades the mesh: its widest
/// focus ball and the two rings of faces of its first pass (half the base size each).
double round_zone(double round_radius, int n, double round_edges) {
  const int depth = round_depth(round_radius, n, round_edges);
  return depth > 0 ? 2 * round_radius * (1 + 0.5 * (depth - 1)) + 2.0 / n : 0.0;
}

/// Makes the parallelogram's opposite sides carry translated copies of each other's vertices again
/// where a refinement split side edges on one side only: a side vertex without a partner across (to
/// 1e-9 in lattice coordinates) splits the opposite side's edge that holds its place, the edge's face
/// becoming a fan. Both sides about a round that crosses them are refined alike (the rounds of the
/// neighbouring holes are focus centres too), so the fans are short.
void match_sides(const LatticeGeometry& L, RemeshedMesh& mesh) {
  const auto snapped = [&](Eigen::Index v) {
    Eigen::Vector2d c = L.coordinates(mesh.vertices.row(v).transpose());
    for (int k = 0; k < 2; ++k)
      if (std::abs(c[k]) < 1e-9) c[k] = 0;
      else if (std::abs(c[k] - 1) < 1e-9) c[k] = 1;
    return c;
  };
  std::vector<Eigen::Vector2d> st(size_t(mesh.vertices.rows()));
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) st[size_t(v)] = snapped(v);
  // Each side (coordinate j at value w) by its vertices' other coordinate.
  std::vector<double> on_side[2][2];
  for (const Eigen::Vector2d& c : st)
    for (int j = 0; j < 2; ++j)
      for (int w = 0; w < 2; ++w)
        if (c[j] == w) on_side[j][w].push_back(c[1 - j]);
  for (auto& family : on_side)
    for (auto& side : family) std::sort(side.begin(), side.end());
  const auto has = [](const std::vector<double>& side, double c) {
    const auto it = std::lower_bound(side.begin(), side.end(), c - 1e-9);
    return it != side.end() && *it <= c + 1e-9;
  };
  // The directed boundary edges along each side, by face: (face, local edge k from vertex k to k + 1).
  std::map<std::pair<int, int>, std::pair<int, int>> directed;
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) directed[{mesh.faces(f, k), mesh.faces(f, (k + 1) % 3)}] = {int(f), k};
  // Points to insert, by face and local edge: their coordinate along the edge (0 at vertex k).
  std::map<std::pair<int, int>, std::vector<std::pair<double, Vec3>>> inserts;
  for (const auto& [edge, at] : directed) {
    if (directed.count({edge.second, edge.first})) continue;  // interior
    const Eigen::Vector2d &a = st[size_t(edge.first)], &b = st[size_t(edge.second)];
    for (int j = 0; j < 2; ++j)
      for (int w = 0; w < 2; ++w) {
        if (a[j] != w || b[j] != w) continue;
        const double lo = std::min(a[1 - j], b[1 - j]), hi = std::max(a[1 - j], b[1 - j]);
        const std::vector<double>& across = on_side[j][1 - w];
        for (auto it = std::upper_bound(across.begin(), across.end(), lo + 1e-9); it != across.end() && *it < hi - 1e-9;
             ++it) {
          if (has(on_side[j][w], *it)) continue;
          Eigen::Vector2d c;
          c[j] = w;
          c[1 - j] = *it;
          inserts[at].emplace_back((*it - a[1 - j]) / (b[1 - j] - a[1 - j]), c[0] * L.a1 + c[1] * L.a2);
        }
      }
  }
  if (inserts.empty()) return;
  std::vector<Vec3> vertices;
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) vertices.push_back(mesh.vertices.row(v).transpose());
  std::vector<Eigen::Vector3i> faces;
  // By face: the points of each of its edges, in order along the edge. A face with points on one
  // edge becomes a fan from the opposite vertex; one at a corner of the parallelogram, with points on
  // two, a fan from its centroid (a fan from a vertex would be flat along one of them).
  std::map<int, std::array<std::vector<std::pair<double, Vec3>>, 3>> by_face;
  for (auto& [at, points] : inserts) {
    std::sort(points.begin(), points.end(), [](const auto& p, const auto& q) { return p.first < q.first; });
    by_face[at.first][size_t(at.second)] = points;
  }
  std::vector<bool> replaced(size_t(mesh.faces.rows()), false);
  for (const auto& [f, edges] : by_face) {
    replaced[size_t(f)] = true;
    int split = 0, k = 0;
    for (int e = 0; e < 3; ++e)
      if (!edges[size_t(e)].empty()) ++split, k = e;
    std::vector<int> ring;  // the face's boundary with the new points, counter-clockwise from vertex 0
    for (int e = 0; e < 3; ++e) {
      ring.push_back(mesh.faces(f, e));
      for (const auto& [t, X] : edges[size_t(e)]) {
        vertices.push_back(X);
        ring.push_back(int(vertices.size()) - 1);
      }
    }
    int apex = mesh.faces(f, (k + 2) % 3);
    if (split > 1) {
      vertices.push_back((mesh.vertices.row(mesh.faces(f, 0)) + mesh.vertices.row(mesh.faces(f, 1)) +
                          mesh.vertices.row(mesh.faces(f, 2))).transpose() / 3.0);
      apex = int(vertices.size()) - 1;
    }
    for (size_t i = 0; i < ring.size(); ++i) {
      const int a = ring[i], b = ring[(i + 1) % ring.size()];
      if (a != apex && b != apex) faces.emplace_back(a, b, apex);
    }
  }
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    if (!replaced[size_t(f)]) faces.push_back(mesh.faces.row(f).transpose());
  mesh.vertices.resize(Eigen::Index(vertices.size()), 3);
  for (size_t v = 0; v < vertices.size(); ++v) mesh.vertices.row(Eigen::Index(v)) = vertices[v].transpose();
  mesh.faces.resize(Eigen::Index(faces.size()), 3);
  for (size_t f = 0; f < faces.size(); ++f) mesh.faces.row(Eigen::Index(f)) = faces[f].transpose();
}

RemeshedMesh refine_rounds(const LatticeGeometry& L, RemeshedMesh mesh, const RowMatX3d& surface_V,
                           const RowMatX3i& surface_F, const std::vector<Vec3>& centres, double round_radius, int n,
                           double round_edges, int remesh_iterations) {
  const int depth = round_depth(round_radius, n, round_edges);
  if (centres.empty() || depth <= 0) return mesh;
  RemeshOptions ro;
  ro.target_edge_length = 1.0 / n;
  ro.iterations = remesh_iterations;
  ro.grading.focus = centres;
  ro.grading.focus_radius = 2 * round_radius;
  ro.grading.focus_depth = depth;
  // Rounds near a side (a hole that crosses the parallelogram) are refined there too, on both sides;
  // match_sides makes them copies of each other again.
  RemeshedMesh refined = refine_about(mesh.vertices, mesh.faces, std::vector<bool>(size_t(mesh.faces.rows()), false),
                                      surface_V, surface_F, ro);
  match_sides(L, refined);
  return refined;
}

/// Collapses every boundary edge of the cut block's centre cell shorter than `tiny` onto one of its
/// ends, as the remesher's step 1 does for a hole inside the cell (isotropic_remesh.h), but so that
/// the sides stay translated copies: a vertex on a side is the one kept, and the sides' own short
/// pieces stay. A collapse that would flip a face or leave it a tenth of its area is not made; the
/// face on the edge goes. Without it the block path kept every short
/// piece the cut made where an outline passes close to a grid line: faces of 1e-9 of the cell's
/// beside them, where the heart's cell at its lowest fill ratios read bending factors of 74 drawn
/// and 130–630 cut by a tool, or no positive definite stiffness at all; and two rim vertices
/// 2e-10 apart (the default ellipse opened by half its size, its arcs ending on the grid's middle
/// line), which tile_cell, welding copies by their lattice coordinates to 1e-8, made one.
void merge_tiny_rim_edges(const LatticeGeometry& L, double tiny, std::vector<Vec3>& vertices,
                          std::vector<Eigen::Vector3i>& faces) {
  std::map<std::pair<int, int>, int> count;
  for (const Eigen::Vector3i& f : faces)
    for (int k = 0; k < 3; ++k) ++count[{std::min(f[k], f[(k + 1) % 3]), std::max(f[k], f[(k + 1) % 3])}];
  // Lattice coordinates snapped onto the sides, as tile_cell snaps them.
  std::vector<Eigen::Vector2d> st(vertices.size());
  for (size_t v = 0; v < vertices.size(); ++v) {
    st[v] = L.coordinates(vertices[v]);
    for (int k = 0; k < 2; ++k)
      if (std::abs(st[v][k]) < 1e-9) st[v][k] = 0;
      else if (std::abs(st[v][k] - 1) < 1e-9) st[v][k] = 1;
  }
  const auto on_side = [&](int v) { return st[size_t(v)].minCoeff() == 0 || st[size_t(v)].maxCoeff() == 1; };
  // Faces by vertex, kept current as vertices merge.
  std::vector<std::vector<int>> around(vertices.size());
  for (size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k) around[size_t(faces[f][k])].push_back(int(f));
  std::vector<bool> gone(faces.size(), false);
  const auto area = [&](const Eigen::Vector3i& f) {
    return 0.5 * (vertices[size_t(f[1])] - vertices[size_t(f[0])]).cross(vertices[size_t(f[2])] - vertices[size_t(f[0])]).z();
  };
  std::vector<bool> dropped(vertices.size(), false);
  for (const auto& [edge, n] : count) {
    const int a = edge.first, b = edge.second;
    if (n != 1 || dropped[size_t(a)] || dropped[size_t(b)]) continue;
    if ((vertices[size_t(a)] - vertices[size_t(b)]).norm() >= tiny) continue;
    // A vertex on a side stays (its copy across must keep its partner), and a side's own pieces are
    // left as they are: whether a collapse is made depends on the faces about it, which differ
    // between a side and its copy.
    if (on_side(a) && on_side(b)) continue;
    const int keep = on_side(a) ? a : on_side(b) ? b : std::min(a, b);
    const int drop = keep == a ? b : a;
    // The faces around the dropped end that stay must keep their orientation and a tenth of their
    // area (an edge collapse that would flip or flatten one is not made).
    bool ok = true;
    for (const int f : around[size_t(drop)]) {
      if (gone[size_t(f)] || (faces[size_t(f)].array() == keep).any()) continue;
      Eigen::Vector3i g = faces[size_t(f)];
      for (int k = 0; k < 3; ++k)
        if (g[k] == drop) g[k] = keep;
      ok = ok && area(g) > 0.1 * area(faces[size_t(f)]);
    }
    if (!ok) continue;
    for (const int f : around[size_t(drop)]) {
      if (gone[size_t(f)]) continue;
      if ((faces[size_t(f)].array() == keep).any()) {
        gone[size_t(f)] = true;
        continue;
      }
      for (int k = 0; k < 3; ++k)
        if (faces[size_t(f)][k] == drop) faces[size_t(f)][k] = keep;
      around[size_t(keep)].push_back(f);
    }
    around[size_t(drop)].clear();
    dropped[size_t(drop)] = true;
  }
  std::vector<Eigen::Vector3i> kept;
  for (size_t f = 0; f < faces.size(); ++f)
    if (!gone[f]) kept.push_back(faces[f]);
  faces = std::move(kept);
}

SurfaceMesh period_cell(const LatticeGeometry& L, const CellHole& hole, double scale, int n, int remesh_iterations,
                        double tool, double round_edges) {
  SurfaceMesh grid = lattice_grid(L, n, 0, 1, 0, 1);
  if (scale <= 0) return grid;
  StencilLibrary library;
  library.add(hole.shape);
  RemeshOptions ro;
  ro.target_edge_length = 1.0 / n;
  ro.iterations = remesh_iterations;
  StencilParams centre;
  centre.position = 0.5 * (L.a1 + L.a2);
  centre.scale = scale;
  // The rounds' points of every hole placed (angle 0: the reference frame's axes are the cell's).
  const auto round_centres = [&](const std::vector<StencilParams>& placed) {
    std::vector<Vec3> out;
    for (const StencilParams& p : placed)
      for (const Vec2& q : hole.rounds) out.push_back(p.position + scale * Vec3(q.x(), q.y(), 0));
    return out;
  };
  if (scale <= L.inscribed) {
    // The hole inside the cell.
    const FaceBvh bvh(grid);
    const CutSurface cut = cut_stencils(bvh, library, AxisTangentField(), std::span(&centre, 1));
    RemeshedMesh r = refine_rounds(L, remesh_isotropic(cut.vertices, cut.faces, ro), cut.vertices, cut.faces,
                                   round_centres({centre}), tool * scale, n, round_edges, remesh_iterations);
    return SurfaceMesh(std::move(r.vertices), std::move(r.faces), "homogenisation cell");
  }
  // A hole larger than the cell's inscribed circle crosses its sides, and its parts outside come
  // back in through the opposite sides: the 3 × 3 block of cells is cut by the nine holes and the
  // centre cell's pieces kept (each piece lies in one grid triangle, so the sides stay edges).
  const SurfaceMesh block = lattice_grid(L, n, -1, 2, -1, 2);
  std::vector<StencilParams> holes;
  for (int m = -1; m <= 1; ++m)
    for (int k = -1; k <= 1; ++k) {
      StencilParams p = centre;
      p.position += m * L.a1 + k * L.a2;
      holes.push_back(p);
    }
  const FaceBvh bvh(block);
  const CutSurface cut = cut_stencils(bvh, library, AxisTangentField(), holes);
  const int w = 3 * n;
  std::vector<int> index(size_t(cut.vertices.rows()), -1);
  std::vector<Vec3> vertices;
  std::vector<Eigen::Vector3i> faces;
  for (Eigen::Index f = 0; f < cut.faces.rows(); ++f) {
    const int source = cut.source_face[f] / 2, i = source % w, j = source / w;
    if (i < n || i >= 2 * n || j < n || j >= 2 * n) continue;
    Eigen::Vector3i face;
    for (int k = 0; k < 3; ++k) {
      int& v = index[size_t(cut.faces(f, k))];
      if (v < 0) {
        v = int(vertices.size());
        vertices.push_back(cut.vertices.row(cut.faces(f, k)).transpose());
      }
      face[k] = v;
    }
    faces.push_back(face);
  }
  merge_tiny_rim_edges(L, 0.1 / n, vertices, faces);
  RowMatX3d V(Eigen::Index(vertices.size()), 3);
  RowMatX3i F(Eigen::Index(faces.size()), 3);
  for (size_t v = 0; v < vertices.size(); ++v) V.row(Eigen::Index(v)) = vertices[v].transpose();
  for (size_t f = 0; f < faces.size(); ++f) F.row(Eigen::Index(f)) = faces[f].transpose();
  // No other short boundary edge is collapsed: a collapse picks an end by the faces around it, which
  // differ on opposite sides, and the sides must stay translated copies of each other (tile_cell
  // checks it).
  ro.min_boundary_edge = 0;
  RemeshedMesh r = refine_rounds(L, remesh_isotropic(V, F, ro), V, F, round_centres(holes), tool * scale, n,
                                 round_edges, remesh_iterations);
  return SurfaceMesh(std::move(r.vertices), std::move(r.faces), "homogenisation cell");
}

/// The cell tiled 3 × 3 (copies translated by m a₁ + n a₂, m, n ∈ {−1, 0, 1}, welded along the
/// shared sides), so that every face of the centre copy has its whole bending patch and every rim
/// point of the centre copy its whole recovery patch; the copies' faces whose centroids lie farther
/// than `margin` (spacings, in lattice coordinates) outside the centre rhombus are left out (the
/// centre copy's elements and rim patches reach a few edges; the rest would only cost time).
/// `period` receives, per tiled vertex, its periodic class (one per distinct cell vertex modulo the
/// lattice); `rim`, per tiled vertex, whether it lies on a hole's rim (a boundary edge of the cell
/// that is not along a side); `centre_faces` the first face of the centre copy.
SurfaceMesh tile_cell(const LatticeGeometry& L, const SurfaceMesh& cell, double margin, std::vector<int>& period,
                      std::vector<bool>& rim, int& centre_faces, int& classes) {
  const int nv = cell.num_vertices(), nf = cell.num_faces();
  // Lattice coordinates, snapped onto the sides so that copies meet exactly.
  std::vector<Eigen::Vector2d> st(static_cast<size_t>(nv));
  for (int v = 0; v < nv; ++v) {
    Eigen::Vector2d c = L.coordinates(cell.vertices().row(v).transpose());
    for (int k = 0; k < 2; ++k)
      if (std::abs(c[k]) < 1e-9) c[k] = 0;
      else if (std::abs(c[k] - 1) < 1e-9) c[k] = 1;
    st[size_t(v)] = c;
  }
  // The cell's rim vertices: ends of boundary edges not along a side (a side's edge has both ends
  // on the same side line).
  std::vector<bool> cell_rim(static_cast<size_t>(nv), false);
  {
    std::map<std::pair<int, int>, int> edges;
    for (int f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) {
        const int a = cell.faces()(f, k), b = cell.faces()(f, (k + 1) % 3);
        ++edges[{std::min(a, b), std::max(a, b)}];
      }
    for (const auto& [e, count] : edges) {
      if (count != 1) continue;
      const Eigen::Vector2d &a = st[size_t(e.first)], &b = st[size_t(e.second)];
      bool side = false;
      for (int k = 0; k < 2; ++k) side = side || (a[k] == b[k] && (a[k] == 0 || a[k] == 1));
      if (!side) cell_rim[size_t(e.first)] = cell_rim[size_t(e.second)] = true;
    }
  }
  const auto key = [](double s, double t) { return std::pair(std::llround(s * 1e8), std::llround(t * 1e8)); };
  std::map<std::pair<long long, long long>, int> tiled_index, class_index;
  std::vector<Vec3> positions;
  std::vector<Eigen::Vector3i> faces;
  period.clear();
  rim.clear();
  for (int n = -1; n <= 1; ++n)
    for (int m = -1; m <= 1; ++m) {
      if (m == 0 && n == 0) centre_faces = int(faces.size());
      std::vector<int> kept;
      std::vector<bool> used(static_cast<size_t>(nv), false);
      for (int f = 0; f < nf; ++f) {
        Eigen::Vector2d c = Eigen::Vector2d(m, n);
        for (int k = 0; k < 3; ++k) c += st[size_t(cell.faces()(f, k))] / 3.0;
        if (c.minCoeff() < -margin || c.maxCoeff() > 1 + margin) continue;
        kept.push_back(f);
        for (int k = 0; k < 3; ++k) used[size_t(cell.faces()(f, k))] = true;
      }
      std::vector<int> local(static_cast<size_t>(nv), -1);
      for (int v = 0; v < nv; ++v) {
        if (!used[size_t(v)]) continue;
        const Eigen::Vector2d& c = st[size_t(v)];
        const auto [it, added] = tiled_index.try_emplace(key(c[0] + m, c[1] + n), int(positions.size()));
        if (added) {
          positions.push_back(cell.vertices().row(v).transpose() + m * L.a1 + n * L.a2);
          const double ps = c[0] - std::floor(c[0] + 1e-12), pt = c[1] - std::floor(c[1] + 1e-12);
          const auto [cls, fresh] = class_index.try_emplace(key(ps, pt), int(class_index.size()));
          period.push_back(cls->second);
          rim.push_back(false);
        }
        if (cell_rim[size_t(v)]) rim[size_t(it->second)] = true;
        local[size_t(v)] = it->second;
      }
      for (const int f : kept)
        faces.emplace_back(local[size_t(cell.faces()(f, 0))], local[size_t(cell.faces()(f, 1))],
                           local[size_t(cell.faces()(f, 2))]);
    }
  classes = int(class_index.size());
  // Opposite sides must carry translated copies of each other's vertices, or the copies would not
  // weld and the periodic problem would have cracks along the sides.
  std::map<std::pair<long long, long long>, int> side_count;
  for (const Eigen::Vector2d& c : st)
    for (int k = 0; k < 2; ++k)
      if (c[k] == 0 || c[k] == 1) {
        const double along = c[1 - k];
        ++side_count[{k, std::llround(along * 1e8)}];
      }
  for (const auto& [side, count] : side_count)
    if (count != 2)
      throw InternalError(fmt::format("homogenisation cell: the sides are not periodic (a vertex at {:.6f} along "
                                      "side {} has no partner on the opposite side)",
                                      double(side.second) * 1e-8, side.first));
  RowMatX3d V(Eigen::Index(positions.size()), 3);
  RowMatX3i F(Eigen::Index(faces.size()), 3);
  for (size_t v = 0; v < positions.size(); ++v) V.row(Eigen::Index(v)) = positions[v].transpose();
  for (size_t f = 0; f < faces.size(); ++f) F.row(Eigen::Index(f)) = faces[f].transpose();
  return SurfaceMesh(std::move(V), std::move(F), "tiled homogenisation cell");
}

/// One element's rest Hessian (3K×3K) over its periodic classes (−1: a node that is not a mesh
/// vertex), with the macroscopic fields at its nodes' true positions (3K × kCases).
struct LocalStiffness {
  int face = -1;  ///< the face of the cell (centre copy) the element belongs to
  std::vector<int> cls;
  Eigen::MatrixXd K;
  Eigen::MatrixXd macro;
};

/// Solves the periodic cell problem: ũ (per class, 3 DOFs; class 0 held, which removes the
/// translations) minimising Σ_e ½ (ū_e + ũ_e)ᵀ K_e (ū_e + ũ_e) for every case. Returns the
/// homogenised 6 × 6 matrix Σ_e (ū_e + ũ_e)ᵢᵀ K_e (ū_e + ũ_e)ⱼ.
/// `fluctuation` (optional) receives ũ: 3(classes − 1) × kCases, rows 3(c − 1) … 3(c − 1) + 2 for class c.
Eigen::Matrix<double, kCases, kCases> solve_periodic(const std::vector<LocalStiffness>& elements, int classes,
                                                     Eigen::MatrixXd* fluctuation = nullptr) {
  const int n = 3 * (classes - 1);
  const auto dof = [](int cls) { return 3 * (cls - 1); };  // class 0 is held
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, kCases);
  for (const LocalStiffness& el : elements) {
    const Eigen::MatrixXd Ku = el.K * el.macro;
    for (size_t a = 0; a < el.cls.size(); ++a) {
      if (el.cls[a] <= 0) continue;
      const int I = dof(el.cls[a]);
      rhs.middleRows<3>(I) -= Ku.middleRows<3>(3 * Eigen::Index(a));
      for (size_t b = 0; b < el.cls.size(); ++b) {
        if (el.cls[b] <= 0) continue;
        const int J = dof(el.cls[b]);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            const double k = el.K(3 * Eigen::Index(a) + i, 3 * Eigen::Index(b) + j);
            if (I + i <= J + j && k != 0) triplets.emplace_back(I + i, J + j, k);
          }
      }
    }
  }
  Eigen::SparseMatrix<double> K(n, n);
  K.setFromTriplets(triplets.begin(), triplets.end());
  K.makeCompressed();
  const std::vector<int> starts(K.outerIndexPtr(), K.outerIndexPtr() + n + 1),
      rows(K.innerIndexPtr(), K.innerIndexPtr() + K.nonZeros());
  CholmodSolver solver;
  solver.analyze(n, starts, rows);
  if (!solver.factorize(K.valuePtr()))
    throw SolveError("homogenisation: the perforated cell's stiffness is not positive definite");
  Eigen::MatrixXd periodic(n, kCases);
  for (int k = 0; k < kCases; ++k) {
    const Eigen::VectorXd b = rhs.col(k);
    solver.solve(b.data(), periodic.col(k).data());
  }
  if (fluctuation) *fluctuation = periodic;
  Eigen::Matrix<double, kCases, kCases> C = Eigen::Matrix<double, kCases, kCases>::Zero();
  for (const LocalStiffness& el : elements) {
    Eigen::MatrixXd u = el.macro;
    for (size_t a = 0; a < el.cls.size(); ++a)
      if (el.cls[a] > 0) u.middleRows<3>(3 * Eigen::Index(a)) += periodic.middleRows<3>(dof(el.cls[a]));
    C += u.transpose() * el.K * u;
  }
  return C;
}

/// The macroscopic states of ConcentrationState (header), as unit Voigt stresses or moments.
std::vector<std::pair<ConcentrationState, Eigen::Vector3d>> concentration_states() {
  std::vector<std::pair<ConcentrationState, Eigen::Vector3d>> states;
  for (int j = 0; j < 12; ++j) {
    const double t = j * std::numbers::pi / 12, c = std::cos(t), s = std::sin(t);
    states.push_back({{"uniaxial", t, 1}, Eigen::Vector3d(c * c, s * s, c * s)});
  }
  states.push_back({{"equibiaxial", 0, 1}, Eigen::Vector3d(1, 1, 0)});
  for (int j = 0; j < 4; ++j) {
    const double t = j * std::numbers::pi / 8;
    states.push_back({{"shear", t, 1}, Eigen::Vector3d(std::cos(2 * t), -std::cos(2 * t), std::sin(2 * t))});
  }
  return states;
}

/// K of every state (CellStiffness::membrane_states, bending_states) from the solved cell problem
/// (see "Reading the peak" in cell_homogenisation.h): per face of the centre copy the quadratic form
/// Q_f = Σ_e u_eᵀ K_e u_e of its elements over the six unit cases (face energy ½ ε̄ᵀ Q_f ε̄), and per
/// rim point of the centre copy's hole the recovered ε_tt, κ_tt, κ_tm of each unit case
/// (rim_recovery.h; linear in the case's displacement, read at amplitude kProbe).
void stress_concentration(const SurfaceMesh& cell, const ShellModel& model, const std::vector<int>& period,
                          int centre, const std::vector<LocalStiffness>& elements, const Eigen::MatrixXd& fluctuation,
                          const std::vector<Vec3>& rounds, double round_zone, CellStiffness& out) {
  const double scale = out.scale;  // the stencil's bounding radius in lattice spacings
  using Mat6 = Eigen::Matrix<double, kCases, kCases>;
  const int nf = cell.num_faces();
  const auto dof = [](int cls) { return 3 * Eigen::Index(cls - 1); };
  std::vector<Mat6> Q(size_t(nf), Mat6::Zero());
  Mat6 total = Mat6::Zero();
  for (const LocalStiffness& el : elements) {
    Eigen::MatrixXd u = el.macro;
    for (size_t a = 0; a < el.cls.size(); ++a)
      if (el.cls[a] > 0) u.middleRows<3>(3 * Eigen::Index(a)) += fluctuation.middleRows<3>(dof(el.cls[a]));
    const Mat6 q = u.transpose() * el.K * u;
    Q[size_t(el.face)] += q;
    total += q;
  }
  // The rim of the whole tiled cell under each unit case, recovered at a small amplitude (the
  // recovery reads Green–Lagrange strain and the deformed normal: quadratic terms of order kProbe).
  const SurfaceMesh& tiled = model.mesh();
  const RowMatX3d& X = tiled.vertices();
  const RimRecoveryOptions ro;
  std::vector<std::vector<RimPoint>> rim(kCases);
  for (int k = 0; k < kCases; ++k) {
    RowMatX3d x(X.rows(), 3);
    for (Eigen::Index v = 0; v < X.rows(); ++v) {
      Vec3 w = macro_displacement(k, X.row(v).transpose());
      const int cls = period[size_t(v)];
      if (cls > 0) w += fluctuation.block<3, 1>(dof(cls), k);
      x.row(v) = X.row(v) + kProbe * w.transpose();
    }
    rim[size_t(k)] = recover_rim(model, x, ro);
    if (rim[size_t(k)].size() != rim[0].size()) throw InternalError("cell rim recovery: the rim changed between cases");
  }
  // The centre copy's rim points (not singular), and per point its unit-case values.
  std::vector<bool> in_centre(size_t(X.rows()), false);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) in_centre[size_t(tiled.faces()(centre + f, k))] = true;
  std::vector<size_t> points;
  for (size_t i = 0; i < rim[0].size(); ++i)
    if (in_centre[size_t(rim[0][i].vertex)] && !rim[0][i].singular) points.push_back(i);
  // Under the corner rule at each node ε_c (in bounding radii, `scale` lattice spacings each): the
  // points farther than ε_c from the singular corners found with a window of ε_c/4 (as verify).
  std::vector<std::vector<size_t>> points_by_corner(kCornerNodes);
  points_by_corner[0] = points;
  // Only the holes' corners: the tiled patch's outer boundary (pinned, no rim) has corners of its own.
  const auto on_rim = [&](const Vec3& q) {
    for (const RimPoint& p : rim[0])
      if ((X.row(p.vertex).transpose() - q).norm() <= 1e-9 * scale) return true;
    return false;
  };
  for (int c = 1; c < kCornerNodes; ++c) {
    const double radius = corner_node(c) * scale;
    std::vector<Vec3> corners;
    for (const Vec3& q : singular_corners(X, tiled.faces(), RimRecoveryOptions{}.corner_angle, 0.25 * radius))
      if (on_rim(q)) corners.push_back(q);
    for (const size_t i : points) {
      bool near = false;
      const Vec3 at = X.row(rim[0][i].vertex).transpose();
      for (const Vec3& q : corners) near = near || (at - q).norm() < radius;
      if (!near) points_by_corner[size_t(c)].push_back(i);
    }
  }
  // Faces within a rim point's patch are left to the rim's reading: a face's constant strain (and
  // its shape-operator curvature) next to a free edge scatters with the faces' shapes (the largest
  // face W next to a dilute circle's rim read 1.2× Goodier's bending peak, and ±7% on Kirsch's).
  // So are the faces the tool's rounds graded (within `round_zone` of their points): next to a face of
  // half its size a face's shape-operator curvature is not the plate's (the discrete shape operator
  // is consistent on regular meshes only), and on a star's rounds of 1/64 its bending W read 4× the
  // rim's peak there.
  std::vector<bool> off_rim(size_t(nf), true);
  for (int f = 0; f < nf; ++f) {
    const Vec3 c = (X.row(tiled.faces()(centre + f, 0)) + X.row(tiled.faces()(centre + f, 1)) +
                    X.row(tiled.faces()(centre + f, 2))).transpose() / 3.0;
    for (const Vec3& q : rounds)
      if ((c - q).norm() <= round_zone) {
        off_rim[size_t(f)] = false;
        break;
      }
    if (!off_rim[size_t(f)]) continue;
    for (const RimPoint& p : rim[0])
      if ((c - p.position).norm() <= p.patch_radius) {
        off_rim[size_t(f)] = false;
        break;
      }
  }
  const Material& material = model.material();
  const double material_area = cell.face_areas().sum();
  const Eigen::VectorXd& A = cell.face_areas();
  out.membrane_states.clear();
  out.bending_states.clear();
  out.membrane_concentration = out.bending_concentration = 0;
  // K of one macroscopic stress (part 0) or moment (part 1) state, Voigt, any amplitude, over the
  // faces off the rim and the rim points of each corner node (`by_corner`: kCornerNodes values;
  // null: node 0 only, returned).
  const auto factor = [&](int part, const Eigen::Vector3d& load, double* by_corner = nullptr) {
    const int o = 3 * part;
    const Eigen::Matrix3d stiffness = part == 0 ? out.membrane : out.bending;
    const Eigen::Vector3d e = stiffness.ldlt().solve(load);
    const double mean = 0.5 * e.dot(total.block<3, 3>(o, o) * e) / material_area;
    double face_peak = 0;
    for (int f = 0; f < nf; ++f)
      if (off_rim[size_t(f)]) face_peak = std::max(face_peak, 0.5 * e.dot(Q[size_t(f)].block<3, 3>(o, o) * e) / A[f]);
    const auto rim_peak = [&](const std::vector<size_t>& pts) {
      double peak = face_peak;
      for (const size_t i : pts) {
        double strain = 0, curvature = 0, twist = 0;
        for (int k = 0; k < 3; ++k) {
          const RimPoint& p = rim[size_t(o + k)][i];
          strain += e[k] * p.strain, curvature += e[k] * p.curvature, twist += e[k] * p.twist;
        }
        // Only the part's own quantities: a flat cell's membrane cases do not bend its rim, nor its
        // bending cases stretch it (both to order kProbe).
        peak = std::max(peak, part == 0 ? free_edge_energy_density(material, strain / kProbe)
                                        : free_edge_energy_density(material, 0, curvature / kProbe, twist / kProbe));
      }
      return peak / mean;
    };
    if (by_corner)
      for (int c = 0; c < kCornerNodes; ++c) by_corner[c] = rim_peak(points_by_corner[size_t(c)]);
    return rim_peak(points);
  };
  for (auto [state, load] : concentration_states()) {
    for (int part = 0; part < 2; ++part) {  // membrane, bending
      state.factor = factor(part, load);
      (part == 0 ? out.membrane_states : out.bending_states).push_back(state);
      double& K = part == 0 ? out.membrane_concentration : out.bending_concentration;
      K = std::max(K, state.factor);
    }
  }
  // By biaxiality: principal values (1, ρ_j) at every angle θ of the 7.5° grid, the largest K.
  out.membrane_concentration_by_biaxiality.assign(kBiaxialityNodes, 0.0);
  out.bending_concentration_by_biaxiality.assign(kBiaxialityNodes, 0.0);
  out.membrane_concentration_by_corner.assign(size_t(kCornerNodes * kBiaxialityNodes), 0.0);
  out.bending_concentration_by_corner.assign(size_t(kCornerNodes * kBiaxialityNodes), 0.0);
  for (int j = 0; j < kBiaxialityNodes; ++j) {
    const double rho = biaxiality_node(j);
    for (int a = 0; a < kBiaxialityAngles; ++a) {
      const double t = a * std::numbers::pi / kBiaxialityAngles, c = std::cos(t), s = std::sin(t);
      const Eigen::Vector3d load(c * c + rho * s * s, s * s + rho * c * c, (1 - rho) * c * s);
      for (int part = 0; part < 2; ++part) {
        double& K = (part == 0 ? out.membrane_concentration_by_biaxiality : out.bending_concentration_by_biaxiality)[size_t(j)];
        std::array<double, kCornerNodes> by_corner{};
        K = std::max(K, factor(part, load, by_corner.data()));
        std::vector<double>& table = part == 0 ? out.membrane_concentration_by_corner : out.bending_concentration_by_corner;
        for (int n = 0; n < kCornerNodes; ++n)
          table[size_t(n * kBiaxialityNodes + j)] = std::max(table[size_t(n * kBiaxialityNodes + j)], by_corner[size_t(n)]);
      }
    }
  }
  // The worst state is the worst of all of them: in bending it lies between uniaxial and
  // equibiaxial (Goodier: ρ ≈ 0.5 gives 4.3 against 3.3 for both, ν = 0.4).
  for (const double k : out.membrane_concentration_by_biaxiality)
    out.membrane_concentration = std::max(out.membrane_concentration, k);
  for (const double k : out.bending_concentration_by_biaxiality)
    out.bending_concentration = std::max(out.bending_concentration, k);
}

}  // namespace

bool tool_changes_cell(const StencilShape& shape, double tool_radius) {
  return !cell_hole(shape, tool_radius).rounds.empty();
}

Eigen::Matrix3d solid_membrane_stiffness(const Material& m) {
  const double nu = m.poisson_ratio;
  return isotropic_voigt(m.youngs_modulus * m.thickness / (1 - nu * nu), nu);
}

Eigen::Matrix3d solid_bending_stiffness(const Material& m) {
  const double nu = m.poisson_ratio;
  return isotropic_voigt(m.youngs_modulus * std::pow(m.thickness, 3) / (12 * (1 - nu * nu)), nu);
}

Eigen::Vector2d isotropic_moduli(const Eigen::Matrix3d& C) {
  const double bulk = (C(0, 0) + C(1, 1) + 2 * C(0, 1)) / 4;
  const double shear = ((C(0, 0) + C(1, 1) - 2 * C(0, 1)) / 4 + C(2, 2)) / 2;
  return {bulk, shear};
}

double lattice_anisotropy(const Eigen::Matrix3d& C) {
  const double g1 = (C(0, 0) + C(1, 1) - 2 * C(0, 1)) / 4, g2 = C(2, 2);
  return (g1 - g2) / (g1 + g2);
}

double max_hole_fraction(const StencilShape& shape, double ligament, CellLattice lattice) {
  // The hole's bounding circle inside the (Voronoi) cell's inscribed circle, radius ½ on both
  // lattices: where the bounding circles of neighbours touch.
  const double s = 0.5 * (1 - ligament);
  return std::min(1.0, shape.area * s * s / LatticeGeometry(lattice).area);
}

CellStiffness homogenise_cell(const StencilShape& shape, const Material& material, double fill_ratio,
                              const CellOptions& options) {
  if (!(options.resolution >= 6 && options.resolution <= 200))
    throw InputError("homogenisation: the cell resolution must be in [6, 200] edges per lattice spacing");
  if (!(options.rim_edges >= 0 && options.rim_edges <= 64))
    throw InputError("homogenisation: rim_edges must be in [0, 64] edges per stencil bounding radius");
  if (!(options.tool_radius >= 0 && options.tool_radius <= 1))
    throw InputError("homogenisation: the tool radius must be in [0, 1] stencil bounding radii");
  if (!(options.round_edges >= 2 && options.round_edges <= 32))
    throw InputError("homogenisation: round_edges must be in [2, 32] edges per tool radius");
  const LatticeGeometry L(options.lattice);
  const double lowest = 1 - max_hole_fraction(shape, 0.1, options.lattice);
  if (!(fill_ratio >= lowest && fill_ratio <= 1))
    throw InputError(fmt::format("homogenisation: fill ratio {} of stencil '{}' outside [{:.3f}, 1] (the hole would "
                                 "reach its neighbours)",
                                 fill_ratio, shape.name, lowest));
  CellStiffness out;
  out.fill_ratio = fill_ratio;
  out.scale = std::sqrt((1 - fill_ratio) * L.area / shape.area);
  // The narrowest ligament (between neighbouring bounding circles, 1 − 2s spacings) gets at least
  // kLigamentElements triangles across: the bending factor and its peak are otherwise too coarse
  // where holes nearly touch (circles at α = 0.30: g_b 0.173 and K_b 22 at 24 edges per spacing,
  // 0.200 and 7.9 at 48, with g_b and K_b smooth and monotone in α at 48 and jumping at 24).
  const double resolution =
      std::min(200.0, std::max({options.resolution, kLigamentElements / (1 - 2 * out.scale), out.scale > 0 ? options.rim_edges / out.scale : 0.0}));
  out.resolution = resolution;
  const CellHole hole = cell_hole(shape, options.tool_radius);
  const SurfaceMesh cell = period_cell(L, hole, out.scale, int(std::lround(resolution)),
                                       options.remesh_iterations, options.tool_radius, options.round_edges);
  out.vertices = cell.num_vertices();
  out.faces = cell.num_faces();
  out.window_fill_ratio = cell.face_areas().sum() / L.area;

  std::vector<int> period;
  std::vector<bool> rim;
  int centre = 0, classes = 0;
  const SurfaceMesh tiled =
      tile_cell(L, cell, std::max(kTileMargin, kTileMarginEdges / resolution), period, rim, centre, classes);
  // The shell on the tiled cell: its outer boundary pinned only to satisfy the model's checks (the
  // centre copy's elements and rim patches, the only ones used, stay a margin away from it); the
  // holes' rims are free, for the rim recovery.
  LoadCase lc;
  lc.fixed = tiled.is_boundary_vertex();
  for (size_t v = 0; v < lc.fixed.size(); ++v) lc.fixed[v] = lc.fixed[v] && !rim[v];
  lc.clamped.assign(size_t(tiled.num_vertices()), false);
  lc.gravity = Vec3(0, 0, -9.81);
  const ShellModel model(tiled, material, lc, MechanicsSettings{});

  const RowMatX3d& X = tiled.vertices();
  std::vector<LocalStiffness> elements;
  for (int e = 0; e < model.num_elements(); ++e) {
    const ElementRef ref = model.element(e);
    const int face = ref.kind == ElementKind::Membrane ? ref.index : model.bends()[size_t(ref.index)].face;
    if (face < centre || face >= centre + cell.num_faces()) continue;
    LocalStiffness el;
    el.face = face - centre;
    visit_element(model, X, e, 1.0, ElementNeed::Hessian, [&](const auto& l) {
      el.K = l.hessian;
      el.macro = Eigen::MatrixXd::Zero(el.K.rows(), kCases);
      for (size_t a = 0; a < l.vertex.size(); ++a) {
        const int v = l.vertex[a];
        el.cls.push_back(v >= 0 ? period[size_t(v)] : -1);
        if (v < 0) continue;
        for (int k = 0; k < kCases; ++k)
          el.macro.block<3, 1>(3 * Eigen::Index(a), k) = macro_displacement(k, X.row(v).transpose());
      }
    });
    elements.push_back(std::move(el));
  }
  Eigen::MatrixXd fluctuation;
  const Eigen::Matrix<double, kCases, kCases> C = solve_periodic(elements, classes, &fluctuation) / L.area;
  out.membrane = C.topLeftCorner<3, 3>();
  out.bending = C.bottomRightCorner<3, 3>();
  out.membrane_factor = (out.membrane * solid_membrane_stiffness(material).inverse()).trace() / 3;
  out.bending_factor = (out.bending * solid_bending_stiffness(material).inverse()).trace() / 3;
  const Eigen::Vector2d m = isotropic_moduli(out.membrane), m0 = isotropic_moduli(solid_membrane_stiffness(material));
  const Eigen::Vector2d b = isotropic_moduli(out.bending), b0 = isotropic_moduli(solid_bending_stiffness(material));
  out.membrane_bulk_factor = m[0] / m0[0], out.membrane_shear_factor = m[1] / m0[1];
  out.bending_bulk_factor = b[0] / b0[0], out.bending_shear_factor = b[1] / b0[1];
  out.membrane_anisotropy = lattice_anisotropy(out.membrane);
  out.bending_anisotropy = lattice_anisotropy(out.bending);
  // The rounds' points of the centre hole and its eight neighbours (those within the zone of the
  // centre cell's faces), in the tiled cell's coordinates (the centre copy's are the cell's).
  std::vector<Vec3> rounds;
  for (int m = -1; m <= 1; ++m)
    for (int k = -1; k <= 1; ++k)
      for (const Vec2& q : hole.rounds)
        rounds.push_back(0.5 * (L.a1 + L.a2) + double(m) * L.a1 + double(k) * L.a2 + out.scale * Vec3(q.x(), q.y(), 0));
  stress_concentration(cell, model, period, centre, elements, fluctuation, rounds,
                       round_zone(options.tool_radius * out.scale, int(std::lround(resolution)), options.round_edges), out);
  return out;
}

}  // namespace cutwork::solvers
