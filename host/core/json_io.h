#pragma once
/// JSON files: reading with the file named in every error, writing atomically.
#include <filesystem>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace cutwork {

/// Deepest nesting of arrays and objects accepted in a JSON document (scenes need about 6).
inline constexpr int max_json_depth = 64;

/// Parses a JSON document strictly: a duplicate key in an object and nesting deeper than
/// max_json_depth are errors (not "last wins", not a stack overflow further on).
/// Throws InputError("<origin>: invalid JSON: <problem>").
nlohmann::json parse_json_text(std::string_view text, const std::string& origin);
/// Reads a JSON file (a regular file of at most max_json_file_bytes) with parse_json_text;
/// throws InputError("<path>: <problem>").
nlohmann::json read_json_file(const std::filesystem::path& path);
/// Writes `doc` pretty-printed (2 spaces) to `path` atomically.
void write_json_atomic(const std::filesystem::path& path, const nlohmann::json& doc);

}  // namespace cutwork
