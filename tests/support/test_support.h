#pragma once
/// Helpers shared by the test suites: paths, temporary directories, running the CLI.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace cutwork::test {

/// tests/data in the source tree.
std::filesystem::path data_dir();
/// A fresh, empty directory under the system temp dir, unique to this process and `tag`.
std::filesystem::path temp_dir(const std::string& tag);

struct CommandResult {
  int exit_code = -1;
  std::string out;   ///< stdout
  std::string err;   ///< stderr
};
/// `<build>/bin/cutwork`.
std::filesystem::path cutwork_binary();
/// Runs `<build>/bin/cutwork <args>` through the shell and captures stdout and stderr.
CommandResult run_cutwork(const std::string& args);
/// The JSON document in file `path` (a report.json, a scene); throws when it cannot be parsed.
nlohmann::json read_json(const std::filesystem::path& path);
/// Runs a shell command line (stdin from /dev/null) and captures stdout and stderr.
CommandResult run_shell(const std::string& command);

}  // namespace cutwork::test
