#include "host/core/json_io.h"

#include <set>
#include <vector>

#include <fmt/format.h>

#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/core/input_file.h"

namespace cutwork {

nlohmann::json parse_json_text(std::string_view text, const std::string& origin) {
  using nlohmann::json;
  // The keys seen so far in each open object, innermost last.
  std::vector<std::set<std::string>> keys;
  const json::parser_callback_t check = [&](int depth, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        if (depth >= max_json_depth)
          throw InputError(fmt::format("{}: invalid JSON: nested more than {} levels deep", origin, max_json_depth));
        if (event == json::parse_event_t::object_start) keys.emplace_back();
        break;
      case json::parse_event_t::object_end:
        if (!keys.empty()) keys.pop_back();
        break;
      case json::parse_event_t::key:
        if (!keys.empty() && !keys.back().insert(parsed.get<std::string>()).second)
          throw InputError(fmt::format("{}: invalid JSON: the key '{}' appears twice in one object", origin,
                                       excerpt(parsed.get<std::string>())));
        break;
      default:
        break;
    }
    return true;
  };
  try {
    return json::parse(text.begin(), text.end(), check);
  } catch (const nlohmann::json::exception& e) {
    // parse_error, and out_of_range for a number beyond a double (1e400). nlohmann's messages
    // start with "[json.exception.parse_error.101] "; keep the useful part.
    std::string msg = e.what();
    if (auto p = msg.find("] "); p != std::string::npos) msg = msg.substr(p + 2);
    throw InputError(origin + ": invalid JSON: " + excerpt(msg, 200));
  }
}

nlohmann::json read_json_file(const std::filesystem::path& path) {
  return parse_json_text(read_input_file(path, max_json_file_bytes, "a JSON file"), path.string());
}

void write_json_atomic(const std::filesystem::path& path, const nlohmann::json& doc) {
  write_file_atomic(path, doc.dump(2) + "\n");
}

}  // namespace cutwork
