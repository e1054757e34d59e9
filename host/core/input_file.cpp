#include "host/core/input_file.h"

#include <fstream>
#include <sstream>
#include <system_error>

#include <fmt/format.h>

#include "host/core/error.h"

namespace cutwork {
namespace fs = std::filesystem;

std::uintmax_t check_input_file(const fs::path& path, std::uintmax_t max_bytes, const std::string& kind) {
  const std::string what = path.string();
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) throw InputError(what + ": no such file");
  if (fs::is_directory(status)) throw InputError(what + ": is a directory, expected " + kind);
  if (!fs::is_regular_file(status))
    throw InputError(what + ": is not a regular file (a pipe, socket or device), expected " + kind);
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw InputError(what + ": cannot be read (" + ec.message() + ")");
  if (size > max_bytes)
    throw InputError(fmt::format("{}: is {:.3g} MB, more than the {:.3g} MB accepted for {}", what, double(size) / 1e6,
                                 double(max_bytes) / 1e6, kind));
  return size;
}

std::string read_input_file(const fs::path& path, std::uintmax_t max_bytes, const std::string& kind) {
  check_input_file(path, max_bytes, kind);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot be opened for reading (check its permissions)");
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw InputError(path.string() + ": read error");
  return std::move(buffer).str();
}

std::string excerpt(std::string_view text, std::size_t max_chars) {
  std::string out;
  const std::size_t n = std::min(text.size(), max_chars);
  out.reserve(n + 32);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    out += c < 0x20 || c == 0x7f ? ' ' : char(c);
  }
  if (text.size() > max_chars) out += fmt::format("... ({} characters)", text.size());
  return out;
}

}  // namespace cutwork
