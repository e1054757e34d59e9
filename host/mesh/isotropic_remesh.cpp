#include "host/mesh/isotropic_remesh.h"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>

#include "host/core/error.h"

namespace cutwork {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using VertexIndex = Mesh::Vertex_index;

/// `index_out` (optional): per input vertex, its vertex in the mesh (null when unreferenced).
Mesh to_cgal(const RowMatX3d& V, const RowMatX3i& F, std::vector<VertexIndex>* index_out = nullptr) {
  Mesh m;
  std::vector<VertexIndex> index(size_t(V.rows()), Mesh::null_vertex());
  std::vector<bool> used(size_t(V.rows()), false);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) used[size_t(F(f, k))] = true;
  for (int v = 0; v < V.rows(); ++v)
    if (used[size_t(v)]) index[size_t(v)] = m.add_vertex(Point(V(v, 0), V(v, 1), V(v, 2)));
  for (int f = 0; f < F.rows(); ++f) {
    const auto face = m.add_face(index[size_t(F(f, 0))], index[size_t(F(f, 1))], index[size_t(F(f, 2))]);
    if (face == Mesh::null_face())
      throw InputError(fmt::format("remeshing: face {} makes the surface non-manifold", f));
  }
  if (index_out) *index_out = std::move(index);
  return m;
}

using EdgeFlags = Mesh::Property_map<Mesh::Edge_index, bool>;
using VertexFlags = Mesh::Property_map<VertexIndex, bool>;

/// Marks the input's feature edges (RemeshOptions::feature_edges) in `feature`; their ends on the
/// boundary become corners (kept by step 1's collapses). Throws InputError for a pair that is no
/// interior edge.
void mark_features(const Mesh& m, const std::vector<VertexIndex>& index, const std::vector<std::array<int, 2>>& pairs,
                   EdgeFlags& feature, VertexFlags& corner) {
  for (const auto& [a, b] : pairs) {
    const bool in_range = a >= 0 && b >= 0 && size_t(a) < index.size() && size_t(b) < index.size();
    const auto h = in_range && index[size_t(a)] != Mesh::null_vertex() && index[size_t(b)] != Mesh::null_vertex()
                       ? m.halfedge(index[size_t(a)], index[size_t(b)])
                       : Mesh::null_halfedge();
    if (h == Mesh::null_halfedge() || m.is_border(m.edge(h)))
      throw InputError(fmt::format("remeshing: feature line ({}, {}) is not an interior edge of the surface", a, b));
    feature[m.edge(h)] = true;
    for (const VertexIndex v : {m.source(h), m.target(h)})
      if (m.is_border(v)) corner[v] = true;
  }
}

/// Per vertex: a corner or an end of a feature edge (what the remeshing must not move).
void mark_kept_vertices(const Mesh& m, const VertexFlags& corner, const EdgeFlags& feature, VertexFlags& kept) {
  for (const auto v : m.vertices()) kept[v] = corner[v];
  for (const auto e : m.edges())
    if (feature[e]) kept[m.vertex(e, 0)] = kept[m.vertex(e, 1)] = true;
}

/// Marks boundary vertices whose boundary turns by more than `angle` (radians) as constrained.
int mark_corners(const Mesh& m, double angle, Mesh::Property_map<VertexIndex, bool>& corner) {
  int count = 0;
  for (const auto h : m.halfedges()) {
    if (!m.is_border(h)) continue;
    // Border halfedges run along the boundary: prev → h, turning at target(prev) = source(h).
    const auto prev = m.prev(h);
    const Point& a = m.point(m.source(prev));
    const Point& b = m.point(m.source(h));
    const Point& c = m.point(m.target(h));
    const Kernel::Vector_3 d0 = b - a, d1 = c - b;
    const double n0 = std::sqrt(d0.squared_length()), n1 = std::sqrt(d1.squared_length());
    if (n0 == 0 || n1 == 0) continue;
    const double cosine = std::clamp(double(d0 * d1) / (n0 * n1), -1.0, 1.0);
    if (std::acos(cosine) > angle) {
      corner[m.source(h)] = true;
      ++count;
    }
  }
  return count;
}

/// Would moving vertex `moved` to `to` flip or flatten a face around it other than `skip`?
bool keeps_orientation(const Mesh& m, VertexIndex moved, const Point& to, Mesh::Face_index skip,
                       Mesh::Face_index skip_too = Mesh::null_face()) {
  for (const auto f : m.faces_around_target(m.halfedge(moved))) {
    if (f == Mesh::null_face() || f == skip || f == skip_too) continue;
    std::array<Point, 3> before, after;
    int k = 0;
    for (const auto v : m.vertices_around_face(m.halfedge(f))) {
      before[size_t(k)] = m.point(v);
      after[size_t(k++)] = v == moved ? to : m.point(v);
    }
    const auto n0 = CGAL::cross_product(before[1] - before[0], before[2] - before[0]);
    const auto n1 = CGAL::cross_product(after[1] - after[0], after[2] - after[0]);
    if (!(n0 * n1 > 0.01 * std::sqrt(n0.squared_length() * n1.squared_length()))) return false;
  }
  return true;
}

/// Collapses edge `e` (between `gone` and `keep`) so that the vertex left is where `keep` was, with
/// its corner flag, when the link condition holds and no face but `skip`/`skip_too` (those the
/// collapse removes) flips. Returns whether it collapsed.
bool collapse_onto(Mesh& m, Mesh::Edge_index e, VertexIndex gone, VertexIndex keep,
                   Mesh::Property_map<VertexIndex, bool>& corner, Mesh::Face_index skip,
                   Mesh::Face_index skip_too = Mesh::null_face()) {
  const Point to = m.point(keep);
  if (!CGAL::Euler::does_satisfy_link_condition(e, m) || !keeps_orientation(m, gone, to, skip, skip_too)) return false;
  const bool was_corner = corner[keep];
  const VertexIndex v = CGAL::Euler::collapse_edge(e, m);  // keeps either end: put it where `keep` was
  m.point(v) = to;
  corner[v] = was_corner;
  return true;
}

/// Collapses boundary edges shorter than `tau` onto one of their ends (a corner when there is one):
/// the cut leaves such edges where an outline crosses a mesh edge next to one of its own vertices,
/// and a protected boundary edge that short would leave a needle beside it. Returns the count.
int collapse_short_border_edges(Mesh& m, double tau, Mesh::Property_map<VertexIndex, bool>& corner) {
  int count = 0;
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<Mesh::Edge_index> candidates;
    for (const auto e : m.edges())
      if (m.is_border(e) && CGAL::squared_distance(m.point(m.vertex(e, 0)), m.point(m.vertex(e, 1))) < tau * tau)
        candidates.push_back(e);
    for (const auto e : candidates) {
      if (m.is_removed(e)) continue;
      const auto h = m.halfedge(e);
      const VertexIndex a = m.source(h), b = m.target(h);
      if (corner[a] && corner[b]) continue;
      if (CGAL::squared_distance(m.point(a), m.point(b)) >= tau * tau) continue;
      // collapse_edge keeps target(h); the kept position is the corner's, else b's.
      const VertexIndex keep = corner[a] ? a : b, gone = keep == a ? b : a;
      const auto face = m.is_border(h) ? m.face(m.opposite(h)) : m.face(h);
      if (!collapse_onto(m, e, gone, keep, corner, face)) continue;
      ++count;
      changed = true;
    }
  }
  return count;
}

/// Step 1b (RemeshOptions::coarsen_straight_runs): vertices where the border, or a feature line, runs
/// straight (on the segment between its two neighbours along the line, to 1e-9 of its length)
/// removed while that segment is at most L long. Corners and feature ends stay; no line moves.
/// Returns the count removed.
int merge_straight_runs(Mesh& m, double L, VertexFlags& corner, const EdgeFlags& feature) {
  int count = 0;
  for (bool changed = true; changed;) {
    changed = false;
    for (const auto v : m.vertices()) {
      if (m.is_removed(v) || m.is_isolated(v) || corner[v]) continue;
      // The line's two edges at v: the border halfedges into and out of v, or v's two feature
      // edges (v inside the surface, on one feature line).
      std::array<Mesh::Halfedge_index, 2> along{Mesh::null_halfedge(), Mesh::null_halfedge()};
      int found = 0;
      const bool border = m.is_border(v);
      for (const auto h : m.halfedges_around_target(m.halfedge(v))) {
        const bool on_line = border ? m.is_border(h) : bool(feature[m.edge(h)]);
        if (!on_line) continue;
        if (found < 2) along[size_t(found)] = h;
        ++found;
      }
      if (border ? found != 1 : found != 2) continue;
      const VertexIndex a = m.source(along[0]);
      const VertexIndex b = border ? m.target(m.next(along[0])) : m.source(along[1]);
      if (a == b) continue;
      const Point pa = m.point(a);
      const Point& pb = m.point(b);
      const Point& pv = m.point(v);
      const double ab2 = CGAL::squared_distance(pa, pb);
      if (ab2 > L * L || ab2 == 0) continue;
      const double t = CGAL::scalar_product(pv - pa, pb - pa) / ab2;
      if (!(t > 0 && t < 1) || CGAL::squared_distance(pv, pa + t * (pb - pa)) > 1e-18 * ab2) continue;
      // v collapsed onto a, which keeps its position and its corner flag; the edge v–b, now a–b,
      // keeps its feature flag.
      if (!collapse_onto(m, m.edge(along[0]), v, a, corner, m.face(along[0]), m.face(m.opposite(along[0]))))
        continue;
      ++count;
      changed = true;
    }
  }
  return count;
}

/// Twice the area over the longest edge squared: 0 for a flat face, √3/2 for an equilateral one.
double flatness(const Mesh& m, Mesh::Face_index f) {
  const auto h = m.halfedge(f);
  const Point& a = m.point(m.source(h));
  const Point& b = m.point(m.target(h));
  const Point& c = m.point(m.target(m.next(h)));
  const double twice_area = std::sqrt(CGAL::cross_product(b - a, c - a).squared_length());
  const double longest = std::max({(b - a).squared_length(), (c - b).squared_length(), (a - c).squared_length()});
  return longest > 0 ? twice_area / longest : 0.0;
}

/// `frozen` (optional): faces whose vertices and edges are constrained as the boundary's are;
/// `feature` (optional): edges constrained as the boundary's are, their ends too.
int repair_caps_and_needles(Mesh& m, double L, const RemeshOptions& options,
                            const Mesh::Property_map<Mesh::Face_index, bool>* frozen = nullptr,
                            const EdgeFlags* feature = nullptr) {
  auto boundary_vertex = m.add_property_map<VertexIndex, bool>("v:on_boundary", false).first;
  auto boundary_edge = m.add_property_map<Mesh::Edge_index, bool>("e:on_boundary", false).first;
  for (const auto e : m.edges()) {
    if (!m.is_border(e) && !(feature && (*feature)[e])) continue;
    boundary_edge[e] = true;
    boundary_vertex[m.vertex(e, 0)] = boundary_vertex[m.vertex(e, 1)] = true;
  }
  if (frozen)
    for (const auto f : m.faces()) {
      if (!(*frozen)[f]) continue;
      for (const auto h : m.halfedges_around_face(m.halfedge(f))) {
        boundary_edge[m.edge(h)] = true;
        boundary_vertex[m.target(h)] = true;
      }
    }
  auto bad = [&] {
    int n = 0;
    for (const auto f : m.faces()) n += flatness(m, f) < options.repair_flatness;
    return n;
  };
  const int before = bad();
  if (before == 0) return 0;
  namespace PMP = CGAL::Polygon_mesh_processing;
  PMP::experimental::remove_almost_degenerate_faces(
      m, std::cos(options.cap_angle * std::numbers::pi / 180.0), options.needle_ratio, 0.5 * L,
      CGAL::parameters::vertex_is_constrained_map(boundary_vertex).edge_is_constrained_map(boundary_edge));
  return before - bad();
}

// --- Grading (see the header) ---

using Segment = Kernel::Segment_3;
using SegmentTree =
    CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_segment_primitive<Kernel, std::vector<Segment>::const_iterator>>>;
using SurfaceTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_face_graph_triangle_primitive<Mesh>>>;

Point face_centroid(const Mesh& m, Mesh::Face_index f) {
  const auto h = m.halfedge(f);
  return CGAL::centroid(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h))));
}

/// Points hashed into cubes of side `cell`, for "is any point within r ≤ cell of q" queries.
class PointGrid {
 public:
  explicit PointGrid(double cell) : m_cell(cell) {}
  void insert(const Point& p) { m_cells[key(cell_of(p.x()), cell_of(p.y()), cell_of(p.z()))].push_back(p); }
  bool any_within(const Point& q, double r) const {
    const long long i = cell_of(q.x()), j = cell_of(q.y()), k = cell_of(q.z());
    for (long long a = i - 1; a <= i + 1; ++a)
      for (long long b = j - 1; b <= j + 1; ++b)
        for (long long c = k - 1; c <= k + 1; ++c) {
          const auto it = m_cells.find(key(a, b, c));
          if (it == m_cells.end()) continue;
          for (const Point& p : it->second)
            if (CGAL::squared_distance(p, q) <= r * r) return true;
        }
    return false;
  }

 private:
  long long cell_of(double x) const { return static_cast<long long>(std::floor(x / m_cell)); }
  static long long key(long long i, long long j, long long k) {
    return (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL);
  }
  double m_cell;
  std::unordered_map<long long, std::vector<Point>> m_cells;
};

double longest_edge(const Mesh& m, Mesh::Face_index f) {
  double longest = 0;
  for (const auto h : m.halfedges_around_face(m.halfedge(f)))
    longest = std::max(longest, (m.point(m.target(h)) - m.point(m.source(h))).squared_length());
  return std::sqrt(longest);
}

/// Adds `rings` rings of faces (sharing a vertex) around the selected ones.
void add_rings(const Mesh& m, std::vector<bool>& selected, int rings) {
  for (int ring = 0; ring < rings; ++ring) {
    std::vector<bool> touched(m.number_of_vertices(), false);
    for (const auto f : m.faces())
      if (selected[f.idx()])
        for (const auto v : m.vertices_around_face(m.halfedge(f))) touched[v.idx()] = true;
    for (const auto f : m.faces())
      for (const auto v : m.vertices_around_face(m.halfedge(f)))
        if (touched[v.idx()]) selected[f.idx()] = true;
  }
}

/// The faces one grading pass refines (header: thin material, or a tight inward turn of the
/// outline, plus `rings` rings): `width` is elements_across × the pass's threshold size.
std::vector<bool> faces_to_grade(const Mesh& m, double width, int rings) {
  std::vector<bool> selected(m.number_of_faces(), false);
  std::vector<Segment> border;
  for (const auto e : m.edges())
    if (m.is_border(e)) border.emplace_back(m.point(m.vertex(e, 0)), m.point(m.vertex(e, 1)));
  if (border.empty()) return selected;
  SegmentTree tree(border.cbegin(), border.cend());
  tree.accelerate_distance_queries();
  // Local width: a face is thick when its centroid lies in a disc of radius R = width/2 inside the
  // material, i.e. within R of a centroid at least R from the boundary. The reach is √2 R (plus
  // the face's longest edge, for the sampling) so that the material's convex corners of 90° or
  // more count as thick (an inscribed disc never reaches into a corner; a corner is not a
  // ligament). Only faces nearer the boundary than R need the search.
  const double R = 0.5 * width;
  std::vector<Point> c(m.number_of_faces());
  std::vector<double> d(m.number_of_faces()), reach(m.number_of_faces());
  double farthest = 0;
  for (const auto f : m.faces()) {
    c[f.idx()] = face_centroid(m, f);
    d[f.idx()] = std::sqrt(CGAL::to_double(tree.squared_distance(c[f.idx()])));
    reach[f.idx()] = std::numbers::sqrt2 * R + longest_edge(m, f);
    farthest = std::max(farthest, reach[f.idx()]);
  }
  PointGrid centres(farthest);
  for (const auto f : m.faces())
    if (d[f.idx()] >= R) centres.insert(c[f.idx()]);
  for (const auto f : m.faces())
    if (d[f.idx()] < R && !centres.any_within(c[f.idx()], reach[f.idx()])) selected[f.idx()] = true;
  // Outline radius: at a boundary vertex where the material's angle θ_m exceeds π, the outline turns
  // by θ_m − π over its two edges; radius = mean edge / turn.
  for (const auto h : m.halfedges()) {
    if (!m.is_border(h)) continue;
    const VertexIndex v = m.source(h);
    double angle = 0;
    for (const auto g : m.halfedges_around_target(m.opposite(h))) {
      if (m.is_border(g)) continue;
      const Point& p = m.point(m.target(g));
      const Kernel::Vector_3 a = m.point(m.source(g)) - p, b = m.point(m.target(m.next(g))) - p;
      angle += std::acos(std::clamp(double(a * b) / std::sqrt(a.squared_length() * b.squared_length()), -1.0, 1.0));
    }
    const double turn = angle - std::numbers::pi;
    if (!(turn > 1e-3)) continue;
    const double mean_edge =
        0.5 * (std::sqrt((m.point(m.target(h)) - m.point(v)).squared_length()) +
               std::sqrt((m.point(v) - m.point(m.source(m.prev(h)))).squared_length()));
    if (mean_edge / turn >= R) continue;
    for (const auto f : m.faces_around_target(m.opposite(h)))
      if (f != Mesh::null_face()) selected[f.idx()] = true;
  }
  add_rings(m, selected, rings);
  return selected;
}

/// The input surface and its outline (its boundary edges): where the grading and the focus put new
/// interior and boundary vertices.
struct InputSurface {
  InputSurface(const RowMatX3d& V, const RowMatX3i& F)
      : mesh(to_cgal(V, F)), surface(CGAL::faces(mesh).first, CGAL::faces(mesh).second, mesh) {
    surface.accelerate_distance_queries();
    for (const auto e : mesh.edges())
      if (mesh.is_border(e)) border.emplace_back(mesh.point(mesh.vertex(e, 0)), mesh.point(mesh.vertex(e, 1)));
    outline.rebuild(border.cbegin(), border.cend());
    if (!border.empty()) outline.accelerate_distance_queries();
  }
  InputSurface(const InputSurface&) = delete;
  InputSurface& operator=(const InputSurface&) = delete;
  Mesh mesh;
  SurfaceTree surface;
  std::vector<Segment> border;
  SegmentTree outline;
};

/// How far from the outline a focus pass refines: everywhere in its balls for the grading's own
/// halvings (k ≤ depth), then within focus_band × the pass's size of the outline.
double focus_band(const GradingOptions& g, int pass, double size) {
  return pass > g.depth && g.focus_band > 0 ? g.focus_band * size : std::numeric_limits<double>::infinity();
}

/// The faces one focus pass refines to `size` (header, GradingOptions::focus): those with a
/// centroid within `radius` of a centre whose longest edge the remeshing would split (over 4/3
/// size), plus `rings` rings; then every face already as fine as `size` (mean edge below it) is
/// taken out again, so the pass never coarsens what an earlier one refined.
std::vector<bool> faces_to_focus(const Mesh& m, const std::vector<Vec3>& centres, double radius, double size,
                                 int rings, const SegmentTree& outline, double band) {
  std::vector<bool> selected(m.number_of_faces(), false);
  for (const auto f : m.faces()) {
    const Point c = face_centroid(m, f);
    const bool near = std::any_of(centres.begin(), centres.end(), [&](const Vec3& x) {
      return CGAL::squared_distance(c, Point(x.x(), x.y(), x.z())) <= radius * radius;
    });
    selected[f.idx()] = near && longest_edge(m, f) > 4.0 / 3.0 * size &&
                        (!std::isfinite(band) || CGAL::to_double(outline.squared_distance(c)) <= band * band);
  }
  add_rings(m, selected, rings);
  for (const auto f : m.faces()) {
    if (!selected[f.idx()]) continue;
    double sum = 0;
    for (const auto h : m.halfedges_around_face(m.halfedge(f)))
      sum += std::sqrt((m.point(m.target(h)) - m.point(m.source(h))).squared_length());
    if (sum / 3 < size) selected[f.idx()] = false;
  }
  return selected;
}

/// Remeshes the faces `selected` (indices of a garbage-free `m`) at `size`: their boundary and
/// feature edges split first (the remeshing protects them), the region's border with the rest kept,
/// then every interior vertex projected onto `surface` (new boundary vertices onto `outline`, the
/// input's boundary edges; feature vertices stay on their straight edges). Returns the number of
/// faces selected.
int refine_region(Mesh& m, const std::vector<bool>& selected, double size, const RemeshOptions& options,
                  Mesh::Property_map<VertexIndex, bool>& corner, const SurfaceTree& surface,
                  const SegmentTree& outline, EdgeFlags& feature) {
  namespace PMP = CGAL::Polygon_mesh_processing;
  const size_t before = m.number_of_faces(), vertices_before = m.number_of_vertices();
  // The boundary and feature edges of the selected faces (a feature edge with a selected face on
  // either side).
  std::vector<Mesh::Edge_index> lines;
  for (const auto e : m.edges()) {
    if (!m.is_border(e) && !feature[e]) continue;
    bool near = false;
    for (const auto h : {m.halfedge(e), m.opposite(m.halfedge(e))})
      near = near || (m.face(h) != Mesh::null_face() && selected[m.face(h).idx()]);
    if (near) lines.push_back(e);
  }
  PMP::split_long_edges(lines, 4.0 / 3.0 * size, m, CGAL::parameters::edge_is_constrained_map(feature));
  // The new boundary vertices onto the input's outline: where step 1 collapsed a short boundary
  // edge, the edge left is a chord of the outline, and its midpoints would stay off it.
  for (const auto v : m.vertices())
    if (size_t(v.idx()) >= vertices_before && m.is_border(v)) m.point(v) = outline.closest_point(m.point(v));
  // Splitting only adds faces (after the existing ones): all of them split selected faces, or the
  // unselected face across a split feature edge, which joins the region.
  std::vector<Mesh::Face_index> region;
  for (const auto f : m.faces())
    if (size_t(f.idx()) >= before || selected[f.idx()]) region.push_back(f);
  // Every boundary and feature vertex pinned (on a face range, CGAL otherwise lets some slide off
  // the outline).
  auto pinned = m.add_property_map<VertexIndex, bool>("v:pinned", false).first;
  mark_kept_vertices(m, corner, feature, pinned);
  for (const auto v : m.vertices()) pinned[v] = pinned[v] || m.is_border(v);
  // Vertices on no face of the region: the remeshing leaves them where they are (vertices it
  // creates, or recycles from the region's, read false).
  auto outside = m.add_property_map<VertexIndex, bool>("v:outside", false).first;
  for (const auto v : m.vertices()) outside[v] = true;
  for (const auto f : region)
    for (const auto v : m.vertices_around_face(m.halfedge(f))) outside[v] = false;
  PMP::isotropic_remeshing(region, size, m,
                           CGAL::parameters::number_of_iterations(unsigned(options.iterations))
                               .vertex_is_constrained_map(pinned)
                               .edge_is_constrained_map(feature)
                               .protect_constraints(true));
  for (const auto v : m.vertices())
    if (!outside[v] && !pinned[v] && !m.is_border(v) && !m.is_isolated(v)) m.point(v) = surface.closest_point(m.point(v));
  m.remove_property_map(pinned);
  m.remove_property_map(outside);
  m.collect_garbage();
  int count = 0;
  for (bool s : selected) count += s;
  return count;
}

/// The garbage-free mesh into `out` (isolated vertices left out).
void write_mesh(Mesh& m, RemeshedMesh& out) {
  m.collect_garbage();
  std::vector<int> index(m.number_of_vertices(), -1);
  out.vertices.resize(Eigen::Index(m.number_of_vertices()), 3);
  int n = 0;
  for (const auto v : m.vertices()) {
    if (m.is_isolated(v)) continue;
    const Point& p = m.point(v);
    out.vertices.row(n) << p.x(), p.y(), p.z();
    index[size_t(v.idx())] = n++;
  }
  out.vertices.conservativeResize(n, 3);
  out.faces.resize(Eigen::Index(m.number_of_faces()), 3);
  int f = 0;
  for (const auto face : m.faces()) {
    int k = 0;
    for (const auto v : m.vertices_around_face(m.halfedge(face))) out.faces(f, k++) = index[size_t(v.idx())];
    ++f;
  }
}

}  // namespace

RemeshedMesh remesh_isotropic(const RowMatX3d& vertices, const RowMatX3i& faces, const RemeshOptions& options) {
  if (!(options.target_edge_length > 0) || !std::isfinite(options.target_edge_length))
    throw InputError(fmt::format("remeshing: target edge length {} is not a positive length (m)",
                                 options.target_edge_length));
  if (options.iterations < 1) throw InputError("remeshing: at least one iteration is needed");
  if (options.grading.depth < 0 || options.grading.depth > 8 || !(options.grading.elements_across > 0) ||
      !(options.grading.feature_scale > 0) || options.grading.rings < 0)
    throw InputError("remeshing: grading needs a depth in [0, 8], positive elements across and feature scale, and "
                     "rings >= 0");
  if (options.grading.focus_depth < 0 || options.grading.depth + options.grading.focus_depth > 10 ||
      (!options.grading.focus.empty() && !(options.grading.focus_radius > 0)))
    throw InputError("remeshing: a focus needs a depth >= 0 (at most 10 halvings in all) and a positive radius");
  std::vector<VertexIndex> index;
  Mesh m = to_cgal(vertices, faces, &index);
  auto corner = m.add_property_map<VertexIndex, bool>("v:corner", false).first;
  auto feature = m.add_property_map<Mesh::Edge_index, bool>("e:feature", false).first;
  RemeshedMesh out;
  out.corner_vertices = mark_corners(m, options.corner_angle * std::numbers::pi / 180.0, corner);
  mark_features(m, index, options.feature_edges, feature, corner);
  namespace PMP = CGAL::Polygon_mesh_processing;
  const double L = options.target_edge_length;
  out.collapsed_boundary_edges = collapse_short_border_edges(m, options.min_boundary_edge * L, corner);
  if (options.coarsen_straight_runs) out.merged_line_vertices = merge_straight_runs(m, L, corner, feature);
  m.collect_garbage();
  // Long boundary and feature edges split at the remeshing's own threshold, then every one is
  // protected: the remeshing neither splits, collapses, flips nor relaxes it.
  std::vector<Mesh::Edge_index> lines;
  for (const auto e : m.edges())
    if (m.is_border(e) || feature[e]) lines.push_back(e);
  PMP::split_long_edges(lines, 4.0 / 3.0 * L, m, CGAL::parameters::edge_is_constrained_map(feature));
  {
    auto kept = m.add_property_map<VertexIndex, bool>("v:kept", false).first;
    mark_kept_vertices(m, corner, feature, kept);
    PMP::isotropic_remeshing(m.faces(), L, m,
                             CGAL::parameters::number_of_iterations(unsigned(options.iterations))
                                 .vertex_is_constrained_map(kept)
                                 .edge_is_constrained_map(feature)
                                 .protect_constraints(true));
    m.remove_property_map(kept);
  }
  m.collect_garbage();
  // Grading: refine where the material is narrow or the outline tight (header).
  if (options.grading.depth > 0 || (!options.grading.focus.empty() && options.grading.focus_depth > 0)) {
    const InputSurface in(vertices, faces);
    const SurfaceTree& surface = in.surface;
    const SegmentTree& outline = in.outline;
    const GradingOptions& g = options.grading;
    for (int pass = 1; pass <= g.depth; ++pass) {
      const double current = L / double(1 << (pass - 1));
      const std::vector<bool> selected =
          faces_to_grade(m, g.elements_across * g.feature_scale * current, g.rings);
      if (std::find(selected.begin(), selected.end(), true) == selected.end()) break;
      out.graded_faces.push_back(refine_region(m, selected, 0.5 * current, options, corner, surface, outline, feature));
    }
    // Focus: halving passes about the centres down to L/2^(depth + focus_depth), each pass's ball
    // a little wider than the next so that sizes change by at most 2 between neighbours.
    const int total = g.depth + g.focus_depth;
    for (int pass = 1; !g.focus.empty() && g.focus_depth > 0 && pass <= total; ++pass) {
      const double size = L / double(1 << pass);
      const double radius = g.focus_radius * (1.0 + 0.5 * double(total - pass));
      const std::vector<bool> selected = faces_to_focus(m, g.focus, radius, size, g.rings, outline, focus_band(g, pass, size));
      if (std::find(selected.begin(), selected.end(), true) == selected.end()) continue;
      out.focused_faces.push_back(refine_region(m, selected, size, options, corner, surface, outline, feature));
    }
  }
  // Caps and needles left beside the protected outline (a valence flip across two collinear
  // boundary edges leaves a flat cap; short outline segments leave needles): caps are flipped away
  // and needles' short interior edges collapsed, the boundary untouched (its edges and vertices
  // constrained). Without this, 3 of 6 built-in designs failed verify with a zero-area face.
  out.repaired_faces = repair_caps_and_needles(m, L, options, nullptr, &feature);
  for (const auto e : m.edges()) out.feature_edges += feature[e];
  write_mesh(m, out);
  return out;
}

RemeshedMesh refine_about(const RowMatX3d& vertices, const RowMatX3i& faces, const std::vector<bool>& frozen,
                          const RowMatX3d& surface_vertices, const RowMatX3i& surface_faces,
                          const RemeshOptions& options) {
  const GradingOptions& g = options.grading;
  const int total = g.depth + g.focus_depth;
  if (!(options.target_edge_length > 0) || !std::isfinite(options.target_edge_length) || options.iterations < 1 ||
      g.focus.empty() || !(g.focus_radius > 0) || g.depth < 0 || g.focus_depth < 0 || total < 1 || total > 10 ||
      g.rings < 0)
    throw InputError("refining about centres: needs a positive size, at least one iteration, centres with a positive "
                     "radius and 1 to 10 halvings in all");
  if (frozen.size() != size_t(faces.rows())) throw InputError("refining about centres: one frozen flag per face expected");
  Mesh m = to_cgal(vertices, faces);  // face f of the input is face index f
  auto corner = m.add_property_map<VertexIndex, bool>("v:corner", false).first;
  RemeshedMesh out;
  out.corner_vertices = mark_corners(m, options.corner_angle * std::numbers::pi / 180.0, corner);
  auto fixed = m.add_property_map<Mesh::Face_index, bool>("f:frozen", false).first;
  for (const auto f : m.faces()) fixed[f] = frozen[f.idx()];
  const InputSurface in(surface_vertices, surface_faces);
  if (in.border.empty()) throw InputError("refining about centres: the input surface has no outline");
  const SurfaceTree& surface = in.surface;
  const SegmentTree& outline = in.outline;
  const double L = options.target_edge_length;
  auto no_features = m.add_property_map<Mesh::Edge_index, bool>("e:feature", false).first;
  for (int pass = 1; pass <= total; ++pass) {
    const double size = L / double(1 << pass);
    const double radius = g.focus_radius * (1.0 + 0.5 * double(total - pass));
    std::vector<bool> selected = faces_to_focus(m, g.focus, radius, size, g.rings, outline, focus_band(g, pass, size));
    for (const auto f : m.faces())
      if (fixed[f]) selected[f.idx()] = false;
    if (std::find(selected.begin(), selected.end(), true) == selected.end()) continue;
    out.focused_faces.push_back(refine_region(m, selected, size, options, corner, surface, outline, no_features));
  }
  out.repaired_faces = repair_caps_and_needles(m, L, options, &fixed);
  write_mesh(m, out);
  return out;
}

}  // namespace cutwork
