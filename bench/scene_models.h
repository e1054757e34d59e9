#pragma once
/// Scene-based models for the scaling and assembly benchmarks, and the process's peak memory.
///
///   sheet_model(faces, bending, stiffness, lattice)
///                                the built-in `sheet` scene (1 m, pinned boundary, self-weight,
///                                h = 2 mm) simulated on its base mesh of about `faces` near-equilateral
///                                triangles, with the given bending model and fill stiffness rule
///                                (calibrated on the given lattice: square adds the anisotropic parts).
///                                Cached per arguments, so every benchmark of one run sees the same model.
///   process_cpu_seconds()        user and system CPU seconds of the whole process so far (every
///                                thread of every pool): the figure to trust on a shared machine.
///   peak_memory_gib()            VmHWM of /proc/self/status (GiB): the resident-set high-water mark of
///                                the whole process so far (monotone: run sizes in increasing order).
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <utility>

#include <sys/resource.h>

#include "host/scene/scene.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::bench {

inline const solvers::ShellModel& sheet_model(int faces, BendingModel bending = BendingModel::ShapeOperator,
                                              FillStiffness stiffness = FillStiffness::Linear,
                                              PerforationLattice lattice = PerforationLattice::Hexagonal) {
  static std::map<std::tuple<int, BendingModel, FillStiffness, PerforationLattice>,
                  std::unique_ptr<solvers::ShellModel>>
      cache;
  std::unique_ptr<solvers::ShellModel>& slot = cache[{faces, bending, stiffness, lattice}];
  if (slot) return *slot;
  Scene scene = load_scene("sheet");
  // Near-equilateral triangles of edge e: √3/4 e² each, on the 1 m² sheet.
  scene.mesh.edge_length = std::sqrt(4.0 / (std::sqrt(3.0) * faces));
  scene.mesh.sim_edge_length = 0;
  scene.mechanics.bending = bending;
  scene.mechanics.stiffness = stiffness;  // homogenised: calibrated, with the isotropic split
  scene.mechanics.lattice = lattice;
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  slot = std::make_unique<solvers::ShellModel>(meshes.sim, scene.material, lc, solvers::scene_mechanics(scene));
  return *slot;
}

inline std::pair<double, double> process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return {double(u.ru_utime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec),
          double(u.ru_stime.tv_sec) + 1e-6 * double(u.ru_stime.tv_usec)};
}

/// User + system: total CPU seconds of the process so far.
inline double process_cpu_total() {
  const auto [user, sys] = process_cpu_seconds();
  return user + sys;
}

inline double peak_memory_gib() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      double kib = 0;
      status >> kib;
      return kib / (1024.0 * 1024.0);
    }
    std::getline(status, key);
  }
  return 0;
}

}  // namespace cutwork::bench
