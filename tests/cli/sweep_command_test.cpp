// `cutwork sweep`: a tiny plate sweep run uninterrupted, killed part way and resumed, run again
// when finished, and under `mpirun -n 2`; one variant fails and the others go on; the Pareto
// front is the non-dominated set of summary.csv; a bad variant is refused before anything runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "host/scene/scene.h"
#include "host/sweep/sweep_results.h"
#include "solvers/report/design_memory.h"
#include "tests/support/test_support.h"

namespace cutwork {
namespace {

namespace fs = std::filesystem;
using test::run_cutwork;
using test::run_shell;

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Four plate variants, two iterations per phase: thickness × where the clamp is. A clamp at
// x < -1 selects no vertex, so v002 and v004 fail when they run (a combination the scene's
// schema accepts but the mesh cannot).
const char* kSweep = R"({
  "name": "tiny-plate",
  "base": "plate",
  "design": {"iterations": 2},
  "axes": [
    {"path": "/material/thickness", "values": [0.002, 0.004]},
    {"path": "/supports/0/select/x/below", "values": [0.0001, -1]}
  ]
})";

fs::path write_sweep(const fs::path& dir, const std::string& text = kSweep) {
  fs::create_directories(dir);
  const fs::path p = dir / "sweep.json";
  std::ofstream(p) << text;
  return p;
}

// summary.csv without its timing column (the only one that differs between equal runs).
std::vector<std::vector<std::string>> summary_without_seconds(const fs::path& out) {
  const CsvTable t = parse_csv(read_text(out / "summary.csv"));
  const size_t s = t.column("seconds");
  std::vector<std::vector<std::string>> rows;
  for (auto row : t.rows) {
    row.erase(row.begin() + std::ptrdiff_t(s));
    rows.push_back(row);
  }
  return rows;
}

class SweepCommand : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root() = test::temp_dir("sweep_command");
    const fs::path sweep = write_sweep(root());
    const auto r = run_cutwork("sweep " + sweep.string() + " --out " + (root() / "reference").string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    reference_log() = r.err;
  }
  static fs::path& root() {
    static fs::path p;
    return p;
  }
  static std::string& reference_log() {
    static std::string s;
    return s;
  }
  static fs::path reference() { return root() / "reference"; }
};

TEST_F(SweepCommand, EveryVariantHasItsFolderAndAFailingOneDoesNotStopTheOthers) {
  const CsvTable t = parse_csv(read_text(reference() / "summary.csv"));
  ASSERT_EQ(t.rows.size(), 4u);
  const std::vector<std::string> ids{"v001", "v002", "v003", "v004"};
  for (size_t i = 0; i < 4; ++i) {
    const auto& row = t.rows[i];
    EXPECT_EQ(row[t.column("id")], ids[i]);
    const fs::path dir = reference() / "variants" / ids[i];
    EXPECT_TRUE(fs::exists(dir / "scene.json"));
    EXPECT_TRUE(fs::exists(dir / "result.json"));
    const bool fails = i % 2 == 1;
    EXPECT_EQ(row[t.column("status")], fails ? "failed" : "ok") << row[t.column("reason")];
    if (fails) {
      EXPECT_NE(row[t.column("reason")].find("/supports/0/select"), std::string::npos) << row[t.column("reason")];
      EXPECT_FALSE(fs::exists(dir / "report.json"));
      continue;
    }
    // A successful variant is a full design: the standard outputs, and the summary says what its report says.
    for (const char* f : {"report.json", "stencils.json", "fields.ply", "cut.obj"}) EXPECT_TRUE(fs::exists(dir / f)) << f;
    std::ifstream in(dir / "report.json");
    const nlohmann::json report = nlohmann::json::parse(in);
    EXPECT_EQ(std::stod(row[t.column("W_max_final")]), report["structure"]["W_max_final"].get<double>());
    EXPECT_EQ(std::stod(row[t.column("material_fraction")]), report["structure"]["material_fraction_final"].get<double>());
    EXPECT_EQ(std::stoi(row[t.column("stencils")]), report["stencils"]["count"].get<int>());
    EXPECT_EQ(std::stod(row[t.column("W_peak_final")]), report["structure"]["W_peak_max_final"].get<double>());
    // How far from converged the compliance is, as its report says.
    const auto& estimate = report["discretisation"]["final"];
    EXPECT_NEAR(std::stod(row[t.column("compliance_error")]), estimate["estimated_error"].get<double>(),
                5e-4 * estimate["estimated_error"].get<double>());  // (four digits)
    EXPECT_EQ(row[t.column("converged")], estimate["converged"].get<bool>() ? "yes" : "no");
    EXPECT_EQ(std::stod(row[t.column("/material/thickness")]), i < 2 ? 0.002 : 0.004);
    std::ifstream sin(dir / "scene.json");
    EXPECT_EQ(nlohmann::json::parse(sin)["material"]["thickness"].get<double>(), i < 2 ? 0.002 : 0.004);
  }
  EXPECT_TRUE(fs::exists(reference() / "pareto.png"));
  EXPECT_GT(fs::file_size(reference() / "pareto.png"), 1000u);
  EXPECT_NE(reference_log().find("2 failed"), std::string::npos) << reference_log();
}

TEST_F(SweepCommand, ParetoFrontIsExactlyTheNonDominatedSetOfTheSummary) {
  const CsvTable s = parse_csv(read_text(reference() / "summary.csv"));
  const CsvTable p = parse_csv(read_text(reference() / "pareto.csv"));
  for (const char* front : {"W_max", "compliance"}) {
    SCOPED_TRACE(front);
    const size_t yc = s.column(std::string(front) == "W_max" ? "W_max_final" : "compliance");
    const size_t xc = s.column("material_fraction");
    std::set<std::string> expected, got;
    for (const auto& a : s.rows) {
      if (a[s.column("status")] != "ok") continue;
      bool dominated = false;
      for (const auto& b : s.rows) {
        if (b[s.column("status")] != "ok") continue;
        const double ax = std::stod(a[xc]), ay = std::stod(a[yc]), bx = std::stod(b[xc]), by = std::stod(b[yc]);
        dominated |= bx <= ax && by <= ay && (bx < ax || by < ay);
      }
      if (!dominated) expected.insert(a[s.column("id")]);
    }
    for (const auto& row : p.rows)
      if (row[p.column("front")] == front) got.insert(row[p.column("id")]);
    EXPECT_FALSE(expected.empty());
    EXPECT_EQ(got, expected);
  }
}

TEST_F(SweepCommand, KilledPartWayAndResumedGivesTheSameSummary) {
  const fs::path out = root() / "killed";
  const fs::path sweep = root() / "sweep.json";
  // One variant at a time; kill -9 as soon as the first variant's marker exists.
  const auto killed = run_shell(
      test::cutwork_binary().string() + " sweep " + sweep.string() + " --out " + out.string() +
      " --jobs 1 --quiet & pid=$!; for i in $(seq 1 1200); do [ -e " + (out / "variants/v001/result.json").string() +
      " ] && break; sleep 0.05; done; kill -9 $pid; wait $pid; echo killed");
  ASSERT_NE(killed.out.find("killed"), std::string::npos) << killed.err;
  ASSERT_TRUE(fs::exists(out / "variants/v001/result.json"));
  ASSERT_FALSE(fs::exists(out / "summary.csv")) << "the sweep finished before it was killed";
  const std::string first_marker = read_text(out / "variants/v001/result.json");
  const auto first_time = fs::last_write_time(out / "variants/v001/result.json");

  const auto resumed = run_cutwork("sweep " + sweep.string() + " --out " + out.string() + " --jobs 1");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(resumed.err.find("(4 run now"), std::string::npos) << resumed.err;
  EXPECT_EQ(read_text(out / "variants/v001/result.json"), first_marker);
  EXPECT_EQ(fs::last_write_time(out / "variants/v001/result.json"), first_time);
  EXPECT_EQ(summary_without_seconds(out), summary_without_seconds(reference()));

  // A finished sweep started again runs nothing and writes the same summary.
  const auto again = run_cutwork("sweep " + sweep.string() + " --out " + out.string());
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("(0 run now, 4 done before)"), std::string::npos) << again.err;
  EXPECT_EQ(summary_without_seconds(out), summary_without_seconds(reference()));
}

// Every variant reserves at most the whole budget, so a budget below one variant's estimate runs
// them one at a time — and the summary does not depend on that.
TEST_F(SweepCommand, AMemoryBudgetBelowOneVariantRunsThemAllOneAtATime) {
  const fs::path out = root() / "memory";
  const auto r = run_cutwork("sweep " + (root() / "sweep.json").string() + " --out " + out.string() +
                             " --jobs 2 --memory 1K");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(summary_without_seconds(out), summary_without_seconds(reference()));
}

TEST_F(SweepCommand, AFolderOfAnotherSweepIsRefused) {
  std::string other = kSweep;
  other.replace(other.find("0.004"), 5, "0.005");
  const fs::path sweep = write_sweep(root() / "other", other);
  const auto r = run_cutwork("sweep " + sweep.string() + " --out " + reference().string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("holds another sweep"), std::string::npos) << r.err;
}

TEST_F(SweepCommand, LocalAndMpiRunsAgree) {
#ifndef CUTWORK_MPIEXEC
  GTEST_SKIP() << "built without MPI (CUTWORK_WITH_MPI)";
#else
  const fs::path out = root() / "mpi";
  const auto r = run_shell(std::string("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ") + CUTWORK_MPIEXEC +
                           " -n 2 --oversubscribe " + test::cutwork_binary().string() + " sweep " +
                           (root() / "sweep.json").string() + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(summary_without_seconds(out), summary_without_seconds(reference()));
  EXPECT_EQ(read_text(out / "pareto.csv"), read_text(reference() / "pareto.csv"));
  // Dynamic balancing handed variants to both ranks.
  std::set<int> ranks;
  for (const char* id : {"v001", "v002", "v003", "v004"}) {
    std::ifstream in(out / "variants" / id / "result.json");
    ranks.insert(nlohmann::json::parse(in)["rank"].get<int>());
  }
  EXPECT_EQ(ranks, (std::set<int>{0, 1}));
#endif
}

TEST(SweepCommandInput, BadVariantIsRefusedBeforeAnythingRuns) {
  const fs::path dir = test::temp_dir("sweep_bad");
  const fs::path sweep = write_sweep(dir, R"({"base": "plate", "axes": [
      {"path": "/material/thickness", "values": [0.003, -0.001]}]})");
  const auto r = run_cutwork("sweep " + sweep.string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("variant v002 (/material/thickness = -0.001): /material/thickness"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out"));

  const fs::path shapes = write_sweep(dir / "shapes", R"({"base": "plate", "axes": [
      {"path": "/stencils/0/kind", "values": ["circle", "blob"]}]})");
  const auto s = run_cutwork("sweep " + shapes.string() + " --out " + (dir / "out").string());
  EXPECT_EQ(s.exit_code, 2);
  EXPECT_NE(s.err.find("variant v002"), std::string::npos) << s.err;
  EXPECT_NE(s.err.find("blob"), std::string::npos) << s.err;
  EXPECT_FALSE(fs::exists(dir / "out"));

  const auto m = run_cutwork("sweep " + sweep.string() + " --out " + (dir / "out").string() + " --memory lots");
  EXPECT_EQ(m.exit_code, 2);
  EXPECT_NE(m.err.find("--memory"), std::string::npos) << m.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(SweepCommandInput, ListPrintsTheVariantsAndWritesNothing) {
  const fs::path dir = test::temp_dir("sweep_list");
  const fs::path sweep = write_sweep(dir);
  const auto r = run_cutwork("sweep " + sweep.string() + " --out " + (dir / "out").string() + " --list");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 4);
  EXPECT_NE(r.out.find("v004  /material/thickness = 0.004, /supports/0/select/x/below = -1"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir / "out"));

  // With --memory, what each variant would reserve and what the sweep sets aside once (the plate:
  // 1944 base and 492 simulated triangles; the discretisation estimate's h/8 level 31,488).
  const auto m = run_cutwork("sweep " + sweep.string() + " --out " + (dir / "out").string() +
                             " --list --memory 4G --jobs 2 --threads 2");
  ASSERT_EQ(m.exit_code, 0) << m.err;
  EXPECT_EQ(std::count(m.out.begin(), m.out.end(), '\n'), 5) << m.out;
  const SceneMeshes plate = build_scene_meshes(load_scene("plate"));
  const solvers::DesignMemory memory = solvers::estimate_design_memory(plate, true);
  ASSERT_GT(memory.on_demand, 0u);
  EXPECT_NE(m.out.find(fmt::format("(reserves {:.0f} MB and {:.0f} MB more if its discretisation estimate solves h/8: "
                                   "1944 base, 492 simulated triangles)",
                                   double(memory.held) / 1e6, double(memory.on_demand) / 1e6)),
            std::string::npos)
      << m.out;
  EXPECT_NE(m.out.find("set aside once: 260 MB (the process and one stiffness calibration on 1 thread(s) per variant) "
                       "of --memory 4G"),
            std::string::npos)
      << m.out;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

}  // namespace
}  // namespace cutwork
