#include "host/export/min_feature.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <unordered_set>

#include <Eigen/Geometry>

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
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if (!directed.count(key(b, a))) edges.push_back({a, b});
    }
  std::vector<int> parent(size_t(cut.vertices.rows()));
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto& [a, b] : edges) parent[size_t(find_root(parent, a))] = find_root(parent, b);
  std::vector<int> loop_of(parent.size(), -1);
  std::vector<Loop> loops;
  const std::vector<bool>& base_border = base.is_boundary_vertex();
  for (const auto& e : edges) {
    const int root = find_root(parent, e[0]);
    if (loop_of[size_t(root)] < 0) {
      loop_of[size_t(root)] = int(loops.size());
      loops.emplace_back();
    }
    Loop& loop = loops[size_t(loop_of[size_t(root)])];
    loop.edges.push_back(e);
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

/// Smallest distance between the edges of loops a and b, if below `bound` (else +inf).
double loop_distance(const CutSurface& cut, const Loop& a, const Loop& b, double bound, Vec3* pa, Vec3* pb) {
  auto near = [&](const Loop& from, const Loop& to) {
    std::vector<std::array<int, 2>> out;
    for (const auto& e : from.edges) {
      Eigen::AlignedBox3d box(cut.vertices.row(e[0]).transpose());
      box.extend(cut.vertices.row(e[1]).transpose());
      if (box_distance(box, to.box) <= bound) out.push_back(e);
    }
    return out;
  };
  const auto ea = near(a, b), eb = near(b, a);
  double best = std::numeric_limits<double>::infinity();
  for (const auto& x : ea)
    for (const auto& y : eb) {
      Vec3 p, q;
      const double d = segment_distance(cut.vertices.row(x[0]), cut.vertices.row(x[1]), cut.vertices.row(y[0]),
                                        cut.vertices.row(y[1]), &p, &q);
      if (d < best) {
        best = d;
        *pa = p;
        *pb = q;
      }
    }
  return best;
}

}  // namespace

MinFeatureReport check_min_feature(const CutSurface& cut, const SurfaceMesh& base, double minimum) {
  MinFeatureReport r;
  r.minimum = minimum;
  const std::vector<Loop> loops = boundary_loops(cut, base);
  for (const Loop& l : loops) (l.border ? r.borders : r.holes) += 1;
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

}  // namespace cutwork
