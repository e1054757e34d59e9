#include "host/io/json_io.h"

#include <fstream>
#include <sstream>

#include "host/core/atomic_file.h"
#include "host/core/error.h"

namespace cutwork {

nlohmann::json read_json_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open file");
  std::stringstream ss;
  ss << in.rdbuf();
  try {
    return nlohmann::json::parse(ss.str());
  } catch (const nlohmann::json::exception& e) {
    // parse_error, and out_of_range for a number beyond a double (1e400). nlohmann's messages
    // start with "[json.exception.parse_error.101] "; keep the useful part.
    std::string msg = e.what();
    if (auto p = msg.find("] "); p != std::string::npos) msg = msg.substr(p + 2);
    throw InputError(path.string() + ": invalid JSON: " + msg);
  }
}

void write_json_atomic(const std::filesystem::path& path, const nlohmann::json& doc) {
  write_file_atomic(path, doc.dump(2) + "\n");
}

}  // namespace cutwork
