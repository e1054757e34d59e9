// The note a run writes where stencils reach over a symmetry plane (solvers/report/run_report.h):
// the built shell has such a hole united with its mirror image, which the half's model cannot see.
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "solvers/report/run_report.h"

namespace cutwork::solvers {
namespace {

TEST(SymmetryPlaneNotes, NameThePlaneAndTheStencilsThatReachOverIt) {
  LoadCase lc;
  lc.symmetry_planes.y() = -0.025;
  const std::vector<StencilParams> stencils = {
      {Vec3(0.0, -0.0240, 0), 0.0012},   // reaches over y = −0.025 (1 mm away, 1.2 mm radius)
      {Vec3(0.01, -0.0260, 0), 0.0012},  // its centre beyond the plane: over it too
      {Vec3(0.02, -0.0230, 0), 0.0012},  // 2 mm away: clear of it
  };
  std::vector<std::string> notes;
  symmetry_plane_notes(lc, stencils, notes);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("2 stencils reach over the symmetry plane y = -0.025"), std::string::npos) << notes[0];
  notes.clear();
  symmetry_plane_notes(lc, std::vector<StencilParams>{stencils[2]}, notes);
  EXPECT_TRUE(notes.empty());
  // Without a plane, nothing to say.
  symmetry_plane_notes(LoadCase{}, stencils, notes);
  EXPECT_TRUE(notes.empty());
}

}  // namespace
}  // namespace cutwork::solvers
