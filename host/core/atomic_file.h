#pragma once
/// Atomic output: write to a temporary file in the target's directory, flush, then rename over
/// the target. An interrupted run never leaves a truncated file behind.
#include <filesystem>
#include <functional>
#include <ostream>
#include <string_view>

namespace cutwork {

/// Writes `content` to `path` atomically. Throws InputError naming the path on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

/// Streams into a temporary file and renames it over `path` when `write` returns normally;
/// if `write` throws, the temporary is removed and `path` is left untouched.
void write_file_atomic(const std::filesystem::path& path,
                       const std::function<void(std::ostream&)>& write, bool binary = false);

/// Creates `dir` (and parents) if needed; throws InputError naming it when that is impossible.
void ensure_directory(const std::filesystem::path& dir);

}  // namespace cutwork
