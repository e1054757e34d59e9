#pragma once
/// Exemplars for discrete element textures (§4.2, Fig. 2): a 2-D domain holding elements, each
/// with a position, a scale (bounding radius, exemplar units), a type and an angle.
///
/// JSON (inline in a scene's `pattern.exemplar`, or a file's content):
///   {"domain": [w, h]                      rectangle [0,w]×[0,h]
///            | [[x, y], [x, y], ...],      or a simple polygon (either orientation)
///    "elements": [{"position": [x, y], "scale": s, "type": "name", "angle": a}, ...],
///    "symmetry": N}                        optional: the arrangement's rotational symmetry
///                                          (stripes: 2), 0 = none/irregular (default)
/// `type` names a stencil of the scene (default: the scene's first stencil); `angle` (rad,
/// default 0) is the element's rotation relative to the exemplar's x axis.
///
/// Built-ins (Fig. 2): "packing" (a blue-noise packing of one shape), "flowers" (irregular
/// flowers of varied size, a few small fillers), "stripes" (rows of elements, dense along the
/// row and sparse across), "circles" (a regular lattice alternating large and small elements),
/// "mix" (a heterogeneous blue-noise mix of three types and sizes). Their types are abstract
/// ("primary", "secondary", "tertiary") and map onto the scene's stencils in order, cycling
/// when the scene has fewer stencils.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/core/types.h"

namespace cutwork {

struct ExemplarElement {
  Vec2 position = Vec2::Zero();
  double scale = 1;   ///< bounding radius (exemplar units)
  int type = 0;       ///< index into Exemplar::type_names
  double angle = 0;   ///< rad, relative to the exemplar's x axis
};

struct Exemplar {
  std::string name;                     ///< built-in name or "inline"
  std::vector<Vec2> domain;             ///< counter-clockwise simple polygon
  std::vector<ExemplarElement> elements;
  std::vector<std::string> type_names;  ///< distinct types, in order of first appearance
  int symmetry = 0;                     ///< rotational symmetry of the arrangement (0: none)
  bool builtin = false;                 ///< abstract types, mapped onto the stencils in order

  /// The exemplar's size: the larger side of the domain's bounding box (r_N is relative to it).
  double size() const;
  double area() const;
  double mean_scale() const;
  /// Distance from p to the domain's boundary (positive inside).
  double distance_to_boundary(const Vec2& p) const;
  bool contains(const Vec2& p) const;
};

/// Names of the built-in exemplars, in Fig. 2's order.
const std::vector<std::string>& builtin_exemplar_names();
/// A built-in exemplar (deterministic), or InputError listing the names.
Exemplar builtin_exemplar(const std::string& name);

/// Parses an exemplar document. `origin` and `path` name it in messages, e.g.
/// "scene.json", "/pattern/exemplar". Types are kept as written; map_exemplar_types checks them.
/// Throws InputError("<origin>: <path>/<key>: <problem>").
Exemplar parse_exemplar(const nlohmann::json& doc, const std::string& origin,
                        const std::string& path);

/// The stencil index of each exemplar type: built-in types cycle over `stencil_names`;
/// inline types must name a stencil (InputError naming the exemplar path otherwise).
std::vector<int> map_exemplar_types(const Exemplar& exemplar,
                                    const std::vector<std::string>& stencil_names,
                                    const std::string& origin = "", const std::string& path = "");

/// The exemplar as JSON (the inline format above).
nlohmann::json exemplar_to_json(const Exemplar& exemplar);

}  // namespace cutwork
