// `cutwork design` checkpoints and --resume (host/cli/checkpoint.h): a run killed with SIGKILL
// after a checkpoint — at the end of the pattern phase, or part way through the pattern or the
// structural phase (inside an L-BFGS-B run) — or stopped by SIGTERM, and resumed, ends with the
// same design as an uninterrupted run, bit for bit. The kill comes from the test hook
// CUTWORK_TEST_SIGNAL_AFTER_CHECKPOINT=SIGNAL@STAGE:N, so it lands at a known moment.
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

/// Killed right after the n-th checkpoint inside `stage` (one at every optimiser boundary:
/// --checkpoint-every 1e-9), then resumed: the uninterrupted design, bit for bit.
void kill_inside_and_resume(const std::string& name, const std::string& spec) {
  const fs::path dir = test::temp_dir(name);
  ASSERT_EQ(design(dir / "whole").exit_code, 0);
  const auto killed = design(dir / "resumed", "--checkpoint-every 1e-9", "CUTWORK_TEST_SIGNAL_AFTER_CHECKPOINT=" + spec);
  EXPECT_NE(killed.exit_code, 0);
  ASSERT_TRUE(fs::exists(dir / "resumed" / ".cutwork-checkpoint.json"));
  const auto checkpoint = nlohmann::json::parse(slurp(dir / "resumed" / ".cutwork-checkpoint.json"));
  EXPECT_EQ(checkpoint["stage"], spec.substr(spec.find('@') + 1, spec.find(':') - spec.find('@') - 1));
  // Inside an L-BFGS-B run: its state (corrections included) is in the checkpoint.
  EXPECT_FALSE(checkpoint["phase"]["optimizer"]["lbfgsb"].is_null()) << spec;
  EXPECT_GT(checkpoint["phase"]["optimizer"]["lbfgsb"]["s"].size(), 0u) << spec;
  const auto resumed = design(dir / "resumed", "--resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  expect_same_design(dir / "whole", dir / "resumed");
  fs::remove_all(dir);
}

TEST(CliCheckpoint, KilledInsideTheStructuralPhaseAndResumedEqualsTheUninterruptedDesign) {
  kill_inside_and_resume("checkpoint_structure", "KILL@structure:3");
}

TEST(CliCheckpoint, KilledInsideThePatternPhaseAndResumedEqualsTheUninterruptedDesign) {
  kill_inside_and_resume("checkpoint_pattern", "KILL@pattern:3");
}

TEST(CliCheckpoint, CheckpointsDoNotChangeTheDesign) {
  const fs::path dir = test::temp_dir("checkpoint_every");
  ASSERT_EQ(design(dir / "whole", "--checkpoint-every 0").exit_code, 0);
  const auto often = design(dir / "often", "--checkpoint-every 1e-9");
  ASSERT_EQ(often.exit_code, 0) << often.err;
  expect_same_design(dir / "whole", dir / "often");
  fs::remove_all(dir);
}

TEST(CliCheckpoint, SigtermInsideAPhaseWritesACheckpointAndStops) {
  const fs::path dir = test::temp_dir("checkpoint_term_inside");
  ASSERT_EQ(design(dir / "whole").exit_code, 0);
  const auto stopped =
      design(dir / "resumed", "--checkpoint-every 1e-9", "CUTWORK_TEST_SIGNAL_AFTER_CHECKPOINT=TERM@structure:2");
  EXPECT_EQ(stopped.exit_code, 128 + 15) << stopped.err;
  EXPECT_EQ(count_lines(stopped.err), 1) << stopped.err;
  EXPECT_NE(stopped.err.find("inside the structural phase"), std::string::npos) << stopped.err;
  ASSERT_EQ(design(dir / "resumed", "--resume").exit_code, 0);
  expect_same_design(dir / "whole", dir / "resumed");
  fs::remove_all(dir);
}

TEST(CliCheckpoint, ADamagedCheckpointIsRefusedWithOneLine) {
  const fs::path dir = test::temp_dir("checkpoint_damaged");
  design(dir / "out", "--checkpoint-every 1e-9", "CUTWORK_TEST_SIGNAL_AFTER_CHECKPOINT=KILL@structure:2");
  const fs::path file = dir / "out" / ".cutwork-checkpoint.json";
  ASSERT_TRUE(fs::exists(file));
  const std::string good = slurp(file);
  // One digit changed inside a number (valid JSON, different state), then the file cut short.
  std::string flipped = good;
  const size_t at = flipped.find("\"scale\":");
  ASSERT_NE(at, std::string::npos);
  size_t digit = flipped.find_first_of("123456789", at + 8);
  flipped[digit] = flipped[digit] == '9' ? '8' : char(flipped[digit] + 1);
  for (const std::string& bad : {flipped, good.substr(0, good.size() / 2)}) {
    std::ofstream(file, std::ios::binary) << bad;
    const auto r = design(dir / "out", "--resume");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("damaged checkpoint"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out" / "report.json"));
  }
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
