// The mesh readers, one target per format (the file's extension picks the reader): read_mesh
// with every check it makes on the file, the parse and the surface.
#include "host/core/error.h"
#include "host/mesh/mesh_io.h"
#include "tests/fuzz/fuzz_support.h"

namespace {
int fuzz_mesh(const char* name, const std::uint8_t* data, std::size_t size) {
  using namespace cutwork;
  fuzz::use_small_limits();
  try {
    read_mesh(fuzz::scratch_file(name, {reinterpret_cast<const char*>(data), size}));
  } catch (const InputError&) {
  }
  return 0;
}
}  // namespace

int fuzz_mesh_obj(const std::uint8_t* data, std::size_t size) { return fuzz_mesh("fuzz.obj", data, size); }
int fuzz_mesh_ply(const std::uint8_t* data, std::size_t size) { return fuzz_mesh("fuzz.ply", data, size); }
int fuzz_mesh_off(const std::uint8_t* data, std::size_t size) { return fuzz_mesh("fuzz.off", data, size); }
int fuzz_mesh_stl(const std::uint8_t* data, std::size_t size) { return fuzz_mesh("fuzz.stl", data, size); }
