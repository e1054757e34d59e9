#include "host/pattern/poisson_disk.h"

#include <algorithm>
#include <cmath>

#include "host/pattern/point_grid.h"

namespace cutwork {

int poisson_disk_sample(const PatternSurface& surface, StencilLayout& layout, PatternRng& rng,
                        const PoissonDiskOptions& o) {
  const double one_plus_s = 1 + o.safety;
  double rmax = o.unit * surface.sizing().max_value();
  for (const auto& st : layout) rmax = std::max(rmax, st.scale);
  DynamicPointGrid grid(2 * one_plus_s * rmax);
  for (const auto& st : layout) grid.insert(st.position);

  int added = 0, misses = 0;
  std::vector<int> near;
  for (;;) {
    if (o.count > 0 && int(layout.size()) >= o.count) break;
    const int limit = o.max_misses > 0 ? o.max_misses : std::max(3000, 30 * int(layout.size()));
    if (misses >= limit) break;
    const SurfacePoint where = surface.sample(rng);
    const int type = o.num_types > 1 ? rng.below(o.num_types) : 0;
    const Vec3 c = surface.mesh().point(where);
    const double r = o.unit * surface.sizing_at(where);
    bool ok = surface.boundary_distance(c, one_plus_s * r) >= one_plus_s * r;
    // Against the stencils and, across symmetry planes, their images and its own (pattern_mirror.h):
    // |g c − c_j| = |c − g c_j|.
    const PatternMirror& mirror = surface.mirror();
    for (int k = -1; ok && k < mirror.num_reflections(); ++k) {
      const Vec3 y = k < 0 ? c : mirror.image(c, k);
      if (k >= 0 && (y - c).norm() < 2 * one_plus_s * r) ok = false;
      grid.in_ball(y, one_plus_s * (r + rmax), near);
      for (int j : near)
        if (ok && (grid.point(j) - y).norm() < one_plus_s * (r + layout[size_t(j)].scale)) ok = false;
    }
    if (!ok) {
      ++misses;
      continue;
    }
    misses = 0;
    layout.push_back({c, where, r, 0.0, type});
    grid.insert(c);
    ++added;
  }
  return added;
}

}  // namespace cutwork
