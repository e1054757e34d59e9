#include "tests/fuzz/fuzz_support.h"

#include <unistd.h>

#include <fstream>

#include "host/core/work_limits.h"

namespace cutwork::fuzz {
namespace fs = std::filesystem;

fs::path scratch_file(const std::string& name, std::string_view data) {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("cutwork-fuzz-" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
  }();
  const fs::path p = dir / name;
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(data.data(), std::streamsize(data.size()));
  return p;
}

void use_small_limits() {
  work_limits().max_faces = 500;
  work_limits().max_stencils = 2'000;
}

}  // namespace cutwork::fuzz
