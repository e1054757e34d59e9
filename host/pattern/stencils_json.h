#pragma once
/// stencils.json: a design's stencils in a self-contained form.
///
///   {"stencils": [{"type": NAME, "position": [x,y,z], "normal": [..], "tangent": [..],
///                  "axis_x": [..], "scale": s, "angle": φ, "bounding_radius": r}, ...],
///    "shapes": {NAME: {"kind": K, "type": id, "polygon": [[x,y], ...], "area": a}, ...}}
///
/// position: the centre on the surface (m); normal: the Phong normal there; tangent: the
/// orientation field's direction t (φ = 0); angle φ (rad) counter-clockwise about the normal
/// from t; axis_x = cos φ t + sin φ (n × t), the direction of the polygon's x axis; scale s
/// (m): the bounding-circle radius, so a polygon point (u, v) lies at
/// position + s (u axis_x + v (n × axis_x)) in the stencil's tangent plane; bounding_radius
/// = s (already scaled; shapes have bounding radius 1). Polygons are counter-clockwise.
#include <filesystem>

#include <nlohmann/json.hpp>

#include "host/pattern/pattern_surface.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork {

nlohmann::json stencils_to_json(const StencilLayout& layout, const PatternSurface& surface,
                                const StencilLibrary& shapes);

/// Writes stencils_to_json(...) to `path` atomically (temporary file, then rename).
void write_stencils_json(const std::filesystem::path& path, const StencilLayout& layout,
                         const PatternSurface& surface, const StencilLibrary& shapes);

/// A design's stencils read back: parameters with `shapes`' type ids (matched by name) and the
/// stored axis_x of each stencil (#S×3; zero rows where the file has none).
struct StencilsFile {
  std::vector<StencilParams> stencils;
  RowMatX3d axis_x;
};

/// The bounding box of the surface the stencils belong to (m).
struct StencilBounds {
  Vec3 lo, hi;
};

/// Reads stencils.json strictly (the format above; normal, tangent and bounding_radius are
/// accepted and ignored). Throws InputError naming the file and JSON path for an unreadable
/// file, an unknown key, a stencil type that is not among `shapes`, a shape whose polygon
/// differs from the scene's shape of that name, a non-finite position or angle, or a scale
/// that is not > 0. With `bounds`, also a scale larger than the box's diagonal (a stencil that
/// covers the whole surface: no design makes one, and 1e308 overflows the clipping) and a
/// position farther than half a diagonal outside the box.
StencilsFile read_stencils_json(const std::filesystem::path& path, const StencilLibrary& shapes,
                                const StencilBounds* bounds = nullptr);

}  // namespace cutwork
