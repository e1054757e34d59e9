// The fill stiffness rules (fill_stiffness_map.h): the monotone interpolant through its samples,
// its derivatives against central differences, the linear rule, and malformed curves.
#include <gtest/gtest.h>

#include "host/core/error.h"
#include "solvers/shell/fill_stiffness_map.h"
#include "tests/solvers/support/shell_fixtures.h"

namespace cutwork::solvers {
namespace {

MechanicsSettings homogenised(const FillStiffnessCurve& curve) {
  MechanicsSettings m;
  m.stiffness = FillStiffness::Homogenised;
  m.stiffness_curve = curve;
  return m;
}

TEST(FillStiffnessMap, LinearRuleIsTheFillRatio) {
  const FillStiffnessMap g;
  for (double a : {1e-4, 0.3, 0.77, 1.0}) {
    double d = -1;
    EXPECT_EQ(g.membrane(a, &d), a);
    EXPECT_EQ(d, 1.0);
    EXPECT_EQ(g.bending(a), a);
    EXPECT_EQ(g.membrane_ratio(a, &d), 1.0);
    EXPECT_EQ(d, 0.0);
  }
  EXPECT_TRUE(FillStiffnessMap(MechanicsSettings{}).linear());
}

TEST(FillStiffnessMap, InterpolatesMonotonicallyThroughTheSamples) {
  const FillStiffnessCurve c = test::test_stiffness_curve();
  const FillStiffnessMap g(homogenised(c));
  ASSERT_FALSE(g.linear());
  for (size_t k = 0; k < c.alpha.size(); ++k) {
    EXPECT_NEAR(g.membrane_ratio(c.alpha[k]), c.membrane[k], 1e-15);
    EXPECT_NEAR(g.bending(c.alpha[k]), c.alpha[k] * c.bending[k], 1e-15);
  }
  // Monotone between samples (the data are), constant below the first sample, g(1) = 1.
  double last_r = 0, last_g = 0;
  for (double a = 1e-4; a <= 1.0; a += 1e-3) {
    const double r = g.membrane_ratio(a), v = g.membrane(a);
    EXPECT_GE(r, last_r - 1e-15);
    EXPECT_GT(v, last_g);
    last_r = r;
    last_g = v;
  }
  EXPECT_EQ(g.membrane_ratio(0.1), c.membrane.front());
  EXPECT_EQ(g.membrane(1.0), 1.0);
}

TEST(FillStiffnessMap, DerivativesMatchCentralDifferencesAndAreContinuous) {
  const FillStiffnessMap g(homogenised(test::test_stiffness_curve()));
  const double h = 1e-6;
  for (double a = 0.05; a < 0.999; a += 0.0137) {
    double dm = 0, db = 0;
    g.membrane(a, &dm);
    g.bending(a, &db);
    EXPECT_NEAR(dm, (g.membrane(a + h) - g.membrane(a - h)) / (2 * h), 1e-6) << "alpha " << a;
    EXPECT_NEAR(db, (g.bending(a + h) - g.bending(a - h)) / (2 * h), 1e-6) << "alpha " << a;
  }
  // C¹ at every sample: one-sided slopes agree.
  for (double a : test::test_stiffness_curve().alpha) {
    if (a >= 1) continue;
    double left = 0, right = 0;
    g.membrane(a - 1e-9, &left);
    g.membrane(a + 1e-9, &right);
    EXPECT_NEAR(left, right, 1e-6) << "alpha " << a;
  }
}

TEST(FillStiffnessMap, RejectsMalformedCurves) {
  FillStiffnessCurve c = test::test_stiffness_curve();
  EXPECT_THROW(FillStiffnessMap(homogenised({})), InputError);
  c.alpha[2] = c.alpha[1];
  EXPECT_THROW(FillStiffnessMap(homogenised(c)), InputError);
  c = test::test_stiffness_curve();
  c.membrane.back() = 0.9;
  EXPECT_THROW(FillStiffnessMap(homogenised(c)), InputError);
  c = test::test_stiffness_curve();
  c.bending.pop_back();
  EXPECT_THROW(FillStiffnessMap(homogenised(c)), InputError);
  c = test::test_stiffness_curve();
  c.membrane[0] = 0;
  EXPECT_THROW(FillStiffnessMap(homogenised(c)), InputError);
  // The split comes whole or not at all, each part a curve of its own.
  c = test::test_stiffness_curve();
  c.bending_shear.clear();
  EXPECT_THROW(FillStiffnessMap(homogenised(c)), InputError);
  c = test::test_stiffness_curve();
  c.membrane_bulk.back() = 0.95;
  EXPECT_THROW(FillStiffnessMap(homogenised(c)), InputError);
  c = test::test_stiffness_curve();
  c.bending_bulk[1] = -0.1;
  EXPECT_THROW(FillStiffnessMap(homogenised(c)), InputError);
}

// The split's four parts interpolate their own samples, with derivatives matching central
// differences; Whole is the scalar curve.
TEST(FillStiffnessMap, SplitPartsInterpolateTheirOwnSamples) {
  const FillStiffnessCurve c = test::test_stiffness_curve();
  const FillStiffnessMap g(homogenised(c));
  ASSERT_TRUE(g.split());
  EXPECT_FALSE(FillStiffnessMap(homogenised(test::test_scalar_stiffness_curve())).split());
  const std::vector<double>* samples[2][2] = {{&c.membrane_bulk, &c.membrane_shear}, {&c.bending_bulk, &c.bending_shear}};
  for (bool bending : {false, true})
    for (FillPart part : {FillPart::Bulk, FillPart::Shear}) {
      const std::vector<double>& r = *samples[bending][part == FillPart::Shear];
      for (size_t k = 0; k < c.alpha.size(); ++k) {
        EXPECT_NEAR(g.part_ratio(bending, part, c.alpha[k]), r[k], 1e-15);
        EXPECT_NEAR(g.factor(bending, part, c.alpha[k]), c.alpha[k] * r[k], 1e-15);
      }
      const double h = 1e-6;
      for (double a = 0.05; a < 0.999; a += 0.0137) {
        double d = 0, dr = 0;
        g.factor(bending, part, a, &d);
        g.part_ratio(bending, part, a, &dr);
        EXPECT_NEAR(d, (g.factor(bending, part, a + h) - g.factor(bending, part, a - h)) / (2 * h), 1e-6);
        EXPECT_NEAR(dr, (g.part_ratio(bending, part, a + h) - g.part_ratio(bending, part, a - h)) / (2 * h), 1e-6);
      }
    }
  for (double a : {0.2, 0.5, 0.93}) {
    EXPECT_EQ(g.factor(false, FillPart::Whole, a), g.membrane(a));
    EXPECT_EQ(g.factor(true, FillPart::Whole, a), g.bending(a));
  }
}

}  // namespace
}  // namespace cutwork::solvers
