// Sweep tables: the Pareto front is exactly the non-dominated set (against brute force, with
// ties), and summary.csv reads back cell for cell.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "host/pattern/random.h"
#include "host/sweep/sweep_results.h"

namespace cutwork {
namespace {

std::vector<size_t> brute_force_front(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<size_t> front;
  for (size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) continue;
    bool dominated = false;
    for (size_t j = 0; j < x.size() && !dominated; ++j)
      dominated = std::isfinite(x[j]) && std::isfinite(y[j]) && x[j] <= x[i] && y[j] <= y[i] &&
                  (x[j] < x[i] || y[j] < y[i]);
    if (!dominated) front.push_back(i);
  }
  return front;
}

TEST(SweepResults, ParetoFrontIsTheNonDominatedSet) {
  PatternRng rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + rng.below(30);
    std::vector<double> x(static_cast<size_t>(n)), y(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
      // Coarse values make ties (equal x, equal y, equal points) common; a few non-finite ones.
      x[size_t(i)] = rng.below(8);
      y[size_t(i)] = rng.below(8);
      if (rng.below(20) == 0) y[size_t(i)] = NAN;
    }
    std::vector<size_t> got = pareto_front(x, y);
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, brute_force_front(x, y)) << "trial " << trial;
  }
}

TEST(SweepResults, ParetoFrontIsSortedByX) {
  const std::vector<double> x{0.5, 0.2, 0.9, 0.3}, y{1.0, 3.0, 0.5, 2.0};
  EXPECT_EQ(pareto_front(x, y), (std::vector<size_t>{1, 3, 0, 2}));
}

TEST(SweepResults, SummaryCsvReadsBackAndQuotesReasons) {
  VariantResult ok, bad;
  ok.id = "v001";
  ok.values = {0.003, "star"};
  ok.ok = true;
  ok.stencils = 12;
  ok.material_fraction = 0.75;
  ok.W_max_uncut = 1.5, ok.W_max_pattern = 3.25, ok.W_max_final = 2.125;
  ok.W_peak_final = 7.5, ok.W_lig_final = 9.25;
  ok.compliance = 0.1;
  ok.compliance_error = 0.012345678, ok.converged = 1;
  ok.max_displacement = 1e-3;
  ok.seconds = 2.5;
  bad.id = "v002";
  bad.values = {0.001, "circle"};
  bad.reason = "plate: the load, \"too much\", cannot be carried";
  const CsvTable t = parse_csv(summary_csv({"/material/thickness", "/stencils/0/kind"}, {ok, bad}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.header[1], "/material/thickness");
  EXPECT_EQ(t.rows[0][t.column("/stencils/0/kind")], "star");
  EXPECT_EQ(t.rows[0][t.column("status")], "ok");
  EXPECT_EQ(std::stod(t.rows[0][t.column("W_max_final")]), 2.125);
  EXPECT_EQ(std::stod(t.rows[0][t.column("material_fraction")]), 0.75);
  EXPECT_EQ(t.rows[1][t.column("status")], "failed");
  EXPECT_EQ(t.rows[1][t.column("reason")], bad.reason);
  EXPECT_EQ(t.rows[1][t.column("W_max_final")], "");
  EXPECT_EQ(std::stod(t.rows[0][t.column("W_peak_final")]), 7.5);
  EXPECT_EQ(std::stod(t.rows[0][t.column("W_lig_final")]), 9.25);
  EXPECT_EQ(t.rows[0][t.column("compliance_error")], "0.01235");  // four digits
  EXPECT_EQ(t.rows[0][t.column("converged")], "yes");
  EXPECT_EQ(t.rows[1][t.column("converged")], "");  // not estimated
  // The marker round trip keeps every field.
  const VariantResult back = VariantResult::from_json(ok.to_json(), "test");
  EXPECT_EQ(back.to_json(), ok.to_json());
  VariantResult no = ok;
  no.converged = 0;
  EXPECT_EQ(VariantResult::from_json(no.to_json(), "test").converged, 0);
  EXPECT_EQ(parse_csv(summary_csv({"/a", "/b"}, {no})).rows[0][t.column("converged")], "no");
  // A marker of an older sweep (without the estimate's fields) still reads, as not estimated.
  nlohmann::json old_marker = ok.to_json();
  for (const char* key : {"W_peak_final", "W_lig_final", "compliance_error", "converged"}) old_marker.erase(key);
  const VariantResult old = VariantResult::from_json(old_marker, "test");
  EXPECT_EQ(old.converged, -1);
  EXPECT_TRUE(std::isnan(old.compliance_error));
}

TEST(SweepResults, TheReportsEstimateAndPeaksReachTheSummary) {
  // take_report reads what a design's report.json says (solvers/report/design_report.h).
  nlohmann::json report = {{"stencils", {{"count", 3}}},
                           {"structure",
                            {{"material_fraction_final", 0.8},
                             {"W_max_uncut", 1.0},
                             {"W_max_pattern", 2.0},
                             {"W_max_final", 1.5},
                             {"W_peak_max_final", 4.5},
                             {"ligaments", {{"W_ligament_max", 6.0}}},
                             {"compliance_final", 0.25},
                             {"max_displacement_final", 0.01}}},
                           {"discretisation", {{"final", {{"estimated_error", 0.031}, {"converged", false}}}}}};
  VariantResult r;
  r.take_report(report);
  EXPECT_EQ(r.W_peak_final, 4.5);
  EXPECT_EQ(r.W_lig_final, 6.0);
  EXPECT_EQ(r.compliance_error, 0.031);
  EXPECT_EQ(r.converged, 0);
  report.erase("discretisation");  // --no-discretisation-estimate
  report["structure"].erase("ligaments");
  VariantResult s;
  s.take_report(report);
  EXPECT_EQ(s.converged, -1);
  EXPECT_TRUE(std::isnan(s.compliance_error));
  EXPECT_TRUE(std::isnan(s.W_lig_final));
}

TEST(SweepResults, FrontsSkipFailedVariants) {
  std::vector<VariantResult> r(3);
  for (int i = 0; i < 3; ++i) {
    r[size_t(i)].id = std::string("v").append(std::to_string(i));
    r[size_t(i)].ok = i != 1;
    r[size_t(i)].material_fraction = 0.5 + 0.1 * i;
    r[size_t(i)].W_max_final = 3.0 - i;
    r[size_t(i)].compliance = 1.0;
  }
  r[1].material_fraction = 0.1;  // would dominate, but failed
  const ParetoFronts f = sweep_pareto_fronts(r);
  EXPECT_EQ(f.w_max, (std::vector<size_t>{0, 2}));
  EXPECT_EQ(f.compliance, (std::vector<size_t>{0}));
}

}  // namespace
}  // namespace cutwork
