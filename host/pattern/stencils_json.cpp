#include "host/pattern/stencils_json.h"

#include <cmath>

#include "host/io/json_io.h"

namespace cutwork {
using nlohmann::json;

namespace {
json vec3(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }
}  // namespace

json stencils_to_json(const StencilLayout& layout, const PatternSurface& surface,
                      const StencilLibrary& shapes) {
  json list = json::array();
  for (const PlacedStencil& s : layout) {
    Vec3 n, t, b;
    surface.frame_at(s.where, n, t, b);
    const Vec3 axis = std::cos(s.angle) * t + std::sin(s.angle) * b;
    list.push_back({{"type", shapes[s.type].name},
                    {"position", vec3(s.position)},
                    {"normal", vec3(n)},
                    {"tangent", vec3(t)},
                    {"axis_x", vec3(axis)},
                    {"scale", s.scale},
                    {"angle", s.angle},
                    {"bounding_radius", s.scale}});
  }
  json shape_map = json::object();
  for (const StencilShape& sh : shapes.shapes()) {
    json poly = json::array();
    for (const Vec2& p : sh.polygon) poly.push_back({p.x(), p.y()});
    shape_map[sh.name] = {{"kind", sh.kind}, {"type", sh.type}, {"polygon", poly}, {"area", sh.area}};
  }
  return {{"stencils", list}, {"shapes", shape_map}};
}

void write_stencils_json(const std::filesystem::path& path, const StencilLayout& layout,
                         const PatternSurface& surface, const StencilLibrary& shapes) {
  write_json_atomic(path, stencils_to_json(layout, surface, shapes));
}

}  // namespace cutwork
