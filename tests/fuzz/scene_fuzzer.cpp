// The scene reader: JSON text -> parse_scene -> meshes -> supports and loads, as `cutwork check`
// runs it (without the solvers).
#include <string_view>

#include "host/core/error.h"
#include "host/core/json_io.h"
#include "host/scene/scene.h"
#include "host/scene/work_estimate.h"
#include "tests/fuzz/fuzz_support.h"

int fuzz_scene(const std::uint8_t* data, std::size_t size) {
  using namespace cutwork;
  fuzz::use_small_limits();
  try {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    const Scene scene = parse_scene(parse_json_text(text, "fuzz.json"), "fuzz.json");
    if (!scene.mesh.generator.empty()) {  // a mesh file named in the scene is the mesh fuzzers' job
      const SceneMeshes meshes = build_scene_meshes(scene);
      resolve_load_case(scene, meshes.sim);
      check_stencil_work(scene, meshes);
    }
  } catch (const InputError&) {
  }
  return 0;
}
