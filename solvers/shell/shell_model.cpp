#include "solvers/shell/shell_model.h"

#include <cmath>
#include <numeric>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"

namespace cutwork::solvers {

namespace {

int find_root(std::vector<int>& parent, int v) {
  while (parent[v] != v) {
    parent[v] = parent[parent[v]];
    v = parent[v];
  }
  return v;
}

std::string point_text(const Vec3& p) { return fmt::format("({:.4g}, {:.4g}, {:.4g})", p.x(), p.y(), p.z()); }

/// The load case must match the mesh (#V entries; empty ones are filled in as "none") and be
/// finite.
void check_load_case(LoadCase& lc, int nv, int nf) {
  if (lc.fixed.empty()) lc.fixed.assign(nv, false);
  if (lc.clamped.empty()) lc.clamped.assign(nv, false);
  if (lc.held_axes.empty()) lc.held_axes.assign(std::size_t(nv), 0);
  if (lc.symmetry_axes.empty()) lc.symmetry_axes.assign(std::size_t(nv), 0);
  if (lc.forces.rows() == 0) lc.forces = RowMatX3d::Zero(nv, 3);
  if (int(lc.fixed.size()) != nv || int(lc.clamped.size()) != nv || int(lc.held_axes.size()) != nv ||
      int(lc.symmetry_axes.size()) != nv || lc.forces.rows() != nv)
    throw InputError(fmt::format("load case: sized for {} / {} / {} / {} / {} vertices, the mesh has {}",
                                 lc.fixed.size(), lc.clamped.size(), lc.held_axes.size(), lc.symmetry_axes.size(),
                                 lc.forces.rows(), nv));
  for (int v = 0; v < nv; ++v)
    for (int a = 0; a < 3; ++a)
      if ((lc.symmetry_axes[std::size_t(v)] & (1u << a)) &&
          (!std::isfinite(lc.symmetry_planes[a]) || !(lc.held_axes[std::size_t(v)] & (1u << a) || lc.fixed[v])))
        throw InputError(fmt::format("load case: vertex {} lies on a symmetry plane across {} that is {}", v,
                                     char('x' + a), std::isfinite(lc.symmetry_planes[a]) ? "not held" : "not given"));
  for (int v = 0; v < nv; ++v)
    if (lc.held_axes[std::size_t(v)] > kHeldAll)
      throw InputError(fmt::format("load case: vertex {} is held along axes {:#x}, not a mask of x, y, z", v,
                                   lc.held_axes[std::size_t(v)]));
  for (int v = 0; v < nv; ++v) {
    if (!lc.forces.row(v).allFinite())
      throw SolveError(fmt::format("the loads are not finite: vertex {} carries the force {} N", v,
                                   point_text(lc.forces.row(v).transpose())));
  }
  if (!lc.gravity.allFinite())
    throw SolveError("the loads are not finite: gravity is " + point_text(lc.gravity) + " m/s^2");
  for (std::size_t l = 0; l < lc.surface_loads.size(); ++l) {
    const SurfaceLoad& sl = lc.surface_loads[l];
    if (sl.areas.size() != sl.faces.size() || sl.nodal.size() != sl.faces.size())
      throw InputError(fmt::format("load case: surface load {} has {} faces, {} areas and {} nodal forces", l,
                                   sl.faces.size(), sl.areas.size(), sl.nodal.size()));
    for (std::size_t i = 0; i < sl.faces.size(); ++i) {
      if (sl.faces[i] < 0 || sl.faces[i] >= nf)
        throw InputError(fmt::format("load case: surface load {} names face {}, the mesh has {}", l, sl.faces[i], nf));
      if (!(sl.areas[i] > 0) || !std::isfinite(sl.areas[i]))
        throw InputError(fmt::format("load case: surface load {} covers {} m^2 of face {}", l, sl.areas[i], sl.faces[i]));
      for (const Vec3& f : sl.nodal[i])
        if (!f.allFinite())
          throw SolveError(fmt::format("the loads are not finite: surface load {} puts {} N on face {}", l,
                                       point_text(f), sl.faces[i]));
    }
  }
}

/// The rigid motion u(p) = t + ω × p that supports of a part leave free, if any: the rows
/// e_a · u(p_v) = 0 of every held axis a of every supported vertex v (all three for a fixed one),
/// accumulated as JᵀJ over (t, ω) with p taken from the part's centre and scaled by its size. An
/// empty string when they hold all six motions, else the motion in words.
std::string free_rigid_motion(const RowMatX3d& X, const std::vector<int>& supported,
                              const std::vector<std::uint8_t>& axes, const Vec3& centre, double size,
                              std::uint8_t mirrored = 0) {
  Eigen::Matrix<double, 6, 6> jtj = Eigen::Matrix<double, 6, 6>::Zero();
  // A symmetry plane across axis a mirrors the slope across it: the half may turn about a alone
  // (ω parallel to e_a), so ω · e_b = 0 for the two other axes b.
  for (int a = 0; a < 3; ++a) {
    if (!(mirrored & (1u << a))) continue;
    for (int b = 0; b < 3; ++b) {
      if (b == a) continue;
      Eigen::Matrix<double, 6, 1> row;
      row << Vec3::Zero(), Vec3::Unit(b);
      jtj += row * row.transpose();
    }
  }
  for (std::size_t i = 0; i < supported.size(); ++i) {
    const Vec3 p = (X.row(supported[i]).transpose() - centre) / size;
    for (int a = 0; a < 3; ++a) {
      if (!(axes[i] & (1u << a))) continue;
      Eigen::Matrix<double, 6, 1> row;
      row << Vec3::Unit(a), p.cross(Vec3::Unit(a));
      jtj += row * row.transpose();
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(jtj);
  const double largest = std::max(eig.eigenvalues()(5), 1e-300);
  if (eig.eigenvalues()(0) > 1e-10 * largest) return {};
  const Eigen::Matrix<double, 6, 1> m = eig.eigenvectors().col(0);
  const Vec3 t = m.head<3>(), w = m.tail<3>();
  auto axis_text = [](const Vec3& d) {
    const Vec3 u = d.normalized();
    return fmt::format("({:.3g}, {:.3g}, {:.3g})", std::abs(u.x()) < 1e-9 ? 0.0 : u.x(),
                       std::abs(u.y()) < 1e-9 ? 0.0 : u.y(), std::abs(u.z()) < 1e-9 ? 0.0 : u.z());
  };
  if (w.norm() < 1e-6 * t.norm()) return "a translation along " + axis_text(t);
  // u(p) = t + ω × p is a rotation about the line through q = ω × t / |ω|² (plus a slide t·ω̂ along it).
  const Vec3 q = centre + size * w.cross(t) / w.squaredNorm();
  return "a rotation about the axis " + axis_text(w) + " through " + point_text(q);
}

/// Every connected part of the mesh must be held against rigid motion: some fixed vertex, and
/// supports off one line unless the part is clamped (a clamp hinge, or a bend element with a
/// ghost node); a part held along some axes only (LoadCase::held_axes) must have its held axes
/// stop all six rigid motions. Throws SolveError naming the part otherwise.
void check_supports(const SurfaceMesh& mesh, const std::vector<bool>& referenced, const std::vector<bool>& fixed,
                    const std::vector<std::uint8_t>& held_axes, const std::vector<ClampHinge>& clamps,
                    const std::vector<ShellBend>& bends, const std::vector<bool>& clamped) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  const RowMatX3d& X = mesh.vertices();
  const RowMatX3i& F = mesh.faces();
  std::vector<int> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  for (int f = 0; f < nf; ++f)
    for (int k = 1; k < 3; ++k) parent[find_root(parent, F(f, k))] = find_root(parent, F(f, 0));
  std::vector<std::vector<int>> fixed_of(nv), held_of(nv);
  std::vector<int> faces_of(nv, 0);
  std::vector<bool> clamped_part(nv, false);
  bool any_fixed = false;
  for (int v = 0; v < nv; ++v) {
    if (!referenced[v]) continue;
    if (fixed[v]) fixed_of[find_root(parent, v)].push_back(v);
    else if (held_axes[std::size_t(v)] != 0) held_of[find_root(parent, v)].push_back(v);
    else continue;
    any_fixed = true;
  }
  for (int f = 0; f < nf; ++f) ++faces_of[find_root(parent, F(f, 0))];
  for (const ClampHinge& ch : clamps) clamped_part[find_root(parent, ch.v[0])] = true;
  std::vector<std::uint8_t> mirrored_part(nv, 0);  // the symmetry planes a part has a mirrored edge on
  for (const ShellBend& b : bends)
    for (int i = 0; i < 3; ++i) {
      if (b.rest.across[i] != PatchNode::Ghost) continue;
      const int r = find_root(parent, F(b.face, 0));
      if (clamped[F(b.face, (i + 1) % 3)] && clamped[F(b.face, (i + 2) % 3)]) {
        clamped_part[r] = true;
      } else {  // a symmetry plane's ghost: its normal is a coordinate axis
        int a = 0;
        b.rest.ghost_conormal[i].cwiseAbs().maxCoeff(&a);
        mirrored_part[r] |= std::uint8_t(1u << a);
      }
    }
  if (!any_fixed)
    throw SolveError(
        "the model is not supported: no fixed vertices, so a rigid motion is possible (add a support "
        "that pins or clamps part of the surface)");
  // Bounding box of every part, for a scale-aware collinearity tolerance and a message a user
  // can place.
  std::vector<Vec3> part_lo(nv, Vec3::Constant(INFINITY)), part_hi(nv, Vec3::Constant(-INFINITY));
  for (int v = 0; v < nv; ++v) {
    if (!referenced[v]) continue;
    const int r = find_root(parent, v);
    part_lo[r] = part_lo[r].cwiseMin(X.row(v).transpose());
    part_hi[r] = part_hi[r].cwiseMax(X.row(v).transpose());
  }
  for (int r = 0; r < nv; ++r) {
    if (faces_of[r] == 0) continue;
    const Vec3 centre = 0.5 * (part_lo[r] + part_hi[r]);
    const double size = (part_hi[r] - part_lo[r]).norm();
    const auto& fx = fixed_of[r];
    if (!held_of[r].empty()) {
      // Held along some axes: whether those rows stop every rigid motion (a clamp stops the
      // rotations about its line, so a clamped part needs only its translations stopped — a fixed
      // vertex does that).
      if (clamped_part[r] && !fx.empty()) continue;
      std::vector<int> supported = fx;
      std::vector<std::uint8_t> axes(fx.size(), kHeldAll);
      for (int v : held_of[r]) {
        supported.push_back(v);
        axes.push_back(held_axes[std::size_t(v)]);
      }
      const std::string motion = free_rigid_motion(X, supported, axes, centre, std::max(size, 1e-300), mirrored_part[r]);
      if (!motion.empty())
        throw SolveError(fmt::format(
            "the model is not supported: the supports of the part with {} triangles around {} leave it free "
            "to move rigidly ({}): hold more axes or more points",
            faces_of[r], point_text(centre), motion));
      continue;
    }
    if (fx.empty())
      throw SolveError(fmt::format(
          "the model is not supported: the part of the mesh with {} triangles around {} has no "
          "fixed vertices, so a rigid motion is possible (support it as well)",
          faces_of[r], point_text(centre)));
    // Spread of the supports: the largest distance from the line through the two farthest ones.
    const Vec3 p0 = X.row(fx[0]);
    int far = fx[0];
    for (int v : fx)
      if ((X.row(v).transpose() - p0).norm() > (X.row(far).transpose() - p0).norm()) far = v;
    const Vec3 dir = X.row(far).transpose() - p0;
    double off_line = 0;
    if (dir.norm() > 1e-12 * size) {
      const Vec3 u = dir.normalized();
      for (int v : fx) {
        const Vec3 q = X.row(v).transpose() - p0;
        off_line = std::max(off_line, (q - q.dot(u) * u).norm());
      }
    }
    if (off_line <= 1e-9 * size && !clamped_part[r]) {
      throw SolveError(fmt::format(
          "the model is not supported: the supports of the part with {} triangles around {} {}, "
          "so it can rotate rigidly about them (pin a third point off that line, or clamp an edge)",
          faces_of[r], point_text(centre),
          dir.norm() > 1e-12 * size ? "lie on one line" : "are a single point"));
    }
  }
}

/// Ĉ and its bulk and shear parts (ShellModel::bending_constitutive), by FillPart.
std::array<Eigen::Matrix3d, 3> bending_constitutive_parts(double nu) {
  std::array<Eigen::Matrix3d, 3> c;
  c[int(FillPart::Whole)] = bending_constitutive(nu);
  c[int(FillPart::Bulk)] << 1, 1, 0, 1, 1, 0, 0, 0, 0;
  c[int(FillPart::Bulk)] *= (1 + nu) / 2;
  c[int(FillPart::Shear)] << 0.5, -0.5, 0, -0.5, 0.5, 0, 0, 0, 2;
  c[int(FillPart::Shear)] *= 1 - nu;
  return c;
}

/// The assembly pattern over the free nodes of `model` (its elements built, DOFs numbered): each
/// element's nodes (−1 for a fixed vertex or a ghost), in element order (membranes, bends,
/// hinges, clamp hinges).
BlockAssembly assembly_pattern(const ShellModel& model) {
  const RowMatX3i& F = model.mesh().faces();
  const int nf = model.num_faces();
  const std::vector<int>& vertex_node = model.vertex_node();
  std::vector<BlockAssembly::ElementNodes> element_nodes;
  element_nodes.reserve(model.num_elements());
  auto node = [&](int v) { return vertex_node[v]; };
  auto node_or_none = [&](int v) { return v < 0 ? -1 : vertex_node[v]; };
  for (int f = 0; f < nf; ++f) element_nodes.push_back(BlockAssembly::nodes({node(F(f, 0)), node(F(f, 1)), node(F(f, 2))}));
  for (const ShellBend& b : model.bends()) {
    BlockAssembly::ElementNodes en;
    for (int a = 0; a < 6; ++a) en[a] = node_or_none(b.v[a]);
    element_nodes.push_back(en);
  }
  for (const ShellHinge& h : model.hinges())
    element_nodes.push_back(BlockAssembly::nodes({node(h.v[0]), node(h.v[1]), node(h.v[2]), node(h.v[3])}));
  for (const ClampHinge& c : model.clamp_hinges())
    element_nodes.push_back(BlockAssembly::nodes({node(c.v[0]), node(c.v[1]), node(c.v[2])}));
  // The shear and anisotropic parts: the same nodes as the membranes' and the bends' bulk parts.
  const std::size_t bulk_parts = std::size_t(nf) + model.bends().size();
  for (int extra = int(model.fill_stiffness().split()) + int(model.fill_stiffness().anisotropic()); extra > 0; --extra)
    for (std::size_t e = 0; e < bulk_parts; ++e) element_nodes.push_back(element_nodes[e]);
  return BlockAssembly(model.num_nodes(), element_nodes);
}

}  // namespace

void ShellModel::set_stiffness_curve(FillStiffnessCurve curve) {
  MechanicsSettings m = m_mechanics;
  m.stiffness_curve = std::move(curve);
  FillStiffnessMap map(m);
  m_mechanics = std::move(m);
  m_fill_stiffness = std::move(map);
}

ShellModel::ShellModel(const SurfaceMesh& mesh, const Material& material, const LoadCase& load_case,
                       const MechanicsSettings& mechanics)
    : m_mesh(std::make_shared<SurfaceMesh>(mesh)),
      m_material(material),
      m_stiffness(shell_stiffness(material)),
      m_mechanics(mechanics),
      m_fill_stiffness(mechanics),
      m_bending_constitutive(bending_constitutive_parts(material.poisson_ratio)),
      m_load_case(load_case) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  const RowMatX3d& X = mesh.vertices();
  const RowMatX3i& F = mesh.faces();

  LoadCase& lc = m_load_case;
  check_load_case(lc, nv, nf);
  std::vector<bool> referenced(nv, false);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) referenced[F(f, k)] = true;

  m_fixed.assign(nv, false);
  for (int v = 0; v < nv; ++v) {
    if (lc.held_axes[std::size_t(v)] == kHeldAll) lc.fixed[v] = true;
    m_fixed[v] = lc.fixed[v] || lc.clamped[v];
    if (m_fixed[v]) lc.held_axes[std::size_t(v)] = 0;
  }

  // --- DOF numbering: free, referenced vertices in vertex order ----------------------------------
  m_vertex_node.assign(nv, -1);
  for (int v = 0; v < nv; ++v) {
    if (!referenced[v]) {
      if (lc.forces.row(v).squaredNorm() > 0)
        throw SolveError(fmt::format("a load acts on vertex {} at {}, which belongs to no triangle", v,
                                     point_text(X.row(v).transpose())));
      continue;
    }
    if (m_fixed[v]) continue;
    m_vertex_node[v] = int(m_node_vertex.size());
    m_node_vertex.push_back(v);
  }
  const Vec3 lo = mesh.bbox_min(), hi = mesh.bbox_max();
  m_model_size = (hi - lo).norm();

  // --- elements ------------------------------------------------------------------------------
  m_membranes.resize(nf);
  for (int f = 0; f < nf; ++f)
    m_membranes[f] = membrane_rest(X.row(F(f, 0)), X.row(F(f, 1)), X.row(F(f, 2)));
  // The square lattice's axis in each face's rest frame (first axis X1 − X0, as membrane_rest and
  // shape_operator_rest lay the face out).
  if (m_fill_stiffness.anisotropic()) {
    if (m_mechanics.lattice != PerforationLattice::Square)
      throw InputError("an anisotropic stiffness curve is the square lattice's: mechanics.lattice must be square");
    m_lattice_orientation.assign(std::size_t(nf), Eigen::Vector2d::Zero());
    // One axis for the shell, or the orientation field's at each face's centroid (the host's
    // function: attach_lattice_field).
    const bool by_field = m_mechanics.lattice_follows_field;
    if (by_field && !m_mechanics.lattice_axis_at)
      throw InternalError("ShellModel: the square lattice follows the orientation field, but no axis function is "
                          "attached (attach_lattice_field)");
    const Vec3 global = m_mechanics.lattice_axis.normalized();
    // (In parallel: the field's axis is a closest-point query per face; TangentField is safe to
    // call concurrently.)
    tbb::parallel_for(tbb::blocked_range<int>(0, nf, 512), [&](const tbb::blocked_range<int>& range) {
      for (int f = range.begin(); f < range.end(); ++f) {
        const Vec3 e1 = X.row(F(f, 1)) - X.row(F(f, 0)), e2 = X.row(F(f, 2)) - X.row(F(f, 0));
        const Vec3 n = e1.cross(e2).normalized(), u1 = e1.normalized(), u2 = n.cross(u1);
        const Vec3 axis =
            by_field ? m_mechanics.lattice_axis_at((X.row(F(f, 0)) + X.row(F(f, 1)) + X.row(F(f, 2))).transpose() / 3)
                     : global;
        const Eigen::Vector2d a(axis.dot(u1), axis.dot(u2));
        if (a.norm() < 1e-3) continue;
        const double phi = std::atan2(a.y(), a.x());
        m_lattice_orientation[std::size_t(f)] = Eigen::Vector2d(std::cos(4 * phi), std::sin(4 * phi));
      }
    });
  }
  if (m_mechanics.bending == BendingModel::ShapeOperator)
    build_bends();
  else
    build_hinges();

  // --- supports: every connected part must be held against rigid motion -----------------------
  if (m_node_vertex.empty())
    throw SolveError("nothing to solve: every vertex of the mesh is fixed");
  check_supports(mesh, referenced, m_fixed, lc.held_axes, m_clamps, m_bends, lc.clamped);

  // --- loads must load the free part ----------------------------------------------------------
  bool loaded = false;
  for (int v = 0; v < nv && !loaded; ++v)
    loaded = m_vertex_node[v] >= 0 && lc.forces.row(v).squaredNorm() > 0;
  if (!loaded && m_stiffness.areal_mass > 0 && lc.gravity.squaredNorm() > 0) loaded = true;
  loaded = loaded || lc.held_motion;
  if (!loaded)
    throw SolveError(
        "the load case applies no load to the free part of the shell (all forces are zero or act on "
        "supported vertices, and there is no self-weight): add a load");

  m_assembly = assembly_pattern(*this);

  // --- DOFs held along some axes: their rows and columns of the Hessian, once -------------------
  std::vector<bool> held(std::size_t(num_dofs()), false);
  for (int n = 0; n < num_nodes(); ++n)
    for (int a = 0; a < 3; ++a)
      if (lc.held_axes[std::size_t(m_node_vertex[n])] & (1u << a)) {
        held[std::size_t(3 * n + a)] = true;
        m_held_dofs.push_back(3 * n + a);
      }
  if (!m_held_dofs.empty()) {
    const std::vector<int>& starts = m_assembly.column_starts();
    const std::vector<int>& rows = m_assembly.row_indices();
    for (int c = 0; c < num_dofs(); ++c)
      for (int k = starts[std::size_t(c)]; k < starts[std::size_t(c) + 1]; ++k) {
        const int r = rows[std::size_t(k)];
        if (r == c && held[std::size_t(c)]) m_held_diagonal.push_back(k);
        else if (held[std::size_t(r)] || held[std::size_t(c)]) m_held_coupling.push_back(k);
      }
  }
}

void ShellModel::zero_held(Eigen::VectorXd& free) const {
  for (int d : m_held_dofs) free[d] = 0;
}

void ShellModel::hold_in_hessian(std::vector<double>& values) const {
  for (long k : m_held_coupling) values[std::size_t(k)] = 0;
  // The diagonal keeps its value (the scale of its neighbours'), so the decoupled row neither
  // spoils the factor's conditioning nor the shift a Newton step may add.
  for (long k : m_held_diagonal)
    if (!(values[std::size_t(k)] > 0)) values[std::size_t(k)] = 1;
}

Eigen::Matrix3d ShellModel::bending_part_constitutive(FillPart part, int face) const {
  if (part != FillPart::Anisotropy) return bending_constitutive(part);
  const double c = m_lattice_orientation[std::size_t(face)].x(), s = m_lattice_orientation[std::size_t(face)].y();
  Eigen::Matrix3d C;
  C << c / 2, -c / 2, s, -c / 2, c / 2, -s, s, -s, -2 * c;
  return (1 - m_material.poisson_ratio) * C;
}

std::array<double, 2> ShellModel::membrane_lame(FillPart part) const {
  switch (part) {
    case FillPart::Whole: return {m_stiffness.mu, m_stiffness.lambda};
    case FillPart::Bulk: return {0.0, m_stiffness.mu + m_stiffness.lambda};
    case FillPart::Shear: return {m_stiffness.mu, -m_stiffness.mu};
    case FillPart::Anisotropy: break;
  }
  throw InternalError("ShellModel::membrane_lame: the anisotropic part has no Lamé form");
}

Eigen::Matrix3d ShellModel::membrane_part_constitutive(FillPart part, int face) const {
  const double mu = m_stiffness.mu, lambda = m_stiffness.lambda;
  Eigen::Matrix3d C;
  switch (part) {
    case FillPart::Whole: return membrane_constitutive(mu, lambda);
    case FillPart::Bulk: C << 1, 1, 0, 1, 1, 0, 0, 0, 0; return (mu + lambda) * C;
    case FillPart::Shear: C << 1, -1, 0, -1, 1, 0, 0, 0, 1; return mu * C;
    case FillPart::Anisotropy: break;
  }
  const double c = m_lattice_orientation[std::size_t(face)].x(), s = m_lattice_orientation[std::size_t(face)].y();
  C << c, -c, s, -c, c, -s, s, -s, -c;
  return mu * C;
}

bool ShellModel::edge_clamped(int a, int b) const { return m_load_case.clamped[a] && m_load_case.clamped[b]; }

int ShellModel::edge_mirror_axis(int a, int b) const {
  const std::uint8_t common = m_load_case.symmetry_axes[std::size_t(a)] & m_load_case.symmetry_axes[std::size_t(b)];
  for (int k = 0; k < 3; ++k)
    if (common & (1u << k)) return k;
  return -1;
}

void ShellModel::build_bends() {
  const SurfaceMesh& mesh = *m_mesh;
  const RowMatX3d& X = mesh.vertices();
  const RowMatX3i& F = mesh.faces();
  const int nf = mesh.num_faces();
  m_bends.resize(nf);
  // Each face's rest state alone (its patch, an SVD of the patch's quadratic fit): in parallel, the
  // same to the bit whatever the threads.
  tbb::parallel_for(tbb::blocked_range<int>(0, nf, 256), [&](const tbb::blocked_range<int>& faces) {
    for (int f = faces.begin(); f < faces.end(); ++f) {
      ShellBend& b = m_bends[f];
      b.face = f;
      std::array<Vec3, 6> rest;
      std::array<PatchNode, 3> across = {PatchNode::Free, PatchNode::Free, PatchNode::Free};
      std::array<Vec3, 3> mirror = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
      bool mirrored = false;
      for (int k = 0; k < 3; ++k) {
        b.v[k] = F(f, k);
        rest[k] = X.row(F(f, k)).transpose();
      }
      for (int i = 0; i < 3; ++i) {
        const int a = F(f, (i + 1) % 3), c = F(f, (i + 2) % 3);
        const int e = mesh.face_edges()(f, (i + 1) % 3);
        const int g = mesh.edge_faces()(e, 0) == f ? mesh.edge_faces()(e, 1) : mesh.edge_faces()(e, 0);
        if (edge_clamped(a, c)) {
          across[i] = PatchNode::Ghost;
        } else if (const int axis = g < 0 ? edge_mirror_axis(a, c) : -1; axis >= 0) {
          // The boundary on a symmetry plane: the mirror image of f's third vertex continues it.
          across[i] = PatchNode::Ghost;
          mirror[i] = Vec3::Unit(axis);
          mirrored = true;
        } else if (g >= 0) {
          int opposite = -1;
          for (int k = 0; k < 3; ++k)
            if (F(g, k) != a && F(g, k) != c) opposite = F(g, k);
          across[i] = PatchNode::Vertex;
          b.v[3 + i] = opposite;
          rest[3 + i] = X.row(opposite).transpose();
        }
      }
      b.rest = shape_operator_rest(rest, across, m_material.poisson_ratio, mirrored ? &mirror : nullptr);
    }
  });
}

void ShellModel::build_hinges() {
  const SurfaceMesh& mesh = *m_mesh;
  const RowMatX3d& X = mesh.vertices();
  const RowMatX3i& F = mesh.faces();
  const Eigen::VectorXd& area = mesh.face_areas();
  const double D = m_stiffness.bending;
  for (int e = 0; e < mesh.num_edges(); ++e)
    if (mesh.edge_faces()(e, 1) < 0 && edge_mirror_axis(mesh.edges()(e, 0), mesh.edges()(e, 1)) >= 0)
      throw InputError("a symmetry plane needs mechanics.bending 'shape_operator': the hinge model has no mirrored "
                       "slope across a boundary");
  for (const Hinge& h : mesh.hinges()) {
    if (edge_clamped(h.v[0], h.v[1])) continue;  // replaced by a clamp hinge on each side
    ShellHinge sh;
    std::copy(h.v, h.v + 4, sh.v);
    sh.face[0] = h.face[0];
    sh.face[1] = h.face[1];
    Vec12 x;
    for (int k = 0; k < 4; ++k) x.segment<3>(3 * k) = X.row(h.v[k]).transpose();
    sh.rest.rest_angle = dihedral_angle(x);
    const double edge_length = (X.row(h.v[1]) - X.row(h.v[0])).norm();
    sh.rest.stiffness = hinge_stiffness(D, edge_length, (area[h.face[0]] + area[h.face[1]]) / 3.0);
    m_hinges.push_back(sh);
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3), c = F(f, (k + 2) % 3);
      // A clamp hinge only acts through the free opposite vertex; with c fixed too it is inert.
      if (!edge_clamped(a, b) || m_fixed[c]) continue;
      ClampHinge ch;
      ch.v[0] = a;
      ch.v[1] = b;
      ch.v[2] = c;
      ch.face = f;
      const Vec3 xa = X.row(a), xb = X.row(b), xc = X.row(c);
      ch.ghost = ghost_point(xa, xb, xc);
      Vec12 x;
      x << xa, xb, xc, ch.ghost;
      ch.rest.rest_angle = dihedral_angle(x);
      ch.rest.stiffness = hinge_stiffness(D, (xb - xa).norm(), area[f] / 3.0);
      m_clamps.push_back(ch);
    }
  }
}

RowMatX3d ShellModel::external_forces(const Eigen::VectorXd& alpha) const {
  RowMatX3d f = m_load_case.forces;
  const RowMatX3i& F = m_mesh->faces();
  if (m_stiffness.areal_mass > 0 && m_load_case.gravity.squaredNorm() > 0) {
    for (int t = 0; t < num_faces(); ++t) {
      const Vec3 w = alpha[t] * self_weight_per_vertex_and_alpha(t);
      for (int k = 0; k < 3; ++k) f.row(F(t, k)) += w.transpose();
    }
  }
  // Surface loads onto the material: `forces` holds them spread by area (α ≡ 1); move each face's
  // share to (s α_t − 1) F_t more, s = Σ a / Σ α a.
  for (const SurfaceLoad& sl : m_load_case.surface_loads) {
    const double s = surface_load_scale(sl, alpha);
    for (std::size_t i = 0; i < sl.faces.size(); ++i) {
      const int t = sl.faces[i];
      for (int k = 0; k < 3; ++k) f.row(F(t, k)) += (s * alpha[t] - 1) * sl.nodal[i][std::size_t(k)].transpose();
    }
  }
  return f;
}

double ShellModel::surface_load_scale(const SurfaceLoad& load, const Eigen::VectorXd& alpha) {
  double area = 0, material = 0;
  for (std::size_t i = 0; i < load.faces.size(); ++i) {
    area += load.areas[i];
    material += alpha[load.faces[i]] * load.areas[i];
  }
  // Fill ratios are positive (check_fill_ratios; the fill kernel clamps at 1e-4), so only a load
  // case built by hand with empty or zero-α faces gets here.
  if (!(material > 0))
    throw SolveError(fmt::format("a load spread over {} faces finds no material there to carry it", load.faces.size()));
  return area / material;
}

void ShellModel::add_load_alpha_product(const RowMatX3d& v, const Eigen::VectorXd& alpha, Eigen::VectorXd& out) const {
  const RowMatX3i& F = m_mesh->faces();
  if (m_stiffness.areal_mass > 0 && m_load_case.gravity.squaredNorm() > 0) {
    for (int t = 0; t < num_faces(); ++t) {
      const Vec3 w = self_weight_per_vertex_and_alpha(t);
      for (int k = 0; k < 3; ++k) out[t] += w.dot(v.row(F(t, k)).transpose());
    }
  }
  // f = s(α) Σ_t α_t F_t with s = A / S, S = Σ α_t a_t:
  //   ∂f/∂α_t = s F_t − (a_t / S) f.
  for (const SurfaceLoad& sl : m_load_case.surface_loads) {
    std::vector<double> d(sl.faces.size());  // v · F_t
    double area = 0, material = 0, weighted = 0;  // A, S, Σ α_t v · F_t
    for (std::size_t i = 0; i < sl.faces.size(); ++i) {
      const int t = sl.faces[i];
      d[i] = 0;
      for (int k = 0; k < 3; ++k) d[i] += sl.nodal[i][std::size_t(k)].dot(v.row(F(t, k)).transpose());
      area += sl.areas[i];
      material += alpha[t] * sl.areas[i];
      weighted += alpha[t] * d[i];
    }
    const double s = area / material, vf = s * weighted;
    for (std::size_t i = 0; i < sl.faces.size(); ++i) out[sl.faces[i]] += s * d[i] - sl.areas[i] / material * vf;
  }
}

Vec3 ShellModel::self_weight_per_vertex_and_alpha(int face) const {
  return m_stiffness.areal_mass * m_mesh->face_areas()[face] / 3.0 * m_load_case.gravity;
}

Eigen::VectorXd ShellModel::gather_free(const RowMatX3d& values) const {
  Eigen::VectorXd out(num_dofs());
  for (int n = 0; n < num_nodes(); ++n) out.segment<3>(3 * n) = values.row(m_node_vertex[n]).transpose();
  return out;
}

void ShellModel::scatter_free(const Eigen::VectorXd& free, RowMatX3d& values) const {
  for (int n = 0; n < num_nodes(); ++n) values.row(m_node_vertex[n]) = free.segment<3>(3 * n).transpose();
}

void ShellModel::check_fill_ratios(const Eigen::VectorXd& alpha) const {
  if (alpha.size() != num_faces())
    throw InputError(fmt::format("fill ratios: {} values for {} triangles", alpha.size(), num_faces()));
  for (int t = 0; t < alpha.size(); ++t)
    if (!std::isfinite(alpha[t]) || alpha[t] <= 0)
      throw InputError(fmt::format("fill ratios: triangle {} has alpha = {} (expected a finite value in "
                                   "[1e-4, 1])",
                                   t, alpha[t]));
}

}  // namespace cutwork::solvers
