#include "host/cut/cut_surface.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/stencil/fill_ratio.h"
#include "kernels/common/stencil_geometry.h"

namespace cutwork {
namespace {

using kernels::orient2;

/// Snapping. Features of the cut closer than the snap distance δ are made one: a polygon
/// vertex within δ of a mesh edge lies on it, within 2δ of a mesh vertex it is that vertex,
/// points of one mesh edge within δ of each other are one vertex and within δ of an end they
/// are that end. Every other feature keeps at least δ from the others, so no output face is a
/// needle or a sliver: twice its area is ≳ δ × its longest edge, i.e. ≳ kSnapRelative × its
/// longest edge² (the mesh loader rejects faces below 1e-12). Moving a polygon vertex by up to
/// δ changes the cut area by at most δ × the polygon's local edge lengths (relative 1e-9 × edge
/// length / stencil size, far inside the agreement with the fill kernel the tests ask for).
///   δ = min(kSnapRelative · longest mesh edge, kSnapMaxRelative · shortest mesh edge)
/// is one length for the whole mesh (in a stencil's frame δ / s), so the faces around a vertex
/// and the two faces of an edge make the same decisions.
constexpr double kSnapRelative = 1e-9;
/// δ never exceeds this fraction of the shortest mesh edge (the ends of an edge are far apart
/// on the scale of δ, so a point is near at most one of them).
constexpr double kSnapMaxRelative = 1e-4;
/// Sub-triangles below this fraction of their face's area are dropped (round-off only: the
/// slivers the CDT makes outside a face where an edge point lies a rounding error off the line).
constexpr double kMinAreaFraction = 1e-14;

// ---- CGAL types: one small CDT per cut triangle -------------------------------------------

/// Index of the vertex in the face's local vertex table; −1 for a vertex CGAL created where
/// two constraints intersect (overlapping stencils).
struct VertexInfo {
  int local = -1;
};
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, Kernel>;
using Fb = CGAL::Constrained_triangulation_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;
using Point2 = Kernel::Point_2;

// ---- Output records of one base face -------------------------------------------------------

/// A point of the base edge (v0, v1), v0 < v1, made by stencil `stencil`: where its polygon
/// edge `feature` crosses the edge (feature < n), or where its polygon vertex feature − n lies
/// on it (n = the polygon's vertex count).
struct CrossingKey {
  int v0, v1, stencil, feature;
  auto tie() const { return std::tie(v0, v1, stencil, feature); }
  bool operator<(const CrossingKey& o) const { return tie() < o.tie(); }
  bool operator==(const CrossingKey& o) const { return tie() == o.tie(); }
};

/// A vertex of a cut face: a base vertex, a point on a base edge (shared with the neighbouring
/// face), or a point inside the face (owned by it).
struct LocalVertex {
  enum class Kind : uint8_t { Base, Crossing, Interior };
  Kind kind = Kind::Base;
  int base = -1;                 ///< Base: base vertex index
  CrossingKey key{};             ///< Crossing
  double tau = 0;                ///< Crossing: parameter along v0 → v1
  Vec3 position = Vec3::Zero();  ///< Interior (m)
  Point2 point;                  ///< in the face's 2-D frame (local use only)
  int edge_bits = 0;             ///< face edges the vertex lies on (bit k: corner k → k+1)
};

enum class FaceStatus : uint8_t { Kept, Split, Removed };

struct FaceCut {
  FaceStatus status = FaceStatus::Kept;
  std::vector<LocalVertex> vertices;      ///< Split: the vertices its faces use
  std::vector<std::array<int, 3>> faces;  ///< Split: CCW, indices into `vertices`
};

// ---- Inputs shared by all faces ------------------------------------------------------------

struct CutContext {
  const SurfaceMesh* mesh;
  const StencilLibrary* shapes;
  const std::vector<kernels::ClipStencil>* stencils;
  const std::vector<kernels::ClipPair>* pairs;
  std::vector<int> face_offsets;  ///< #F+1 into pairs
  std::vector<char> active;       ///< #P: the pair covers part of its face
  std::vector<char> covered;      ///< #F: some stencil covers the whole face
  double snap = 0;                ///< δ (m): see kSnapRelative
};

// ---- One base face -------------------------------------------------------------------------

/// The face in an isometric 2-D frame, and the canonical orientation of its edges: edge k
/// (corner k → k+1) runs from corner cu[k] to cv[k] with ids[cu] < ids[cv]; sigma[k] = +1
/// when that is the face's own direction. Every test about an edge is made in its canonical
/// orientation, so the two faces of the edge decide alike, bit for bit.
struct FaceFrame {
  int ids[3];
  Vec3 X[3];
  double p[6];        ///< corner 0 at the origin, corner 1 on +x, corner 2 above
  double twice_area;  ///< in the 2-D frame (> 0)
  int cu[3], cv[3];
  double sigma[3];

  void barycentric(double x, double y, double* lambda) const {
    const double inv = 1.0 / twice_area;
    lambda[0] = orient2(p[2], p[3], p[4], p[5], x, y) * inv;
    lambda[1] = orient2(p[4], p[5], p[0], p[1], x, y) * inv;
    lambda[2] = 1.0 - lambda[0] - lambda[1];
  }
  Vec3 position(const double* lambda) const {
    return lambda[0] * X[0] + lambda[1] * X[1] + lambda[2] * X[2];
  }
  Point2 point(const double* lambda) const {
    return Point2(lambda[1] * p[2] + lambda[2] * p[4], lambda[2] * p[5]);
  }
};

FaceFrame make_frame(const SurfaceMesh& mesh, int f) {
  FaceFrame fr;
  for (int k = 0; k < 3; ++k) {
    fr.ids[k] = mesh.faces()(f, k);
    fr.X[k] = mesh.vertices().row(fr.ids[k]).transpose();
  }
  const Vec3 e1 = fr.X[1] - fr.X[0], e2 = fr.X[2] - fr.X[0];
  const double l1 = e1.norm();
  fr.p[0] = fr.p[1] = 0.0;
  fr.p[2] = l1;
  fr.p[3] = 0.0;
  fr.p[4] = e2.dot(e1) / l1;
  fr.p[5] = e1.cross(e2).norm() / l1;
  fr.twice_area = l1 * fr.p[5];
  for (int k = 0; k < 3; ++k) {
    const int k1 = k == 2 ? 0 : k + 1;
    const bool forward = fr.ids[k] < fr.ids[k1];
    fr.cu[k] = forward ? k : k1;
    fr.cv[k] = forward ? k1 : k;
    fr.sigma[k] = forward ? 1.0 : -1.0;
  }
  return fr;
}

/// One stencil as seen from one face. Active stencils cover part of the face: they cut it.
/// The others are active in a neighbour only: they just split the shared edge where the
/// neighbour splits it, so that the output stays watertight.
struct StencilView {
  int stencil = -1;
  bool active = false;
  int edge_mask = 0;  ///< face edges whose points this stencil makes
  const double* polygon = nullptr;
  int count = 0;
  double w[6] = {};                ///< the face's corners in the stencil's reference frame
  std::vector<double> side;        ///< 3 per polygon vertex: canonical orientation vs. edge k
  std::vector<int8_t> sign;        ///< 3 per polygon vertex: sign of side, 0 on the line
  std::vector<int> vertex_point;   ///< per polygon vertex: edge point index, −1 if not on an edge
  std::vector<int> vertex_local;   ///< per polygon vertex: local vertex, −1 if outside the face
  std::vector<int8_t> vertex_corner;  ///< per polygon vertex: the corner it is, −1 if none
};

/// A point on face edge k, before merging.
struct EdgePoint {
  int k;
  double tau;  ///< along the canonical direction
  CrossingKey key;
  int local = -1;
};

/// A crossing of an active stencil's polygon edge with a face edge.
struct FaceCrossing {
  int view, edge;  ///< stencil view, polygon edge
  int point;       ///< EdgePoint index
  double s;        ///< along the polygon edge (for ordering)
};

/// Crossing-number point-in-polygon test in the stencil's reference frame.
bool inside_polygon(const double* poly, int n, double x, double y) {
  bool inside = false;
  for (int i = 0, j = n - 1; i < n; j = i++) {
    const double xi = poly[2 * i], yi = poly[2 * i + 1];
    const double xj = poly[2 * j], yj = poly[2 * j + 1];
    if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi) inside = !inside;
  }
  return inside;
}

/// Stencils active on face f, as pair indices (sorted by stencil, since pairs are).
void active_stencils(const CutContext& ctx, int f, std::vector<int>& out) {
  out.clear();
  for (int i = ctx.face_offsets[size_t(f)]; i < ctx.face_offsets[size_t(f) + 1]; ++i)
    if (ctx.active[size_t(i)]) out.push_back((*ctx.pairs)[size_t(i)].stencil);
}

/// The key of the point that stencil `stencil`'s `feature` makes on face edge k (canonical
/// orientation, so both faces of the edge make the same key).
CrossingKey edge_point_key(const FaceFrame& fr, int k, int stencil, int feature) {
  return CrossingKey{fr.ids[fr.cu[k]], fr.ids[fr.cv[k]], stencil, feature};
}

/// Step 1 of cut_face: the stencils to look at, the face's own (active, first; their count is
/// returned) then its neighbours' (edge points only, `edge_mask` naming the shared edges).
size_t gather_views(const CutContext& ctx, int f, std::vector<StencilView>& views) {
  const SurfaceMesh& mesh = *ctx.mesh;
  std::vector<int> ids;
  active_stencils(ctx, f, ids);
  for (int s : ids) {
    views.emplace_back();
    views.back().stencil = s;
    views.back().active = true;
    views.back().edge_mask = 7;
  }
  const size_t num_active = views.size();
  for (int k = 0; k < 3; ++k) {
    const int e = mesh.face_edges()(f, k);
    const int g = mesh.edge_faces()(e, 0) == f ? mesh.edge_faces()(e, 1) : mesh.edge_faces()(e, 0);
    if (g < 0) continue;
    active_stencils(ctx, g, ids);
    for (int s : ids) {
      auto it = std::find_if(views.begin(), views.end(),
                             [s](const StencilView& v) { return v.stencil == s; });
      if (it == views.end()) {
        views.emplace_back();
        it = views.end() - 1;
        it->stencil = s;
      }
      it->edge_mask |= 1 << k;
    }
  }
  return num_active;
}

/// The face's three corners as its first local vertices (local index k = corner k).
void add_corner_vertices(const FaceFrame& fr, std::vector<LocalVertex>& verts) {
  for (int k = 0; k < 3; ++k) {
    LocalVertex v;
    v.kind = LocalVertex::Kind::Base;
    v.base = fr.ids[k];
    v.point = Point2(fr.p[2 * k], fr.p[2 * k + 1]);
    v.edge_bits = (1 << k) | (1 << (k == 0 ? 2 : k - 1));
    verts.push_back(v);
  }
}

/// Step 2 of cut_face, for one stencil: its polygon vertices' canonical sides of the face's
/// edges, which lie on an edge (an edge point, appended to `points`), which are a corner, and
/// which lie inside the face (an interior vertex, appended to `verts`; active stencils only).
void classify_polygon_vertices(const CutContext& ctx, const FaceFrame& fr, StencilView& sv,
                               std::vector<LocalVertex>& verts, std::vector<EdgePoint>& points) {
  const kernels::ClipStencil& st = (*ctx.stencils)[size_t(sv.stencil)];
  const kernels::ClipShape& shape = ctx.shapes->clip_shapes()[size_t(st.shape)];
  sv.polygon = &ctx.shapes->packed_polygons()[2 * size_t(shape.polygon_offset)];
  sv.count = shape.polygon_count;
  for (int k = 0; k < 3; ++k) {
    kernels::project_equidistant(fr.X[k].data(), st.origin, st.axis_x, st.axis_y, st.scale,
                                 nullptr, nullptr, nullptr, &sv.w[2 * k], nullptr);
  }
  sv.side.assign(3 * size_t(sv.count), 0.0);
  sv.sign.assign(3 * size_t(sv.count), 0);
  sv.vertex_point.assign(size_t(sv.count), -1);
  sv.vertex_local.assign(size_t(sv.count), -1);
  sv.vertex_corner.assign(size_t(sv.count), -1);
  const double snap = ctx.snap / st.scale;  // δ in the stencil's frame
  for (int j = 0; j < sv.count; ++j) {
    const double x = sv.polygon[2 * j], y = sv.polygon[2 * j + 1];
    // Within 2δ of a corner: that corner (the lowest base vertex if several), alike in every
    // face around it. 2δ covers the points within δ of an edge and of its end.
    int corner = -1;
    for (int k = 0; k < 3; ++k) {
      const double dx = x - sv.w[2 * k], dy = y - sv.w[2 * k + 1];
      if (dx * dx + dy * dy <= 4.0 * snap * snap &&
          (corner < 0 || fr.ids[k] < fr.ids[corner]))
        corner = k;
    }
    sv.vertex_corner[size_t(j)] = int8_t(corner);
    bool inside = corner < 0;
    for (int k = 0; k < 3; ++k) {
      if (!(sv.edge_mask >> k & 1)) continue;
      const double* wu = &sv.w[2 * fr.cu[k]];
      const double* wv = &sv.w[2 * fr.cv[k]];
      const double ex = wv[0] - wu[0], ey = wv[1] - wu[1];
      const double len2 = ex * ex + ey * ey;
      const double c = orient2(wu[0], wu[1], wv[0], wv[1], x, y);
      const double tau = ((x - wu[0]) * ex + (y - wu[1]) * ey) / len2;
      // On the edge: at one of its ends, or within δ of its line between them. Then its
      // polygon edges do not cross the edge (sign 0); otherwise the side decides, a zero
      // counting as positive (beyond the edge's ends: the crossing, if any, is elsewhere).
      const bool at_end = corner == fr.cu[k] || corner == fr.cv[k];
      const bool on = at_end || (corner < 0 && std::abs(c) <= snap * std::sqrt(len2) &&
                                 tau >= 0.0 && tau <= 1.0);
      const int8_t sgn = on ? 0 : (c >= 0.0 ? 1 : -1);
      sv.side[3 * size_t(j) + size_t(k)] = c;
      sv.sign[3 * size_t(j) + size_t(k)] = sgn;
      inside = inside && fr.sigma[k] * sgn > 0;
      if (on && !at_end && sv.vertex_point[size_t(j)] < 0) {
        sv.vertex_point[size_t(j)] = int(points.size());
        points.push_back({k, tau, edge_point_key(fr, k, sv.stencil, sv.count + j), -1});
      }
    }
    if (corner >= 0) {
      sv.vertex_local[size_t(j)] = corner;
      continue;
    }
    if (!sv.active || !inside) continue;
    // Barycentrics from the sides: edge k is opposite corner k+2.
    double lambda[3];
    for (int k = 0; k < 3; ++k)
      lambda[k == 0 ? 2 : k - 1] = fr.sigma[k] * sv.side[3 * size_t(j) + size_t(k)];
    const double sum = lambda[0] + lambda[1] + lambda[2];
    for (double& l : lambda) l /= sum;
    LocalVertex v;
    v.kind = LocalVertex::Kind::Interior;
    v.position = fr.position(lambda);
    v.point = fr.point(lambda);
    sv.vertex_local[size_t(j)] = int(verts.size());
    verts.push_back(v);
  }
}

/// An extra point on polygon edge `edge` of view `view` (step 2b): another stencil's vertex
/// `local` at parameter s along it.
struct ExtraEvent {
  int view, edge;
  double s;
  int local;
};

/// Step 2b of cut_face: where active stencils overlap or touch inside the face, a polygon
/// vertex within δ of another stencil's polygon vertex is that vertex (`alias`, #verts, and the
/// view's vertex_local); within δ of another stencil's polygon edge it splits that edge (an
/// event in `extra`), so the two outlines meet there instead of running a needle's width apart.
/// Inside the face only, so no neighbour is concerned.
void snap_overlapping_stencils(const CutContext& ctx, const FaceFrame& fr, size_t num_active,
                               std::vector<StencilView>& views,
                               const std::vector<LocalVertex>& verts, std::vector<int>& alias,
                               std::vector<ExtraEvent>& extra) {
  struct Inner {
    int view, j, local;
    double lambda[3];
  };
  std::vector<Inner> inner;
  for (size_t a = 0; a < num_active; ++a) {
    const StencilView& sv = views[a];
    for (int j = 0; j < sv.count; ++j) {
      const int l = sv.vertex_local[size_t(j)];
      if (l < 3 || verts[size_t(l)].kind != LocalVertex::Kind::Interior) continue;
      Inner in{int(a), j, l, {}};
      fr.barycentric(verts[size_t(l)].point.x(), verts[size_t(l)].point.y(), in.lambda);
      inner.push_back(in);
    }
  }
  for (size_t p = 0; p < inner.size(); ++p) {
    Inner& in = inner[p];
    // Another stencil's vertex (the first one, in view order) within δ: merge into it.
    for (size_t q = 0; q < p && alias[size_t(in.local)] < 0; ++q) {
      const Inner& o = inner[q];
      if (o.view == in.view || alias[size_t(o.local)] >= 0) continue;
      const Point2& x = verts[size_t(in.local)].point;
      const Point2& y = verts[size_t(o.local)].point;
      const double dx = x.x() - y.x(), dy = x.y() - y.y();
      if (dx * dx + dy * dy <= ctx.snap * ctx.snap) {
        alias[size_t(in.local)] = o.local;
        views[size_t(in.view)].vertex_local[size_t(in.j)] = o.local;
      }
    }
  }
  for (const Inner& in : inner) {
    if (alias[size_t(in.local)] >= 0) continue;
    for (size_t b = 0; b < num_active; ++b) {
      if (int(b) == in.view) continue;
      const StencilView& ov = views[b];
      const double snap = ctx.snap / (*ctx.stencils)[size_t(ov.stencil)].scale;
      const double x = in.lambda[0] * ov.w[0] + in.lambda[1] * ov.w[2] + in.lambda[2] * ov.w[4];
      const double y = in.lambda[0] * ov.w[1] + in.lambda[1] * ov.w[3] + in.lambda[2] * ov.w[5];
      for (int j = 0; j < ov.count; ++j) {
        const int jn = j + 1 == ov.count ? 0 : j + 1;
        const double ax = ov.polygon[2 * j], ay = ov.polygon[2 * j + 1];
        const double ex = ov.polygon[2 * jn] - ax, ey = ov.polygon[2 * jn + 1] - ay;
        const double len2 = ex * ex + ey * ey;
        const double t = ((x - ax) * ex + (y - ay) * ey) / len2;
        if (!(t > 0.0 && t < 1.0)) continue;
        if (std::abs(orient2(ax, ay, ax + ex, ay + ey, x, y)) > snap * std::sqrt(len2)) continue;
        // Not at the edge's ends (those are vertices: merged above, or on the face's edges).
        const double along = std::sqrt(len2) * std::min(t, 1.0 - t);
        if (along <= snap) continue;
        extra.push_back({int(b), j, t, in.local});
      }
    }
  }
}

/// Step 3 of cut_face: proper crossings of polygon edges with face edges, from the edge's side
/// only: the polygon edge's ends strictly on both sides of the edge's line, the edge's ends on
/// both sides of the polygon edge's line (a zero counts as positive, alike in both faces). Each
/// makes an edge point (appended to `points`); those of active stencils are returned, grouped by
/// (view, polygon edge) in order.
std::vector<FaceCrossing> find_crossings(const FaceFrame& fr, const std::vector<StencilView>& views,
                                         std::vector<EdgePoint>& points) {
  std::vector<FaceCrossing> crossings;
  for (size_t a = 0; a < views.size(); ++a) {
    const StencilView& sv = views[a];
    for (int j = 0; j < sv.count; ++j) {
      const int jn = j + 1 == sv.count ? 0 : j + 1;
      const double ax = sv.polygon[2 * j], ay = sv.polygon[2 * j + 1];
      const double bx = sv.polygon[2 * jn], by = sv.polygon[2 * jn + 1];
      for (int k = 0; k < 3; ++k) {
        if (!(sv.edge_mask >> k & 1)) continue;
        const int8_t sa = sv.sign[3 * size_t(j) + size_t(k)];
        const int8_t sb = sv.sign[3 * size_t(jn) + size_t(k)];
        if (sa == 0 || sb == 0 || sa == sb) continue;
        const double* wu = &sv.w[2 * fr.cu[k]];
        const double* wv = &sv.w[2 * fr.cv[k]];
        const double du = orient2(ax, ay, bx, by, wu[0], wu[1]);
        const double dv = orient2(ax, ay, bx, by, wv[0], wv[1]);
        if ((du >= 0.0) == (dv >= 0.0)) continue;
        const double tau = std::clamp(du / (du - dv), 0.0, 1.0);
        const double ca = sv.side[3 * size_t(j) + size_t(k)];
        const double cb = sv.side[3 * size_t(jn) + size_t(k)];
        if (sv.active) crossings.push_back({int(a), j, int(points.size()), ca / (ca - cb)});
        points.push_back({k, tau, edge_point_key(fr, k, sv.stencil, j), -1});
      }
    }
  }
  return crossings;
}

/// Step 4 of cut_face: the vertices on the face's edges, sorted by (τ, key); points within δ of
/// the first of a run merge into it, points within δ of an end are that corner. The neighbour
/// sees the same points (same stencils on the edge) and the same edge length, so it makes the
/// same vertices. Sets every point's `local` and the views' vertex_local of polygon vertices on
/// an edge; returns the new vertices of each face edge in canonical order.
std::array<std::vector<int>, 3> place_edge_points(const CutContext& ctx, const FaceFrame& fr,
                                                  std::vector<EdgePoint>& points,
                                                  std::vector<StencilView>& views,
                                                  std::vector<LocalVertex>& verts) {
  std::array<std::vector<int>, 3> on_edge;  // local vertices in canonical order
  double snap_tau[3];  // δ in τ, from the edge's own (canonical) length
  for (int k = 0; k < 3; ++k) snap_tau[k] = ctx.snap / (fr.X[fr.cv[k]] - fr.X[fr.cu[k]]).norm();
  std::vector<int> order(points.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = int(i);
  std::sort(order.begin(), order.end(), [&](int x, int y) {
    const EdgePoint& px = points[size_t(x)];
    const EdgePoint& py = points[size_t(y)];
    if (px.k != py.k) return px.k < py.k;
    if (px.tau != py.tau) return px.tau < py.tau;
    return px.key < py.key;
  });
  int run_k = -1, run_local = -1;
  double run_tau = 0.0;
  for (int i : order) {
    EdgePoint& pt = points[size_t(i)];
    const double tol = snap_tau[pt.k];
    if (pt.tau <= tol) {
      pt.local = fr.cu[pt.k];
    } else if (pt.tau >= 1.0 - tol) {
      pt.local = fr.cv[pt.k];
    } else if (run_k == pt.k && pt.tau - run_tau <= tol) {
      pt.local = run_local;
    } else {
      LocalVertex v;
      v.kind = LocalVertex::Kind::Crossing;
      v.key = pt.key;
      v.tau = pt.tau;
      const double* pu = &fr.p[2 * fr.cu[pt.k]];
      const double* pv = &fr.p[2 * fr.cv[pt.k]];
      v.point = Point2(pu[0] + pt.tau * (pv[0] - pu[0]), pu[1] + pt.tau * (pv[1] - pu[1]));
      v.edge_bits = 1 << pt.k;
      pt.local = int(verts.size());
      verts.push_back(v);
      on_edge[size_t(pt.k)].push_back(pt.local);
      run_k = pt.k;
      run_tau = pt.tau;
      run_local = pt.local;
    }
  }
  for (StencilView& sv : views)
    for (int j = 0; j < sv.count; ++j)
      if (sv.vertex_point[size_t(j)] >= 0)
        sv.vertex_local[size_t(j)] = points[size_t(sv.vertex_point[size_t(j)])].local;
  return on_edge;
}

/// Step 5 of cut_face, first half: every vertex inserted into the triangulation (an aliased one
/// shares its target's handle) and the face's boundary constrained, split at its edge points.
/// Returns the handle of each local vertex.
std::vector<Cdt::Vertex_handle> insert_face_boundary(Cdt& cdt, const FaceFrame& fr,
                                                     const std::vector<LocalVertex>& verts,
                                                     const std::vector<int>& alias,
                                                     const std::array<std::vector<int>, 3>& on_edge) {
  std::vector<Cdt::Vertex_handle> handle(verts.size());
  for (size_t i = 0; i < verts.size(); ++i) {
    if (i < alias.size() && alias[i] >= 0) continue;
    handle[i] = cdt.insert(verts[i].point);
    if (handle[i]->info().local < 0) handle[i]->info().local = int(i);
  }
  for (size_t i = 0; i < alias.size(); ++i)
    if (alias[i] >= 0) handle[i] = handle[size_t(alias[i])];
  for (int k = 0; k < 3; ++k) {
    std::vector<int> chain = on_edge[size_t(k)];
    if (fr.sigma[k] < 0) std::reverse(chain.begin(), chain.end());
    chain.insert(chain.begin(), k);
    chain.push_back(k == 2 ? 0 : k + 1);
    for (size_t i = 0; i + 1 < chain.size(); ++i)
      if (handle[size_t(chain[i])] != handle[size_t(chain[i + 1])])
        cdt.insert_constraint(handle[size_t(chain[i])], handle[size_t(chain[i + 1])]);
  }
  return handle;
}

/// Step 5 of cut_face, second half: the pieces of the active polygons' edges inside the face
/// constrained, each polygon edge split at its events (its ends inside the face, its crossings
/// with the face's edges, the extra points of step 2b).
void constrain_polygon_edges(Cdt& cdt, const FaceFrame& fr, const std::vector<Cdt::Vertex_handle>& handle,
                             const std::vector<LocalVertex>& verts, const std::vector<StencilView>& views,
                             size_t num_active, const std::vector<FaceCrossing>& crossings,
                             const std::vector<EdgePoint>& points, const std::vector<ExtraEvent>& extra) {
  auto constrain = [&](int x, int y) {
    // Two points of one face edge: that piece of the boundary is constrained already.
    if (verts[size_t(x)].edge_bits & verts[size_t(y)].edge_bits) return;
    if (handle[size_t(x)] != handle[size_t(y)])
      cdt.insert_constraint(handle[size_t(x)], handle[size_t(y)]);
  };
  struct Event {
    double s;
    int local;
  };
  std::vector<Event> events;
  size_t next = 0;  // crossings are grouped by (view, polygon edge), in order
  for (size_t a = 0; a < num_active; ++a) {
    const StencilView& sv = views[a];
    for (int j = 0; j < sv.count; ++j) {
      const int jn = j + 1 == sv.count ? 0 : j + 1;
      events.clear();
      if (sv.vertex_local[size_t(j)] >= 0) events.push_back({0.0, sv.vertex_local[size_t(j)]});
      for (; next < crossings.size() && crossings[next].view == int(a) &&
             crossings[next].edge == j;
           ++next) {
        events.push_back({crossings[next].s, points[size_t(crossings[next].point)].local});
      }
      if (sv.vertex_local[size_t(jn)] >= 0) events.push_back({1.0, sv.vertex_local[size_t(jn)]});
      for (const ExtraEvent& x : extra)
        if (x.view == int(a) && x.edge == j) events.push_back({x.s, x.local});
      std::stable_sort(events.begin(), events.end(),
                       [](const Event& x, const Event& y) { return x.s < y.s; });
      events.erase(std::unique(events.begin(), events.end(),
                               [](const Event& x, const Event& y) { return x.local == y.local; }),
                   events.end());
      if (events.size() == 2) {
        constrain(events[0].local, events[1].local);
      } else if (events.size() > 2) {
        // Only where round-off made the tests inconsistent: keep the pieces whose midpoint lies
        // inside the face.
        const double ax = sv.polygon[2 * j], ay = sv.polygon[2 * j + 1];
        const double bx = sv.polygon[2 * jn], by = sv.polygon[2 * jn + 1];
        for (size_t e = 0; e + 1 < events.size(); ++e) {
          const double s = 0.5 * (events[e].s + events[e + 1].s);
          const double x = ax + s * (bx - ax), y = ay + s * (by - ay);
          bool inside = true;
          for (int k = 0; k < 3; ++k) {
            const double* wu = &sv.w[2 * fr.cu[k]];
            const double* wv = &sv.w[2 * fr.cv[k]];
            inside = inside && fr.sigma[k] * orient2(wu[0], wu[1], wv[0], wv[1], x, y) > 0.0;
          }
          if (inside) constrain(events[e].local, events[e + 1].local);
        }
      }
    }
  }
}

/// Step 6 of cut_face: the sub-triangles inside the face, not degenerate, and outside every
/// active polygon (their centroid decides: constraints separate inside from outside), appended
/// to out.faces; a vertex CGAL made where two constraints intersect becomes an interior vertex.
/// `used` (#out.vertices on return) marks the vertices the kept sub-triangles use.
void keep_outside_triangles(Cdt& cdt, const FaceFrame& fr, const std::vector<StencilView>& views,
                            size_t num_active, FaceCut& out, std::vector<char>& used) {
  std::vector<LocalVertex>& verts = out.vertices;
  const double min_twice_area = kMinAreaFraction * fr.twice_area;
  used.assign(verts.size(), 0);
  for (auto fit = cdt.finite_faces_begin(); fit != cdt.finite_faces_end(); ++fit) {
    double xy[6];
    for (int i = 0; i < 3; ++i) {
      const Point2& q = fit->vertex(i)->point();
      xy[2 * i] = q.x();
      xy[2 * i + 1] = q.y();
    }
    if (!(orient2(xy[0], xy[1], xy[2], xy[3], xy[4], xy[5]) >= min_twice_area)) continue;
    double lambda[3];
    fr.barycentric((xy[0] + xy[2] + xy[4]) / 3.0, (xy[1] + xy[3] + xy[5]) / 3.0, lambda);
    if (!(std::min({lambda[0], lambda[1], lambda[2]}) > 0.0)) continue;
    bool removed = false;
    for (size_t a = 0; a < num_active && !removed; ++a) {
      const StencilView& sv = views[a];
      const double x = lambda[0] * sv.w[0] + lambda[1] * sv.w[2] + lambda[2] * sv.w[4];
      const double y = lambda[0] * sv.w[1] + lambda[1] * sv.w[3] + lambda[2] * sv.w[5];
      removed = inside_polygon(sv.polygon, sv.count, x, y);
    }
    if (removed) continue;
    std::array<int, 3> tri;
    for (int i = 0; i < 3; ++i) {
      VertexInfo& info = fit->vertex(i)->info();
      if (info.local < 0) {  // where two constraints intersect
        double l[3];
        fr.barycentric(xy[2 * i], xy[2 * i + 1], l);
        LocalVertex v;
        v.kind = LocalVertex::Kind::Interior;
        v.position = fr.position(l);
        v.point = fit->vertex(i)->point();
        info.local = int(verts.size());
        verts.push_back(v);
        used.push_back(0);
      }
      tri[size_t(i)] = info.local;
      used[size_t(info.local)] = 1;
    }
    out.faces.push_back(tri);
  }
}

/// The status of a face whose sub-triangles step 6 kept: Removed when none, Kept when the one
/// left is the face itself, else Split with the vertices compacted to those the faces use.
void finish_face_cut(FaceCut& out, const std::vector<char>& used) {
  std::vector<LocalVertex>& verts = out.vertices;
  if (out.faces.empty()) {
    out.status = FaceStatus::Removed;
    out.vertices.clear();
    return;
  }
  if (out.faces.size() == 1 && verts.size() == 3) {  // nothing of the face was cut
    out.vertices.clear();
    out.faces.clear();
    return;
  }
  std::vector<int> remap(verts.size(), -1);
  std::vector<LocalVertex> compact;
  for (size_t i = 0; i < verts.size(); ++i) {
    if (!used[i]) continue;
    remap[i] = int(compact.size());
    compact.push_back(verts[i]);
  }
  for (auto& tri : out.faces)
    for (int& v : tri) v = remap[size_t(v)];
  out.vertices = std::move(compact);
  out.status = FaceStatus::Split;
}

/// The cut of base face f. Returns Kept when nothing touches it. The steps are the functions
/// above, numbered as they run.
FaceCut cut_face(const CutContext& ctx, int f) {
  FaceCut out;
  if (ctx.covered[size_t(f)]) {
    out.status = FaceStatus::Removed;
    return out;
  }
  std::vector<StencilView> views;
  const size_t num_active = gather_views(ctx, f, views);
  if (views.empty()) return out;

  const FaceFrame fr = make_frame(*ctx.mesh, f);
  std::vector<LocalVertex>& verts = out.vertices;
  add_corner_vertices(fr, verts);
  std::vector<EdgePoint> points;
  for (StencilView& sv : views) classify_polygon_vertices(ctx, fr, sv, verts, points);

  std::vector<ExtraEvent> extra;
  std::vector<int> alias(verts.size(), -1);  // a merged polygon vertex: the vertex it is
  if (num_active > 1) snap_overlapping_stencils(ctx, fr, num_active, views, verts, alias, extra);

  const std::vector<FaceCrossing> crossings = find_crossings(fr, views, points);
  if (num_active == 0 && points.empty()) return out;
  const std::array<std::vector<int>, 3> on_edge = place_edge_points(ctx, fr, points, views, verts);

  Cdt cdt;
  const std::vector<Cdt::Vertex_handle> handle = insert_face_boundary(cdt, fr, verts, alias, on_edge);
  constrain_polygon_edges(cdt, fr, handle, verts, views, num_active, crossings, points, extra);

  std::vector<char> used;
  keep_outside_triangles(cdt, fr, views, num_active, out, used);
  finish_face_cut(out, used);
  return out;
}

/// What every face's cut shares: the stencils and pairs the evaluator made, which pairs cut
/// (active) and which faces a stencil covers whole, and the snap distance δ of the mesh.
CutContext make_cut_context(const SurfaceMesh& mesh, const StencilLibrary& shapes,
                            const FillRatioEvaluator& evaluator) {
  const int nf = mesh.num_faces();
  CutContext ctx;
  ctx.mesh = &mesh;
  ctx.shapes = &shapes;
  ctx.stencils = &evaluator.clip_stencils();
  ctx.pairs = &evaluator.pairs();
  const auto& overlaps = evaluator.overlaps();
  ctx.face_offsets.assign(size_t(nf) + 1, 0);
  ctx.active.resize(ctx.pairs->size());
  ctx.covered.assign(size_t(nf), 0);
  for (size_t i = 0; i < ctx.pairs->size(); ++i) {
    const int f = (*ctx.pairs)[i].face;
    const kernels::ClipResult& r = overlaps[i];
    // Back-facing pairs contribute nothing to α; neither do they cut.
    ctx.active[i] = r.triangle_area > 0.0 && r.fraction > 0.0;
    if (ctx.active[i] && r.fraction >= 1.0) ctx.covered[size_t(f)] = 1;
    ++ctx.face_offsets[size_t(f) + 1];
  }
  for (int f = 0; f < nf; ++f) ctx.face_offsets[size_t(f) + 1] += ctx.face_offsets[size_t(f)];
  double longest = 0.0, shortest = std::numeric_limits<double>::infinity();
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const double l = (mesh.vertices().row(mesh.edges()(e, 1)) -
                      mesh.vertices().row(mesh.edges()(e, 0))).norm();
    longest = std::max(longest, l);
    shortest = std::min(shortest, l);
  }
  ctx.snap = std::min(kSnapRelative * longest, kSnapMaxRelative * shortest);
  return ctx;
}

/// The per-face cuts (#F) merged into one mesh, in face order: base vertices, then edge points
/// by key (one vertex per key, shared by the edge's two faces), then interior vertices.
CutSurface merge_face_cuts(const SurfaceMesh& mesh, const std::vector<FaceCut>& cuts) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  CutSurface out;
  std::vector<int> base_id(size_t(nv), -1);
  std::vector<std::pair<CrossingKey, double>> edge_points;
  int num_faces = 0, num_interior = 0;
  for (int f = 0; f < nf; ++f) {
    const FaceCut& c = cuts[size_t(f)];
    switch (c.status) {
      case FaceStatus::Kept:
        ++out.kept_faces;
        ++num_faces;
        for (int k = 0; k < 3; ++k) base_id[size_t(mesh.faces()(f, k))] = 0;
        break;
      case FaceStatus::Removed: ++out.removed_faces; break;
      case FaceStatus::Split:
        ++out.split_faces;
        num_faces += int(c.faces.size());
        for (const LocalVertex& v : c.vertices) {
          if (v.kind == LocalVertex::Kind::Base) base_id[size_t(v.base)] = 0;
          if (v.kind == LocalVertex::Kind::Crossing) edge_points.emplace_back(v.key, v.tau);
          if (v.kind == LocalVertex::Kind::Interior) ++num_interior;
        }
        break;
    }
  }
  std::sort(edge_points.begin(), edge_points.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  edge_points.erase(std::unique(edge_points.begin(), edge_points.end(),
                                [](const auto& x, const auto& y) { return x.first == y.first; }),
                    edge_points.end());
  int num_vertices = 0;
  for (int v = 0; v < nv; ++v)
    if (base_id[size_t(v)] == 0) base_id[size_t(v)] = num_vertices++;
  const int first_edge_point = num_vertices;
  num_vertices += int(edge_points.size());

  out.vertices.resize(num_vertices + num_interior, 3);
  out.source_vertex.resize(num_vertices + num_interior);
  for (int v = 0; v < nv; ++v) {
    if (base_id[size_t(v)] < 0) continue;
    out.vertices.row(base_id[size_t(v)]) = mesh.vertices().row(v);
    out.source_vertex[base_id[size_t(v)]] = v;
  }
  for (size_t i = 0; i < edge_points.size(); ++i) {
    const auto& [key, tau] = edge_points[i];
    const Vec3 xu = mesh.vertices().row(key.v0).transpose();
    const Vec3 xv = mesh.vertices().row(key.v1).transpose();
    out.vertices.row(first_edge_point + int(i)) = (xu + tau * (xv - xu)).transpose();
    out.source_vertex[first_edge_point + int(i)] = -1;
  }
  out.faces.resize(num_faces, 3);
  out.source_face.resize(num_faces);
  int row = 0;
  std::vector<int> local_id;
  for (int f = 0; f < nf; ++f) {
    const FaceCut& c = cuts[size_t(f)];
    if (c.status == FaceStatus::Kept) {
      for (int k = 0; k < 3; ++k) out.faces(row, k) = base_id[size_t(mesh.faces()(f, k))];
      out.source_face[row++] = f;
      continue;
    }
    if (c.status != FaceStatus::Split) continue;
    local_id.resize(c.vertices.size());
    for (size_t i = 0; i < c.vertices.size(); ++i) {
      const LocalVertex& v = c.vertices[i];
      switch (v.kind) {
        case LocalVertex::Kind::Base: local_id[i] = base_id[size_t(v.base)]; break;
        case LocalVertex::Kind::Crossing: {
          const auto it = std::lower_bound(
              edge_points.begin(), edge_points.end(), v.key,
              [](const auto& x, const CrossingKey& k) { return x.first < k; });
          local_id[i] = first_edge_point + int(it - edge_points.begin());
          break;
        }
        case LocalVertex::Kind::Interior:
          local_id[i] = num_vertices;
          out.vertices.row(num_vertices) = v.position.transpose();
          out.source_vertex[num_vertices++] = -1;
          break;
      }
    }
    for (const auto& tri : c.faces) {
      for (int k = 0; k < 3; ++k) out.faces(row, k) = local_id[size_t(tri[size_t(k)])];
      out.source_face[row++] = f;
    }
  }
  for (int i = 0; i < num_faces; ++i) {
    const Vec3 a = out.vertices.row(out.faces(i, 0)).transpose();
    const Vec3 b = out.vertices.row(out.faces(i, 1)).transpose();
    const Vec3 c = out.vertices.row(out.faces(i, 2)).transpose();
    out.area += 0.5 * (b - a).cross(c - a).norm();
  }
  return out;
}

}  // namespace

CutSurface cut_stencils(const FaceBvh& surface_bvh, const StencilLibrary& shapes,
                        const TangentField& field, std::span<const StencilParams> stencils) {
  if (surface_bvh.mesh() == nullptr) throw InternalError("cut surface: the BVH has no mesh");
  const SurfaceMesh& mesh = *surface_bvh.mesh();
  const int nf = mesh.num_faces();

  std::vector<FaceCut> cuts(static_cast<size_t>(nf));
  if (!stencils.empty()) {
    FillRatioOptions options;
    options.derivatives = false;
    FillRatioEvaluator evaluator(surface_bvh, surface_bvh, shapes, &field, options);
    evaluator.evaluate(stencils);
    const CutContext ctx = make_cut_context(mesh, shapes, evaluator);
    tbb::parallel_for(tbb::blocked_range<int>(0, nf), [&](const tbb::blocked_range<int>& range) {
      for (int f = range.begin(); f != range.end(); ++f) cuts[size_t(f)] = cut_face(ctx, f);
    });
  }
  return merge_face_cuts(mesh, cuts);
}

CutSurface cut_with_tool(const FaceBvh& surface_bvh, const StencilLibrary& shapes, const TangentField& field,
                         std::span<const StencilParams> stencils, double tool_radius, ToolCutStencils* tool) {
  if (!(tool_radius >= 0) || !std::isfinite(tool_radius))
    throw InputError("tool radius " + std::to_string(tool_radius) + " m: expected a finite radius of at least 0");
  if (tool_radius == 0) return cut_stencils(surface_bvh, shapes, field, stencils);
  ToolCutStencils own;
  ToolCutStencils& t = tool ? *tool : own;
  t = tool_cut_stencils(shapes, stencils, tool_radius);
  return cut_stencils(surface_bvh, t.shapes, field, t.stencils);
}

}  // namespace cutwork
