#pragma once
/// What a design run holds in memory at its peak, estimated before it runs from its meshes: what
/// `cutwork sweep --memory` reserves per variant and sets aside once (host/cli/sweep_runner.h,
/// docs/SWEEP.md "Memory"). Measured on one thread with /usr/bin/time; each constant's source is
/// in design_memory.cpp and tests/cli/sweep_memory_test.cpp checks them against real designs.
#include <cstddef>
#include <span>

#include "host/scene/scene.h"

namespace cutwork::solvers {

/// Estimated peak memory (bytes) of one design beyond what the process holds anyway
/// (kProcessMemory) and beyond a calibration of its stencils' stiffness (calibration_memory, set
/// aside once per process).
struct DesignMemory {
  /// The design on its meshes and, with the discretisation estimate, the largest of the levels it
  /// always solves (h/2, h/4): held from the start.
  size_t held = 0;
  /// More, only where the estimate solves its extra level (h/8; DiscretisationOptions::
  /// extra_refinements), which it does where the levels before it have not settled: the extra
  /// level's memory less the largest always-solved level's, which is freed before it is built.
  size_t on_demand = 0;
  size_t most() const { return held + on_demand; }
};

/// DesignMemory of one design on these meshes (`discretisation_estimate`: with the estimate's
/// levels, DiscretisationOptions: h/2, h/4 and h/8, each kept only while it has at most max_faces
/// triangles, h/2 always). A file's simulation mesh still to be chosen (sim_choice_pending) counts
/// as the finest the choice may take, with the levels the choice solves. Measured on the bowl at three sizes and the built-in scenes
/// (docs/SWEEP.md "Memory"), with a margin.
DesignMemory estimate_design_memory(const SceneMeshes& meshes, bool discretisation_estimate = true);

/// The triangles of the largest level the discretisation estimate may solve for a simulation mesh
/// of `sim_faces` triangles (the refinements multiply them by 4 each); `extra` false: of the levels
/// it always solves.
size_t largest_refined_level(size_t sim_faces, bool extra = true);

/// Resident memory of a design process before any design (the executable, its libraries, TBB).
inline constexpr size_t kProcessMemory = size_t(40e6);

/// Peak memory of one stiffness calibration (solvers/homogenise/fill_stiffness_calibration.h) run
/// with `threads` threads, for the scenes that need one (mechanics.stiffness homogenised), with a
/// tool where any scene has fabrication.tool_radius > 0; 0 when none does. A process calibrates one
/// curve at a time (the rest wait for it and share it), so a sweep sets this aside once.
size_t calibration_memory(std::span<const Scene> scenes, int threads);

}  // namespace cutwork::solvers
