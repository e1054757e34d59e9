// The sizing field: constant, per-vertex file (and its errors), brushes.
#include <gtest/gtest.h>

#include <fstream>

#include "host/core/error.h"
#include "host/field/sizing_field.h"
#include "tests/support/test_support.h"
#include "../pattern/pattern_test_util.h"

namespace cutwork {
namespace {

TEST(SizingField, ConstantAndInterpolation) {
  const SurfaceMesh mesh = test::flat_plate(0.2, 0.1, 0.01);
  PatternSettings ps;
  ps.sizing = 1.7;
  const SizingField f = SizingField::from_settings(ps, mesh);
  EXPECT_EQ(f.vertex_values().size(), mesh.num_vertices());
  EXPECT_DOUBLE_EQ(f.min_value(), 1.7);
  EXPECT_DOUBLE_EQ(f.max_value(), 1.7);
  EXPECT_NEAR(f.value(mesh, SurfacePoint{3, Vec3(0.2, 0.3, 0.5)}), 1.7, 1e-15);
  EXPECT_NEAR(f.mean_power(mesh, -2), 1 / (1.7 * 1.7), 1e-14);
}

TEST(SizingField, BrushesPaintAbsoluteValuesSmoothly) {
  const SurfaceMesh mesh = test::flat_plate(0.2, 0.1, 0.005);
  PatternSettings ps;
  ps.brushes = {SizingBrush{Vec3(0.05, 0.05, 0), 0.04, 2.0}, SizingBrush{Vec3(0.15, 0.05, 0), 0.03, 0.5}};
  const SizingField f = SizingField::from_settings(ps, mesh);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 x = mesh.vertices().row(v).transpose();
    const double d1 = (x - ps.brushes[0].center).norm(), d2 = (x - ps.brushes[1].center).norm();
    const double val = f.vertex_values()[v];
    if (d1 <= 0.02) {
      EXPECT_DOUBLE_EQ(val, 2.0);  // inner half: the brush's value
    }
    if (d2 <= 0.015) {
      EXPECT_DOUBLE_EQ(val, 0.5);
    }
    if (d1 >= 0.04 && d2 >= 0.03) {
      EXPECT_DOUBLE_EQ(val, 1.0);  // outside: untouched
    }
    EXPECT_GE(val, 0.5);
    EXPECT_LE(val, 2.0);
  }
  // The weight is C¹: 1 → 0 between half the radius and the radius, flat at both ends.
  EXPECT_DOUBLE_EQ(brush_weight(0.5), 1.0);
  EXPECT_DOUBLE_EQ(brush_weight(1.0), 0.0);
  EXPECT_NEAR(brush_weight(0.75), 0.5, 1e-15);
  const double h = 1e-6;
  EXPECT_NEAR((brush_weight(0.5 + h) - brush_weight(0.5)) / h, 0.0, 1e-4);
  EXPECT_NEAR((brush_weight(1.0) - brush_weight(1.0 - h)) / h, 0.0, 1e-4);
}

TEST(SizingField, FileValuesAndErrors) {
  const SurfaceMesh mesh = test::flat_plate(0.2, 0.1, 0.02);
  const auto dir = test::temp_dir("sizing");
  PatternSettings ps;
  ps.sizing = 2.0;
  ps.sizing_file = dir / "good.txt";
  {
    std::ofstream out(ps.sizing_file);
    out << "# one value per vertex\n";
    for (int v = 0; v < mesh.num_vertices(); ++v) out << 1.0 + 0.001 * v << "\n\n";
  }
  const SizingField f = SizingField::from_settings(ps, mesh);
  for (int v = 0; v < mesh.num_vertices(); ++v)
    EXPECT_NEAR(f.vertex_values()[v], 2.0 * (1.0 + 0.001 * v), 1e-12);

  auto expect_error = [&](const std::string& content, const std::string& fragment) {
    ps.sizing_file = dir / "bad.txt";
    {
      std::ofstream out(ps.sizing_file);
      out << content;
    }
    try {
      SizingField::from_settings(ps, mesh);
      ADD_FAILURE() << "expected an InputError containing '" << fragment << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  };
  expect_error("1\n2\n", "has 2 sizing values but the base mesh has");
  expect_error("1\nabc\n", "bad.txt:2: expected one number per line");
  expect_error("1\n-3\n", "bad.txt:2: sizing value -3 must be finite and positive");
  expect_error("1 2\n", "bad.txt:1: expected one number per line");
  ps.sizing_file = dir / "missing.txt";
  EXPECT_THROW(SizingField::from_settings(ps, mesh), InputError);
}

}  // namespace
}  // namespace cutwork
