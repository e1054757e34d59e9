// The bond-orientational order of stencil centres (host/pattern/lattice_order.h): a square grid
// reads |ψ₄| = 1, |ψ₆| = 0 and its axes' angle from the stated axis; a hexagonal one the other way
// round; a jittered hexagonal one stays hexagonal; a tilted plane is measured in its own tangent
// plane.
#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Geometry>
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
