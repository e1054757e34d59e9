// "lattice": "auto" read from stencils on a surface (solvers/homogenise/fill_stiffness_calibration.h
// measured_lattice) and what the reports say of the stencils' order (solvers/report/run_report.h
// lattice_order_json): stencils on a plane, their frames from a fixed-axis field.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "host/mesh/bvh.h"
#include "host/stencil/frame.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/report/run_report.h"

namespace cutwork::solvers {
namespace {

constexpr double kDegree = std::numbers::pi / 180;

/// A 60 × 60 square in z = 0, two triangles.
SurfaceMesh plane() {
  RowMatX3d v(4, 3);
  v << -30, -30, 0, 30, -30, 0, 30, 30, 0, -30, 30, 0;
  RowMatX3i f(2, 3);
  f << 0, 1, 2, 0, 2, 3;
  return SurfaceMesh(std::move(v), std::move(f), "plane");
}

/// A square grid of spacing 1 turned by `degrees`, n × n, centred at `centre`.
void add_grid(std::vector<StencilParams>& out, double degrees, int n, const Vec3& centre) {
  const double c = std::cos(degrees * kDegree), s = std::sin(degrees * kDegree);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = i - (n - 1) / 2.0, y = j - (n - 1) / 2.0;
      StencilParams p;
      p.position = centre + Vec3(c * x - s * y, s * x + c * y, 0);
      p.scale = 0.3;
      out.push_back(p);
    }
}

bool mentions(const std::vector<std::string>& notes, const std::string& fragment) {
  for (const std::string& n : notes)
    if (n.find(fragment) != std::string::npos) return true;
  return false;
}

MechanicsSettings automatic() {
  MechanicsSettings m;
  m.lattice_source = LatticeSource::Auto;
  return m;
}

TEST(LatticeReading, AutoReadsTheGridsAxisAndAStatedLatticeIsKept) {
  const SurfaceMesh mesh = plane();
  const FaceBvh bvh(mesh);
  const AxisTangentField field;
  std::vector<StencilParams> grid;
  add_grid(grid, 30, 12, Vec3::Zero());
  std::vector<std::string> notes;
  const MechanicsSettings read = measured_lattice(automatic(), bvh, field, grid, notes);
  EXPECT_EQ(read.lattice, PerforationLattice::Square);
  EXPECT_EQ(read.lattice_source, LatticeSource::Stencils);
  EXPECT_FALSE(read.lattice_follows_field);
  const double theta = std::atan2(read.lattice_axis.y(), read.lattice_axis.x());
  EXPECT_GT(std::cos(4 * (theta - 30 * kDegree)), 1 - 1e-9);
  EXPECT_TRUE(notes.empty());
  // Its report: measured as used, no note.
  nlohmann::json order = lattice_order_json(read, bvh, field, grid, notes);
  EXPECT_EQ(order["stated"], "auto");
  EXPECT_EQ(order["used"], "square");
  EXPECT_NEAR(order["axis_misfit_degrees"].get<double>(), 0.0, 1e-6);
  EXPECT_TRUE(notes.empty());

  // Stated hexagonal: kept, and the report says the stencils form a square lattice.
  MechanicsSettings hexagonal;
  const MechanicsSettings kept = measured_lattice(hexagonal, bvh, field, grid, notes);
  EXPECT_EQ(kept.lattice, PerforationLattice::Hexagonal);
  EXPECT_EQ(kept.lattice_source, LatticeSource::Scene);
  order = lattice_order_json(kept, bvh, field, grid, notes);
  EXPECT_EQ(order["stated"], "hexagonal");
  EXPECT_TRUE(mentions(notes, "the stencils lie on a square lattice")) << ::testing::PrintToString(notes);

  // Without stencils auto stays hexagonal, not yet read.
  notes.clear();
  const MechanicsSettings none = measured_lattice(automatic(), bvh, field, {}, notes);
  EXPECT_EQ(none.lattice, PerforationLattice::Hexagonal);
  EXPECT_EQ(none.lattice_source, LatticeSource::Auto);
}

// Three square patches at 0°, 30° and 60° under a fixed-axis field: neither one axis nor the field
// fits, so auto keeps the isotropic calibration and says why; the report then does not advise a
// square lattice the model could not follow.
TEST(LatticeReading, ATurningLatticeKeepsTheIsotropicCalibrationWithOneNote) {
  const SurfaceMesh mesh = plane();
  const FaceBvh bvh(mesh);
  const AxisTangentField field;
  std::vector<StencilParams> patches;
  for (int k = 0; k < 3; ++k) add_grid(patches, 30.0 * k, 8, Vec3(-18 + 18.0 * k, 0, 0));
  std::vector<std::string> notes;
  const MechanicsSettings read = measured_lattice(automatic(), bvh, field, patches, notes);
  EXPECT_EQ(read.lattice, PerforationLattice::Hexagonal);
  EXPECT_EQ(read.lattice_source, LatticeSource::Stencils);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("turn over the surface"), std::string::npos) << notes[0];
  notes.clear();
  lattice_order_json(read, bvh, field, patches, notes);
  EXPECT_FALSE(mentions(notes, "the stencils lie on a square lattice")) << ::testing::PrintToString(notes);
  MechanicsSettings hexagonal;  // stated: no advice to state what the model cannot follow either
  lattice_order_json(hexagonal, bvh, field, patches, notes);
  EXPECT_TRUE(notes.empty()) << ::testing::PrintToString(notes);
}

// "lattice_axis": "field" stated: the axis function is attached, the field's direction (x here).
TEST(LatticeReading, AStatedFieldAxisGetsTheFieldsDirection) {
  const SurfaceMesh mesh = plane();
  const FaceBvh bvh(mesh);
  const AxisTangentField field;
  MechanicsSettings stated;
  stated.lattice = PerforationLattice::Square;
  stated.lattice_follows_field = true;
  std::vector<std::string> notes;
  const MechanicsSettings m = measured_lattice(stated, bvh, field, {}, notes);
  ASSERT_TRUE(bool(m.lattice_axis_at));
  EXPECT_NEAR((m.lattice_axis_at(Vec3(3, -2, 0)) - Vec3::UnitX()).norm(), 0.0, 1e-12);
  EXPECT_FALSE(bool(measured_lattice(MechanicsSettings{}, bvh, field, {}, notes).lattice_axis_at));
}

}  // namespace
}  // namespace cutwork::solvers
