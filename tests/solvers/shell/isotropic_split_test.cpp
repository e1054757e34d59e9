// The isotropic split of the homogenised fill stiffness (fill_stiffness_map.h): membranes and
// shape-operator bends carry their bulk and shear parts as elements of their own, each scaled by its
// own g(α). Checked here: with equal bulk and shear ratios the split is the scalar rule (energy,
// forces, Hessian, the α-partials the adjoint needs, W and W_peak); uniform equibiaxial and
// deviatoric states of a flat plate (stretch and curvature) store exactly g_K and g_G times the
// solid's energy. Central-difference checks of the split's derivatives run in the adjoint, energy
// density and peak tests, whose homogenised fixtures carry the split (test_stiffness_curve).
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <random>

#include <gtest/gtest.h>

#include "host/core/internal_error.h"

#include "solvers/objective/energy_density.h"
#include "solvers/objective/peak_energy_density.h"
#include "solvers/shell/fill_ratio_partials.h"
#include "solvers/shell/shell_energy.h"
#include "tests/solvers/support/shell_fixtures.h"
#include "tests/solvers/support/test_meshes.h"

namespace cutwork::solvers {
namespace {

/// The scalar test curve split into bulk and shear parts that equal it.
FillStiffnessCurve equal_parts(FillStiffnessCurve c) {
  c.membrane_bulk = c.membrane_shear = c.membrane;
  c.bending_bulk = c.bending_shear = c.bending;
  c.membrane_concentration = {3.1, 2.7, 2.4, 2.2, 2.05, 2.0};
  c.bending_concentration = {1.9, 1.8, 1.7, 1.6, 1.5, 1.45};
  return c;
}

double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() / b.norm(); }

TEST(IsotropicSplit, EqualBulkAndShearRatiosReproduceTheScalarRule) {
  for (BendingModel bending : {BendingModel::ShapeOperator, BendingModel::Hinge}) {
    SCOPED_TRACE(bending == BendingModel::Hinge ? "hinge" : "shape operator");
    test::CapFixture fx(71, bending, FillStiffness::Homogenised);
    MechanicsSettings scalar_mech = fx.model->mechanics(), split_mech = scalar_mech;
    split_mech.stiffness_curve = equal_parts(test::test_scalar_stiffness_curve());
    scalar_mech.stiffness_curve = split_mech.stiffness_curve;
    scalar_mech.stiffness_curve.membrane_bulk.clear();
    scalar_mech.stiffness_curve.membrane_shear.clear();
    scalar_mech.stiffness_curve.bending_bulk.clear();
    scalar_mech.stiffness_curve.bending_shear.clear();
    const ShellModel scalar(fx.mesh, test::pa12(), fx.lc, scalar_mech), split(fx.mesh, test::pa12(), fx.lc, split_mech);
    ASSERT_FALSE(scalar.fill_stiffness().split());
    ASSERT_TRUE(split.fill_stiffness().split());
    const int parts = bending == BendingModel::ShapeOperator ? 2 * fx.mesh.num_faces() : fx.mesh.num_faces();
    EXPECT_EQ(split.num_elements(), scalar.num_elements() + parts);

    const RowMatX3d x = fx.perturbed(72);
    const Eigen::VectorXd& alpha = fx.alpha;
    EXPECT_NEAR(shell_energy(split, x, alpha), shell_energy(scalar, x, alpha), 1e-12 * shell_energy(scalar, x, alpha));
    ShellAssembly a, b;
    assemble_shell(scalar, x, alpha, true, a);
    assemble_shell(split, x, alpha, true, b);
    EXPECT_LT(relative(b.gradient, a.gradient), 1e-12);
    ASSERT_EQ(a.hessian.size(), b.hessian.size());  // the same pattern: the parts share their nodes
    const Eigen::Map<const Eigen::VectorXd> ha(a.hessian.data(), Eigen::Index(a.hessian.size())),
        hb(b.hessian.data(), Eigen::Index(b.hessian.size()));
    EXPECT_LT(relative(hb, ha), 1e-12);

    EXPECT_LT(relative(energy_alpha_gradient(split, x, alpha), energy_alpha_gradient(scalar, x, alpha)), 1e-12);
    std::mt19937 rng(73);
    std::normal_distribution<double> n;
    Eigen::VectorXd lambda(scalar.num_dofs()), c(scalar.num_faces());
    for (double& v : lambda) v = n(rng);
    for (double& v : c) v = n(rng);
    EXPECT_LT(relative(force_alpha_product(split, x, alpha, lambda), force_alpha_product(scalar, x, alpha, lambda)),
              1e-12);
    EXPECT_LT(relative(energy_density(split, x, alpha), energy_density(scalar, x, alpha)), 1e-12);
    const ConcentrationMap K(split_mech.stiffness_curve);
    EXPECT_LT(relative(peak_energy_density(split, x, alpha, K), peak_energy_density(scalar, x, alpha, K)), 1e-12);
    RowMatX3d dx_a, dx_b;
    Eigen::VectorXd da_a, da_b;
    peak_energy_density_vjp(scalar, x, alpha, K, nullptr, c, &dx_a, &da_a);
    peak_energy_density_vjp(split, x, alpha, K, nullptr, c, &dx_b, &da_b);
    EXPECT_LT((dx_b - dx_a).norm() / dx_a.norm(), 1e-12);
    EXPECT_LT(relative(da_b, da_a), 1e-12);
  }
}

// The assembly and the energy-only sum evaluate a split element's two parts in one pass
// (visit_split_element); the α-partials evaluate them one by one. Both must agree, with the parts'
// ratios unequal (the test curve's), and with the square lattice's anisotropic parts.
TEST(IsotropicSplit, FusedEvaluationMatchesThePartsOneByOne) {
  for (bool square : {false, true})
  for (BendingModel bending : {BendingModel::ShapeOperator, BendingModel::Hinge}) {
    SCOPED_TRACE(bending == BendingModel::Hinge ? "hinge" : "shape operator");
    SCOPED_TRACE(square ? "square lattice (three parts)" : "hexagonal lattice");
    test::CapFixture fx(74, bending, FillStiffness::Homogenised, square);
    const ShellModel& model = *fx.model;
    ASSERT_TRUE(model.fill_stiffness().split());
    const RowMatX3d x = fx.perturbed(75);
    ElementEnergies unit;
    const double parts = shell_energy(model, x, fx.alpha, &unit), fused = shell_energy(model, x, fx.alpha);
    EXPECT_NEAR(fused, parts, 1e-12 * parts);
    ShellAssembly a;
    assemble_shell(model, x, fx.alpha, false, a);
    EXPECT_NEAR(a.energy, parts, 1e-12 * parts);
    Eigen::VectorXd factor(model.num_elements());
    for (int e = 0; e < factor.size(); ++e) factor[e] = element_fill_factor(model, fx.alpha, e);
    EXPECT_LT(relative(a.gradient, weighted_element_gradient(model, x, factor)), 1e-12);
  }
}

/// A flat 0.4 m × 0.3 m plate clamped along x = 0 (a model needs supports; the states below are
/// imposed, not solved for), with faces at every sample fill ratio of the test curve and between.
struct FlatPlate {
  SurfaceMesh mesh = test::grid_rectangle(0.4, 0.3, 8, 6);
  LoadCase lc;
  Eigen::VectorXd alpha;

  FlatPlate() {
    lc.fixed.assign(mesh.num_vertices(), false);
    lc.clamped.assign(mesh.num_vertices(), false);
    for (int v : test::select_vertices(mesh, [](const Vec3& p) { return p.x() < 1e-9; })) lc.fixed[v] = lc.clamped[v] = true;
    lc.forces = RowMatX3d::Zero(mesh.num_vertices(), 3);
    for (int v : test::select_vertices(mesh, [](const Vec3& p) { return p.x() > 0.4 - 1e-9; })) lc.forces(v, 2) = -1;
    alpha.resize(mesh.num_faces());
    const double values[] = {0.3, 0.38, 0.45, 0.52, 0.6, 0.71, 0.75, 0.84, 0.9, 0.97, 1.0};
    for (int t = 0; t < alpha.size(); ++t) alpha[t] = values[t % 11];
  }
  ShellModel model(FillStiffness rule) const {
    MechanicsSettings mech;
    mech.stiffness = rule;
    if (rule == FillStiffness::Homogenised) mech.stiffness_curve = test::test_stiffness_curve();
    return ShellModel(mesh, test::pa12(), lc, mech);
  }
  /// The homogenised rule on a square lattice whose axis is `axis` (in the plate's plane or not).
  ShellModel square(const Vec3& axis) const {
    MechanicsSettings mech;
    mech.stiffness = FillStiffness::Homogenised;
    mech.stiffness_curve = test::test_square_stiffness_curve();
    mech.lattice = PerforationLattice::Square;
    mech.lattice_axis = axis;
    return ShellModel(mesh, test::pa12(), lc, mech);
  }
  /// The same, the lattice's axis following a field: `axis_at` a point (mechanics.lattice_axis_at).
  ShellModel square_by_field(std::function<Vec3(const Vec3&)> axis_at) const {
    MechanicsSettings mech;
    mech.stiffness = FillStiffness::Homogenised;
    mech.stiffness_curve = test::test_square_stiffness_curve();
    mech.lattice = PerforationLattice::Square;
    mech.lattice_follows_field = true;
    mech.lattice_axis_at = std::move(axis_at);
    return ShellModel(mesh, test::pa12(), lc, mech);
  }
};

/// Per face, the fill-scaled energy of its elements of `kind` (bends: interior faces only, whose
/// patches are complete) in `model`, over the unit energy of the same element in `whole` (the
/// linear model: the solid's energy at this state).
Eigen::VectorXd energy_ratio(const ShellModel& model, const ShellModel& whole, const RowMatX3d& x,
                             const Eigen::VectorXd& alpha, ElementKind kind) {
  ElementEnergies unit, unit_whole;
  shell_energy(model, x, alpha, &unit);
  shell_energy(whole, x, alpha, &unit_whole);
  const int nf = model.num_faces();
  Eigen::VectorXd scaled = Eigen::VectorXd::Zero(nf), solid = Eigen::VectorXd::Constant(nf, NAN);
  auto face_of = [&](const ShellModel& m, const ElementRef& r) { return r.kind == ElementKind::Bend ? m.bends()[size_t(r.index)].face : r.index; };
  for (int e = 0; e < model.num_elements(); ++e) {
    const ElementRef r = model.element(e);
    if (r.kind == kind) scaled[face_of(model, r)] += element_fill_factor(model, alpha, e) * unit[e];
  }
  for (int e = 0; e < whole.num_elements(); ++e) {
    const ElementRef r = whole.element(e);
    if (r.kind != kind) continue;
    if (kind == ElementKind::Bend) {
      const auto& across = whole.bends()[size_t(r.index)].rest.across;
      if (across[0] != PatchNode::Vertex || across[1] != PatchNode::Vertex || across[2] != PatchNode::Vertex) continue;
    }
    solid[face_of(whole, r)] = unit_whole[e];
  }
  return scaled.cwiseQuotient(solid);
}

TEST(IsotropicSplit, UniformEquibiaxialAndDeviatoricStatesScaleByTheirOwnModulus) {
  const FlatPlate p;
  const ShellModel split = p.model(FillStiffness::Homogenised), linear = p.model(FillStiffness::Linear);
  const FillStiffnessMap& g = split.fill_stiffness();
  const RowMatX3d& X = p.mesh.vertices();
  struct State {
    const char* name;
    ElementKind kind;
    FillPart part;
    double tolerance;  ///< relative; the simple shear's trace is γ²/2, not 0
    std::function<Vec3(const Vec3&)> displacement;
  };
  const double e = 2e-3, gamma = 1e-6, kappa = 0.05;
  const std::vector<State> states = {
      {"equibiaxial stretch", ElementKind::Membrane, FillPart::Bulk, 1e-12, [&](const Vec3& q) { return Vec3(e * q.x(), e * q.y(), 0); }},
      {"simple shear", ElementKind::Membrane, FillPart::Shear, 1e-5, [&](const Vec3& q) { return Vec3(gamma * q.y(), 0, 0); }},
      {"spherical curvature", ElementKind::Bend, FillPart::Bulk, 1e-9,
       [&](const Vec3& q) { return Vec3(0, 0, 0.5 * kappa * (q.x() * q.x() + q.y() * q.y())); }},
      {"saddle curvature", ElementKind::Bend, FillPart::Shear, 1e-9,
       [&](const Vec3& q) { return Vec3(0, 0, 0.5 * kappa * (q.x() * q.x() - q.y() * q.y())); }},
  };
  for (const State& s : states) {
    SCOPED_TRACE(s.name);
    RowMatX3d x = X;
    for (int v = 0; v < x.rows(); ++v) x.row(v) += s.displacement(X.row(v).transpose()).transpose();
    const Eigen::VectorXd ratio = energy_ratio(split, linear, x, p.alpha, s.kind);
    int checked = 0;
    for (int t = 0; t < ratio.size(); ++t) {
      if (std::isnan(ratio[t])) continue;  // a bend at the boundary
      const double expected = g.factor(s.kind == ElementKind::Bend, s.part, p.alpha[t]);
      EXPECT_NEAR(ratio[t], expected, s.tolerance * expected) << "face " << t << " α " << p.alpha[t];
      ++checked;
    }
    EXPECT_GT(checked, p.mesh.num_faces() / 2);
  }
  // The two parts differ where the test curve says so (bending bulk 0.50 against shear 0.91 at
  // α = 0.6): a scalar rule could not pass both curvature states.
  EXPECT_LT(g.factor(true, FillPart::Bulk, 0.6), 0.6 * g.factor(true, FillPart::Shear, 0.6));
}

// The square lattice's anisotropic part (fill_stiffness_map.h). On a flat plate whose lattice axis
// lies at 30° to x — and so at other angles to each face's own frame (its first edge) — a uniform
// deviator along the lattice's axes stores g_G (1 + q) times the solid's energy and one at 45° to
// them g_G (1 − q), in stretch and in bending; equibiaxial states g_K, as on the hexagonal lattice.
// A wrong sign of 4φ, a frame mix-up or a missing part fails one of the eight.
TEST(SquareLattice, UniformDeviatorsAlongAndAcrossItsAxesStoreTheirOwnModuli) {
  const FlatPlate p;
  const double theta = std::numbers::pi / 6;
  const ShellModel square = p.square(Vec3(std::cos(theta), std::sin(theta), 0)), linear = p.model(FillStiffness::Linear);
  const FillStiffnessMap& g = square.fill_stiffness();
  ASSERT_TRUE(g.anisotropic());
  EXPECT_EQ(square.num_elements(), linear.num_elements() + 2 * 2 * p.mesh.num_faces());
  const RowMatX3d& X = p.mesh.vertices();
  const double e = 1e-3, kappa = 0.05;
  struct State {
    std::string name;
    ElementKind kind;
    double sign;  ///< +1 along the axes (G₁), −1 at 45° (G₂), 0 equibiaxial (K)
    double tolerance;
    std::function<Vec3(const Vec3&)> displacement;
  };
  std::vector<State> states;
  for (const double sign : {1.0, -1.0}) {
    const double a = theta + (sign > 0 ? 0.0 : std::numbers::pi / 4);
    const Eigen::Vector2d n(std::cos(a), std::sin(a)), m(-std::sin(a), std::cos(a));
    const std::string where = sign > 0 ? " along the axes" : " at 45°";
    // u = e (n nᵀ − m mᵀ) q: E = ε + ½ e² I, the quadratic part an isotropic e⁴ term.
    states.push_back({"deviatoric stretch" + where, ElementKind::Membrane, sign, 1e-5, [=](const Vec3& q) {
                        const Eigen::Vector2d u = e * (n * n.dot(q.head<2>()) - m * m.dot(q.head<2>()));
                        return Vec3(u.x(), u.y(), 0);
                      }});
    states.push_back({"saddle curvature" + where, ElementKind::Bend, sign, 1e-9, [=](const Vec3& q) {
                        const double s = n.dot(q.head<2>()), t = m.dot(q.head<2>());
                        return Vec3(0, 0, 0.5 * kappa * (s * s - t * t));
                      }});
  }
  states.push_back({"equibiaxial stretch", ElementKind::Membrane, 0, 1e-12,
                    [&](const Vec3& q) { return Vec3(e * q.x(), e * q.y(), 0); }});
  states.push_back({"spherical curvature", ElementKind::Bend, 0, 1e-9,
                    [&](const Vec3& q) { return Vec3(0, 0, 0.5 * kappa * (q.x() * q.x() + q.y() * q.y())); }});
  for (const State& s : states) {
    SCOPED_TRACE(s.name);
    RowMatX3d x = X;
    for (int v = 0; v < x.rows(); ++v) x.row(v) += s.displacement(X.row(v).transpose()).transpose();
    const Eigen::VectorXd ratio = energy_ratio(square, linear, x, p.alpha, s.kind);
    const bool bend = s.kind == ElementKind::Bend;
    int checked = 0;
    for (int t = 0; t < ratio.size(); ++t) {
      if (std::isnan(ratio[t])) continue;  // a bend at the boundary
      const double a = p.alpha[t];
      const double expected = s.sign == 0 ? g.factor(bend, FillPart::Bulk, a)
                                          : g.factor(bend, FillPart::Shear, a) * (1 + s.sign * g.anisotropy(bend, a));
      EXPECT_NEAR(ratio[t], expected, s.tolerance * expected) << "face " << t << " α " << a;
      ++checked;
    }
    EXPECT_GT(checked, p.mesh.num_faces() / 2);
  }
  // The test curve's membrane q is 0.33 at α = 0.6: the axes' and the diagonal's moduli differ by 2×.
  EXPECT_GT(g.anisotropy(false, 0.6), 0.3);
}

// The lattice's axis is projected onto each face: an axis normal to a flat plate gives no direction
// and the isotropic parts alone (the anisotropic parts store nothing); one tilted out of the plane
// is its projection's.
TEST(SquareLattice, TheAxisIsProjectedOntoEachFace) {
  const FlatPlate p;
  const ShellModel normal = p.square(Vec3::UnitZ()), tilted = p.square(Vec3(1, 1, 3)),
                   flat = p.square(Vec3(1, 1, 0));
  for (const Eigen::Vector2d& o : normal.lattice_orientation()) EXPECT_EQ(o.norm(), 0.0);
  // An axis and the one at 90° to it in the plane are the same square lattice.
  const ShellModel along_x = p.square(Vec3::UnitX()), along_y = p.square(Vec3::UnitY());
  for (int f = 0; f < p.mesh.num_faces(); ++f)
    EXPECT_NEAR((along_x.lattice_orientation()[size_t(f)] - along_y.lattice_orientation()[size_t(f)]).norm(), 0.0, 1e-12);
  for (int f = 0; f < p.mesh.num_faces(); ++f) {
    EXPECT_NEAR((tilted.lattice_orientation()[size_t(f)] - flat.lattice_orientation()[size_t(f)]).norm(), 0.0, 1e-12);
    EXPECT_NEAR(flat.lattice_orientation()[size_t(f)].norm(), 1.0, 1e-12);
  }
  RowMatX3d x = p.mesh.vertices();
  for (int v = 0; v < x.rows(); ++v) x(v, 0) += 1e-3 * x(v, 0);
  ElementEnergies unit;
  shell_energy(normal, x, p.alpha, &unit);
  for (int e = 0; e < normal.num_elements(); ++e)
    if (normal.element(e).part == FillPart::Anisotropy) {
      EXPECT_EQ(unit[e], 0.0);
    }
}

// A lattice that follows the orientation field reads its axis at each face's centroid: a constant
// field is the one axis; a field that turns with x gives each face its own centroid's axis; without
// the field's function attached the model refuses to guess.
TEST(SquareLattice, AnAxisThatFollowsAFieldIsReadAtEachFace) {
  const FlatPlate p;
  const Vec3 a(std::cos(0.4), std::sin(0.4), 0);
  const ShellModel one = p.square(a), constant = p.square_by_field([&](const Vec3&) { return a; });
  for (int f = 0; f < p.mesh.num_faces(); ++f)
    EXPECT_EQ((one.lattice_orientation()[size_t(f)] - constant.lattice_orientation()[size_t(f)]).norm(), 0.0);
  const ShellModel turning = p.square_by_field([](const Vec3& q) { return Vec3(std::cos(3 * q.x()), std::sin(3 * q.x()), 0); });
  const auto& F = p.mesh.faces();
  const RowMatX3d& X = p.mesh.vertices();
  for (int f = 0; f < p.mesh.num_faces(); f += 7) {  // one model per sampled face
    const Vec3 c = (X.row(F(f, 0)) + X.row(F(f, 1)) + X.row(F(f, 2))).transpose() / 3;
    const ShellModel here = p.square(Vec3(std::cos(3 * c.x()), std::sin(3 * c.x()), 0));
    EXPECT_NEAR((turning.lattice_orientation()[size_t(f)] - here.lattice_orientation()[size_t(f)]).norm(), 0.0, 1e-12);
  }
  EXPECT_THROW(p.square_by_field(nullptr), InternalError);
}

}  // namespace
}  // namespace cutwork::solvers
