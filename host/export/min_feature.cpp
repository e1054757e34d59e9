#include "host/export/min_feature.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <unordered_set>

#include <Eigen/Geometry>
#include <Eigen/SVD>

namespace cutwork {

double segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, Vec3* on_p, Vec3* on_q) {
  // Closest points of two segments: minimise |p0 + s d1 − q0 − t d2| over [0,1]², clamping s
  // and t in turn (the quadratic is convex, so the clamped solution is the minimiser).
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= 0 && e <= 0) {
    s = t = 0;
  } else if (a <= 0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  const Vec3 cp = p0 + s * d1, cq = q0 + t * d2;
  if (on_p) *on_p = cp;
  if (on_q) *on_q = cq;
  return (cp - cq).norm();
}

namespace {

struct Loop {
  std::vector<std::array<int, 2>> edges;
  std::vector<int> edge_faces;  ///< the face each edge bounds
  Eigen::AlignedBox3d box;
  bool border = false;
};

int find_root(std::vector<int>& parent, int v) {
  while (parent[size_t(v)] != v) v = parent[size_t(v)] = parent[size_t(parent[size_t(v)])];
  return v;
}

/// The boundary loops of `cut`: components of its boundary edges (a directed edge whose reverse
/// no face uses), joined where they share a vertex.
std::vector<Loop> boundary_loops(const CutSurface& cut, const SurfaceMesh& base) {
  const RowMatX3i& F = cut.faces;
  auto key = [](int a, int b) { return (uint64_t(uint32_t(a)) << 32) | uint32_t(b); };
  std::unordered_set<uint64_t> directed;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) directed.insert(key(F(f, k), F(f, (k + 1) % 3)));
  std::vector<std::array<int, 2>> edges;
  std::vector<int> edge_faces;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if (!directed.count(key(b, a))) {
        edges.push_back({a, b});
        edge_faces.push_back(int(f));
      }
    }
  std::vector<int> parent(size_t(cut.vertices.rows()));
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& [a, b] : edges) parent[size_t(find_root(parent, a))] = find_root(parent, b);
  std::vector<int> loop_of(parent.size(), -1);
  std::vector<Loop> loops;
  const std::vector<bool>& base_border = base.is_boundary_vertex();
  for (size_t i = 0; i < edges.size(); ++i) {
    const auto& e = edges[i];
    const int root = find_root(parent, e[0]);
    if (loop_of[size_t(root)] < 0) {
      loop_of[size_t(root)] = int(loops.size());
      loops.emplace_back();
    }
    Loop& loop = loops[size_t(loop_of[size_t(root)])];
    loop.edges.push_back(e);
    loop.edge_faces.push_back(edge_faces[i]);
    for (int v : e) {
      loop.box.extend(cut.vertices.row(v).transpose());
      const int s = cut.source_vertex.size() > v ? cut.source_vertex[v] : -1;
      if (s >= 0 && size_t(s) < base_border.size() && base_border[size_t(s)]) loop.border = true;
    }
  }
  return loops;
}

double box_distance(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
  const Vec3 gap = (a.min() - b.max()).cwiseMax(b.min() - a.max()).cwiseMax(0.0);
  return gap.norm();
}

/// Smallest distance between the edges of loops a and b, if below `bound` (else +inf), with the
/// closest points and (optional) the indices of the closest edges in a.edges and b.edges.
double loop_distance(const CutSurface& cut, const Loop& a, const Loop& b, double bound, Vec3* pa, Vec3* pb,
                     int* edge_a = nullptr, int* edge_b = nullptr) {
  auto near = [&](const Loop& from, const Loop& to) {
    std::vector<int> out;
    for (size_t i = 0; i < from.edges.size(); ++i) {
      const auto& e = from.edges[i];
      Eigen::AlignedBox3d box(cut.vertices.row(e[0]).transpose());
      box.extend(cut.vertices.row(e[1]).transpose());
      if (box_distance(box, to.box) <= bound) out.push_back(int(i));
    }
    return out;
  };
  const auto ea = near(a, b), eb = near(b, a);
  double best = std::numeric_limits<double>::infinity();
  for (int i : ea)
    for (int j : eb) {
      const auto& x = a.edges[size_t(i)];
      const auto& y = b.edges[size_t(j)];
      Vec3 p, q;
      const double d = segment_distance(cut.vertices.row(x[0]), cut.vertices.row(x[1]), cut.vertices.row(y[0]),
                                        cut.vertices.row(y[1]), &p, &q);
      if (d < best) {
        best = d;
        *pa = p;
        *pb = q;
        if (edge_a) *edge_a = i;
        if (edge_b) *edge_b = j;
      }
    }
  return best;
}

}  // namespace

MinFeatureReport check_min_feature(const CutSurface& cut, const SurfaceMesh& base, double minimum,
                                   const Vec3& mirror_planes) {
  MinFeatureReport r;
  r.minimum = minimum;
  std::vector<Loop> loops = boundary_loops(cut, base);
  for (const Loop& l : loops) (l.border ? r.borders : r.holes) += 1;
  // Symmetry planes: the border's edges on a plane are no border; each hole meets its own image.
  const double tol = 1e-6 * (base.bbox_max() - base.bbox_min()).norm();
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(mirror_planes[a])) continue;
    const double c = mirror_planes[a];
    for (int li = 0; li < int(loops.size()); ++li) {
      Loop& l = loops[size_t(li)];
      if (l.border) {
        Loop kept;
        kept.border = true;
        for (size_t e = 0; e < l.edges.size(); ++e) {
          const auto& [u, v] = l.edges[e];
          if (std::abs(cut.vertices(u, a) - c) <= tol && std::abs(cut.vertices(v, a) - c) <= tol) continue;
          kept.edges.push_back(l.edges[e]);
          kept.edge_faces.push_back(l.edge_faces[e]);
          kept.box.extend(cut.vertices.row(u).transpose());
          kept.box.extend(cut.vertices.row(v).transpose());
        }
        l = std::move(kept);
        continue;
      }
      // The nearest point of a polyline to a plane is one of its vertices.
      int nearest = -1;
      for (const auto& e : l.edges)
        if (nearest < 0 || std::abs(cut.vertices(e[0], a) - c) < std::abs(cut.vertices(nearest, a) - c)) nearest = e[0];
      if (nearest < 0) continue;
      const Vec3 p = cut.vertices.row(nearest).transpose();
      Vec3 q = p;
      q[a] = 2 * c - p[a];
      const double width = (p - q).norm();
      r.narrowest_between_stencils = std::min(r.narrowest_between_stencils, width);
      if (width < minimum) r.violations.push_back({"stencils", width, p, q, li, li});
    }
  }
  struct Pair {
    int a, b;
    double lower;
  };
  std::vector<Pair> pairs;
  for (int i = 0; i < int(loops.size()); ++i)
    for (int j = i + 1; j < int(loops.size()); ++j)
      if (!loops[size_t(i)].border || !loops[size_t(j)].border)
        pairs.push_back({i, j, box_distance(loops[size_t(i)].box, loops[size_t(j)].box)});
  std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) {
    return x.lower < y.lower || (x.lower == y.lower && (x.a < y.a || (x.a == y.a && x.b < y.b)));
  });
  for (const Pair& p : pairs) {
    const Loop& a = loops[size_t(p.a)];
    const Loop& b = loops[size_t(p.b)];
    const bool to_border = a.border || b.border;
    double& narrowest = to_border ? r.narrowest_to_boundary : r.narrowest_between_stencils;
    const double bound = std::max(minimum, narrowest);
    if (p.lower > bound) continue;
    Vec3 pa, pb;
    const double d = loop_distance(cut, a, b, bound, &pa, &pb);
    narrowest = std::min(narrowest, d);
    if (d < minimum) {
      // The hole first, so a "boundary" violation reads hole → border.
      const bool swap = a.border;
      r.violations.push_back({to_border ? "boundary" : "stencils", d, swap ? pb : pa, swap ? pa : pb,
                              swap ? p.b : p.a, swap ? p.a : p.b});
    }
  }
  std::sort(r.violations.begin(), r.violations.end(),
            [](const LigamentViolation& x, const LigamentViolation& y) { return x.width < y.width; });
  return r;
}

namespace {

/// The radius of curvature of `loop` about its point p (on edge `edge`), convex towards `towards`
/// (the other rim's closest point): the least-squares circle (Kåsa's algebraic fit) through p and
/// the loop's vertices within r of it, in the plane of the face the edge bounds; r starts at
/// 4 × `width` and doubles until at least five vertices take part (or the whole loop does). +inf
/// where the rim is straight or concave there (the circle's centre on the ligament's side).
double rim_radius(const CutSurface& cut, const Loop& loop, int edge, const Vec3& p, const Vec3& towards,
                  double width) {
  const RowMatX3i& F = cut.faces;
  const int f = loop.edge_faces[size_t(edge)];
  const Vec3 a = cut.vertices.row(F(f, 0)), b = cut.vertices.row(F(f, 1)), c = cut.vertices.row(F(f, 2));
  const Vec3 n = (b - a).cross(c - a).normalized();
  const auto& e = loop.edges[size_t(edge)];
  const Vec3 e1 = (Vec3(cut.vertices.row(e[1])) - Vec3(cut.vertices.row(e[0]))).normalized();
  const Vec3 e2 = n.cross(e1);
  std::vector<int> verts;
  for (const auto& x : loop.edges) verts.push_back(x[0]);
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  const double extent = loop.box.diagonal().norm();
  std::vector<Vec2> pts;
  for (double r = 4 * std::max(width, 1e-12);; r *= 2) {
    pts.assign(1, Vec2::Zero());
    for (int v : verts) {
      const Vec3 d = Vec3(cut.vertices.row(v)) - p;
      if (d.norm() <= r && d.norm() > 0) pts.emplace_back(d.dot(e1), d.dot(e2));
    }
    if (pts.size() >= 6 || r > extent) break;
  }
  if (pts.size() < 3) return std::numeric_limits<double>::infinity();
  // x² + y² + D x + E y + G = 0 in the least-squares sense.
  Eigen::MatrixXd A(Eigen::Index(pts.size()), 3);
  Eigen::VectorXd rhs(Eigen::Index(pts.size()));
  for (size_t i = 0; i < pts.size(); ++i) {
    A.row(Eigen::Index(i)) << pts[i].x(), pts[i].y(), 1.0;
    rhs(Eigen::Index(i)) = -pts[i].squaredNorm();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  if (svd.singularValues()(2) <= 1e-12 * svd.singularValues()(0)) return std::numeric_limits<double>::infinity();
  const Eigen::Vector3d s = svd.solve(rhs);
  const Vec2 centre(-0.5 * s(0), -0.5 * s(1));
  const double r2 = centre.squaredNorm() - s(2);
  if (!(r2 > 0)) return std::numeric_limits<double>::infinity();
  const Vec3 g = towards - p;
  const Vec2 to_other(g.dot(e1), g.dot(e2));
  // Convex towards the ligament: the centre lies on the hole's side of p, away from the other rim.
  if (centre.dot(to_other) >= 0) return std::numeric_limits<double>::infinity();
  return std::sqrt(r2);
}

}  // namespace

namespace {

/// A distance between a vertex of `a` and one of `b` (so at least the loops' distance): from a's
/// vertex nearest b's box centre, nearest vertices taken in turn three times. It narrows the edges
/// loop_distance pairs from all of both loops to those facing each other.
double vertex_upper_bound(const CutSurface& cut, const Loop& a, const Loop& b) {
  auto nearest = [&](const Loop& l, const Vec3& q) {
    int best = l.edges.front()[0];
    double d2 = std::numeric_limits<double>::infinity();
    for (const auto& e : l.edges) {
      const double d = (Vec3(cut.vertices.row(e[0])) - q).squaredNorm();
      if (d < d2) d2 = d, best = e[0];
    }
    return best;
  };
  int va = nearest(a, b.box.center()), vb = nearest(b, cut.vertices.row(va).transpose());
  for (int round = 0; round < 3; ++round) {
    va = nearest(a, cut.vertices.row(vb).transpose());
    vb = nearest(b, cut.vertices.row(va).transpose());
  }
  return (cut.vertices.row(va) - cut.vertices.row(vb)).norm();
}

}  // namespace

std::vector<Ligament> find_ligaments(const CutSurface& cut, const SurfaceMesh& base, double relative_width,
                                     const Vec3& mirror_planes) {
  std::vector<Ligament> out;
  if (!(relative_width > 0)) return out;
  const std::vector<Loop> loops = boundary_loops(cut, base);
  // A loop's size: half the largest extent of its box (a circle's radius).
  auto size = [](const Loop& l) { return 0.5 * (l.box.max() - l.box.min()).maxCoeff(); };
  // Sweep and prune along x: the holes by the lower end of their boxes; a later hole whose box
  // starts beyond the earlier's end plus its bound cannot pair with it, nor can any after it.
  std::vector<int> order;
  for (int i = 0; i < int(loops.size()); ++i)
    if (!loops[size_t(i)].border) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](int x, int y) {
    return loops[size_t(x)].box.min().x() < loops[size_t(y)].box.min().x() || (loops[size_t(x)].box.min().x() ==
           loops[size_t(y)].box.min().x() && x < y);
  });
  for (std::size_t oi = 0; oi < order.size(); ++oi) {
    const int i = order[oi];
    const Loop& a = loops[size_t(i)];
    const double reach = a.box.max().x() + relative_width * size(a);
    for (std::size_t oj = oi + 1; oj < order.size(); ++oj) {
      const Loop& b = loops[size_t(order[oj])];
      if (b.box.min().x() > reach) break;
      const int j = order[oj];
      const double bound = relative_width * std::min(size(a), size(b));
      if (box_distance(a.box, b.box) > bound) continue;
      Ligament l;
      int ea = -1, eb = -1;
      l.width = loop_distance(cut, a, b, std::min(bound, vertex_upper_bound(cut, a, b)), &l.point_a, &l.point_b, &ea,
                              &eb);
      if (!(l.width <= bound) || ea < 0 || eb < 0) continue;
      l.loop_a = i;
      l.loop_b = j;
      l.size_a = size(a);
      l.size_b = size(b);
      l.radius_a = rim_radius(cut, a, ea, l.point_a, l.point_b, l.width);
      l.radius_b = rim_radius(cut, b, eb, l.point_b, l.point_a, l.width);
      out.push_back(l);
    }
  }
  // Symmetry planes: each hole and its own image, across the ligament at the hole's nearest vertex.
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(mirror_planes[a])) continue;
    const double c = mirror_planes[a];
    for (const int i : order) {
      const Loop& h = loops[size_t(i)];
      int edge = -1;
      for (int e = 0; e < int(h.edges.size()); ++e)
        if (edge < 0 || std::abs(cut.vertices(h.edges[size_t(e)][0], a) - c) <
                            std::abs(cut.vertices(h.edges[size_t(edge)][0], a) - c))
          edge = e;
      if (edge < 0) continue;
      Ligament l;
      l.point_a = cut.vertices.row(h.edges[size_t(edge)][0]).transpose();
      l.point_b = l.point_a;
      l.point_b[a] = 2 * c - l.point_a[a];
      l.width = (l.point_a - l.point_b).norm();
      l.size_a = l.size_b = size(h);
      if (!(l.width <= relative_width * l.size_a)) continue;
      l.loop_a = l.loop_b = i;
      l.radius_a = l.radius_b = rim_radius(cut, h, edge, l.point_a, l.point_b, l.width);
      out.push_back(l);
    }
  }
  std::sort(out.begin(), out.end(), [](const Ligament& x, const Ligament& y) { return x.width < y.width; });
  return out;
}

double Ligament::neck_radius() const {
  // The neck's width about its narrowest point: w + s²/(2 ρ_a) + s²/(2 ρ_b) = w + s²/R_h.
  const double a = capped_radius_a(), b = capped_radius_b();
  return a + b > 0 ? 2 * a * b / (a + b) : 0.0;
}

double Ligament::pair_radius() const {
  const double a = capped_radius_a(), b = capped_radius_b();
  return a + b > 0 ? (a * a + b * b) / (a + b) : 0.0;
}

}  // namespace cutwork
