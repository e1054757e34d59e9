#include "solvers/report/design_memory.h"

#include <algorithm>

#include "solvers/conforming/discretisation_estimate.h"
#include "solvers/conforming/simulation_mesh_choice.h"

namespace cutwork::solvers {

size_t largest_refined_level(size_t sim_faces, bool extra) {
  const DiscretisationOptions o;
  size_t largest = 4 * sim_faces;  // h/2 is always made
  size_t faces = sim_faces;
  for (int k = 0; k < o.refinements + (extra ? o.extra_refinements : 0); ++k) {
    faces *= 4;
    if (faces > size_t(o.max_faces)) break;
    largest = faces;
  }
  return largest;
}

DesignMemory estimate_design_memory(const SceneMeshes& meshes, bool discretisation_estimate) {
  // Peak resident memory of single designs on one thread (/usr/bin/time), the process's own 28 MB
  // aside (kProcessMemory) and with the linear rule (no calibration: calibration_memory). The bowl
  // at its edge lengths and at 1/2 and 1/4 of them (2646/1350, 11094/5400, 44376/22326 base/
  // simulated triangles) peaked at 95, 119 and 388 MB without the discretisation estimate: the
  // pattern context, the cut and the files (~2 kB per base triangle), the shell model with its
  // element Hessians and the Cholesky factor (~12 kB per simulated triangle at 22k, growing with
  // the factor's fill) and about 55 MB besides, held here with a margin of 1.5 (more stencils mean
  // more clip pairs). With the estimate they peaked at 233, 776 and 882 MB, the pavilion (h/8
  // solved) at 398 MB: a level's mesh, model and factor, 6.9–8 kB per triangle at 21.6k–89k, held
  // at 9 kB per triangle of the largest level solved. The levels are solved one after another,
  // each freed before the next is built (their meshes, a few per cent of it, are kept), so h/8,
  // which a design solves only where the first three levels have not settled (the pavilion's;
  // not the bowl's, the table's or the chair's, which would hold 3–7× their peak for it), is on
  // demand: its memory less the always-solved level's.
  //
  // A file's simulation mesh still to be chosen ("auto", SceneMeshes::sim_choice_pending) is
  // counted as the finest the choice may take, and the levels its study solves first (those of the
  // file's mesh, h/8 included) as a level held.
  const size_t file = size_t(meshes.sim.num_faces());
  const int most = meshes.sim_choice_pending ? most_simulation_subdivisions(size_t(meshes.base.num_faces())) : 0;
  const size_t n = file << (2 * most);
  const double design = 55e6 + 2e3 * double(meshes.base.num_faces()) + 12e3 * double(n);
  DesignMemory m;
  m.held = size_t(1.5 * design);
  size_t level = most > 0 ? largest_refined_level(file, true) : 0;
  if (discretisation_estimate) {
    const size_t always = largest_refined_level(n, false), extra = largest_refined_level(n, true);
    level = std::max(level, always);
    m.on_demand = size_t(9e3 * double(extra - always));
  }
  m.held += size_t(9e3 * double(level));
  return m;
}

size_t calibration_memory(std::span<const Scene> scenes, int threads) {
  // A calibration solves its cells side by side, one per thread, each cut, remeshed and factorised
  // alone. `cutwork simulate` of the built-in scenes (the uncut shell: the calibration is all it
  // holds beyond the process's 28 MB, measured with the linear rule) peaked at 155–242 MB on one
  // thread and 191–303 MB on two (the drawn holes' cells, 10³–2·10⁴ triangles: up to 214 MB for
  // the largest, 36–61 MB more for a second at once); BM_ToolCalibration's default star by the
  // tool at 447 and 791 MB (3–5·10⁴ triangles, about 350 MB more per cell at once). Held as the
  // largest cell's at every thread.
  bool any = false, tool = false;
  for (const Scene& s : scenes)
    if (s.mechanics.stiffness == FillStiffness::Homogenised) {
      any = true;
      tool = tool || s.mechanics.tool_radius > 0;
    }
  if (!any) return 0;
  const double per_cell = tool ? 420e6 : 220e6;
  return size_t(per_cell * std::max(1, threads));
}

}  // namespace cutwork::solvers
