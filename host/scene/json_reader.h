#pragma once
/// Strict, path-aware reading of JSON objects for scene validation: every accessor names the
/// JSON path and the accepted range in its error, and finish() rejects keys nobody asked for.
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/core/types.h"

namespace cutwork {

class JsonObjectReader {
 public:
  /// `origin` names the document in messages ("scene.json", "builtin:plate"); `path` is the
  /// JSON pointer of `object` ("" for the root). Throws InputError unless `object` is an object.
  JsonObjectReader(const nlohmann::json& object, std::string origin, std::string path);

  bool has(const std::string& key) const;
  /// Full JSON path of a key, for messages.
  std::string path_of(const std::string& key) const;

  /// A number in [lo, hi] (open ends where `lo_open`/`hi_open`); `fallback` when absent.
  double number(const std::string& key, double fallback, double lo, double hi,
                bool lo_open = false, bool hi_open = false);
  double required_number(const std::string& key, double lo, double hi, bool lo_open = false,
                         bool hi_open = false);
  int integer(const std::string& key, int fallback, int lo, int hi);
  bool boolean(const std::string& key, bool fallback);
  /// A string; when `allowed` is non-empty the value must be one of them.
  std::string string(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& allowed = {});
  std::string required_string(const std::string& key, const std::vector<std::string>& allowed = {});
  Vec3 vec3(const std::string& key, const Vec3& fallback);
  Vec3 required_vec3(const std::string& key);
  /// The raw child (marked as read), or nullptr when absent.
  const nlohmann::json* child(const std::string& key);
  /// A child that must be an array (empty when absent).
  const nlohmann::json& array(const std::string& key);
  /// A child object reader (the child must be an object).
  JsonObjectReader object(const std::string& key);

  /// Rejects keys that were never read, listing the accepted ones.
  void finish() const;

  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;
  const std::string& origin() const { return m_origin; }
  const std::string& path() const { return m_path; }

 private:
  const nlohmann::json& m_object;
  std::string m_origin, m_path;
  std::set<std::string> m_read;
  std::set<std::string> m_accepted;
};

/// Parses "x" as a 3-vector (array of 3 finite numbers) or throws InputError naming `path`.
Vec3 json_to_vec3(const nlohmann::json& value, const std::string& origin, const std::string& path);
/// Formats a number compactly for messages (no trailing zeros).
std::string format_number(double v);

}  // namespace cutwork
