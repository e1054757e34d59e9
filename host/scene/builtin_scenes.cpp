// The built-in scenes: the paper's examples (Fig. 4, Fig. 5, Figs. 1 and 6–9) made procedurally,
// with Table 2's parameters. Their sizes follow Table 1 (#v, #v_sim of the same order).
#include <algorithm>
#include <utility>

#include "host/core/error.h"
#include "host/scene/scene.h"

namespace cutwork {
using nlohmann::json;

namespace {

struct Entry {
  BuiltinScene info;     ///< name and description, also written into the document
  const char* base;      ///< the scene this one varies, or nullptr
  const char* document;  ///< the scene without name and description; with a base, a JSON merge
                         ///< patch (RFC 7386) of the base's document
};

// Materials. PA12 (laser sintered, the paper's prints) for the small objects; bent plywood for
// full-size furniture; glass-fibre reinforced concrete for the pavilion.
#define CUTWORK_PA12 R"("material": {"youngs_modulus": 1.7e9, "poisson_ratio": 0.4, "thickness": 0.003, "density": 1010})"
#define CUTWORK_PLYWOOD R"("material": {"youngs_modulus": 9e9, "poisson_ratio": 0.3, "thickness": 0.012, "density": 600})"

const std::vector<Entry>& entries() {
  static const std::vector<Entry> list{
      {{"plate", "Fig. 5: plate clamped on one short side, loaded at the middle of the opposite side"},
       nullptr, R"json({
  "mesh": {"generator": "plate", "params": {"width": 0.2, "height": 0.1}, "edge_length": 0.005, "sim_edge_length": 0.01},
  )json" CUTWORK_PA12 R"json(,
  "supports": [{"type": "clamped", "select": {"entity": "vertices", "x": {"below": -0.0999}}}],
  "loads": [{"type": "point", "force": [0, 0, -1.0],
             "select": {"entity": "vertices", "near": {"point": [0.1, 0, 0], "radius": 0.005}}}],
  "stencils": [{"name": "circle", "kind": "circle"}],
  "pattern": {"objective": "packing", "s": 0.2, "epsilon": 0.25, "seed": 1},
  "structure": {"objective": "energy_density", "w_S": 500, "beta": 0.5}
})json"},
      {{"sheet", "Fig. 4: unit sheet fixed along its outer boundary, under self-weight, one circular stencil"},
       nullptr, R"json({
  "mesh": {"generator": "sheet", "edge_length": 0.025, "sim_edge_length": 0.05},
  "material": {"youngs_modulus": 1.7e9, "poisson_ratio": 0.4, "thickness": 0.002, "density": 1010},
  "supports": [{"type": "pinned", "select": {"entity": "boundary_vertices"}}],
  "loads": [{"type": "self_weight", "gravity": [0, 0, -9.81]}],
  "stencils": [{"name": "circle", "kind": "circle"}],
  "pattern": {"objective": "packing", "count": 1, "scale": 0.2, "s": 0.0, "seed": 1},
  "structure": {"objective": "none", "w_S": 0, "beta": 1.0}
})json"},
      {{"bowl", "Fig. 9: fruit bowl hanging from its rim, pulled at the bottom"},
       nullptr, R"json({
  "mesh": {"generator": "bowl", "edge_length": 0.0085, "sim_edge_length": 0.012},
  )json" CUTWORK_PA12 R"json(,
  "supports": [{"type": "pinned", "select": {"entity": "boundary_vertices"}}],
  "loads": [{"type": "point", "force": [0, 0, -20],
             "select": {"entity": "vertices", "near": {"point": [0, 0, 0], "radius": 0.015}}}],
  "stencils": [{"name": "flower", "kind": "flower"}, {"name": "circle", "kind": "circle"}],
  "pattern": {"objective": "exemplar", "exemplar": "flowers", "s": 0.1, "r_N": 0.3, "seed": 1, "count": 185},
  "structure": {"objective": "energy_density", "w_S": 200, "beta": 0.8}
})json"},
      {{"table", "Fig. 8: monocoque table fixed at its feet, loaded on the top"},
       nullptr, R"json({
  "mesh": {"generator": "table", "edge_length": 0.035, "sim_edge_length": 0.04},
  )json" CUTWORK_PLYWOOD R"json(,
  "mechanics": {"lattice": "square", "lattice_axis": [0, 1, 0]},
  "supports": [{"type": "clamped", "select": {"entity": "vertices", "z": {"below": 1e-6}}}],
  "loads": [{"type": "area", "force": [0, 0, -1500], "select": {"entity": "faces", "z": {"above": 0.6}}}],
  "stencils": [{"name": "circle", "kind": "circle"}],
  "pattern": {"objective": "exemplar", "exemplar": "circles", "s": 0.0, "r_N": 0.3, "seed": 1, "count": 462},
  "structure": {"objective": "energy_density", "w_S": 10000, "beta": 0.5}
})json"},
      {{"chair", "Fig. 6: monocoque cantilever chair fixed on its runner, loaded on seat and back rest"},
       nullptr, R"json({
  "mesh": {"generator": "chair", "edge_length": 0.022, "sim_edge_length": 0.03},
  )json" CUTWORK_PLYWOOD R"json(,
  "supports": [{"type": "clamped", "select": {"entity": "vertices", "z": {"below": 1e-6}}}],
  "loads": [{"type": "area", "force": [0, 0, -4000], "select": {"entity": "faces", "x": {"above": 0.05, "below": 0.4}, "z": {"above": 0.4, "below": 0.5}}},
            {"type": "area", "force": [-800, 0, 0], "select": {"entity": "faces", "z": {"above": 0.6}}}],
  "stencils": [{"name": "star", "kind": "star"}, {"name": "circle", "kind": "circle"}],
  "pattern": {"objective": "exemplar", "exemplar": "mix", "s": 0.2, "r_N": 0.3, "seed": 1, "count": 436},
  "structure": {"objective": "energy_density", "w_S": 1000, "beta": 0.7}
})json"},
      {{"pavilion", "Figs. 1, 7: doubly curved vault on four legs under self-weight, energy-density objective"},
       nullptr, R"json({
  "mesh": {"generator": "pavilion", "edge_length": 0.22, "sim_edge_length": 0.35},
  "material": {"youngs_modulus": 2e10, "poisson_ratio": 0.2, "thickness": 0.03, "density": 2000},
  "supports": [{"type": "clamped", "select": {"entity": "vertices", "z": {"below": 1e-6}}}],
  "loads": [{"type": "self_weight", "gravity": [0, 0, -9.81]}],
  "stencils": [{"name": "flower", "kind": "flower"}],
  "pattern": {"objective": "exemplar", "exemplar": "stripes", "s": 0.2, "r_N": 0.3, "seed": 1, "count": 310},
  "structure": {"objective": "energy_density", "w_S": 500, "beta": 0.2}
})json"},
      {{"pavilion-adaptive", "Fig. 7: the pavilion with the adaptive energy-density threshold (median)"},
       "pavilion", R"json({"structure": {"objective": "adaptive", "adaptive_mode": "median"}})json"},
      {{"pavilion-compliance", "Fig. 7: the pavilion minimising compliance at constant stencil area"},
       "pavilion", R"json({"structure": {"objective": "compliance"}})json"},
  };
  return list;
}

}  // namespace

const std::vector<BuiltinScene>& builtin_scenes() {
  // A plain loop: clang 14 (the fuzzing build) cannot compile libstdc++ 12's ranges.
  static const std::vector<BuiltinScene> list = [] {
    std::vector<BuiltinScene> infos;
    for (const Entry& e : entries()) infos.push_back(e.info);
    return infos;
  }();
  return list;
}

json builtin_scene_json(const std::string& name) {
  for (const auto& e : entries()) {
    if (e.info.name != name) continue;
    json doc = json::parse(e.document);
    if (e.base != nullptr) {
      json base = builtin_scene_json(e.base);
      base.merge_patch(doc);
      doc = std::move(base);
    }
    doc["name"] = e.info.name;
    doc["description"] = e.info.description;
    return doc;
  }
  std::string names;
  for (const auto& e : entries()) names += (names.empty() ? "" : ", ") + e.info.name;
  throw InputError("'" + name + "' is not a built-in scene (built-in: " + names + ")");
}

}  // namespace cutwork
