#pragma once
/// Shell models shared by the sensitivity and objective tests.
#include <memory>
#include <random>

#include "solvers/shell/shell_model.h"
#include "tests/solvers/support/test_meshes.h"

namespace cutwork::test {

using solvers::ShellModel;

/// Laser-sintered PA12, 3 mm.
inline Material pa12() {
  Material m;
  m.youngs_modulus = 1.7e9;
  m.poisson_ratio = 0.4;
  m.thickness = 0.003;
  m.density = 1010;
  return m;
}

/// A shallow cap (0.5 m × 0.4 m, 5 cm rise) of PA12, clamped on x = 0, pinned at the opposite
/// corners, under an oblique pressure and self-weight, with random fill ratios in [0.2, 1].
/// A homogenised fill stiffness curve of the shape calibrations give (circles, ν = 0.4), fixed here
/// so that derivative tests do not depend on a calibration run: the scalar ratios only.
inline FillStiffnessCurve test_scalar_stiffness_curve() {
  FillStiffnessCurve c;
  c.alpha = {0.3, 0.45, 0.6, 0.75, 0.9, 1.0};
  c.membrane = {0.30, 0.41, 0.55, 0.70, 0.86, 1.0};
  c.bending = {0.42, 0.52, 0.63, 0.76, 0.90, 1.0};
  return c;
}

/// The same with the isotropic split (bulk and shear ratios near a calibration's: a perforation
/// softens the bending bulk modulus much more than the shear one), as calibrations return it.
inline FillStiffnessCurve test_stiffness_curve() {
  FillStiffnessCurve c = test_scalar_stiffness_curve();
  c.membrane_bulk = {0.31, 0.42, 0.54, 0.68, 0.85, 1.0};
  c.membrane_shear = {0.29, 0.40, 0.56, 0.71, 0.87, 1.0};
  c.bending_bulk = {0.33, 0.41, 0.50, 0.62, 0.78, 1.0};
  c.bending_shear = {0.80, 0.86, 0.91, 0.94, 0.97, 1.0};
  return c;
}

/// The same on the square lattice (anisotropy q near a calibration's: large and positive in the
/// membrane, small and negative in bending), as calibrations return it for mechanics.lattice square.
inline FillStiffnessCurve test_square_stiffness_curve() {
  FillStiffnessCurve c = test_stiffness_curve();
  c.membrane_anisotropy = {0.58, 0.47, 0.33, 0.21, 0.08, 0.0};
  c.bending_anisotropy = {-0.09, -0.06, -0.04, -0.02, -0.01, 0.0};
  return c;
}

/// Tables of K by biaxiality (rows per sample, kBiaxialityNodes each) made from worst-state samples:
/// K(ρ) = 1 + (K − 1)(0.8 + 0.1ρ − 0.15ρ²), lowest at pure shear, not symmetric in ρ, and ≥ 1.
inline std::vector<std::vector<double>> test_biaxiality_table(const std::vector<double>& worst) {
  std::vector<std::vector<double>> t;
  for (const double k : worst) {
    std::vector<double> row;
    for (int j = 0; j < kBiaxialityNodes; ++j) {
      const double r = biaxiality_node(j);
      row.push_back(1 + (k - 1) * (0.8 + 0.1 * r - 0.15 * r * r));
    }
    t.push_back(row);
  }
  return t;
}

struct CapFixture {
  SurfaceMesh mesh = test::cap(0.5, 0.4, 8, 0.05);
  LoadCase lc;
  std::unique_ptr<ShellModel> model;
  Eigen::VectorXd alpha;

  /// `square`: the homogenised rule on a square lattice whose axis (1, 0.4, 0.2) crosses the
  /// curved cap's faces at varying angles (test_square_stiffness_curve).
  /// `roller`: instead of its two pinned corners, the edge x = 0.5 is held along x and z only
  /// (LoadCase::held_axes), free to slide along y.
  /// `mirror`: the edge y = 0 lies on a symmetry plane (LoadCase::symmetry_axes), which the cap
  /// meets at an angle: held along y, its slope mirrored.
  explicit CapFixture(unsigned seed, BendingModel bending = BendingModel::ShapeOperator,
                      FillStiffness stiffness = FillStiffness::Linear, bool square = false, bool roller = false,
                      bool mirror = false) {
    const int nv = mesh.num_vertices();
    lc.fixed.assign(nv, false);
    lc.clamped.assign(nv, false);
    if (roller || mirror) lc.held_axes.assign(std::size_t(nv), 0);
    if (mirror) {
      lc.symmetry_axes.assign(std::size_t(nv), 0);
      lc.symmetry_planes.y() = 0;
    }
    for (int v = 0; v < nv; ++v) {
      const Vec3 p = mesh.vertices().row(v);
      if (mirror && p.y() < 1e-9) {
        lc.held_axes[std::size_t(v)] |= kHeldY;
        lc.symmetry_axes[std::size_t(v)] = kHeldY;
      }
      if (p.x() < 1e-9) lc.clamped[v] = lc.fixed[v] = true;
      if (roller && p.x() > 0.5 - 1e-9) lc.held_axes[std::size_t(v)] |= kHeldX | kHeldZ;
      else if (p.x() > 0.5 - 1e-9 && (p.y() < 1e-9 || p.y() > 0.4 - 1e-9)) lc.fixed[v] = true;
    }
    lc.forces = test::pressure_forces(mesh, 400.0, Vec3(0.2, 0, -1).normalized());
    // A second load spread over part of the surface, carried by the material (SurfaceLoad): 300 Pa
    // normal to the faces beyond x = 0.2, over a share of each face as a region's clipped piece
    // would cover (0.3–1 of it), so the partials and the adjoint see its non-local derivative.
    SurfaceLoad patch;
    std::mt19937 cover(seed + 1000);
    std::uniform_real_distribution<double> share(0.3, 1.0);
    for (int t = 0; t < mesh.num_faces(); ++t) {
      const Vec3 c = (mesh.vertices().row(mesh.faces()(t, 0)) + mesh.vertices().row(mesh.faces()(t, 1)) +
                      mesh.vertices().row(mesh.faces()(t, 2))).transpose() / 3.0;
      if (c.x() < 0.2) continue;
      const double a = share(cover) * mesh.face_areas()[t];
      const Vec3 f = 300.0 * a / 3.0 * mesh.face_normals().row(t).transpose();
      patch.faces.push_back(t);
      patch.areas.push_back(a);
      patch.nodal.push_back({f, f, f});
      for (int k = 0; k < 3; ++k) lc.forces.row(mesh.faces()(t, k)) += f.transpose();
    }
    lc.surface_loads.push_back(std::move(patch));
    lc.gravity = Vec3(0, 0, -9.81);
    MechanicsSettings mech;
    mech.bending = bending;
    mech.stiffness = stiffness;
    if (stiffness == FillStiffness::Homogenised) mech.stiffness_curve = test_stiffness_curve();
    if (stiffness == FillStiffness::Homogenised && square) {
      mech.stiffness_curve = test_square_stiffness_curve();
      mech.lattice = PerforationLattice::Square;
      mech.lattice_axis = Vec3(1, 0.4, 0.2).normalized();
    }
    model = std::make_unique<ShellModel>(mesh, pa12(), lc, mech);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> a(0.2, 1.0);
    alpha.resize(mesh.num_faces());
    for (int f = 0; f < alpha.size(); ++f) alpha[f] = a(rng);
  }

  /// Positions slightly off any equilibrium (partials do not need one).
  RowMatX3d perturbed(unsigned seed) const {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    RowMatX3d x = mesh.vertices();
    for (int v = 0; v < x.rows(); ++v)
      if (!model->fixed()[v]) x.row(v) += 0.004 * Vec3(u(rng), u(rng), u(rng)).transpose();
    return x;
  }
};

}  // namespace cutwork::test
