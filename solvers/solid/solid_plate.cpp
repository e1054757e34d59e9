#include "solvers/solid/solid_plate.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <unordered_map>
#include <utility>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_criteria_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <Eigen/Dense>
#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "host/core/error.h"
#include "host/core/timer.h"
#include "host/stencil/stencil_shape.h"
#include "solvers/linear/cholmod_solver.h"

namespace cutwork::solvers {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Tds = CGAL::Triangulation_data_structure_2<CGAL::Delaunay_mesh_vertex_base_2<Kernel>,
                                                 CGAL::Delaunay_mesh_face_base_2<Kernel>>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds>;

// ---------------------------------------------------------------------------------------------
// Geometry helpers

/// Drops a closing point equal to the first and points that repeat their predecessor.
std::vector<Vec2> clean_loop(const std::vector<Vec2>& loop, double tolerance) {
  std::vector<Vec2> out;
  for (const Vec2& p : loop)
    if (out.empty() || (p - out.back()).norm() > tolerance) out.push_back(p);
  while (out.size() > 1 && (out.front() - out.back()).norm() <= tolerance) out.pop_back();
  return out;
}

/// The in-plane edge length asked at a point: rim_edge + growth · (distance to the focus), at most
/// max_edge. The focus is a set of segments (the holes' rims) and of points (the caller's).
class SizeField {
 public:
  SizeField(const SolidPlateMeshOptions& options, std::vector<std::pair<Vec2, Vec2>> segments)
      : m_rim(options.rim_edge), m_max(options.max_edge), m_growth(options.growth),
        m_points(options.focus), m_segments(std::move(segments)) {}

  double operator()(const Vec2& p) const {
    double d = std::numeric_limits<double>::infinity();
    for (const Vec2& q : m_points) d = std::min(d, (p - q).norm());
    for (const auto& [a, b] : m_segments) d = std::min(d, segment_distance(a, b, p));
    return std::min(m_max, m_rim + m_growth * d);
  }

 private:
  double m_rim, m_max, m_growth;
  std::vector<Vec2> m_points;
  std::vector<std::pair<Vec2, Vec2>> m_segments;
};

/// The hole's closed polyline written with edges of the size field: its corners (vertices turning by
/// more than `corner_turn`) kept, the pieces between them split evenly in ∫ ds / h(s) (the number of
/// edges h asks for, rounded), so that an edge is about h where it lies.
std::vector<Vec2> resample_loop(const std::vector<Vec2>& loop, const SizeField& h, double corner_turn) {
  const int n = static_cast<int>(loop.size());
  std::vector<int> corners;
  for (int i = 0; i < n; ++i) {
    const Vec2 a = loop[i] - loop[(i + n - 1) % n];
    const Vec2 b = loop[(i + 1) % n] - loop[i];
    const double turn = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
    if (std::abs(turn) > corner_turn) corners.push_back(i);
  }
  const bool smooth = corners.empty();
  if (smooth) corners.push_back(0);
  std::vector<Vec2> out;
  for (std::size_t c = 0; c < corners.size(); ++c) {
    const int begin = corners[c];
    const int end = smooth ? begin + n : (c + 1 < corners.size() ? corners[c + 1] : corners[0] + n);
    // The piece's points, each polyline segment cut into steps no longer than a quarter of the
    // smallest h so that ∫ ds/h is integrated closely (the midpoint rule per step).
    std::vector<Vec2> pts;
    std::vector<double> phi{0.0};
    pts.push_back(loop[begin % n]);
    for (int i = begin; i < end; ++i) {
      const Vec2 a = loop[i % n], b = loop[(i + 1) % n];
      const double len = (b - a).norm();
      const int steps = std::max(1, static_cast<int>(std::ceil(len / (0.25 * h(a)))));
      for (int s = 1; s <= steps; ++s) {
        const Vec2 p = a + (b - a) * (static_cast<double>(s) / steps);
        const Vec2 mid = a + (b - a) * ((s - 0.5) / steps);
        phi.push_back(phi.back() + len / steps / h(mid));
        pts.push_back(p);
      }
    }
    const int pieces = std::max(smooth ? 8 : 1, static_cast<int>(std::lround(phi.back())));
    out.push_back(pts.front());
    std::size_t k = 1;
    for (int j = 1; j < pieces; ++j) {
      const double target = phi.back() * j / pieces;
      while (phi[k] < target) ++k;
      const double w = (target - phi[k - 1]) / (phi[k] - phi[k - 1]);
      out.push_back(pts[k - 1] + w * (pts[k] - pts[k - 1]));
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// CGAL's Delaunay refinement with a graded size: a triangle is too big when its longest edge exceeds
// the size field at its centroid (the size criterion of Delaunay_mesh_size_criteria_2 with a
// varying bound), too flat when the squared sine of its smallest angle is below B (0.125: 20.7°).

class GradedCriteria : public CGAL::Delaunay_mesh_criteria_2<Cdt> {
 public:
  using Base = CGAL::Delaunay_mesh_criteria_2<Cdt>;
  using Quality = CGAL::Delaunay_mesh_size_criteria_2<Cdt>::Quality;

  explicit GradedCriteria(const SizeField* size) : Base(0.125), m_size(size) {}

  class Is_bad : public Base::Is_bad {
   public:
    Is_bad(double bound, const Kernel& traits, const SizeField* size) : Base::Is_bad(bound, traits), m_size(size) {}

    CGAL::Mesh_2::Face_badness operator()(const Quality q) const {
      if (q.size() > 1) return CGAL::Mesh_2::IMPERATIVELY_BAD;
      return q.sine() < this->B ? CGAL::Mesh_2::BAD : CGAL::Mesh_2::NOT_BAD;
    }

    CGAL::Mesh_2::Face_badness operator()(const Cdt::Face_handle& fh, Quality& q) const {
      const auto& pa = fh->vertex(0)->point();
      const auto& pb = fh->vertex(1)->point();
      const auto& pc = fh->vertex(2)->point();
      const Vec2 a(pa.x(), pa.y()), b(pb.x(), pb.y()), c(pc.x(), pc.y());
      std::array<double, 3> sq{(b - c).squaredNorm(), (c - a).squaredNorm(), (a - b).squaredNorm()};
      std::sort(sq.begin(), sq.end());
      const double h = (*m_size)((a + b + c) / 3.0);
      q.second = sq[2] / (h * h);
      if (q.size() > 1) {
        q.first = 1;
        return CGAL::Mesh_2::IMPERATIVELY_BAD;
      }
      const double area2 = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
      q.first = area2 * area2 / (sq[2] * sq[1]);
      return q.sine() < this->B ? CGAL::Mesh_2::BAD : CGAL::Mesh_2::NOT_BAD;
    }

   private:
    const SizeField* m_size;
  };

  Is_bad is_bad_object() const { return Is_bad(this->bound(), this->traits, m_size); }

 private:
  const SizeField* m_size;
};

struct PlaneMesh {
  std::vector<Vec2> vertices;
  std::vector<std::array<int, 3>> triangles;  ///< counter-clockwise
  std::vector<char> on_outer;                 ///< per vertex
  std::vector<std::pair<int, int>> outer_edges, rim_edges;
};

/// Meshes the plate's outline with the (resampled) holes, graded by the size field.
PlaneMesh mesh_plane(const std::vector<Vec2>& outer, const std::vector<std::vector<Vec2>>& holes,
                     const SizeField& size, double tolerance) {
  Cdt cdt;
  auto insert_loop = [&](const std::vector<Vec2>& loop) {
    std::vector<Cdt::Vertex_handle> vh;
    for (const Vec2& p : loop) vh.push_back(cdt.insert(Cdt::Point(p.x(), p.y())));
    for (std::size_t i = 0; i < vh.size(); ++i) cdt.insert_constraint(vh[i], vh[(i + 1) % vh.size()]);
  };
  insert_loop(outer);
  for (const auto& hole : holes) insert_loop(hole);

  // The domain: faces nested once inside the constraints (inside the outline, outside the holes),
  // found by a flood fill that counts the constrained edges crossed from the infinite face.
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->set_in_domain(false);
  std::unordered_map<const void*, int> depth;  // by the face's address
  std::vector<Cdt::Face_handle> frontier{cdt.infinite_face()}, next;
  depth[&*cdt.infinite_face()] = 0;
  for (int level = 0; !frontier.empty(); ++level) {
    // Faces reached without crossing a constraint are at this level; across one, the next level.
    while (!frontier.empty()) {
      const Cdt::Face_handle f = frontier.back();
      frontier.pop_back();
      for (int i = 0; i < 3; ++i) {
        const Cdt::Face_handle g = f->neighbor(i);
        if (depth.count(&*g)) continue;
        if (cdt.is_constrained(Cdt::Edge(f, i))) {
          next.push_back(g);
        } else {
          depth[&*g] = level;
          frontier.push_back(g);
        }
      }
    }
    for (const auto& g : next)
      if (!depth.count(&*g)) {
        depth[&*g] = level + 1;
        frontier.push_back(g);
      }
    next.clear();
  }
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) f->set_in_domain(depth[&*f] == 1);

  GradedCriteria criteria(&size);
  CGAL::refine_Delaunay_mesh_2(cdt, criteria, true);

  PlaneMesh mesh;
  std::unordered_map<const void*, int> index;  // by the vertex's address
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    std::array<int, 3> tri{};
    for (int i = 0; i < 3; ++i) {
      auto [it, added] = index.emplace(&*f->vertex(i), static_cast<int>(mesh.vertices.size()));
      if (added) mesh.vertices.emplace_back(f->vertex(i)->point().x(), f->vertex(i)->point().y());
      tri[i] = it->second;
    }
    mesh.triangles.push_back(tri);
  }
  // Boundary edges (one domain triangle): on the outline, or a hole's rim.
  std::unordered_map<std::uint64_t, int> edge_count;
  auto key = [](int a, int b) {
    return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
  };
  for (const auto& t : mesh.triangles)
    for (int i = 0; i < 3; ++i) ++edge_count[key(t[i], t[(i + 1) % 3])];
  auto on_outline = [&](const Vec2& p) {
    for (std::size_t i = 0; i < outer.size(); ++i)
      if (segment_distance(outer[i], outer[(i + 1) % outer.size()], p) <= tolerance) return true;
    return false;
  };
  mesh.on_outer.assign(mesh.vertices.size(), 0);
  for (const auto& t : mesh.triangles)
    for (int i = 0; i < 3; ++i) {
      const int a = t[i], b = t[(i + 1) % 3];
      if (edge_count[key(a, b)] != 1) continue;
      if (on_outline(0.5 * (mesh.vertices[a] + mesh.vertices[b]))) {
        mesh.outer_edges.emplace_back(a, b);
        mesh.on_outer[a] = mesh.on_outer[b] = 1;
      } else {
        mesh.rim_edges.emplace_back(a, b);
      }
    }
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// The 10-node tetrahedron: corners 0–3, then the mid-edge nodes of kTetEdges in order.

constexpr std::array<std::array<int, 2>, 6> kTetEdges{{{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}}};

/// Gradients of the barycentric coordinates (rows) and the volume of a straight tetrahedron.
double barycentric_gradients(const std::array<Vec3, 4>& x, Eigen::Matrix<double, 4, 3>& grad) {
  Eigen::Matrix3d jac;
  jac.col(0) = x[1] - x[0];
  jac.col(1) = x[2] - x[0];
  jac.col(2) = x[3] - x[0];
  const double det = jac.determinant();
  const Eigen::Matrix3d inv = jac.inverse();
  grad.row(1) = inv.row(0);
  grad.row(2) = inv.row(1);
  grad.row(3) = inv.row(2);
  grad.row(0) = -(grad.row(1) + grad.row(2) + grad.row(3));
  return det / 6.0;
}

/// The ten shape functions' gradients (rows) at barycentrics `l`.
Eigen::Matrix<double, 10, 3> shape_gradients(const Eigen::Matrix<double, 4, 3>& grad, const Eigen::Vector4d& l) {
  Eigen::Matrix<double, 10, 3> g;
  for (int i = 0; i < 4; ++i) g.row(i) = (4.0 * l[i] - 1.0) * grad.row(i);
  for (int e = 0; e < 6; ++e) {
    const int i = kTetEdges[e][0], j = kTetEdges[e][1];
    g.row(4 + e) = 4.0 * (l[i] * grad.row(j) + l[j] * grad.row(i));
  }
  return g;
}

/// The element stiffness (30×30, unknowns node-major): Σ_q w_q (λ g_a ⊗ g_b + μ g_b ⊗ g_a +
/// μ (g_a·g_b) I) over the 4-point rule, exact for a straight quadratic tetrahedron.
Eigen::Matrix<double, 30, 30> element_stiffness(const Eigen::Matrix<double, 4, 3>& grad, double volume, double lambda,
                                                double mu) {
  constexpr double kA = 0.5854101966249685, kB = 0.1381966011250105;
  Eigen::Matrix<double, 30, 30> k = Eigen::Matrix<double, 30, 30>::Zero();
  for (int q = 0; q < 4; ++q) {
    Eigen::Vector4d l = Eigen::Vector4d::Constant(kB);
    l[q] = kA;
    const Eigen::Matrix<double, 10, 3> g = shape_gradients(grad, l);
    const double w = volume / 4.0;
    const Eigen::Matrix<double, 10, 10> dots = g * g.transpose();
    for (int a = 0; a < 10; ++a)
      for (int b = 0; b < 10; ++b) {
        const Eigen::Matrix3d block = lambda * g.row(a).transpose() * g.row(b) +
                                      mu * g.row(b).transpose() * g.row(a) +
                                      mu * dots(a, b) * Eigen::Matrix3d::Identity();
        k.block<3, 3>(3 * a, 3 * b) += w * block;
      }
  }
  return k;
}

/// Stress from the displacement gradient H (H_ij = ∂u_i/∂x_j).
Eigen::Matrix3d hooke(const Eigen::Matrix3d& h, double lambda, double mu) {
  const Eigen::Matrix3d eps = 0.5 * (h + h.transpose());
  return lambda * eps.trace() * Eigen::Matrix3d::Identity() + 2.0 * mu * eps;
}

/// The far field's stress per unit z (bending) or its constant stress (membrane), in plane.
Eigen::Matrix2d load_stress(const SolidPlateInput& input) {
  const PlateLoad& l = input.load;
  Eigen::Matrix2d s;
  s << l.xx, l.xy, l.xy, l.yy;
  if (l.kind == PlateLoadKind::Bending) s *= 12.0 / std::pow(input.thickness, 3);
  return s;
}

void validate(const SolidPlateInput& in) {
  auto fail = [](const std::string& what) { throw InputError("solid plate: " + what); };
  if (!(in.thickness > 0) || !std::isfinite(in.thickness)) fail("thickness must be positive");
  if (!(in.young > 0) || !std::isfinite(in.young)) fail("Young's modulus must be positive");
  if (!(in.poisson > -1 && in.poisson < 0.5)) fail("Poisson's ratio must lie in (-1, 0.5)");
  const auto& m = in.mesh;
  if (!(m.rim_edge > 0) || !(m.max_edge >= m.rim_edge) || !std::isfinite(m.max_edge))
    fail("mesh sizes: need 0 < rim_edge <= max_edge");
  if (!(m.growth > 0) || !std::isfinite(m.growth)) fail("mesh growth must be positive");
  if (m.layers < 1 || m.layers > 64) fail("layers must lie in [1, 64]");
  if (!(m.layer_ratio > 0 && m.layer_ratio <= 1)) fail("layer_ratio must lie in (0, 1]");
  if (in.outer.size() < 3) fail("the outline needs at least 3 points");
  if (!(polygon_signed_area(in.outer) > 0)) fail("the outline must be counter-clockwise");
  for (std::size_t h = 0; h < in.holes.size(); ++h) {
    if (in.holes[h].size() < 3) fail(fmt::format("hole {} needs at least 3 points", h));
    for (const Vec2& p : in.holes[h])
      if (!p.allFinite() || !point_in_polygon(in.outer, p)) fail(fmt::format("hole {} is not inside the outline", h));
  }
}

std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
}

}  // namespace

std::vector<Vec2> circle_polyline(const Vec2& centre, double radius, int segments) {
  std::vector<Vec2> out(segments);
  for (int i = 0; i < segments; ++i) {
    const double a = 2.0 * std::numbers::pi * i / segments;
    out[i] = centre + radius * Vec2(std::cos(a), std::sin(a));
  }
  return out;
}

Vec3 plate_exact_displacement(const SolidPlateInput& input, const Vec3& p) {
  const double e = input.young, nu = input.poisson;
  const Eigen::Matrix2d s = load_stress(input);
  // Plane-stress compliance of s; k3 the through-thickness strain.
  const double kxx = (s(0, 0) - nu * s(1, 1)) / e, kyy = (s(1, 1) - nu * s(0, 0)) / e;
  const double kxy = (1 + nu) * s(0, 1) / e, k3 = -nu * (s(0, 0) + s(1, 1)) / e;
  const double x = p.x(), y = p.y(), z = p.z();
  if (input.load.kind == PlateLoadKind::Membrane) return {kxx * x + kxy * y, kxy * x + kyy * y, k3 * z};
  return {z * (kxx * x + kxy * y), z * (kxy * x + kyy * y),
          -0.5 * (kxx * x * x + 2 * kxy * x * y + kyy * y * y) + 0.5 * k3 * z * z};
}

Eigen::Matrix3d plate_exact_stress(const SolidPlateInput& input, double z) {
  const Eigen::Matrix2d s = load_stress(input) * (input.load.kind == PlateLoadKind::Bending ? z : 1.0);
  Eigen::Matrix3d out = Eigen::Matrix3d::Zero();
  out.topLeftCorner<2, 2>() = s;
  return out;
}

SolidPlateResult solve_solid_plate(const SolidPlateInput& input) {
  validate(input);
  SolidPlateResult result;
  Stopwatch watch;
  const auto& opt = input.mesh;
  const double t = input.thickness, half = 0.5 * t;

  // ---- In-plane mesh.
  double size = 0;
  for (const Vec2& p : input.outer) size = std::max(size, (p - input.outer[0]).norm());
  const double tolerance = 1e-9 * size;
  std::vector<std::vector<Vec2>> holes;
  std::vector<std::pair<Vec2, Vec2>> rim_segments;
  for (const auto& hole : input.holes) {
    holes.push_back(clean_loop(hole, tolerance));
    if (holes.back().size() < 3) throw InputError("solid plate: a hole has fewer than 3 distinct points");
    if (polygon_signed_area(holes.back()) < 0) std::reverse(holes.back().begin(), holes.back().end());
    if (opt.focus.empty())
      for (std::size_t i = 0; i < holes.back().size(); ++i)
        rim_segments.emplace_back(holes.back()[i], holes.back()[(i + 1) % holes.back().size()]);
  }
  const SizeField size_field(opt, std::move(rim_segments));
  for (auto& hole : holes) hole = resample_loop(hole, size_field, opt.corner_turn);
  const PlaneMesh plane = mesh_plane(clean_loop(input.outer, tolerance), holes, size_field, tolerance);
  const int nv = static_cast<int>(plane.vertices.size());
  result.vertices_2d = nv;
  result.triangles_2d = static_cast<int>(plane.triangles.size());

  // ---- Layers: z_0 = 0 < … < z_n = t/2, each layer layer_ratio times the one below.
  const int nl = opt.layers;
  std::vector<double> z(nl + 1, 0.0);
  {
    std::vector<double> dz(nl);
    double sum = 0;
    for (int k = 0; k < nl; ++k) sum += (dz[k] = std::pow(opt.layer_ratio, k));
    for (int k = 0; k < nl; ++k) z[k + 1] = z[k] + half * dz[k] / sum;
    z[nl] = half;
  }

  // ---- Tetrahedra. Corner node (layer k, vertex v) = k·nv + v; mid-edge nodes after them. Each
  // node remembers the in-plane edge (or vertex, a == b) it lies over, to find the outer face.
  std::vector<Vec3> nodes;
  std::vector<std::pair<int, int>> over;
  for (int k = 0; k <= nl; ++k)
    for (int v = 0; v < nv; ++v) {
      nodes.emplace_back(plane.vertices[v].x(), plane.vertices[v].y(), z[k]);
      over.emplace_back(v, v);
    }
  std::unordered_map<std::uint64_t, int> mid_node;
  auto mid = [&](int a, int b) {
    auto [it, added] = mid_node.emplace(edge_key(a, b), static_cast<int>(nodes.size()));
    if (added) {
      nodes.push_back(0.5 * (nodes[a] + nodes[b]));
      over.emplace_back(std::min(a % nv, b % nv), std::max(a % nv, b % nv));
    }
    return it->second;
  };
  std::vector<std::array<int, 10>> tets;
  tets.reserve(3 * nl * plane.triangles.size());
  for (const auto& tri : plane.triangles) {
    // The prism's vertices by global index, a < b < c: every side's diagonal from its smallest
    // vertex, on the lower layer (k·nv + v grows with both), to the other's upper copy.
    std::array<int, 3> s = tri;
    std::sort(s.begin(), s.end());
    for (int k = 0; k < nl; ++k) {
      const int a0 = k * nv + s[0], b0 = k * nv + s[1], c0 = k * nv + s[2];
      const int a1 = a0 + nv, b1 = b0 + nv, c1 = c0 + nv;
      const std::array<std::array<int, 4>, 3> split{{{a0, b0, c0, c1}, {a0, b0, b1, c1}, {a0, a1, b1, c1}}};
      for (auto corners : split) {
        const Vec3 &p0 = nodes[corners[0]], &p1 = nodes[corners[1]], &p2 = nodes[corners[2]], &p3 = nodes[corners[3]];
        if ((p1 - p0).cross(p2 - p0).dot(p3 - p0) < 0) std::swap(corners[1], corners[2]);
        std::array<int, 10> tet{};
        for (int i = 0; i < 4; ++i) tet[i] = corners[i];
        for (int e = 0; e < 6; ++e) tet[4 + e] = mid(corners[kTetEdges[e][0]], corners[kTetEdges[e][1]]);
        tets.push_back(tet);
      }
    }
  }
  const int n_nodes = static_cast<int>(nodes.size());
  result.tetrahedra = static_cast<int>(tets.size());
  result.nodes = n_nodes;
  result.dofs = 3 * n_nodes;
  result.mesh_seconds = watch.seconds();
  watch.restart();

  // ---- Dirichlet data: the outer lateral face takes the exact field (all components); the
  // mid-plane the kind's symmetry.
  std::unordered_map<std::uint64_t, char> outer_edge;
  for (const auto& [a, b] : plane.outer_edges) outer_edge[edge_key(a, b)] = 1;
  std::vector<char> fixed(3 * n_nodes, 0);
  std::vector<double> value(3 * n_nodes, 0.0);
  const bool bending = input.load.kind == PlateLoadKind::Bending;
  for (int n = 0; n < n_nodes; ++n) {
    const auto [a, b] = over[n];
    const bool lateral = a == b ? plane.on_outer[a] != 0 : outer_edge.count(edge_key(a, b)) > 0;
    if (lateral) {
      const Vec3 u = plate_exact_displacement(input, nodes[n]);
      for (int c = 0; c < 3; ++c) {
        fixed[3 * n + c] = 1;
        value[3 * n + c] = u[c];
      }
    } else if (nodes[n].z() == 0.0) {
      if (bending) {
        fixed[3 * n] = fixed[3 * n + 1] = 1;
      } else {
        fixed[3 * n + 2] = 1;
      }
    }
  }
  std::vector<int> free_index(3 * n_nodes, -1);
  int n_free = 0;
  for (int d = 0; d < 3 * n_nodes; ++d)
    if (!fixed[d]) free_index[d] = n_free++;
  result.free_dofs = n_free;

  // ---- The upper triangle's pattern over the free unknowns (node-major, so rows come sorted).
  std::vector<std::vector<int>> lower_nodes(n_nodes);  // per node q: adjacent nodes p ≤ q
  for (const auto& tet : tets)
    for (int i = 0; i < 10; ++i)
      for (int j = 0; j < 10; ++j)
        if (tet[i] <= tet[j]) lower_nodes[tet[j]].push_back(tet[i]);
  std::vector<int> column_starts{0}, rows;
  for (int q = 0; q < n_nodes; ++q) {
    auto& adj = lower_nodes[q];
    std::sort(adj.begin(), adj.end());
    adj.erase(std::unique(adj.begin(), adj.end()), adj.end());
    for (int c = 0; c < 3; ++c) {
      if (free_index[3 * q + c] < 0) continue;
      for (int p : adj)
        for (int d = 0; d < 3; ++d)
          if (free_index[3 * p + d] >= 0 && (p < q || d <= c)) rows.push_back(free_index[3 * p + d]);
      column_starts.push_back(static_cast<int>(rows.size()));
    }
    std::vector<int>().swap(adj);
  }

  // ---- Assembly, parallel over tetrahedra (atomic adds: two elements may share an entry).
  const double e_mod = input.young, nu = input.poisson;
  const double lambda = e_mod * nu / ((1 + nu) * (1 - 2 * nu)), mu = e_mod / (2 * (1 + nu));
  std::vector<double> values(rows.size(), 0.0), rhs(n_free, 0.0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tets.size(), 256), [&](const auto& range) {
    for (std::size_t e = range.begin(); e != range.end(); ++e) {
      const auto& tet = tets[e];
      Eigen::Matrix<double, 4, 3> grad;
      const double volume = barycentric_gradients({nodes[tet[0]], nodes[tet[1]], nodes[tet[2]], nodes[tet[3]]}, grad);
      const Eigen::Matrix<double, 30, 30> k = element_stiffness(grad, volume, lambda, mu);
      for (int a = 0; a < 30; ++a) {
        const int ga = 3 * tet[a / 3] + a % 3, fa = free_index[ga];
        if (fa < 0) continue;
        double load = 0;
        for (int b = 0; b < 30; ++b) {
          const int gb = 3 * tet[b / 3] + b % 3, fb = free_index[gb];
          if (fb < 0) {
            load -= k(a, b) * value[gb];
          } else if (fa <= fb) {
            const auto first = rows.begin() + column_starts[fb], last = rows.begin() + column_starts[fb + 1];
            const auto pos = std::lower_bound(first, last, fa) - rows.begin();
            std::atomic_ref<double>(values[pos]).fetch_add(k(a, b), std::memory_order_relaxed);
          }
        }
        if (load != 0) std::atomic_ref<double>(rhs[fa]).fetch_add(load, std::memory_order_relaxed);
      }
    }
  });
  result.assembly_seconds = watch.seconds();
  watch.restart();

  // ---- Solve.
  CholmodSolver solver;
  solver.analyze(n_free, column_starts, rows);
  std::vector<int>().swap(rows);
  if (!solver.factorize(values.data())) throw SolveError("solid plate: the stiffness is not positive definite");
  std::vector<double>().swap(values);
  std::vector<double> x(n_free);
  solver.solve(rhs.data(), x.data());
  result.factor_nonzeros = solver.factor_nonzeros();
  result.solve_seconds = watch.seconds();

  std::vector<Vec3> u(n_nodes);
  for (int n = 0; n < n_nodes; ++n)
    for (int c = 0; c < 3; ++c) {
      const int d = 3 * n + c;
      u[n][c] = fixed[d] ? value[d] : x[free_index[d]];
    }

  // ---- Rim loops in order (each rim vertex has two rim neighbours), oriented counter-clockwise.
  std::vector<std::array<int, 2>> rim_next(nv, {-1, -1});
  for (const auto& [a, b] : plane.rim_edges) {
    (rim_next[a][0] < 0 ? rim_next[a][0] : rim_next[a][1]) = b;
    (rim_next[b][0] < 0 ? rim_next[b][0] : rim_next[b][1]) = a;
  }
  std::vector<char> seen(nv, 0);
  std::vector<std::vector<int>> loops(input.holes.size());
  for (int v = 0; v < nv; ++v) {
    if (seen[v] || rim_next[v][0] < 0) continue;
    std::vector<int> loop;
    for (int prev = -1, cur = v; !seen[cur];) {
      seen[cur] = 1;
      loop.push_back(cur);
      const int nxt = rim_next[cur][0] != prev ? rim_next[cur][0] : rim_next[cur][1];
      prev = cur;
      cur = nxt;
      if (cur < 0) throw SolveError("solid plate: a hole's rim is not a closed loop in the mesh");
    }
    std::vector<Vec2> pts;
    for (int w : loop) pts.push_back(plane.vertices[w]);
    if (polygon_signed_area(pts) < 0) std::reverse(loop.begin(), loop.end());
    // Its hole: the input hole nearest to its first vertex.
    int best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t h = 0; h < holes.size(); ++h)
      for (std::size_t i = 0; i < holes[h].size(); ++i) {
        const double d = segment_distance(holes[h][i], holes[h][(i + 1) % holes[h].size()], pts[0]);
        if (d < best_d) best_d = d, best = static_cast<int>(h);
      }
    loops[best] = std::move(loop);
  }

  // ---- Stress at the rim nodes of every layer: the mean over the tetrahedra at the node of each
  // one's stress there (a corner i of a tetrahedron: L = e_i in shape_gradients).
  std::vector<int> rim_slot(n_nodes, -1);
  std::vector<Eigen::Matrix3d> rim_sum;
  std::vector<int> rim_count;
  for (const auto& loop : loops)
    for (int v : loop)
      for (int k = 0; k <= nl; ++k) {
        rim_slot[k * nv + v] = static_cast<int>(rim_sum.size());
        rim_sum.push_back(Eigen::Matrix3d::Zero());
        rim_count.push_back(0);
      }
  for (const auto& tet : tets)
    for (int i = 0; i < 4; ++i) {
      const int slot = rim_slot[tet[i]];
      if (slot < 0) continue;
      Eigen::Matrix<double, 4, 3> grad;
      barycentric_gradients({nodes[tet[0]], nodes[tet[1]], nodes[tet[2]], nodes[tet[3]]}, grad);
      const Eigen::Matrix<double, 10, 3> g = shape_gradients(grad, Eigen::Vector4d::Unit(i));
      Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
      for (int a = 0; a < 10; ++a) h += u[tet[a]] * g.row(a);
      rim_sum[slot] += hooke(h, lambda, mu);
      ++rim_count[slot];
    }

  result.rims.resize(loops.size());
  result.peak_sigma_tt = -std::numeric_limits<double>::infinity();
  result.peak_sigma_tt_any_z = -std::numeric_limits<double>::infinity();
  for (std::size_t h = 0; h < loops.size(); ++h) {
    const auto& loop = loops[h];
    const int m = static_cast<int>(loop.size());
    for (int i = 0; i < m; ++i) {
      const int v = loop[i];
      const Vec2 tangent = (plane.vertices[loop[(i + 1) % m]] - plane.vertices[loop[(i + m - 1) % m]]).normalized();
      const Vec3 t3(tangent.x(), tangent.y(), 0.0);
      for (int k = 0; k <= nl; ++k) {
        const int slot = rim_slot[k * nv + v];
        const Eigen::Matrix3d sigma = rim_sum[slot] / std::max(1, rim_count[slot]);
        const double stt = t3.dot(sigma * t3);
        if (stt > result.peak_sigma_tt_any_z) {
          result.peak_sigma_tt_any_z = stt;
          result.peak_z = z[k];
        }
        if (k != nl) continue;
        result.rims[h].push_back({plane.vertices[v], tangent, sigma, stt});
        if (stt > result.peak_sigma_tt) {
          result.peak_sigma_tt = stt;
          result.peak_hole = static_cast<int>(h);
          result.peak_position = plane.vertices[v];
        }
      }
    }
  }

  const Eigen::Matrix2d face = plate_exact_stress(input, half).topLeftCorner<2, 2>();
  result.nominal = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(face).eigenvalues().maxCoeff();
  result.k = result.nominal != 0 && !loops.empty() ? result.peak_sigma_tt / result.nominal : 0.0;
  result.node_positions = std::move(nodes);
  result.displacements = std::move(u);
  return result;
}

}  // namespace cutwork::solvers
