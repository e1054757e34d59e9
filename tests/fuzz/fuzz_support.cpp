#include "tests/fuzz/fuzz_support.h"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cstdint>
#include <fstream>
#include <utility>
#include <vector>

#include "host/core/work_limits.h"

namespace cutwork::fuzz {
namespace fs = std::filesystem;

namespace {
/// The per-process scratch folder, removed when the process ends normally.
struct ScratchFolder {
  fs::path dir = fs::temp_directory_path() / ("cutwork-fuzz-" + std::to_string(::getpid()));
  ScratchFolder() { fs::create_directories(dir); }
  ~ScratchFolder() {
    std::error_code ignore;
    fs::remove_all(dir, ignore);
  }
};
}  // namespace

fs::path scratch_file(const std::string& name, std::string_view data) {
  static const ScratchFolder scratch;
  const fs::path p = scratch.dir / name;
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(data.data(), std::streamsize(data.size()));
  return p;
}

void use_small_limits() {
  work_limits().max_faces = 500;
  work_limits().max_stencils = 2'000;
}

std::string header_count_value(std::uint64_t c, unsigned index, std::uint32_t* low32) {
  struct Value {
    std::string text;
    std::uint32_t low32;
  };
  auto u = [](std::uint64_t v) { return Value{std::to_string(v), std::uint32_t(v)}; };
  Value v;
  switch (index % 16) {
    case 0: v = u(0); break;
    case 1: v = u(1); break;
    case 2: v = c == 0 ? Value{"-1", 0xFFFFFFFFu} : u(c - 1); break;
    case 3: v = u(c + 1); break;  // c < 2^63: no wrap
    case 4: v = u(2 * c); break;
    case 5: v = u(c + (std::uint64_t(1) << 32)); break;  // a 32-bit reader wraps it back to c
    case 6: v = u(INT32_MAX); break;
    case 7: v = u(std::uint64_t(1) << 31); break;
    case 8: v = u(UINT32_MAX); break;
    case 9: v = u(std::uint64_t(1) << 32); break;
    case 10: v = u(INT64_MAX); break;
    case 11: v = u(std::uint64_t(1) << 63); break;
    case 12: v = u(UINT64_MAX); break;
    case 13: v = {"18446744073709551616", 0}; break;  // 2^64
    case 14: v = {"-1", 0xFFFFFFFFu}; break;
    default: v = {"1000000000000000000000000000000", 0x40000000u}; break;  // 10^30
  }
  if (low32 != nullptr) *low32 = v.low32;
  return v.text;
}

namespace {
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

std::uint64_t declared(std::string_view token) {
  std::uint64_t c = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), c);
  return ec == std::errc() && ptr == token.data() + token.size() && c <= std::uint64_t(INT64_MAX) ? c : 0;
}

/// `text` with the token at [begin, end) replaced by count value `index` of the token's value.
std::string replace_count(std::string_view text, std::size_t begin, std::size_t end, unsigned index) {
  std::string out(text.substr(0, begin));
  out += header_count_value(declared(text.substr(begin, end - begin)), index);
  out += text.substr(end);
  return out;
}
}  // namespace

std::string mutate_header_counts(const std::string& extension, std::string_view file, std::uint8_t selector) {
  const unsigned which = selector >> 4, value = selector & 15u;
  if (extension == ".stl") {
    if (file.size() < 84) return std::string(file);
    std::uint32_t c = 0;
    for (int b = 3; b >= 0; --b) c = (c << 8) | std::uint8_t(file[std::size_t(80 + b)]);
    std::uint32_t low32 = 0;
    header_count_value(c, value, &low32);
    std::string out(file);
    for (int b = 0; b < 4; ++b) out[std::size_t(80 + b)] = char((low32 >> (8 * b)) & 0xFF);
    return out;
  }
  // The tokens [begin, end) that hold the counts.
  std::vector<std::pair<std::size_t, std::size_t>> counts;
  if (extension == ".off") {
    // The first tokens, comments skipped: [magic [dim]] nv nf [ne].
    std::vector<std::pair<std::size_t, std::size_t>> tokens;
    for (std::size_t pos = 0; pos < file.size() && tokens.size() < 5;) {
      if (file[pos] == '#') {
        while (pos < file.size() && file[pos] != '\n') ++pos;
      } else if (is_space(file[pos])) {
        ++pos;
      } else {
        const std::size_t begin = pos;
        while (pos < file.size() && !is_space(file[pos]) && file[pos] != '#') ++pos;
        tokens.emplace_back(begin, pos);
      }
    }
    std::size_t first = 0;
    if (!tokens.empty()) {
      const std::string_view magic = file.substr(tokens[0].first, tokens[0].second - tokens[0].first);
      if (magic.size() >= 3 && magic.substr(magic.size() - 3) == "OFF") {
        first = 1;
        if (magic.substr(0, magic.size() - 3).find('n') != std::string_view::npos) first = 2;
      }
    }
    for (std::size_t t = first; t < tokens.size() && counts.size() < 3; ++t) counts.push_back(tokens[t]);
  } else if (extension == ".ply") {
    // The last token of each "element NAME COUNT" line before end_header.
    const std::size_t header_end = std::min(file.find("end_header"), file.size());
    for (std::size_t pos = 0; pos < header_end;) {
      std::size_t eol = file.find('\n', pos);
      if (eol == std::string_view::npos || eol > header_end) eol = header_end;
      std::string_view line = file.substr(pos, eol - pos);
      std::size_t lead = 0;
      while (lead < line.size() && is_space(line[lead])) ++lead;
      if (line.substr(lead, 8) == "element ") {
        std::size_t end = line.size();
        while (end > 0 && is_space(line[end - 1])) --end;
        std::size_t begin = end;
        while (begin > 0 && !is_space(line[begin - 1])) --begin;
        if (begin < end) counts.emplace_back(pos + begin, pos + end);
      }
      pos = eol + 1;
    }
  }
  if (counts.empty()) return std::string(file);
  const auto& [begin, end] = counts[which % counts.size()];
  return replace_count(file, begin, end, value);
}

std::string mesh_fuzz_input(const std::string& extension, std::string_view input) {
  if (input.size() < kHeaderMutationTag.size() + 1 || input.substr(0, kHeaderMutationTag.size()) != kHeaderMutationTag ||
      (extension != ".off" && extension != ".ply" && extension != ".stl"))
    return std::string(input);
  return mutate_header_counts(extension, input.substr(kHeaderMutationTag.size() + 1),
                              std::uint8_t(input[kHeaderMutationTag.size()]));
}

}  // namespace cutwork::fuzz
