#include "host/pattern/stencils_json.h"

#include <cmath>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/json_io.h"
#include "host/scene/json_reader.h"

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

StencilsFile read_stencils_json(const std::filesystem::path& path, const StencilLibrary& shapes,
                                const StencilBounds* bounds) {
  const json doc = read_json_file(path);
  const std::string origin = path.string();
  JsonObjectReader root(doc, origin, "");
  if (const json* shape_map = root.child("shapes")) {
    if (!shape_map->is_object()) root.fail("shapes", "must be an object of shapes by name");
    for (auto it = shape_map->begin(); it != shape_map->end(); ++it) {
      JsonObjectReader sh(it.value(), origin, "/shapes/" + it.key());
      const int id = shapes.find(it.key());
      if (id < 0)
        root.fail("shapes", fmt::format("shape '{}' is not among the scene's stencil shapes", it.key()));
      const json& poly = sh.array("polygon");
      const auto& mine = shapes[id].polygon;
      bool same = poly.size() == mine.size();
      for (size_t k = 0; same && k < poly.size(); ++k) {
        const json& q = poly[k];
        same = q.is_array() && q.size() == 2 && q[0].is_number() && q[1].is_number() &&
               (Vec2(q[0].get<double>(), q[1].get<double>()) - mine[k]).norm() <= 1e-9;
      }
      if (!same)
        sh.fail("polygon", "differs from the scene's shape of that name: this file was made with other "
                           "stencil shapes");
      sh.string("kind", "");
      sh.integer("type", 0, 0, 1 << 20);
      sh.number("area", 0, 0, INFINITY);
      sh.finish();
    }
  }
  const json& list = root.array("stencils");
  root.finish();
  StencilsFile out;
  out.axis_x = RowMatX3d::Zero(Eigen::Index(list.size()), 3);
  for (size_t i = 0; i < list.size(); ++i) {
    JsonObjectReader r(list[i], origin, "/stencils/" + std::to_string(i));
    std::vector<std::string> names;
    for (const auto& sh : shapes.shapes()) names.push_back(sh.name);
    const std::string type = r.required_string("type", names);
    StencilParams p;
    p.type = shapes.find(type);
    p.position = r.required_vec3("position");
    const double diagonal = bounds ? (bounds->hi - bounds->lo).norm() : INFINITY;
    if (bounds) {
      const Vec3 outside = (p.position - bounds->hi).cwiseMax(bounds->lo - p.position).cwiseMax(0.0);
      if (outside.norm() > 0.5 * diagonal)
        r.fail("position", fmt::format("lies {:.4g} m outside the surface's bounding box (diagonal {:.4g} m): this "
                                       "file was made for another surface",
                                       outside.norm(), diagonal));
    }
    p.scale = r.required_number("scale", 0, diagonal, true, false);
    p.angle = r.number("angle", 0.0, -1e6, 1e6);
    out.axis_x.row(Eigen::Index(i)) = r.vec3("axis_x", Vec3::Zero()).transpose();
    r.vec3("normal", Vec3::Zero());
    r.vec3("tangent", Vec3::Zero());
    r.number("bounding_radius", p.scale, 0, INFINITY);
    r.finish();
    out.stencils.push_back(p);
  }
  return out;
}

}  // namespace cutwork
