// The bond-orientational order of stencil centres (host/pattern/lattice_order.h): a square grid
// reads |ψ₄| = 1, |ψ₆| = 0 and its axes' angle from the stated axis; a hexagonal one the other way
// round; a jittered hexagonal one stays hexagonal; a tilted plane is measured in its own tangent
// plane.
#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Geometry>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "host/core/error.h"
#include "host/pattern/lattice_order.h"

namespace cutwork {
namespace {

constexpr double kDegree = std::numbers::pi / 180;

/// Centres of an n × n lattice (spacing 1, second basis vector b) turned by `angle` about z, then
/// by `tilt` about y; normals alike.
void lattice(int n, const Eigen::Vector2d& b, double angle, double tilt, RowMatX3d& centres, RowMatX3d& normals,
             double jitter = 0, unsigned seed = 1) {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(tilt, Vec3::UnitY()) * Eigen::AngleAxisd(angle, Vec3::UnitZ())).matrix();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  centres.resize(n * n, 3);
  normals.resize(n * n, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector2d p = Eigen::Vector2d(i, 0) + j * b - (j / 2) * Eigen::Vector2d(b.x() * 2, 0);
      centres.row(i * n + j) = (R * Vec3(p.x() + u(rng), p.y() + u(rng), 0)).transpose();
      normals.row(i * n + j) = (R * Vec3::UnitZ()).transpose();
    }
}

TEST(LatticeOrder, ASquareGridReadsItsOrderAndItsAxesAngle) {
  RowMatX3d c, nrm;
  for (const double degrees : {0.0, 20.0, 65.0}) {
    SCOPED_TRACE(degrees);
    lattice(14, Eigen::Vector2d(0, 1), degrees * kDegree, 0, c, nrm);
    const LatticeOrder o = measure_lattice_order(c, nrm, Vec3::UnitX());
    EXPECT_GT(o.stencils, 14 * 14 / 2);
    EXPECT_NEAR(o.square, 1.0, 1e-9);
    EXPECT_NEAR(o.hexagonal, 0.0, 1e-9);
    // 65° is 25° from the axis at 90°: the square lattice's axes are 90° apart.
    EXPECT_NEAR(o.axis_misfit, degrees == 65.0 ? 25.0 : degrees, 1e-6);
  }
}

TEST(LatticeOrder, AHexagonalLatticeIsNotSquareAndJitterKeepsItHexagonal) {
  RowMatX3d c, nrm;
  lattice(14, Eigen::Vector2d(0.5, std::sqrt(3.0) / 2), 10 * kDegree, 0, c, nrm);
  LatticeOrder o = measure_lattice_order(c, nrm, Vec3::UnitX());
  EXPECT_NEAR(o.square, 0.0, 1e-9);
  EXPECT_NEAR(o.hexagonal, 1.0, 1e-9);
  lattice(14, Eigen::Vector2d(0.5, std::sqrt(3.0) / 2), 10 * kDegree, 0, c, nrm, 0.08);
  o = measure_lattice_order(c, nrm, Vec3::UnitX());
  EXPECT_LT(o.square, 0.5);
  EXPECT_GT(o.hexagonal, 0.7);
}

TEST(LatticeOrder, ATiltedPlaneIsMeasuredInItsTangentPlane) {
  RowMatX3d c, nrm;
  // A square grid along x in a plane tilted 50° about y: the global x axis projects onto its axis.
  lattice(12, Eigen::Vector2d(0, 1), 0, 50 * kDegree, c, nrm);
  LatticeOrder o = measure_lattice_order(c, nrm, Vec3::UnitX());
  EXPECT_NEAR(o.square, 1.0, 1e-9);
  EXPECT_NEAR(o.axis_misfit, 0.0, 1e-6);
  // An axis normal to the plane gives no direction: the order is measured, the misfit is not.
  o = measure_lattice_order(c, nrm, Vec3(std::sin(50 * kDegree), 0, std::cos(50 * kDegree)));
  EXPECT_NEAR(o.square, 1.0, 1e-9);
  EXPECT_TRUE(std::isnan(o.axis_misfit));
}

/// cos 4θ between two directions: 1 when they are the same square lattice axes (90° apart).
double quarter_turn_fit(const Vec3& a, const Vec3& b) {
  const double theta = std::atan2(a.cross(b).norm(), a.dot(b));
  return std::cos(4 * theta);
}

/// Concatenates (centres, normals) blocks.
void append(RowMatX3d& c, RowMatX3d& n, const RowMatX3d& more_c, const RowMatX3d& more_n, const Vec3& shift) {
  const Eigen::Index k = c.rows();
  c.conservativeResize(k + more_c.rows(), 3);
  n.conservativeResize(k + more_n.rows(), 3);
  c.bottomRows(more_c.rows()) = more_c.rowwise() + shift.transpose();
  n.bottomRows(more_n.rows()) = more_n;
}

// "lattice": "auto" (measure_lattice): a square grid at any angle, in a tilted plane and jittered,
// is read as square along its own axis; the hexagonal lattice and a random arrangement are not.
TEST(LatticeOrder, AutoReadsASquareGridAndItsAxis) {
  RowMatX3d c, nrm;
  for (const double tilt : {0.0, 50.0})
    for (const double degrees : {0.0, 20.0, 65.0}) {
      SCOPED_TRACE(fmt::format("{}° in a plane tilted {}°", degrees, tilt));
      lattice(14, Eigen::Vector2d(0, 1), degrees * kDegree, tilt * kDegree, c, nrm);
      const MeasuredLattice m = measure_lattice(c, nrm);
      EXPECT_TRUE(m.square);
      EXPECT_FALSE(m.turning);
      const Eigen::Matrix3d R =
          (Eigen::AngleAxisd(tilt * kDegree, Vec3::UnitY()) * Eigen::AngleAxisd(degrees * kDegree, Vec3::UnitZ())).matrix();
      EXPECT_GT(quarter_turn_fit(m.axis, R * Vec3::UnitX()), 1 - 1e-9);
      EXPECT_NEAR(m.axis.norm(), 1.0, 1e-12);
      EXPECT_NEAR(m.order.axis_misfit, 0.0, 1e-6);
    }
  // Jittered by 5% of the spacing: still square, the axis within a degree.
  lattice(14, Eigen::Vector2d(0, 1), 20 * kDegree, 0, c, nrm, 0.05);
  const MeasuredLattice jittered = measure_lattice(c, nrm);
  EXPECT_TRUE(jittered.square);
  EXPECT_GT(quarter_turn_fit(jittered.axis, Vec3(std::cos(20 * kDegree), std::sin(20 * kDegree), 0)),
            std::cos(4 * kDegree));

  lattice(14, Eigen::Vector2d(0.5, std::sqrt(3.0) / 2), 10 * kDegree, 0, c, nrm);
  EXPECT_FALSE(measure_lattice(c, nrm).square);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 14);
  for (Eigen::Index i = 0; i < c.rows(); ++i) c.row(i) = Vec3(u(rng), u(rng), 0).transpose();
  nrm.rowwise() = Vec3::UnitZ().transpose();
  const MeasuredLattice random = measure_lattice(c, nrm);
  EXPECT_FALSE(random.square);
  EXPECT_FALSE(random.turning);
}

// On a cylinder (axis y), a grid along its length and round it: one axis, y, fits every stencil.
TEST(LatticeOrder, AutoFindsTheOneAxisOfAGridOnACylinder) {
  const double radius = 5;
  const int around = 24, along = 10;
  RowMatX3d c(around * along, 3), nrm(around * along, 3);
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < along; ++j) {
      const double phi = 0.6 * i / radius;  // arc-length spacing 0.6 round, 0.6 along
      c.row(i * along + j) = Vec3(radius * std::sin(phi), 0.6 * j, radius * std::cos(phi)).transpose();
      nrm.row(i * along + j) = Vec3(std::sin(phi), 0, std::cos(phi)).transpose();
    }
  const MeasuredLattice m = measure_lattice(c, nrm);
  EXPECT_TRUE(m.square);
  EXPECT_GT(std::abs(m.axis.dot(Vec3::UnitY())), 1 - 1e-9);
}

// Three square patches at 0°, 30° and 60°: square order everywhere, but no one axis fits
// (the median misfit is 30°): turning, and not read as square.
TEST(LatticeOrder, AutoDoesNotGiveATurningGridOneAxis) {
  RowMatX3d c(0, 3), nrm(0, 3), pc, pn;
  for (int k = 0; k < 3; ++k) {
    lattice(10, Eigen::Vector2d(0, 1), 30.0 * k * kDegree, 0, pc, pn);
    append(c, nrm, pc, pn, Vec3(30.0 * k, 0, 0));
  }
  const MeasuredLattice m = measure_lattice(c, nrm);
  EXPECT_GT(m.order.square, 0.7);
  EXPECT_TRUE(m.turning);
  EXPECT_FALSE(m.square);
  EXPECT_NEAR(m.order.axis_misfit, 30.0, 1e-6);
}

// The same three patches, each stencil given the field's direction 10° past its patch's axis: the
// lattice follows the field (δ₀ = −10°), and is square; with the field's directions at random it
// does not.
TEST(LatticeOrder, AutoFollowsAFieldTheLatticeTurnsWith) {
  RowMatX3d c(0, 3), nrm(0, 3), pc, pn;
  std::vector<double> patch_angle;
  for (int k = 0; k < 3; ++k) {
    lattice(10, Eigen::Vector2d(0, 1), 30.0 * k * kDegree, 0, pc, pn);
    append(c, nrm, pc, pn, Vec3(30.0 * k, 0, 0));
    patch_angle.insert(patch_angle.end(), size_t(pc.rows()), (30.0 * k + 10) * kDegree);
  }
  RowMatX3d t(c.rows(), 3);
  for (Eigen::Index i = 0; i < c.rows(); ++i)
    t.row(i) = Vec3(std::cos(patch_angle[size_t(i)]), std::sin(patch_angle[size_t(i)]), 0).transpose();
  const MeasuredLattice m = measure_lattice(c, nrm, &t);
  EXPECT_TRUE(m.square);
  EXPECT_TRUE(m.follows_field);
  EXPECT_FALSE(m.turning);
  EXPECT_NEAR(m.field_angle, -10 * kDegree, 1e-9);
  EXPECT_NEAR(m.field_misfit, 0.0, 1e-6);
  // Measured from the field's axes (t turned by δ₀) the order has no misfit.
  RowMatX3d axes(c.rows(), 3);
  for (Eigen::Index i = 0; i < c.rows(); ++i)
    axes.row(i) = Vec3(std::cos(patch_angle[size_t(i)] - 10 * kDegree), std::sin(patch_angle[size_t(i)] - 10 * kDegree), 0).transpose();
  EXPECT_NEAR(measure_lattice_order(c, nrm, Vec3::UnitX(), &axes).axis_misfit, 0.0, 1e-6);

  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 2 * std::numbers::pi);
  for (Eigen::Index i = 0; i < c.rows(); ++i) {
    const double a = u(rng);
    t.row(i) = Vec3(std::cos(a), std::sin(a), 0).transpose();
  }
  const MeasuredLattice random = measure_lattice(c, nrm, &t);
  EXPECT_FALSE(random.follows_field);
  EXPECT_FALSE(random.square);
  EXPECT_TRUE(random.turning);
}

TEST(LatticeOrder, RejectsMismatchedInput) {
  RowMatX3d c(5, 3), nrm(4, 3);
  c.setZero();
  nrm.setZero();
  EXPECT_THROW(measure_lattice_order(c, nrm, Vec3::UnitX()), InputError);
  const LatticeOrder few = measure_lattice_order(RowMatX3d::Zero(2, 3), RowMatX3d::Zero(2, 3), Vec3::UnitX());
  EXPECT_EQ(few.stencils, 0);
  EXPECT_TRUE(std::isnan(few.square));
}

}  // namespace
}  // namespace cutwork
