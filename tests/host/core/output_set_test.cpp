// Output sets, all or nothing: every publishing step failed in turn, and killed in turn, leaves the
// folder holding the complete previous set or the complete new one; a second OutputSet on a
// locked folder fails at once; a failed run leaves nothing.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <map>
#include <sstream>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/core/output_set.h"
#include "tests/support/test_support.h"

namespace cutwork {
namespace {
namespace fs = std::filesystem;
using Files = std::map<std::string, std::string>;

void write_text(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

/// Every entry of `dir` with its content (folders as "<dir>").
Files contents(const fs::path& dir) {
  Files files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_directory()) {
      files[e.path().filename().string()] = "<dir>";
      continue;
    }
    std::ifstream in(e.path(), std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    files[e.path().filename().string()] = ss.str();
  }
  return files;
}

/// Publishes `files` into `dir` as one set.
void publish(const fs::path& dir, const Files& files) {
  OutputSet set(dir);
  for (const auto& [name, text] : files) write_text(set.stage(name), text);
  set.publish();
}

const Files old_set = {{"report.json", "old report"}, {"stencils.json", "old stencils"}, {"cut.obj", "old cut"}};
const Files new_set = {{"report.json", "new report"}, {"fields.ply", "new fields"}, {"stencils.json", "new stencils"}};

/// `files` plus the manifest publish() adds, and a user's file that no set touches.
Files as_published(Files files) {
  std::string manifest;
  for (const auto& [name, text] : files)
    if (name != "report.json") manifest += name + "\n";
  manifest += std::string(OutputSet::manifest_name) + "\n" + "report.json\n";
  files[OutputSet::manifest_name] = manifest;
  files["notes.txt"] = "mine";
  return files;
}

fs::path folder_with_old_set(const std::string& tag) {
  const fs::path dir = test::temp_dir(tag);
  write_text(dir / "notes.txt", "mine");
  publish(dir, old_set);
  EXPECT_EQ(contents(dir), as_published(old_set));
  return dir;
}

TEST(OutputSet, PublishesTheNewSetAndRemovesWhatTheOldSetHadBeyondIt) {
  const fs::path dir = folder_with_old_set("outset_basic");
  publish(dir, new_set);
  EXPECT_EQ(contents(dir), as_published(new_set)) << "the old cut.obj must go: it is no part of the new set";
  fs::remove_all(dir);
}

TEST(OutputSet, EveryFailedPublishingStepLeavesThePreviousSet) {
  int steps = 0;
  for (int fail_at = 0;; ++fail_at) {
    SCOPED_TRACE(fail_at);
    const fs::path dir = folder_with_old_set("outset_fail");
    bool fired = false;
    OutputSet::set_step_hook_for_testing([&](int step, const std::string& what) {
      if (step == fail_at) {
        fired = true;
        throw std::runtime_error("injected failure before: " + what);
      }
    });
    try {
      publish(dir, new_set);
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("previous outputs are left in place"), std::string::npos) << e.what();
    }
    OutputSet::set_step_hook_for_testing({});
    if (!fired) {
      EXPECT_EQ(contents(dir), as_published(new_set));
      steps = fail_at;
      fs::remove_all(dir);
      break;
    }
    EXPECT_EQ(contents(dir), as_published(old_set)) << "no staging folder, no mixed set";
    fs::remove_all(dir);
  }
  // Remove report.json; move the old cut.obj, stencils.json and manifest aside; move fields.ply,
  // stencils.json and the manifest in; report.json.
  EXPECT_EQ(steps, 1 + 3 + 3 + 1);
}

TEST(OutputSet, AKillAtEveryPublishingStepLeavesTheOldSetOrTheNewOne) {
  for (int kill_at = 0; kill_at <= 8; ++kill_at) {
    SCOPED_TRACE(kill_at);
    const fs::path dir = folder_with_old_set("outset_kill");
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      OutputSet::set_step_hook_for_testing([&](int step, const std::string&) {
        if (step == kill_at) ::_exit(0);  // dies on the spot: no unwinding, no clean-up
      });
      publish(dir, new_set);
      ::_exit(0);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    // A complete set is marked by its report.json; without one the next run puts the old set back.
    const Files after_kill = contents(dir);
    if (after_kill.count("report.json")) {
      Files visible = after_kill;
      for (auto it = visible.begin(); it != visible.end();)
        it = it->first.rfind(".cutwork-staging.", 0) == 0 ? visible.erase(it) : std::next(it);
      EXPECT_TRUE(visible == as_published(old_set) || visible == as_published(new_set));
    }
    { OutputSet next(dir); }  // the next run cleans up after the dead one
    const Files after = contents(dir);
    EXPECT_EQ(after, as_published(kill_at < 8 ? old_set : new_set))
        << "report.json: " << (after.count("report.json") ? after.at("report.json") : "none");
    fs::remove_all(dir);
  }
}

TEST(OutputSet, ASecondRunIntoTheSameFolderFailsAtOnce) {
  const fs::path dir = test::temp_dir("outset_lock");
  OutputSet first(dir);
  try {
    OutputSet second(dir);
    FAIL() << "the second run must not get the folder";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(dir.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("another cutwork run"), std::string::npos) << msg;
    EXPECT_NE(msg.find("--wait"), std::string::npos) << msg;
  }
  write_text(first.stage("report.json"), "first");
  first.publish();
  EXPECT_EQ(contents(dir).at("report.json"), "first");
  fs::remove_all(dir);
}

TEST(OutputSet, AFailedRunIntoANewFolderLeavesNothing) {
  const fs::path root = test::temp_dir("outset_new");
  const fs::path dir = root / "a" / "b";
  {
    OutputSet set(dir);
    write_text(set.stage("report.json"), "never published");
    EXPECT_TRUE(fs::is_directory(dir));
  }
  EXPECT_FALSE(fs::exists(root / "a"));
  // Into an existing folder, a failed run leaves it as it was.
  write_text(root / "notes.txt", "mine");
  { OutputSet set(root); write_text(set.stage("cut.obj"), "x"); }
  EXPECT_EQ(contents(root), (Files{{"notes.txt", "mine"}}));
  fs::remove_all(root);
}

TEST(OutputSet, StaleTemporariesOfDeadRunsAreRemoved) {
  const fs::path dir = test::temp_dir("outset_stale");
  write_text(dir / ".stencils.json.tmp123456", std::string(131072, 'x'));
  fs::create_directory(dir / ".cutwork-staging.99999999");
  write_text(dir / ".cutwork-staging.99999999" / "fields.ply", "partial");
  write_text(dir / ".hidden.tmp", "not a temporary of ours");
  write_text(dir / "data.tmp1", "not hidden: not ours");
  publish(dir, {{"report.json", "r"}});
  const Files after = contents(dir);
  EXPECT_FALSE(after.count(".stencils.json.tmp123456"));
  EXPECT_FALSE(after.count(".cutwork-staging.99999999"));
  EXPECT_TRUE(after.count(".hidden.tmp"));
  EXPECT_TRUE(after.count("data.tmp1"));
  fs::remove_all(dir);
}

TEST(OutputSet, RefusesASetWithoutReportAndOddNames) {
  const fs::path dir = test::temp_dir("outset_odd");
  OutputSet set(dir);
  EXPECT_THROW(set.stage("../x"), InternalError);
  EXPECT_THROW(set.stage(".hidden"), InternalError);
  write_text(set.stage("fields.ply"), "x");
  EXPECT_THROW(set.publish(), InternalError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cutwork
