#include "host/field/orientation_field.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <complex>
#include <numeric>

#include <Eigen/SparseCore>
#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "solvers/linear/cholmod_solver.h"

namespace cutwork {

namespace {

using Complex = std::complex<double>;

int find_root(std::vector<int>& parent, int i) {
  while (parent[size_t(i)] != i) {
    parent[size_t(i)] = parent[size_t(parent[size_t(i)])];
    i = parent[size_t(i)];
  }
  return i;
}

/// Angle of vector v in the basis (e1, e2).
double angle_in(const Vec3& v, const Vec3& e1, const Vec3& e2) {
  return std::atan2(v.dot(e2), v.dot(e1));
}

Vec3 rotate_about(const Vec3& v, const Vec3& axis, double angle) {
  // Rodrigues for v ⟂ axis (the component along the axis is kept as is).
  return std::cos(angle) * v + std::sin(angle) * axis.cross(v) +
         (1 - std::cos(angle)) * axis.dot(v) * axis;
}

/// Stroke constraints c_f (#F, normalised; step 1 of the field): the mean N-th power of the
/// strokes' directions, in face f's basis (E1, E2), of the faces within the stroke band of a
/// stroke. Appends the constrained faces, ascending, to `stroke_faces` (crossing strokes that
/// cancel exactly leave a face unconstrained). Throws InputError for a stroke point off the surface.
std::vector<Complex> stroke_targets(const SurfaceMesh& mesh, const FaceBvh& bvh,
                                    const OrientationFieldOptions& options, int N,
                                    const std::vector<Vec3>& E1, const std::vector<Vec3>& E2,
                                    std::vector<int>& stroke_faces) {
  const int F = mesh.num_faces();
  std::vector<Complex> target(static_cast<size_t>(F), Complex(0, 0));
  std::vector<int> hits(static_cast<size_t>(F), 0);
  const double diag = (mesh.bbox_max() - mesh.bbox_min()).norm();
  const double band = options.stroke_band > 0 ? options.stroke_band : mesh.mean_edge_length();
  std::vector<int> near;
  for (size_t s = 0; s < options.strokes.size(); ++s) {
    const auto& pts = options.strokes[s].points;
    for (size_t k = 0; k < pts.size(); ++k) {
      const ClosestPoint cp = bvh.closest_point(pts[k]);
      if (std::sqrt(cp.squared_distance) > 0.1 * diag)
        throw InputError(fmt::format(
            "pattern.strokes[{}] point {} ({}, {}, {}) is {:.4g} m from the surface (more than 10% "
            "of the model's size {:.4g} m): strokes must be drawn on the surface",
            s, k, pts[k].x(), pts[k].y(), pts[k].z(), std::sqrt(cp.squared_distance), diag));
    }
    for (size_t k = 0; k + 1 < pts.size(); ++k) {
      const Vec3 a = pts[k], b = pts[k + 1];
      const Vec3 dir = b - a;
      if (!(dir.norm() > 0)) continue;
      const int samples = int(std::ceil(dir.norm() / (0.5 * band))) + 1;
      for (int i = 0; i < samples; ++i) {
        const Vec3 p = a + (double(i) / (samples - 1)) * dir;
        const ClosestPoint cp = bvh.closest_point(p);
        bvh.faces_in_ball(cp.point, band, near);
        for (int f : near) {
          const Vec3 n = mesh.face_normals().row(f).transpose();
          const Vec3 d = dir - n * n.dot(dir);
          if (d.norm() < 1e-9 * dir.norm()) continue;
          target[size_t(f)] += std::polar(1.0, N * angle_in(d, E1[size_t(f)], E2[size_t(f)]));
          ++hits[size_t(f)];
        }
      }
    }
  }
  for (int f = 0; f < F; ++f) {
    if (hits[size_t(f)] == 0) continue;
    const double mag = std::abs(target[size_t(f)]);
    // Crossing strokes that cancel exactly leave the face unconstrained.
    if (mag > 1e-9 * hits[size_t(f)]) {
      target[size_t(f)] /= mag;
      stroke_faces.push_back(f);
    }
  }
  return target;
}

/// Hard constraints (step 2 of the field): in every connected component (through interior
/// edges) that no stroke touches, the face nearest to the component's centroid is aligned with
/// the mesh's longest bounding-box axis. Sets `fixed` (#F, 1 for those faces) and their values
/// u_f in `fixed_value` (#F).
void anchor_free_components(const SurfaceMesh& mesh, const std::vector<int>& stroke_faces, int N,
                            const std::vector<Vec3>& E1, const std::vector<Vec3>& E2, const Vec3& mirror_planes,
                            std::vector<int>& fixed, std::vector<Complex>& fixed_value) {
  const int F = mesh.num_faces();
  const RowMatX3d& V = mesh.vertices();
  std::vector<int> parent(static_cast<size_t>(F));
  std::iota(parent.begin(), parent.end(), 0);
  const RowMatX2i& EF = mesh.edge_faces();
  for (int e = 0; e < mesh.num_edges(); ++e)
    if (EF(e, 1) >= 0) parent[size_t(find_root(parent, EF(e, 0)))] = find_root(parent, EF(e, 1));
  std::vector<int> comp(static_cast<size_t>(F));
  for (int f = 0; f < F; ++f) comp[size_t(f)] = find_root(parent, f);
  std::vector<bool> comp_has_stroke(static_cast<size_t>(F), false);
  for (int f : stroke_faces) comp_has_stroke[size_t(comp[size_t(f)])] = true;

  // Reference axes, longest bounding-box extent first (ties: x before y before z); of the whole on
  // symmetry planes (each plane's axis spans twice the mesh's reach from it).
  Vec3 extent = mesh.bbox_max() - mesh.bbox_min();
  for (int a = 0; a < 3; ++a)
    if (std::isfinite(mirror_planes[a]))
      extent[a] = 2 * std::max(std::abs(mesh.bbox_max()[a] - mirror_planes[a]),
                               std::abs(mesh.bbox_min()[a] - mirror_planes[a]));
  std::array<int, 3> axes{0, 1, 2};
  std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) { return extent[a] > extent[b]; });

  std::vector<Vec3> comp_centroid(static_cast<size_t>(F), Vec3::Zero());
  std::vector<double> comp_area(static_cast<size_t>(F), 0.0);
  for (int f = 0; f < F; ++f) {
    const auto t = mesh.faces().row(f);
    const Vec3 c = (V.row(t[0]) + V.row(t[1]) + V.row(t[2])).transpose() / 3.0;
    comp_centroid[size_t(comp[size_t(f)])] += mesh.face_areas()[f] * c;
    comp_area[size_t(comp[size_t(f)])] += mesh.face_areas()[f];
  }
  std::vector<int> comp_anchor(static_cast<size_t>(F), -1);
  std::vector<double> anchor_dist(static_cast<size_t>(F), INFINITY);
  for (int f = 0; f < F; ++f) {
    const int c = comp[size_t(f)];
    if (comp_has_stroke[size_t(c)]) continue;
    const auto t = mesh.faces().row(f);
    const Vec3 x = (V.row(t[0]) + V.row(t[1]) + V.row(t[2])).transpose() / 3.0;
    const double d = (x - comp_centroid[size_t(c)] / comp_area[size_t(c)]).squaredNorm();
    if (d < anchor_dist[size_t(c)]) {
      anchor_dist[size_t(c)] = d;
      comp_anchor[size_t(c)] = f;
    }
  }
  fixed.assign(static_cast<size_t>(F), 0);
  fixed_value.assign(static_cast<size_t>(F), Complex());
  for (int c = 0; c < F; ++c) {
    const int f = comp_anchor[size_t(c)];
    if (f < 0) continue;
    const Vec3 n = mesh.face_normals().row(f).transpose();
    Vec3 d = Vec3::Zero();
    for (int a : axes) {
      d = Vec3::Unit(a) - n * n[a];
      if (d.norm() > 0.2) break;
    }
    fixed[size_t(f)] = 1;
    fixed_value[size_t(f)] = std::polar(1.0, N * angle_in(d, E1[size_t(f)], E2[size_t(f)]));
  }
}

/// The smoothness system in real 2×2 blocks over the free faces (step 3 of the field), solved:
/// u_f (#F) for every face, the fixed faces' values from `fixed_value`.
std::vector<Complex> solve_smoothness(const SurfaceMesh& mesh, const OrientationFieldOptions& options, int N,
                                      const std::vector<Vec3>& E1, const std::vector<Vec3>& E2,
                                      const std::vector<int>& stroke_faces, const std::vector<Complex>& target,
                                      const std::vector<int>& fixed, const std::vector<Complex>& fixed_value) {
  const int F = mesh.num_faces();
  const RowMatX3d& V = mesh.vertices();
  const RowMatX2i& EF = mesh.edge_faces();
  std::vector<int> var(static_cast<size_t>(F), -1);
  int nvar = 0;
  for (int f = 0; f < F; ++f)
    if (!fixed[size_t(f)]) var[size_t(f)] = nvar++;
  std::vector<Eigen::Triplet<double>> trip;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * nvar);
  auto add_block = [&](int row, int col, const Eigen::Matrix2d& B) {
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        if (B(a, b) != 0) trip.emplace_back(2 * row + a, 2 * col + b, B(a, b));
  };
  auto vec2 = [](Complex z) { return Eigen::Vector2d(z.real(), z.imag()); };
  const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const int f = EF(e, 0), g = EF(e, 1);
    if (g < 0) continue;
    const Vec3 edge = (V.row(mesh.edges()(e, 1)) - V.row(mesh.edges()(e, 0))).transpose();
    const double tf = angle_in(edge, E1[size_t(f)], E2[size_t(f)]);
    const double tg = angle_in(edge, E1[size_t(g)], E2[size_t(g)]);
    const double rot = N * (tg - tf);
    Eigen::Matrix2d R;
    R << std::cos(rot), -std::sin(rot), std::sin(rot), std::cos(rot);
    // Energy |x_g − R x_f|²: H_gg += I, H_ff += I, H_gf −= R, H_fg −= Rᵀ.
    const int vf = var[size_t(f)], vg = var[size_t(g)];
    if (vf >= 0) add_block(vf, vf, I);
    if (vg >= 0) add_block(vg, vg, I);
    if (vf >= 0 && vg >= 0) {
      add_block(vg, vf, -R);
      add_block(vf, vg, -R.transpose());
    } else if (vg >= 0) {
      rhs.segment<2>(2 * vg) += R * vec2(fixed_value[size_t(f)]);
    } else if (vf >= 0) {
      rhs.segment<2>(2 * vf) += R.transpose() * vec2(fixed_value[size_t(g)]);
    }
  }
  // Symmetry planes: across a boundary edge on a plane the whole has the face's mirror image, whose
  // field is the reflected one — in the edge's frame the conjugate of v_f = u_f e^(−iN θ_e). The
  // whole's edge term |v̄_f − v_f|² = 4 Im(v_f)² is shared by the half and its image: 2 Im(v_f)²
  // here, so that the half's energy is the symmetric whole's over 2 (Im v = w · x_f, w = (−sin Nθ_e,
  // cos Nθ_e)).
  const std::vector<bool>& on_boundary = mesh.is_boundary_vertex();
  const double plane_tol = 1e-6 * (mesh.bbox_max() - mesh.bbox_min()).norm();
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const int f = EF(e, 0);
    if (EF(e, 1) >= 0 || var[size_t(f)] < 0) continue;
    const int a0 = mesh.edges()(e, 0), a1 = mesh.edges()(e, 1);
    if (!on_boundary[size_t(a0)] || !on_boundary[size_t(a1)]) continue;
    bool on_plane = false;
    for (int a = 0; a < 3; ++a)
      on_plane = on_plane || (std::isfinite(options.mirror_planes[a]) &&
                              std::abs(V(a0, a) - options.mirror_planes[a]) <= plane_tol &&
                              std::abs(V(a1, a) - options.mirror_planes[a]) <= plane_tol);
    if (!on_plane) continue;
    const Vec3 edge = (V.row(a1) - V.row(a0)).transpose();
    const double alpha = N * angle_in(edge, E1[size_t(f)], E2[size_t(f)]);
    const Eigen::Vector2d w(-std::sin(alpha), std::cos(alpha));
    add_block(var[size_t(f)], var[size_t(f)], 2.0 * w * w.transpose());
  }
  const double lambda = options.stroke_weight;
  for (int f : stroke_faces) {
    const int vf = var[size_t(f)];
    if (vf < 0 || !(lambda > 0)) continue;
    add_block(vf, vf, lambda * I);
    rhs.segment<2>(2 * vf) += lambda * vec2(target[size_t(f)]);
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * nvar);
  if (nvar > 0) {
    // CHOLMOD's supernodal factorisation of the upper triangle (rows sorted within columns, as
    // Eigen compresses them) under the process's thread policy: 2 unknowns per face, 4.6 M on a
    // 2.3 M-face base mesh.
    Eigen::SparseMatrix<double> H(2 * nvar, 2 * nvar);
    H.setFromTriplets(trip.begin(), trip.end());
    Eigen::SparseMatrix<double> upper = H.triangularView<Eigen::Upper>();
    upper.makeCompressed();
    const int n = int(upper.rows());
    const std::vector<int> starts(upper.outerIndexPtr(), upper.outerIndexPtr() + n + 1);
    const std::vector<int> rows(upper.innerIndexPtr(), upper.innerIndexPtr() + upper.nonZeros());
    solvers::CholmodSolver solver;
    solver.analyze(n, starts, rows);
    if (!solver.factorize(upper.valuePtr()))
      throw SolveError("orientation field: the smoothness system could not be factorised "
                       "(a face with a zero stroke weight and no neighbours?)");
    solver.solve(rhs.data(), x.data());
    if (!x.allFinite()) throw SolveError("orientation field: the smoothness solve failed");
  }
  std::vector<Complex> u(static_cast<size_t>(F));
  for (int f = 0; f < F; ++f)
    u[size_t(f)] = fixed[size_t(f)] ? fixed_value[size_t(f)]
                                    : Complex(x[2 * var[size_t(f)]], x[2 * var[size_t(f)] + 1]);
  return u;
}

/// Per-vertex representatives (step 5 of the field, #V×3): the area-weighted N-th-power average
/// of the faces' directions `face_dirs` in each vertex's tangent plane; zero rows for
/// unreferenced vertices.
RowMatX3d vertex_representatives(const SurfaceMesh& mesh, int N, const std::vector<Vec3>& E1,
                                 const std::vector<Vec3>& E2, const RowMatX3d& face_dirs) {
  const int F = mesh.num_faces();
  const int nv = mesh.num_vertices();
  RowMatX3d vertex_dirs = RowMatX3d::Zero(nv, 3);
  std::vector<Complex> acc(static_cast<size_t>(nv), Complex(0, 0));
  std::vector<Vec3> ve1(static_cast<size_t>(nv), Vec3::Zero()), ve2(static_cast<size_t>(nv), Vec3::Zero());
  std::vector<int> first_face(static_cast<size_t>(nv), -1);
  for (int f = 0; f < F; ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces()(f, k);
      if (first_face[size_t(v)] < 0) {
        first_face[size_t(v)] = f;
        const Vec3 n = mesh.vertex_normals().row(v).transpose();
        Vec3 e = E1[size_t(f)] - n * n.dot(E1[size_t(f)]);
        if (e.norm() < 1e-9) e = E2[size_t(f)] - n * n.dot(E2[size_t(f)]);
        ve1[size_t(v)] = e.normalized();
        ve2[size_t(v)] = n.cross(ve1[size_t(v)]);
      }
      const Vec3 d = face_dirs.row(f).transpose();
      acc[size_t(v)] += mesh.face_areas()[f] *
                        std::polar(1.0, N * angle_in(d, ve1[size_t(v)], ve2[size_t(v)]));
    }
  const double cancelled = 1e-12 * (F > 0 ? mesh.face_areas().maxCoeff() : 0.0);
  for (int v = 0; v < nv; ++v) {
    if (first_face[size_t(v)] < 0) continue;  // unreferenced vertex
    double th;
    if (std::abs(acc[size_t(v)]) > cancelled)
      th = std::arg(acc[size_t(v)]) / N;
    else
      th = angle_in(face_dirs.row(first_face[size_t(v)]).transpose(), ve1[size_t(v)], ve2[size_t(v)]);
    vertex_dirs.row(v) = (std::cos(th) * ve1[size_t(v)] + std::sin(th) * ve2[size_t(v)]).transpose();
  }
  return vertex_dirs;
}

}  // namespace

void OrientationField::face_basis(int face, Vec3& e1, Vec3& e2) const {
  const auto f = m_mesh->faces().row(face);
  const RowMatX3d& V = m_mesh->vertices();
  e1 = (V.row(f[1]) - V.row(f[0])).transpose().normalized();
  const Vec3 n = m_mesh->face_normals().row(face).transpose();
  e2 = n.cross(e1);
}

OrientationField::OrientationField(const SurfaceMesh& mesh, const FaceBvh& bvh,
                                   const OrientationFieldOptions& options)
    : m_mesh(&mesh), m_symmetry(options.symmetry) {
  if (m_symmetry < 1)
    throw InputError(fmt::format("orientation field: symmetry must be at least 1 (got {})", m_symmetry));
  const int F = mesh.num_faces();
  const int N = m_symmetry;

  std::vector<Vec3> E1(static_cast<size_t>(F)), E2(static_cast<size_t>(F));
  for (int f = 0; f < F; ++f) face_basis(f, E1[size_t(f)], E2[size_t(f)]);

  // Steps 1–3: stroke targets, one anchor per stroke-free component, the smoothness solve.
  const std::vector<Complex> target = stroke_targets(mesh, bvh, options, N, E1, E2, m_stroke_faces);
  std::vector<int> fixed;
  std::vector<Complex> fixed_value;
  anchor_free_components(mesh, m_stroke_faces, N, E1, E2, options.mirror_planes, fixed, fixed_value);
  const std::vector<Complex> u = solve_smoothness(mesh, options, N, E1, E2, m_stroke_faces, target, fixed, fixed_value);

  // ---- 4. per-face directions.
  m_face_dirs.resize(F, 3);
  m_face_angles.resize(F);
  for (int f = 0; f < F; ++f) {
    // A vanishing u sits on a singularity: any direction is as good as another.
    const double th = std::abs(u[size_t(f)]) > 1e-12 ? std::arg(u[size_t(f)]) / N : 0.0;
    m_face_angles[f] = th;
    m_face_dirs.row(f) = (std::cos(th) * E1[size_t(f)] + std::sin(th) * E2[size_t(f)]).transpose();
  }

  // ---- 5. per-vertex representatives.
  m_vertex_dirs = vertex_representatives(mesh, N, E1, E2, m_face_dirs);

  // ---- 6. corner directions, each turned by a multiple of 2π/N towards its face's direction.
  m_corner_dirs.resize(F, 9);
  for (int f = 0; f < F; ++f) {
    const Vec3 df = m_face_dirs.row(f).transpose();
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces()(f, k);
      const Vec3 n = mesh.vertex_normals().row(v).transpose();
      const Vec3 dv = m_vertex_dirs.row(v).transpose();
      Vec3 best = dv;
      double best_dot = -INFINITY;
      for (int m = 0; m < N; ++m) {
        const Vec3 c = rotate_about(dv, n, 2 * std::numbers::pi * m / N);
        if (c.dot(df) > best_dot) {
          best_dot = c.dot(df);
          best = c;
        }
      }
      m_corner_dirs.block<1, 3>(f, 3 * k) = best.transpose();
    }
  }
}

Vec3 OrientationField::direction(const SurfacePoint& p, Eigen::Matrix3d* d_point) const {
  const SurfaceMesh& mesh = *m_mesh;
  const auto t = mesh.faces().row(p.face);
  Eigen::Matrix3d A, Nm;  // columns: corner directions, vertex normals
  for (int k = 0; k < 3; ++k) {
    A.col(k) = m_corner_dirs.block<1, 3>(p.face, 3 * k).transpose();
    Nm.col(k) = mesh.vertex_normals().row(t[k]).transpose();
  }
  const Vec3 w = A * p.bary;
  const Vec3 m = Nm * p.bary;
  const double mn = m.norm();
  if (!(mn > 1e-12)) {
    // Opposite vertex normals cancelled (a knife edge); the face direction is all we have.
    if (d_point) d_point->setZero();
    return m_face_dirs.row(p.face).transpose();
  }
  const Vec3 n = m / mn;
  const Vec3 y = w - n * n.dot(w);
  const double yn = y.norm();
  if (!(yn > 1e-9)) {
    // The corner directions cancel (next to a singularity): use the face's own direction.
    if (d_point) d_point->setZero();
    const Vec3 df = m_face_dirs.row(p.face).transpose();
    const Vec3 z = df - n * n.dot(df);
    return z.norm() > 1e-12 ? Vec3(z.normalized()) : df;
  }
  const Vec3 dir = y / yn;
  if (d_point) {
    const RowMatX3d& V = mesh.vertices();
    const Vec3 x0 = V.row(t[0]).transpose();
    const Vec3 e1 = V.row(t[1]).transpose() - x0, e2 = V.row(t[2]).transpose() - x0;
    Eigen::Matrix2d G;
    G << e1.dot(e1), e1.dot(e2), e2.dot(e1), e2.dot(e2);
    Eigen::Matrix<double, 2, 3> Et;
    Et.row(0) = e1.transpose();
    Et.row(1) = e2.transpose();
    const Eigen::Matrix<double, 2, 3> M = G.inverse() * Et;  // (b1, b2) = M (x − x0)
    Eigen::Matrix3d DB;                                       // rows: ∂b_k/∂x
    DB.row(1) = M.row(0);
    DB.row(2) = M.row(1);
    DB.row(0) = -(M.row(0) + M.row(1));
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d P = I - n * n.transpose();
    const Eigen::Matrix3d dw = A * DB;
    const Eigen::Matrix3d dn = P / mn * (Nm * DB);
    const Eigen::Matrix3d dy = P * dw - n * (w.transpose() * dn) - n.dot(w) * dn;
    *d_point = (I - dir * dir.transpose()) / yn * dy;
  }
  return dir;
}

Vec3 OrientationField::tangent(const SurfaceMesh& mesh, const SurfacePoint& where,
                               const Vec3& /*point*/, const Vec3& /*normal*/, const Mat3& d_point,
                               const Mat3& /*d_normal*/, Mat3* d_tangent) const {
  if (&mesh != m_mesh)
    throw InternalError("OrientationField::tangent: called with a mesh the field was not solved on");
  if (!d_tangent) return direction(where);
  Eigen::Matrix3d dt;
  const Vec3 t = direction(where, &dt);
  *d_tangent = dt * d_point;
  return t;
}

int polygon_symmetry_order(const std::vector<Vec2>& polygon) {
  const int n = int(polygon.size());
  if (n < 2) return 1;
  double radius = 0;
  for (const Vec2& p : polygon) radius = std::max(radius, p.norm());
  const double tol = 1e-6 * std::max(radius, 1e-300);
  for (int k = n; k >= 2; --k) {
    if (n % k) continue;
    const double a = 2 * std::numbers::pi / k;
    const double c = std::cos(a), s = std::sin(a);
    bool ok = true;
    for (const Vec2& p : polygon) {
      const Vec2 r(c * p.x() - s * p.y(), s * p.x() + c * p.y());
      bool found = false;
      for (const Vec2& q : polygon)
        if ((q - r).norm() <= tol) {
          found = true;
          break;
        }
      if (!found) {
        ok = false;
        break;
      }
    }
    if (ok) return k;
  }
  return 1;
}

int field_symmetry_for(const std::vector<int>& shape_orders, int exemplar_symmetry,
                       int isotropic_order) {
  int g = 0;
  for (int o : shape_orders)
    if (o >= 1 && o <= isotropic_order) g = std::gcd(g, o);
  if (exemplar_symmetry > 0) g = std::gcd(g, exemplar_symmetry);
  if (g == 0) return 4;
  for (int d = std::min(g, 6); d >= 1; --d)
    if (g % d == 0) return d;
  return 1;
}

}  // namespace cutwork
