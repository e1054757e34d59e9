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
  ok.compliance = 0.1;
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
  // The marker round trip keeps every field.
  const VariantResult back = VariantResult::from_json(ok.to_json(), "test");
  EXPECT_EQ(back.to_json(), ok.to_json());
}

TEST(SweepResults, FrontsSkipFailedVariants) {
  std::vector<VariantResult> r(3);
  for (int i = 0; i < 3; ++i) {
    r[size_t(i)].id = "v" + std::to_string(i);
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
