// `cutwork design` checkpoints and --resume (host/cli/checkpoint.h): a run killed with SIGKILL
// after its checkpoint, or stopped by SIGTERM, and resumed, ends with the same design as an
// uninterrupted run, bit for bit. The kill comes from the test hook
// CUTWORK_TEST_SIGNAL_AFTER_CHECKPOINT, so it lands at a known moment (during the structural
// phase, right after the checkpoint of the pattern phase).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "tests/support/test_support.h"

namespace cutwork {
namespace {
namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

const std::string design_args = "design plate --iterations 5 --device cpu --quiet";

test::CommandResult design(const fs::path& out, const std::string& extra = "", const std::string& env = "") {
  return test::run_shell(env + " timeout -s KILL 120 " + test::cutwork_binary().string() + " " + design_args + " " +
                         extra + " --out " + out.string());
}

/// The report without what differs between runs by nature (wall-clock seconds, the resume note).
nlohmann::json comparable_report(const fs::path& out) {
  nlohmann::json r = nlohmann::json::parse(slurp(out / "report.json"));
  r.erase("timings");
  r.erase("notes");
  for (auto& phase : r["phases"]) phase.erase("seconds");
  return r;
}

/// Every output of `a` equals that of `b` (the report up to timings and notes).
void expect_same_design(const fs::path& a, const fs::path& b) {
  for (const char* f : {"stencils.json", "fields.ply", "cut.obj"}) EXPECT_EQ(slurp(a / f), slurp(b / f)) << f;
  EXPECT_EQ(comparable_report(a), comparable_report(b));
  EXPECT_FALSE(fs::exists(b / ".cutwork-checkpoint.json")) << "a finished run keeps no checkpoint";
}

TEST(CliCheckpoint, KilledAfterTheCheckpointAndResumedEqualsTheUninterruptedDesign) {
  const fs::path dir = test::temp_dir("checkpoint_kill");
  ASSERT_EQ(design(dir / "whole").exit_code, 0);
  EXPECT_FALSE(fs::exists(dir / "whole" / ".cutwork-checkpoint.json"));

  const auto killed = design(dir / "resumed", "", "CUTWORK_TEST_SIGNAL_AFTER_CHECKPOINT=KILL");
  EXPECT_NE(killed.exit_code, 0);
  EXPECT_TRUE(fs::exists(dir / "resumed" / ".cutwork-checkpoint.json"));
  EXPECT_FALSE(fs::exists(dir / "resumed" / "report.json")) << "killed before publishing: no set";

  const double checkpointed_seconds =
      nlohmann::json::parse(slurp(dir / "resumed" / ".cutwork-checkpoint.json"))["pattern"]["seconds"];
  const auto resumed = design(dir / "resumed", "--resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expect_same_design(dir / "whole", dir / "resumed");
  // The pattern phase was not run again: its figures are the checkpoint's.
  const auto report = nlohmann::json::parse(slurp(dir / "resumed" / "report.json"));
  EXPECT_EQ(report["phases"][0]["seconds"].get<double>(), checkpointed_seconds);
  const auto notes = nlohmann::json::parse(slurp(dir / "resumed" / "report.json"))["notes"].dump();
  EXPECT_NE(notes.find("resumed from the checkpoint"), std::string::npos) << notes;
  fs::remove_all(dir);
}

TEST(CliCheckpoint, SigtermStopsCleanlyKeepingTheCheckpoint) {
  const fs::path dir = test::temp_dir("checkpoint_term");
  ASSERT_EQ(design(dir / "whole").exit_code, 0);
  const auto stopped = design(dir / "resumed", "", "CUTWORK_TEST_SIGNAL_AFTER_CHECKPOINT=TERM");
  EXPECT_EQ(stopped.exit_code, 128 + 15) << stopped.err;
  EXPECT_EQ(count_lines(stopped.err), 1) << stopped.err;
  EXPECT_NE(stopped.err.find("interrupted by SIGTERM"), std::string::npos) << stopped.err;
  EXPECT_NE(stopped.err.find("--resume"), std::string::npos) << stopped.err;
  // Only the checkpoint: no staging folder, no partial set.
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir / "resumed")) left.push_back(e.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{".cutwork-checkpoint.json"});

  ASSERT_EQ(design(dir / "resumed", "--resume").exit_code, 0);
  expect_same_design(dir / "whole", dir / "resumed");
  fs::remove_all(dir);
}

TEST(CliCheckpoint, ACheckpointOfOtherOptionsIsRefusedAndNoneMeansFromTheStart) {
  const fs::path dir = test::temp_dir("checkpoint_other");
  design(dir / "out", "", "CUTWORK_TEST_SIGNAL_AFTER_CHECKPOINT=KILL");
  ASSERT_TRUE(fs::exists(dir / "out" / ".cutwork-checkpoint.json"));
  const auto other = test::run_cutwork("design plate --iterations 6 --device cpu --resume --out " + (dir / "out").string());
  EXPECT_EQ(other.exit_code, 2) << other.err;
  EXPECT_EQ(count_lines(other.err), 1) << other.err;
  EXPECT_NE(other.err.find("another scene or other options"), std::string::npos) << other.err;
  // --resume with no checkpoint: a whole run, saying so.
  const auto fresh = test::run_cutwork("design plate --iterations 2 --device cpu --resume --out " + (dir / "new").string());
  ASSERT_EQ(fresh.exit_code, 0) << fresh.err;
  EXPECT_NE(fresh.err.find("no checkpoint"), std::string::npos) << fresh.err;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cutwork
