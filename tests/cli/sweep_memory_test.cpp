// The sweep's memory budget: what a variant reserves (estimate_design_memory) and what the sweep
// sets aside once (kProcessMemory, calibration_memory) against the peak resident memory of real
// designs, measured from a child process (wait4's ru_maxrss).
#include <gtest/gtest.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <string>
#include <vector>

#include <fmt/format.h>

#include "host/scene/scene.h"
#include "solvers/conforming/discretisation_estimate.h"
#include "solvers/report/design_memory.h"
#include "tests/support/test_support.h"

extern char** environ;

namespace cutwork {
namespace {

namespace fs = std::filesystem;

/// Peak resident memory (bytes) of `cutwork args…` run as a child; its exit code in `exit_code`.
size_t peak_of_cutwork(const std::vector<std::string>& args, int& exit_code) {
  std::vector<std::string> argv_s{test::cutwork_binary().string()};
  argv_s.insert(argv_s.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    exit_code = -1;
    return 0;
  }
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return size_t(usage.ru_maxrss) * 1024;  // kB on Linux
}

TEST(SweepMemory, TheLargestRefinedLevelFollowsTheDiscretisationOptions) {
  const solvers::DiscretisationOptions o;
  ASSERT_EQ(o.refinements + o.extra_refinements, 3);  // h/2, h/4, h/8
  EXPECT_EQ(solvers::largest_refined_level(1000), 64'000u);
  EXPECT_EQ(solvers::largest_refined_level(size_t(o.max_faces) / 64), size_t(o.max_faces) / 64 * 64);
  EXPECT_EQ(solvers::largest_refined_level(10'000), 160'000u);   // h/8 would be 640k
  EXPECT_EQ(solvers::largest_refined_level(100'000), 400'000u);  // h/2 is always made
}

// A design of a built-in scene on one thread must fit in what a sweep holds for it — the process,
// one calibration, the variant's reservation — and not by a factor that would idle a budget. The
// reservation counts the discretisation estimate's h/8 level, which the pavilion solves (its peak)
// and the bowl does not (its reservation is then about 4× its peak); without the estimate the
// design alone.
TEST(SweepMemory, TheEstimateBoundsTheMeasuredPeakOfDesigns) {
  struct Case {
    std::string scene;
    bool discretisation_estimate;
    double largest_ratio;
  };
  for (const Case& c : {Case{"pavilion", true, 2.5}, Case{"bowl", true, 5.0}, Case{"bowl", false, 2.5}}) {
    const Scene scene = load_scene(c.scene);
    const SceneMeshes meshes = build_scene_meshes(scene);
    const size_t design = solvers::estimate_design_memory(meshes, c.discretisation_estimate);
    const size_t estimate = solvers::kProcessMemory + solvers::calibration_memory(std::span(&scene, 1), 1) + design;
    const fs::path out = test::temp_dir("sweep-memory-" + c.scene);
    std::vector<std::string> args{"design", c.scene, "-o", out.string(), "--threads", "1", "-q", "--no-render",
                                  "--iterations", "5"};
    if (!c.discretisation_estimate) args.push_back("--no-discretisation-estimate");
    int exit_code = 0;
    const size_t peak = peak_of_cutwork(args, exit_code);
    ASSERT_EQ(exit_code, 0) << c.scene;
    const std::string what =
        fmt::format("{}{}: measured peak {:.0f} MB, held {:.0f} MB (the variant's reservation {:.0f} MB)", c.scene,
                    c.discretisation_estimate ? "" : " without the discretisation estimate", double(peak) / 1e6,
                    double(estimate) / 1e6, double(design) / 1e6);
    std::cout << what << "\n";
    EXPECT_GE(estimate, peak) << what;
    EXPECT_LE(double(estimate), c.largest_ratio * double(peak)) << what;
    fs::remove_all(out);
  }
}

}  // namespace
}  // namespace cutwork
