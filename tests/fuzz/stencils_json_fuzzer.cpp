// The stencils.json reader, against the shapes of a two-stencil scene and a unit box.
#include "host/core/error.h"
#include "host/pattern/stencils_json.h"
#include "host/stencil/stencil_shape.h"
#include "tests/fuzz/fuzz_support.h"

int fuzz_stencils_json(const std::uint8_t* data, std::size_t size) {
  using namespace cutwork;
  static const StencilLibrary shapes = [] {
    StencilLibrary lib;
    lib.add(make_builtin_stencil("circle", {}, "circle"));
    lib.add(make_builtin_stencil("flower", {}, "flower"));
    return lib;
  }();
  const StencilBounds bounds{Vec3(-1, -1, -1), Vec3(1, 1, 1)};
  try {
    const auto path = fuzz::scratch_file("stencils.json", {reinterpret_cast<const char*>(data), size});
    read_stencils_json(path, shapes, &bounds);
  } catch (const InputError&) {
  }
  return 0;
}
