// The design's files (host/export/design_files.h): a model of a quarter on two symmetry planes is
// printed whole.
#include "host/export/design_files.h"

#include <gtest/gtest.h>

#include <cmath>

#include "host/cut/cut_surface.h"
#include "host/mesh/bvh.h"
#include "host/surfaces/generators.h"

namespace cutwork {
namespace {

// A quarter of a perforated plate (x ∈ [−0.1, 0], y ∈ [−0.05, 0], the planes x = 0 and y = 0) is
// printed as the whole plate its mirror images make: one closed, manifold, outward solid of four
// times the quarter's volume, which report.json says was mirrored across x and y; without planes the
// quarter itself.
TEST(DesignFiles, AQuarterOnTwoSymmetryPlanesIsPrintedWhole) {
  SurfaceMesh plate = generate_shape("plate", {{"width", 0.1}, {"height", 0.05}}, 0.004);
  RowMatX3d X = plate.vertices();
  X.col(0).array() -= 0.05;
  X.col(1).array() -= 0.025;
  const SurfaceMesh quarter(X, plate.faces(), "quarter");
  const FaceBvh bvh(quarter);
  StencilLibrary shapes;
  shapes.add(make_builtin_stencil("circle", {}, "circle"));
  const AxisTangentField field;
  const std::vector<StencilParams> stencils = {{Vec3(-0.08, -0.025, 0), 0.008}, {Vec3(-0.05, -0.025, 0), 0.008},
                                                {Vec3(-0.02, -0.025, 0), 0.008}};
  const CutSurface cut = cut_stencils(bvh, shapes, field, stencils);
  DesignFileInputs in;
  in.title = "quarter";
  in.base = &quarter;
  in.sim = &quarter;
  in.cut = &cut;
  in.thickness = 0.003;
  DesignFileOptions options;
  options.render = false;
  const nlohmann::json alone = prepare_design_files(in, options).fabrication_report();
  in.symmetry_planes = Vec3(0, 0, NAN);
  const nlohmann::json whole = prepare_design_files(in, options).fabrication_report();
  ASSERT_TRUE(alone["solid"]["valid"].get<bool>()) << alone.dump();
  ASSERT_TRUE(whole["solid"]["valid"].get<bool>()) << whole["solid"].dump();
  EXPECT_TRUE(whole["solid"]["closed"].get<bool>() && whole["solid"]["manifold"].get<bool>() &&
              whole["solid"]["outward"].get<bool>());
  EXPECT_FALSE(whole["solid"]["self_intersecting"].get<bool>());
  EXPECT_NEAR(whole["solid"]["volume"].get<double>(), 4 * alone["solid"]["volume"].get<double>(),
              1e-9 * whole["solid"]["volume"].get<double>());
  EXPECT_NEAR(whole["solid"]["volume"].get<double>(), 4 * cut.area * in.thickness, 1e-9 * whole["solid"]["volume"].get<double>());
  EXPECT_EQ(whole["solid"]["mirrored"], nlohmann::json::array({"x", "y"}));
  EXPECT_EQ(alone["solid"]["mirrored"], nlohmann::json::array());
}

}  // namespace
}  // namespace cutwork
