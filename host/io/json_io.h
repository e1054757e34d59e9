#pragma once
/// JSON files: reading with the file named in every error, writing atomically.
#include <filesystem>

#include <nlohmann/json.hpp>

namespace cutwork {

/// Parses a JSON file; throws InputError("<path>: <problem>").
nlohmann::json read_json_file(const std::filesystem::path& path);
/// Writes `doc` pretty-printed (2 spaces) to `path` atomically.
void write_json_atomic(const std::filesystem::path& path, const nlohmann::json& doc);

}  // namespace cutwork
