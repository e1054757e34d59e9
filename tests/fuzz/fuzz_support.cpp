#include "tests/fuzz/fuzz_support.h"

#include <unistd.h>

#include <fstream>

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

}  // namespace cutwork::fuzz
