#include "host/mesh/mesh_mapping.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/mesh/bvh.h"

namespace cutwork {

namespace {

bool same_mesh(const SurfaceMesh& a, const SurfaceMesh& b) {
  if (&a == &b) return true;
  return a.num_vertices() == b.num_vertices() && a.num_faces() == b.num_faces() &&
         a.vertices() == b.vertices() && a.faces() == b.faces();
}

}  // namespace

MeshMapping map_meshes(const SurfaceMesh& base, const SurfaceMesh& sim) {
  MeshMapping map;
  const int nv = base.num_vertices(), nf = base.num_faces();
  map.vertex_on_sim.resize(nv);
  map.face_to_sim_face.resize(nf);

  if (same_mesh(base, sim)) {
    // Identity: every vertex is a corner of (the first face using) it; a closest-point search
    // could land on any of the faces sharing the vertex, which is equally right but noisier.
    for (int f = 0; f < nf; ++f) {
      map.face_to_sim_face[f] = f;
      for (int k = 0; k < 3; ++k) {
        SurfacePoint& p = map.vertex_on_sim[base.faces()(f, k)];
        if (p.face >= 0) continue;
        p.face = f;
        p.bary = Vec3::Zero();
        p.bary[k] = 1;
      }
    }
    // Unreferenced vertices (kept by SurfaceMesh) have no face of their own: locate them like
    // any other point.
    const FaceBvh bvh(sim);
    for (int v = 0; v < nv; ++v) {
      if (map.vertex_on_sim[v].face >= 0) continue;
      const ClosestPoint c = bvh.closest_point(base.vertices().row(v).transpose());
      map.vertex_on_sim[v] = c.where;
      map.max_distance = std::max(map.max_distance, std::sqrt(c.squared_distance));
    }
    return map;
  }

  if (sim.num_faces() == 0)
    throw InputError("mesh mapping: the simulation mesh has no faces to map the base mesh onto");
  const FaceBvh bvh(sim);
  std::vector<double> distance2(nv, 0.0);
  tbb::parallel_for(0, nv, [&](int v) {
    const ClosestPoint c = bvh.closest_point(base.vertices().row(v).transpose());
    map.vertex_on_sim[v] = c.where;
    distance2[v] = c.squared_distance;
  });
  tbb::parallel_for(0, nf, [&](int f) {
    const auto& F = base.faces();
    const auto& V = base.vertices();
    const Vec3 centroid = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).transpose() / 3.0;
    map.face_to_sim_face[f] = bvh.closest_point(centroid).where.face;
  });
  const double max2 = distance2.empty() ? 0.0 : *std::max_element(distance2.begin(), distance2.end());
  map.max_distance = std::sqrt(max2);
  return map;
}

RowMatX3d interpolate_vertex_field(const FaceBvh& from, const RowMatX3d& field, const RowMatX3d& points) {
  const SurfaceMesh* mesh = from.mesh();
  if (mesh == nullptr || mesh->num_faces() == 0 || field.rows() != mesh->num_vertices())
    throw InternalError("interpolate_vertex_field: no mesh, or a field that does not fit its vertices");
  RowMatX3d out(points.rows(), 3);
  tbb::parallel_for(Eigen::Index(0), points.rows(), [&](Eigen::Index i) {
    const SurfacePoint w = from.closest_point(points.row(i).transpose()).where;
    Vec3 value = Vec3::Zero();
    for (int k = 0; k < 3; ++k) value += w.bary[k] * field.row(mesh->faces()(w.face, k)).transpose();
    out.row(i) = value.transpose();
  });
  return out;
}

Eigen::VectorXd sim_to_base_faces(const MeshMapping& map, const Eigen::VectorXd& sim_field) {
  const int nf = int(map.face_to_sim_face.size());
  Eigen::VectorXd base_field(nf);
  for (int f = 0; f < nf; ++f) {
    const int s = map.face_to_sim_face[f];
    if (s < 0 || s >= sim_field.size())
      throw InputError(fmt::format("mesh mapping: base face {} maps to simulation face {}, but the "
                                   "simulation field has {} entries (one per simulation face expected)",
                                   f, s, sim_field.size()));
    base_field[f] = sim_field[s];
  }
  return base_field;
}

std::vector<bool> boundary_vertices_on_boundary_of(const SurfaceMesh& mesh, const SurfaceMesh& reference,
                                                   double tolerance) {
  // Reference boundary edges, each with its bounding box grown by the tolerance (a brute-force
  // scan: boundaries are short, and this runs once per verification).
  struct Segment {
    Vec3 a, b, lo, hi;
  };
  std::vector<Segment> segments;
  for (int e = 0; e < reference.num_edges(); ++e) {
    if (reference.edge_faces()(e, 1) >= 0) continue;
    const Vec3 a = reference.vertices().row(reference.edges()(e, 0));
    const Vec3 b = reference.vertices().row(reference.edges()(e, 1));
    segments.push_back({a, b, a.cwiseMin(b).array() - tolerance, a.cwiseMax(b).array() + tolerance});
  }
  std::vector<bool> out(size_t(mesh.num_vertices()), false);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!mesh.is_boundary_vertex()[v]) continue;
    const Vec3 p = mesh.vertices().row(v);
    for (const Segment& s : segments) {
      if ((p.array() < s.lo.array()).any() || (p.array() > s.hi.array()).any()) continue;
      const Vec3 d = s.b - s.a;
      const double t = std::clamp((p - s.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      if ((p - (s.a + t * d)).norm() <= tolerance) {
        out[size_t(v)] = true;
        break;
      }
    }
  }
  return out;
}

}  // namespace cutwork
