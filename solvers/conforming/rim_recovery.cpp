#include "solvers/conforming/rim_recovery.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "host/core/error.h"
#include "solvers/homogenise/free_edge_strain.h"

namespace cutwork::solvers {
namespace {

/// The interior angle (radians) of face f at its vertex v.
double angle_at(const RowMatX3d& X, const RowMatX3i& F, int f, int v) {
  int k = 0;
  while (F(f, k) != v) ++k;
  const Vec3 p = X.row(v), a = X.row(F(f, (k + 1) % 3)), b = X.row(F(f, (k + 2) % 3));
  const Vec3 u = a - p, w = b - p;
  return std::atan2(u.cross(w).norm(), u.dot(w));
}

/// Vertex → faces in compressed rows.
struct VertexFaces {
  std::vector<int> start, faces;
  VertexFaces(int nv, const RowMatX3i& F) : start(std::size_t(nv) + 1, 0), faces(std::size_t(3 * F.rows())) {
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) ++start[std::size_t(F(f, k)) + 1];
    for (int v = 0; v < nv; ++v) start[std::size_t(v) + 1] += start[std::size_t(v)];
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (Eigen::Index f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) faces[std::size_t(fill[std::size_t(F(f, k))]++)] = int(f);
  }
  std::span<const int> of(int v) const {
    return {faces.data() + start[std::size_t(v)], std::size_t(start[std::size_t(v) + 1] - start[std::size_t(v)])};
  }
};

int monomials(int degree) { return (degree + 1) * (degree + 2) / 2; }

/// Per-thread scratch: the vertices of a patch, and a mark per vertex (kept all clear between uses).
struct Scratch {
  std::vector<int> nodes;
  std::vector<char> mark;
};

/// The vertices within r of X_v reached from v through faces (v first).
void gather_nodes(int v, double r, const RowMatX3d& X, const RowMatX3i& F, const VertexFaces& vf, Scratch& s) {
  s.nodes.assign(1, v);
  s.mark[std::size_t(v)] = 1;
  for (std::size_t q = 0; q < s.nodes.size(); ++q)
    for (int f : vf.of(s.nodes[q]))
      for (int k = 0; k < 3; ++k) {
        const int w = F(f, k);
        if (s.mark[std::size_t(w)]) continue;
        s.mark[std::size_t(w)] = 1;
        if ((X.row(w) - X.row(v)).norm() <= r) s.nodes.push_back(w);
        else s.mark[std::size_t(w)] = 2;  // seen, outside: cleared below
      }
  // Clear every mark set (inside and outside nodes alike): walk the same faces again.
  for (int w : s.nodes)
    for (int f : vf.of(w))
      for (int k = 0; k < 3; ++k) s.mark[std::size_t(F(f, k))] = 0;
}

/// Each point's ε_tt, κ_tt, κ_tm replaced by the value at its own arc position of the quadratic
/// least-squares fit (in arc length) through the points of its run within its patch radius, at
/// least two on each side where the run has them.
template <class Runs>
void smooth_along_runs(std::vector<RimPoint>& rim, const Runs& runs) {
  for (const auto& run : runs) {
    const int n = int(run.slots.size());
    if (n < 3) continue;
    std::vector<double> arc(static_cast<std::size_t>(n) + 1, 0.0);  // arc[k]: length from the run's first point
    for (int k = 1; k <= n; ++k)
      if (k < n || run.cyclic)
        arc[std::size_t(k)] = arc[std::size_t(k) - 1] +
                              (rim[std::size_t(run.slots[std::size_t(k % n)])].position -
                               rim[std::size_t(run.slots[std::size_t(k - 1)])].position).norm();
    const double total = arc[std::size_t(n)];
    std::vector<Eigen::Vector3d> smoothed(static_cast<std::size_t>(n));
    std::vector<std::pair<double, int>> window;
    for (int k = 0; k < n; ++k) {
      const RimPoint& p = rim[std::size_t(run.slots[std::size_t(k)])];
      window.clear();
      window.push_back({0.0, k});
      // Walk each way: within the radius, and at least two points.
      for (int dir : {-1, 1}) {
        for (int step = 1; step < n; ++step) {
          int j = k + dir * step;
          double d;
          if (run.cyclic) {
            j = ((j % n) + n) % n;
            d = arc[std::size_t(j)] - arc[std::size_t(k)];
            if (dir > 0 && d <= 0) d += total;
            if (dir < 0 && d >= 0) d -= total;
            if (2 * step >= n + (dir > 0 ? 1 : 0)) break;  // each point once, split between the sides
          } else {
            if (j < 0 || j >= n) break;
            d = arc[std::size_t(j)] - arc[std::size_t(k)];
          }
          if (step > 2 && std::abs(d) > p.patch_radius) break;
          window.push_back({d, j});
        }
      }
      const int m = int(window.size());
      const int terms = std::min(3, m);
      Eigen::MatrixXd A(m, terms);
      Eigen::MatrixXd y(m, 3);
      const double scale = std::max(p.patch_radius, 1e-300);
      for (int i = 0; i < m; ++i) {
        const double d = window[std::size_t(i)].first / scale;
        for (int c = 0; c < terms; ++c) A(i, c) = std::pow(d, c);
        const RimPoint& q = rim[std::size_t(run.slots[std::size_t(window[std::size_t(i)].second)])];
        y.row(i) << q.strain, q.curvature, q.twist;
      }
      smoothed[std::size_t(k)] = A.colPivHouseholderQr().solve(y).row(0).transpose();
    }
    for (int k = 0; k < n; ++k) {
      RimPoint& p = rim[std::size_t(run.slots[std::size_t(k)])];
      p.strain = smoothed[std::size_t(k)](0);
      p.curvature = smoothed[std::size_t(k)](1);
      p.twist = smoothed[std::size_t(k)](2);
    }
  }
}

/// Degrees a boundary vertex turns by at least to count as one of the outline's own vertices (a
/// 64-gon's turn 5.6°, a 128-gon's 2.8°). A remeshed vertex on a straight outline segment turns by
/// round-off or, on a curved shell, by its faces' angle defect: 0.006° at 1 mm on the bowl, but
/// 0.2° where the table's free border runs around its fillets, which at 0.05° had made the whole
/// 0.85 m top edge between them one "segment" and its patches 0.85 m wide (a rim W of 1000 J/m²
/// where the faces read 4).
constexpr double kOutlineTurn = 1.0;

}  // namespace

std::vector<RimPoint> recover_rim(const ShellModel& model, const RowMatX3d& x, const RimRecoveryOptions& o) {
  if (!(o.patch_radius > 0) || !std::isfinite(o.patch_radius) || !(o.nodes_per_coefficient >= 1.5) ||
      !(o.nodes_per_coefficient <= 10) || o.degree < 2 || o.degree > 4 ||
      !(o.corner_angle > 0) || !(o.corner_angle < 180) || !(o.corner_radius >= 0) ||
      !std::isfinite(o.corner_radius) || !(o.support_radius >= 0) || !std::isfinite(o.support_radius) ||
      !(o.outline_radius >= 0) || !(o.outline_radius <= 4))
    throw InputError(fmt::format("rim recovery: bad options (patch radius {}, degree {}, corner angle {}°, "
                                 "singular radii {} m at corners, {} m at supports, outline radius {})",
                                 o.patch_radius, o.degree, o.corner_angle, o.corner_radius, o.support_radius,
                                 o.outline_radius));
  const SurfaceMesh& mesh = model.mesh();
  const RowMatX3d& X = mesh.vertices();
  const RowMatX3i& F = mesh.faces();
  if (x.rows() != X.rows() || !x.allFinite()) throw InputError("rim recovery: positions do not match the mesh");
  const VertexFaces vf(mesh.num_vertices(), F);
  constexpr double kDegree = std::numbers::pi / 180;

  // The rim points (free vertices of the boundary loops, with their loop neighbours) and the
  // singular corners (any boundary vertex, supported or not, turning into the material).
  struct Slot {
    int vertex, prev, next;
    double outline_segment;  // m: the outline's own segment length about the vertex (0: none)
  };
  std::vector<Slot> slots;
  std::vector<Vec3> corners, support_ends;
  std::vector<double> angles;
  // Runs of consecutive free rim points along a loop (a whole loop without support is one cyclic
  // run), for the smoothing along the rim.
  struct Run {
    std::vector<int> slots;
    bool cyclic = false;
  };
  std::vector<Run> runs;
  for (const std::vector<int>& loop : mesh.boundary_loops()) {
    const std::size_t n = loop.size();
    std::vector<double> angle(n, 0.0);
    std::vector<char> breaks(n, 0);  // supported vertices and corners (either way) end a run
    for (std::size_t i = 0; i < n; ++i) {
      for (int f : vf.of(loop[i])) angle[i] += angle_at(X, F, f, loop[i]);
      angle[i] /= kDegree;
      if (!o.corners && angle[i] > 180 + o.corner_angle) corners.push_back(X.row(loop[i]).transpose());
      breaks[i] = model.fixed()[std::size_t(loop[i])] || std::abs(angle[i] - 180) > o.corner_angle;
    }
    // The outline's own segments: a smooth outline (a circle, an arch) comes as a polygon whose
    // vertices turn by a little (outline vertices: between kOutlineTurn and corner_angle degrees);
    // remeshing finer puts straight-line vertices between them. Each vertex gets the arc length
    // between the outline vertices on either side of it (the mean of its two segments when it is
    // one), or 0 where either of them is a corner, a support or there are none.
    std::vector<double> arc(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) arc[i + 1] = arc[i] + (X.row(loop[(i + 1) % n]) - X.row(loop[i])).norm();
    auto turning = [&](std::size_t i) { return std::abs(angle[i] - 180) > kOutlineTurn || model.fixed()[std::size_t(loop[i])]; };
    auto smooth_vertex = [&](std::size_t i) {
      return std::abs(angle[i] - 180) <= o.corner_angle && !model.fixed()[std::size_t(loop[i])];
    };
    std::vector<std::size_t> turns;
    for (std::size_t i = 0; i < n; ++i)
      if (turning(i)) turns.push_back(i);
    // The end of the outline's segment from i in direction `step` (±1): the first turning vertex
    // (returned with true), unless the turns of the vertices before it, summed from i, exceed
    // kOutlineTurn first (returned with false): the outline between is then no straight side of a
    // polygon but a curve sampled finer than kOutlineTurn per vertex (a circle of many segments as
    // the remesher's collapses leave it, or a fillet's border), with no corner for the patch to
    // reach over, and the mesh alone sets the patch. With the turning vertices alone, a 1024-gon's
    // rim at R/40, turning 0.85° per vertex, made segments of a whole quadrant between the few
    // vertices that turned by more, and the neck of two such holes read 10% low
    // (Ligament.AFinelySegmentedCircleReadsAsTheCircle).
    auto segment_end = [&](std::size_t i, int step) {
      double summed = 0;
      std::size_t j = i;
      for (std::size_t k = 1; k < n; ++k) {
        const std::size_t next = (i + n + std::size_t(step) * k) % n;
        if (turning(next)) return std::pair(next, true);
        summed += angle[next] - 180;
        if (std::abs(summed) > kOutlineTurn) return std::pair(j, false);
        j = next;
      }
      return std::pair(j, false);
    };
    std::vector<double> segment(n, 0.0);
    if (turns.size() >= 3) {
      const double perimeter = arc[n];
      for (std::size_t i = 0; i < n; ++i) {
        // The segment's ends before and after i (cyclically, i itself left out).
        const auto [b, b_turns] = segment_end(i, +1);
        const auto [a, a_turns] = segment_end(i, -1);
        if (!a_turns || !b_turns || !smooth_vertex(a) || !smooth_vertex(b) || (turning(i) && !smooth_vertex(i)))
          continue;
        double span = arc[b] - arc[a];
        if (span <= 0) span += perimeter;
        segment[i] = turning(i) ? 0.5 * span : span;
      }
    }
    // Where a support ends along the rim (a clamp's or a pin's last vertex next to a free one).
    for (std::size_t i = 0; i < n; ++i)
      if (model.fixed()[std::size_t(loop[i])] && (!model.fixed()[std::size_t(loop[(i + 1) % n])] ||
                                                  !model.fixed()[std::size_t(loop[(i + n - 1) % n])]))
        support_ends.push_back(X.row(loop[i]).transpose());
    // Walk from a break, if there is one: each run then lies in one piece.
    std::size_t first = 0;
    while (first < n && !breaks[first]) ++first;
    const bool cyclic = first == n;
    if (cyclic) first = 0;
    runs.push_back({{}, cyclic});
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = (first + k) % n;
      const int v = loop[i];
      if (breaks[i] && !runs.back().slots.empty()) runs.push_back({});
      if (model.fixed()[std::size_t(v)]) continue;
      runs.back().slots.push_back(int(slots.size()));
      slots.push_back({v, loop[(i + n - 1) % n], loop[(i + 1) % n], segment[i]});
      angles.push_back(angle[i]);
      if (breaks[i]) runs.push_back({});  // a corner stands alone: its two sides differ
    }
    while (!runs.empty() && runs.back().slots.empty()) runs.pop_back();
  }

  const Material& mat = model.material();
  const int wanted = int(std::ceil(o.nodes_per_coefficient * monomials(o.degree)));
  std::vector<RimPoint> rim(slots.size());
  // One scratch per thread: its mark array is #V long, too long to clear per chunk.
  tbb::enumerable_thread_specific<Scratch> scratch(
      [&] { return Scratch{{}, std::vector<char>(std::size_t(mesh.num_vertices()), 0)}; });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, slots.size(), 64), [&](const tbb::blocked_range<std::size_t>& range) {
    Scratch& s = scratch.local();
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const Slot& slot = slots[i];
      const int v = slot.vertex;
      RimPoint& p = rim[i];
      p.vertex = v;
      p.position = X.row(v).transpose();
      p.material_angle = angles[i];
      const Vec3 normal = mesh.vertex_normals().row(v).transpose();
      Vec3 t = (X.row(slot.next) - X.row(slot.prev)).transpose();
      t -= t.dot(normal) * normal;
      t.normalize();
      const Vec3 m = normal.cross(t);
      p.tangent = t;

      // The patch: vertices within r, r doubled until it holds enough of them.
      double mean_edge = 0;
      int edges = 0;
      for (int f : vf.of(v))
        for (int k = 0; k < 3; ++k)
          if (F(f, k) != v) {
            mean_edge += (X.row(F(f, k)) - X.row(v)).norm();
            ++edges;
          }
      double r = std::max(o.patch_radius * mean_edge / std::max(edges, 1), o.outline_radius * slot.outline_segment);
      for (int attempt = 0;; ++attempt) {
        gather_nodes(v, r, X, F, vf, s);
        if (int(s.nodes.size()) >= wanted || attempt == 8) break;
        r *= 2;
      }
      p.patch_nodes = int(s.nodes.size());
      p.patch_radius = r;

      // u = x − X fitted by the complete polynomial of the degree (lower where the nodes cannot
      // determine it) in (s, q)/r; monomials ordered 1, s, q, s², sq, q², s³, …
      for (int degree = o.degree; degree >= 1; --degree) {
        const int nc = monomials(degree);
        const Eigen::Index rows = Eigen::Index(s.nodes.size());
        Eigen::MatrixXd B(rows, nc), U(rows, 6);  // columns: X − X_v (rest), u = x − X
        for (Eigen::Index j = 0; j < rows; ++j) {
          const int w = s.nodes[std::size_t(j)];
          const Vec3 d = X.row(w).transpose() - p.position;
          const double sj = d.dot(t) / r, qj = d.dot(m) / r;
          int c = 0;
          for (int deg = 0; deg <= degree; ++deg)
            for (int iq = 0; iq <= deg; ++iq) B(j, c++) = std::pow(sj, deg - iq) * std::pow(qj, iq);
          U.row(j) << d.transpose(), x.row(w) - X.row(w);
        }
        Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(B);
        qr.setThreshold(1e-6);  // columns are O(1) on the scaled patch: a smaller pivot is a lost one
        if (degree > 1 && (qr.rank() < nc || rows < nc + 2)) continue;
        const Eigen::MatrixXd c = qr.solve(U);
        // Derivatives at (0, 0) in metres: rest X_,α and displacement u_,α, then the second ones.
        auto first = [&](int k, int col) -> Vec3 { return c.block(k, col, 1, 3).transpose() / r; };
        const Vec3 Xs = first(1, 0), Xq = first(2, 0), us = first(1, 3), uq = first(2, 3);
        p.fit_degree = degree;
        // Green–Lagrange: ½(|x_,s|² − |X_,s|²) per |X_,s|², invariant under the rotations the
        // geometrically nonlinear solve carries (a linear t·u_,s read −θ²/2 for a rotation θ:
        // −2.5e-3 on the plate design's tip, 20× its real strain).
        p.strain = (Xs.dot(us) + 0.5 * us.squaredNorm()) / Xs.squaredNorm();
        if (degree >= 2) {
          auto second = [&](int k, int col, double factor) -> Vec3 {
            return factor * c.block(k, col, 1, 3).transpose() / (r * r);
          };
          const Vec3 Xss = second(3, 0, 2), Xsq = second(4, 0, 1), uss = second(3, 3, 2), usq = second(4, 3, 1);
          const Vec3 n_rest = Xs.cross(Xq).normalized();
          const Vec3 n = (Xs + us).cross(Xq + uq).normalized();
          // k = b − b̄, b = n · x_,αβ: the change of the second fundamental form, per unit rest length.
          p.curvature = ((n - n_rest).dot(Xss) + n.dot(uss)) / Xs.squaredNorm();
          p.twist = ((n - n_rest).dot(Xsq) + n.dot(usq)) / (Xs.norm() * Xq.norm());
        }
        break;
      }
    }
  });
  if (o.smoothing) smooth_along_runs(rim, runs);
  for (RimPoint& p : rim) p.energy_density = free_edge_energy_density(mat, p.strain, p.curvature, p.twist);
  if (o.corners) corners = *o.corners;
  auto near = [](const Vec3& x, const std::vector<Vec3>& points, double radius) {
    return std::any_of(points.begin(), points.end(),
                       [&](const Vec3& c) { return (x - c).norm() <= radius || (x - c).squaredNorm() == 0; });
  };
  for (RimPoint& p : rim) {
    p.at_corner = near(p.position, corners, o.corner_radius);
    p.singular = p.at_corner || near(p.position, support_ends, o.support_radius);
  }
  return rim;
}

std::vector<Vec3> singular_corners(const RowMatX3d& V, const RowMatX3i& F, double corner_angle, double window) {
  const VertexFaces vf(int(V.rows()), F);
  // Boundary halfedges: a face's edge a → b whose twin b → a no face has.
  std::vector<std::pair<int, int>> halfedges;
  halfedges.reserve(std::size_t(3 * F.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) halfedges.emplace_back(F(f, k), F(f, (k + 1) % 3));
  std::vector<std::pair<int, int>> sorted = halfedges;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t nv = std::size_t(V.rows());
  std::vector<int> next(nv, -1), outgoing(nv, 0);
  std::vector<char> boundary(nv, 0);
  for (const auto& [a, b] : halfedges)
    if (!std::binary_search(sorted.begin(), sorted.end(), std::make_pair(b, a))) {
      boundary[std::size_t(a)] = boundary[std::size_t(b)] = 1;
      next[std::size_t(a)] = b;
      ++outgoing[std::size_t(a)];
    }
  // The turn into the material at each boundary vertex (degrees; the sum of its face angles − 180°).
  std::vector<double> turn(nv, 0.0);
  for (std::size_t v = 0; v < nv; ++v) {
    if (!boundary[v]) continue;
    double angle = 0;
    for (int f : vf.of(int(v))) angle += angle_at(V, F, f, int(v));
    turn[v] = angle * 180 / std::numbers::pi - 180;
  }
  std::vector<char> corner(nv, 0);
  for (std::size_t v = 0; v < nv; ++v) corner[v] = boundary[v] && turn[v] > corner_angle;
  // The turns within `window` of arc summed along each simple boundary loop (a corner cut as a few
  // small turns close together is one corner; a vertex with two outgoing boundary edges is left
  // to its own turn).
  std::vector<char> walked(nv, 0);
  for (std::size_t start = 0; window > 0 && start < nv; ++start) {
    if (!boundary[start] || walked[start] || outgoing[start] != 1) continue;
    std::vector<int> loop;
    int v = int(start);
    bool simple = true;
    while (!walked[std::size_t(v)]) {
      walked[std::size_t(v)] = 1;
      loop.push_back(v);
      if (outgoing[std::size_t(v)] != 1) {
        simple = false;
        break;
      }
      v = next[std::size_t(v)];
    }
    if (!simple || v != int(start) || loop.size() < 3) continue;
    const std::size_t n = loop.size();
    std::vector<double> arc(n + 1, 0.0);
    for (std::size_t i = 0; i < n; ++i) arc[i + 1] = arc[i] + (V.row(loop[(i + 1) % n]) - V.row(loop[i])).norm();
    const double perimeter = arc[n];
    for (std::size_t i = 0; i < n; ++i) {
      double sum = turn[std::size_t(loop[i])];
      for (std::size_t k = 1; k < n; ++k) {  // ahead
        const std::size_t j = (i + k) % n;
        double d = arc[j] - arc[i];
        if (d < 0) d += perimeter;
        if (d > 0.5 * window) break;
        sum += turn[std::size_t(loop[j])];
      }
      for (std::size_t k = 1; k < n; ++k) {  // behind
        const std::size_t j = (i + n - k) % n;
        double d = arc[i] - arc[j];
        if (d < 0) d += perimeter;
        if (d > 0.5 * window) break;
        sum += turn[std::size_t(loop[j])];
      }
      if (sum > corner_angle) corner[std::size_t(loop[i])] = 1;
    }
  }
  std::vector<Vec3> out;
  for (std::size_t v = 0; v < nv; ++v)
    if (corner[v]) out.push_back(V.row(Eigen::Index(v)).transpose());
  return out;
}

RimPeak rim_peak(const std::vector<RimPoint>& rim) { return rim_peak_near(rim, {}, INFINITY); }

RimPeak rim_peak_near(const std::vector<RimPoint>& rim, const std::vector<Vec3>& centres, double radius) {
  RimPeak out;
  for (std::size_t i = 0; i < rim.size(); ++i) {
    if (rim[i].singular || !(out.index < 0 || rim[i].energy_density > out.energy_density)) continue;
    const bool near = centres.empty() || std::any_of(centres.begin(), centres.end(), [&](const Vec3& c) {
                        return (rim[i].position - c).norm() <= radius;
                      });
    if (!near) continue;
    out.energy_density = rim[i].energy_density;
    out.index = int(i);
  }
  return out;
}

std::vector<Vec3> rim_peak_candidates(const std::vector<RimPoint>& rim, double fraction, double separation, int count) {
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < rim.size(); ++i)
    if (!rim[i].singular) order.push_back(i);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return rim[a].energy_density > rim[b].energy_density; });
  std::vector<Vec3> out;
  for (const std::size_t i : order) {
    if (int(out.size()) >= count || rim[i].energy_density < fraction * rim[order.front()].energy_density) break;
    const bool apart = std::all_of(out.begin(), out.end(),
                                   [&](const Vec3& c) { return (rim[i].position - c).norm() > separation; });
    if (apart) out.push_back(rim[i].position);
  }
  return out;
}

}  // namespace cutwork::solvers
