// How the command line ends on an exception (host/core/exit_status.h, used by host/cli/main.cpp):
// errors a user can cause and fix exit 2, a broken precondition inside cutwork (InternalError, any
// other exception) exits 1 and says "internal error", interruptions 128 + signal. A user error
// through the real executable is in tests/cli/cli_test.cpp (exit 2); no input can reach an
// InternalError, so its exit code is checked here on thrown exceptions, one of them from a real
// precondition.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "host/core/error.h"
#include "host/core/exit_status.h"
#include "host/core/internal_error.h"
#include "host/core/output_set.h"
#include "host/core/json_io.h"
#include "tests/support/test_support.h"

namespace cutwork {
namespace {

template <typename E>
ExitStatus status_of(const E& e) {
  return exit_status_for(std::make_exception_ptr(e));
}

TEST(ExitStatus, UserErrorsExitTwoWithTheirMessage) {
  const ExitStatus input = status_of(InputError("plate.json: /material/poisson_ratio: must be in [0, 0.5)"));
  EXPECT_EQ(input.code, 2);
  EXPECT_EQ(input.line, "cutwork: plate.json: /material/poisson_ratio: must be in [0, 0.5)");
  EXPECT_EQ(status_of(SolveError("the loads are not finite")).code, 2);
  EXPECT_EQ(status_of(DeviceError("no Vulkan device")).code, 2);
  EXPECT_EQ(status_of(std::bad_alloc()).code, 2);
}

TEST(ExitStatus, InternalErrorsExitOneAndSaySo) {
  // InternalError is deliberately not a cutwork::Error.
  static_assert(!std::is_base_of_v<Error, InternalError>);
  const ExitStatus internal = status_of(InternalError("CHOLMOD solve without a valid factor"));
  EXPECT_EQ(internal.code, 1);
  EXPECT_EQ(internal.line, "cutwork: internal error: CHOLMOD solve without a valid factor");
  EXPECT_EQ(status_of(std::logic_error("x")).code, 1);
  EXPECT_EQ(status_of(std::runtime_error("x")).code, 1);
  EXPECT_EQ(exit_status_for(std::make_exception_ptr(42)).code, 1);
}

TEST(ExitStatus, InterruptionsExitWithTheSignal) {
  EXPECT_EQ(status_of(Interrupted("interrupted by SIGINT", SIGINT)).code, 128 + SIGINT);
  EXPECT_EQ(status_of(Interrupted("interrupted by SIGTERM", SIGTERM)).code, 128 + SIGTERM);
}

TEST(ExitStatus, OneLineOfBoundedLength) {
  const ExitStatus s = status_of(InputError("bad\nkey " + std::string(10000, 'k')));
  EXPECT_EQ(s.line.find('\n'), std::string::npos);
  EXPECT_LT(s.line.size(), 2100u);
}

/// The exit status of what `f` throws (−1 when it throws nothing).
template <typename F>
int exit_code_of(F&& f) {
  try {
    f();
  } catch (...) {
    return exit_status_for(std::current_exception()).code;
  }
  return -1;
}

TEST(ExitStatus, RealFailuresMapToTheirCodes) {
  const std::filesystem::path dir = test::temp_dir("exit_status");
  // A user error: a scene file that does not exist.
  EXPECT_EQ(exit_code_of([&] { read_json_file(dir / "missing.json"); }), 2);
  // A broken precondition: publishing a set without report.json (the pipeline always stages it).
  OutputSet set(dir / "out");
  EXPECT_EQ(exit_code_of([&] { set.publish(); }), 1);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cutwork
