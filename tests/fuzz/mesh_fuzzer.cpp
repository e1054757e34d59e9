// The mesh readers, one target per format (the file's extension picks the reader): read_mesh
// with every check it makes on the file, the parse and the surface, then what a file's simulation
// mesh goes through next (its union-jack diagonals turned one way). OFF, PLY and STL inputs
// that start with fuzz::kHeaderMutationTag get a header count rewritten first (fuzz_support.h).
#include <cstdlib>

#include "host/core/error.h"
#include "host/mesh/mesh_io.h"
#include "host/mesh/union_jack_flips.h"
#include "tests/fuzz/fuzz_support.h"

namespace {
int fuzz_mesh(const char* name, const std::uint8_t* data, std::size_t size) {
  using namespace cutwork;
  fuzz::use_small_limits();
  // An input tagged for it gets one of its header's counts rewritten (lying headers): see
  // fuzz::mesh_fuzz_input. Other inputs are the file as they are.
  const std::string extension = std::filesystem::path(name).extension().string();
  const std::string file = fuzz::mesh_fuzz_input(extension, {reinterpret_cast<const char*>(data), size});
  try {
    // What a mesh file's simulation mesh goes through next: its union-jack diagonals turned.
    const SurfaceMesh mesh = read_mesh(fuzz::scratch_file(name, file));
    const UnionJackFlips flipped = flip_union_jack_diagonals(mesh);
    if (flipped.mesh.num_faces() != mesh.num_faces() || flipped.mesh.num_vertices() != mesh.num_vertices()) std::abort();
  } catch (const InputError&) {
  }
  return 0;
}
}  // namespace

int fuzz_mesh_obj(const std::uint8_t* data, std::size_t size) { return fuzz_mesh("fuzz.obj", data, size); }
int fuzz_mesh_ply(const std::uint8_t* data, std::size_t size) { return fuzz_mesh("fuzz.ply", data, size); }
int fuzz_mesh_off(const std::uint8_t* data, std::size_t size) { return fuzz_mesh("fuzz.off", data, size); }
int fuzz_mesh_stl(const std::uint8_t* data, std::size_t size) { return fuzz_mesh("fuzz.stl", data, size); }
