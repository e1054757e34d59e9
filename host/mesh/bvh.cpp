#include "host/mesh/bvh.h"

#include <algorithm>
#include <limits>
#include <numeric>

namespace cutwork {

namespace {

/// Faces per leaf: small enough that leaves are cheap to scan, large enough that the tree has
/// few nodes (≈ F/2 in total).
constexpr int kLeafSize = 4;

/// Closest point on segment [a, b] to p, as the parameter t in [0, 1] (a + t (b − a)).
double closest_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0) return 0;
  return std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
}

ClosestPoint make_result(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double u,
                         double v, double w) {
  ClosestPoint r;
  r.where.bary = Vec3(u, v, w);
  r.point = u * a + v * b + w * c;
  r.squared_distance = (p - r.point).squaredNorm();
  return r;
}

/// Fallback for a degenerate (zero-area) triangle: the closest point lies on one of its edges.
ClosestPoint closest_on_degenerate_triangle(const Vec3& p, const Vec3& a, const Vec3& b,
                                            const Vec3& c) {
  const double tab = closest_on_segment(p, a, b), tbc = closest_on_segment(p, b, c),
               tca = closest_on_segment(p, c, a);
  ClosestPoint best = make_result(p, a, b, c, 1 - tab, tab, 0);
  const ClosestPoint on_bc = make_result(p, a, b, c, 0, 1 - tbc, tbc);
  const ClosestPoint on_ca = make_result(p, a, b, c, tca, 0, 1 - tca);
  if (on_bc.squared_distance < best.squared_distance) best = on_bc;
  if (on_ca.squared_distance < best.squared_distance) best = on_ca;
  return best;
}

}  // namespace

ClosestPoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Ericson, Real-Time Collision Detection §5.1.5: classify p against the Voronoi regions of
  // the vertices, then the edges, else it projects inside the face.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return make_result(p, a, b, c, 1, 0, 0);

  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return make_result(p, a, b, c, 0, 1, 0);

  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) {
    const double v = d1 / (d1 - d3);
    return make_result(p, a, b, c, 1 - v, v, 0);
  }

  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return make_result(p, a, b, c, 0, 0, 1);

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0) {
    const double w = d2 / (d2 - d6);
    return make_result(p, a, b, c, 1 - w, 0, w);
  }

  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0 && (d4 - d3) + (d5 - d6) > 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return make_result(p, a, b, c, 0, 1 - w, w);
  }

  const double sum = va + vb + vc;  // = |ab × ac|², zero only for a degenerate triangle
  if (!(sum > 0)) return closest_on_degenerate_triangle(p, a, b, c);
  const double v = vb / sum, w = vc / sum;
  return make_result(p, a, b, c, 1 - v - w, v, w);
}

FaceBvh::FaceBvh(const SurfaceMesh& mesh) : m_mesh(&mesh) {
  const int nf = mesh.num_faces();
  m_order.resize(nf);
  std::iota(m_order.begin(), m_order.end(), 0);
  m_nodes.clear();
  if (nf == 0) return;
  m_nodes.reserve(std::size_t(2 * (nf / kLeafSize + 1)));
  std::vector<Vec3> centroids(nf);
  const auto& V = mesh.vertices();
  const auto& F = mesh.faces();
  for (int f = 0; f < nf; ++f)
    centroids[f] = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).transpose() / 3.0;
  build_node(0, nf, centroids, 0);
}

int FaceBvh::build_node(int first, int count, std::vector<Vec3>& centroids, int depth) {
  const auto& V = m_mesh->vertices();
  const auto& F = m_mesh->faces();
  const int index = int(m_nodes.size());
  m_nodes.emplace_back();
  Eigen::AlignedBox3d box, centroid_box;
  for (int i = first; i < first + count; ++i) {
    const int f = m_order[i];
    for (int k = 0; k < 3; ++k) box.extend(V.row(F(f, k)).transpose());
    centroid_box.extend(centroids[f]);
  }
  m_nodes[index].box = box;
  if (count <= kLeafSize) {
    m_nodes[index].first = first;
    m_nodes[index].count = count;
    return index;
  }
  // Median split along the widest extent of the centroids: balanced depth ⌈log2(F/4)⌉
  // whatever the triangle distribution.
  int axis = 0;
  centroid_box.sizes().maxCoeff(&axis);
  const int half = count / 2;
  std::nth_element(m_order.begin() + first, m_order.begin() + first + half,
                   m_order.begin() + first + count, [&](int a, int b) {
                     const double ca = centroids[a][axis], cb = centroids[b][axis];
                     return ca < cb || (ca == cb && a < b);
                   });
  const int left = build_node(first, half, centroids, depth + 1);
  const int right = build_node(first + half, count - half, centroids, depth + 1);
  m_nodes[index].left = left;
  m_nodes[index].right = right;
  return index;
}

ClosestPoint FaceBvh::closest_point(const Vec3& p) const {
  ClosestPoint best;
  best.squared_distance = std::numeric_limits<double>::infinity();
  if (m_nodes.empty()) return best;
  const auto& V = m_mesh->vertices();
  const auto& F = m_mesh->faces();
  // Depth-first, nearer child first; a node is skipped only when its box is strictly farther
  // than the best so far, so an equally close face with a lower index is still visited.
  int stack[128];
  double stack_dist[128];
  int top = 0;
  stack[top] = 0;
  stack_dist[top++] = m_nodes[0].box.squaredExteriorDistance(p);
  while (top > 0) {
    --top;
    if (stack_dist[top] > best.squared_distance) continue;
    const Node& node = m_nodes[stack[top]];
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const int f = m_order[i];
        ClosestPoint c = closest_point_on_triangle(p, V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)));
        if (c.squared_distance < best.squared_distance ||
            (c.squared_distance == best.squared_distance && f < best.where.face)) {
          best = c;
          best.where.face = f;
        }
      }
      continue;
    }
    const double dl = m_nodes[node.left].box.squaredExteriorDistance(p);
    const double dr = m_nodes[node.right].box.squaredExteriorDistance(p);
    // Push the farther child first so the nearer one is popped next.
    if (dl <= dr) {
      stack[top] = node.right, stack_dist[top++] = dr;
      stack[top] = node.left, stack_dist[top++] = dl;
    } else {
      stack[top] = node.left, stack_dist[top++] = dl;
      stack[top] = node.right, stack_dist[top++] = dr;
    }
  }
  return best;
}

void FaceBvh::faces_in_ball(const Vec3& center, double radius, std::vector<int>& out) const {
  out.clear();
  if (m_nodes.empty() || !(radius >= 0)) return;
  const auto& V = m_mesh->vertices();
  const auto& F = m_mesh->faces();
  const double r2 = radius * radius;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = m_nodes[stack[--top]];
    if (node.box.squaredExteriorDistance(center) > r2) continue;
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const int f = m_order[i];
        if (closest_point_on_triangle(center, V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)))
                .squared_distance <= r2)
          out.push_back(f);
      }
      continue;
    }
    stack[top++] = node.left;
    stack[top++] = node.right;
  }
  std::sort(out.begin(), out.end());
}

ClosestPoint closest_point_brute_force(const SurfaceMesh& mesh, const Vec3& p) {
  ClosestPoint best;
  best.squared_distance = std::numeric_limits<double>::infinity();
  const auto& V = mesh.vertices();
  const auto& F = mesh.faces();
  for (int f = 0; f < mesh.num_faces(); ++f) {
    ClosestPoint c = closest_point_on_triangle(p, V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)));
    if (c.squared_distance < best.squared_distance) {
      best = c;
      best.where.face = f;
    }
  }
  return best;
}

void faces_in_ball_brute_force(const SurfaceMesh& mesh, const Vec3& center, double radius,
                               std::vector<int>& out) {
  out.clear();
  if (!(radius >= 0)) return;
  const auto& V = mesh.vertices();
  const auto& F = mesh.faces();
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (closest_point_on_triangle(center, V.row(F(f, 0)), V.row(F(f, 1)), V.row(F(f, 2)))
            .squared_distance <= radius * radius)
      out.push_back(f);
}

}  // namespace cutwork
