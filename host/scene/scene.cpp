#include "host/scene/scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/core/work_limits.h"
#include "host/core/json_io.h"
#include "host/mesh/mesh_io.h"
#include "host/mesh/union_jack_flips.h"
#include "host/pattern/exemplar.h"
#include "host/scene/json_reader.h"
#include "host/scene/load_regions.h"
#include "host/surfaces/generators.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr double kInf = INFINITY;

/// A JSON name and the enum value it stands for. The tables below list the names in the order
/// error messages offer them; the mapping never depends on an enum's numbering.
template <class E>
struct NamedValue {
  const char* name;
  E value;
};

constexpr NamedValue<Entity> kEntities[] = {{"vertices", Entity::Vertices},
                                            {"boundary_vertices", Entity::BoundaryVertices},
                                            {"edges", Entity::Edges},
                                            {"boundary_edges", Entity::BoundaryEdges},
                                            {"faces", Entity::Faces}};
constexpr NamedValue<LoadKind> kLoadKinds[] = {{"point", LoadKind::Point},
                                               {"edge", LoadKind::Edge},
                                               {"area", LoadKind::Area},
                                               {"pressure", LoadKind::Pressure},
                                               {"self_weight", LoadKind::SelfWeight}};
constexpr NamedValue<StructuralObjective> kStructuralObjectives[] = {
    {"none", StructuralObjective::None},
    {"energy_density", StructuralObjective::EnergyDensity},
    {"adaptive", StructuralObjective::Adaptive},
    {"compliance", StructuralObjective::Compliance}};
constexpr NamedValue<DensityMeasure> kDensityMeasures[] = {{"mean", DensityMeasure::Mean},
                                                           {"peak", DensityMeasure::Peak}};
const std::vector<std::string> kSupportTypes{"pinned", "clamped", "symmetry"};

/// The names of a table, in its order (what a reader accepts).
template <class E, size_t N>
std::vector<std::string> names_of(const NamedValue<E> (&table)[N]) {
  std::vector<std::string> names;
  for (const NamedValue<E>& entry : table) names.emplace_back(entry.name);
  return names;
}

/// The name of `value` in `table` (every enumerator has one).
template <class E, size_t N>
std::string name_of(const NamedValue<E> (&table)[N], E value) {
  for (const NamedValue<E>& entry : table)
    if (entry.value == value) return entry.name;
  throw Error("scene: an enumerator without a name in its table");
}

/// The value named `name` in `table`; `name` was accepted by a reader given names_of(table).
template <class E, size_t N>
E value_of(const NamedValue<E> (&table)[N], const std::string& name) {
  for (const NamedValue<E>& entry : table)
    if (name == entry.name) return entry.value;
  throw Error("scene: '" + name + "' is not in its table");
}

/// The optional member `key` of `r`, one of the names of `table` (`fallback` when absent).
template <class E, size_t N>
E read_named(JsonObjectReader& r, const std::string& key, E fallback, const NamedValue<E> (&table)[N]) {
  return value_of(table, r.string(key, name_of(table, fallback), names_of(table)));
}

const std::vector<std::string>& exemplar_names() {
  // The built-in exemplars of Fig. 2 (host/pattern implements them).
  static const std::vector<std::string> names{"packing", "flowers", "stripes", "circles", "mix"};
  return names;
}

Selector parse_selector(JsonObjectReader r, Entity default_entity) {
  Selector sel;
  sel.json_path = r.path();
  sel.entity = read_named(r, "entity", default_entity, kEntities);
  const char* axes[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    if (!r.has(axes[k])) {
      r.child(axes[k]);
      continue;
    }
    JsonObjectReader a = r.object(axes[k]);
    sel.above[k] = a.number("above", -kInf, -kInf, kInf);
    sel.below[k] = a.number("below", kInf, -kInf, kInf);
    if (!a.has("above") && !a.has("below"))
      a.fail("", "needs 'above' and/or 'below'");
    if (sel.above[k] >= sel.below[k])
      a.fail("", "'above' (" + format_number(sel.above[k]) + ") must be less than 'below' (" +
                     format_number(sel.below[k]) + ")");
    a.finish();
  }
  if (r.has("near")) {
    JsonObjectReader n = r.object("near");
    sel.near_point = n.required_vec3("point");
    sel.near_radius = n.number("radius", kInf, 0, kInf, true, false);
    n.finish();
  } else {
    r.child("near");
  }
  sel.nearest = r.integer("nearest", 0, 0, 1'000'000);
  if (sel.nearest > 0 && !sel.near_point)
    r.fail("nearest", "needs 'near': {\"point\": [x, y, z]} to measure distance from");
  r.finish();
  return sel;
}

nlohmann::ordered_json selector_to_json(const Selector& s) {
  using json = nlohmann::ordered_json;
  json j;
  j["entity"] = name_of(kEntities, s.entity);
  const char* axes[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    json a = json::object();
    if (std::isfinite(s.above[k])) a["above"] = s.above[k];
    if (std::isfinite(s.below[k])) a["below"] = s.below[k];
    if (!a.empty()) j[axes[k]] = a;
  }
  if (s.near_point) {
    j["near"] = {{"point", {(*s.near_point)[0], (*s.near_point)[1], (*s.near_point)[2]}}};
    if (std::isfinite(s.near_radius)) j["near"]["radius"] = s.near_radius;
  }
  if (s.nearest > 0) j["nearest"] = s.nearest;
  return j;
}

nlohmann::ordered_json vec3_json(const Vec3& v) { return nlohmann::ordered_json::array({v[0], v[1], v[2]}); }

// ---- the sections of a scene, one function each (parse_scene calls them in file order)

/// /mesh: a built-in generator with its parameters, or a mesh file (relative to `base_dir`).
MeshSpec parse_mesh_section(JsonObjectReader& root, const fs::path& base_dir) {
  MeshSpec mesh;
  JsonObjectReader m = root.object("mesh");
  if (!root.has("mesh")) root.fail("mesh", "is required: {\"generator\": NAME} or {\"file\": PATH}");
  const bool has_gen = m.has("generator"), has_file = m.has("file");
  if (has_gen == has_file) m.fail("", "needs exactly one of 'generator' or 'file'");
  if (has_gen) {
    std::vector<std::string> names;
    for (const auto& s : builtin_shapes()) names.push_back(s.name);
    mesh.generator = m.string("generator", "", names);
    const ShapeInfo* info = find_shape(mesh.generator);
    JsonObjectReader p = m.object("params");
    for (const auto& [key, def] : info->defaults)
      mesh.params[key] = p.number(key, def, -kInf, kInf);
    p.finish();  // unknown parameters named with the accepted ones; ranges checked by shapes
    mesh.edge_length = m.number("edge_length", info->base_edge_length, 0, kInf, true);
    mesh.sim_edge_length = m.number("sim_edge_length", info->sim_edge_length, 0, kInf);
  } else {
    const std::string f = m.string("file", "");
    if (f.empty()) m.fail("file", "must name a mesh file");
    fs::path p(f);
    mesh.file = p.is_absolute() || base_dir.empty() ? p : base_dir / p;
    if (!is_mesh_file(mesh.file))
      m.fail("file", "'" + f + "' is not a mesh file (accepted: .obj .ply .off .stl)");
    mesh.sim_edge_length = 0;
    static const std::vector<std::pair<std::string, double>> units = {
        {"m", 1.0}, {"cm", 0.01}, {"mm", 0.001}, {"in", 0.0254}};
    std::vector<std::string> names;
    for (const auto& [n, v] : units) names.push_back(n);
    mesh.unit_name = m.string("unit", "m", names);
    for (const auto& [n, v] : units)
      if (n == mesh.unit_name) mesh.unit = v;
    const nlohmann::json* sub = m.child("sim_subdivisions");
    if (sub && sub->is_string())
      (void)m.string("sim_subdivisions", "auto", {"auto"});
    else
      mesh.sim_subdivisions = m.integer("sim_subdivisions", kAutoSubdivisions, 0, kMaxSimSubdivisions);
  }
  m.finish();
  return mesh;
}

/// /material: the shell's elastic constants, thickness and density.
Material parse_material_section(JsonObjectReader& root) {
  JsonObjectReader m = root.object("material");
  const Material d;
  Material material;
  material.youngs_modulus = m.number("youngs_modulus", d.youngs_modulus, 0, 1e13, true);
  material.poisson_ratio = m.number("poisson_ratio", d.poisson_ratio, 0, 0.5, false, true);
  material.thickness = m.number("thickness", d.thickness, 0, 10, true);
  material.density = m.number("density", d.density, 0, 1e5);
  m.finish();
  return material;
}

/// /mechanics: the bending model, the fill stiffness rule and the fill-ratio filter.
MechanicsSettings parse_mechanics_section(JsonObjectReader& root) {
  MechanicsSettings mechanics;
  JsonObjectReader m = root.object("mechanics");
  const std::string bending = m.string("bending", "shape_operator", {"shape_operator", "hinge"});
  mechanics.bending = bending == "hinge" ? BendingModel::Hinge : BendingModel::ShapeOperator;
  const std::string stiffness = m.string("stiffness", "homogenised", {"linear", "homogenised"});
  mechanics.stiffness = stiffness == "homogenised" ? FillStiffness::Homogenised : FillStiffness::Linear;
  const std::string filter = m.string("filter", "cell", {"none", "cell"});
  mechanics.filter = filter == "cell" ? FillFilter::Cell : FillFilter::None;
  const std::string loads = m.string("loads", "material", {"material", "area"});
  mechanics.loads = loads == "area" ? LoadSpread::Area : LoadSpread::Material;
  const std::string lattice = m.string("lattice", "auto", {"auto", "hexagonal", "square"});
  mechanics.lattice = lattice == "square" ? PerforationLattice::Square : PerforationLattice::Hexagonal;
  mechanics.lattice_source = lattice == "auto" ? LatticeSource::Auto : LatticeSource::Scene;
  // A hexagonal lattice's stiffness is isotropic in its plane, so an axis given with it would be
  // read and do nothing: the scene says something the model cannot honour; "auto" measures it.
  if (lattice != "square" && m.has("lattice_axis"))
    m.fail("lattice_axis", fmt::format("is only read with \"lattice\": \"square\" ({})",
                                       lattice == "auto" ? "with \"auto\" the stencils' own axis is measured"
                                                         : "a hexagonal lattice is isotropic in its plane"));
  // "field": the lattice's axes follow the orientation field (a square-grid exemplar laid along a
  // field that turns over a curved shell).
  if (const nlohmann::json* given = m.child("lattice_axis"); given && given->is_string()) {
    if (m.string("lattice_axis", "", {"field"}) == "field") mechanics.lattice_follows_field = true;
  } else {
    const Vec3 axis = m.vec3("lattice_axis", Vec3::UnitX());
    if (!(axis.norm() > 1e-12)) m.fail("lattice_axis", "must be a non-zero direction or \"field\"");
    mechanics.lattice_axis = axis.normalized();
  }
  m.finish();
  return mechanics;
}

/// /supports: pinned or clamped vertex selections.
std::vector<SupportSpec> parse_supports_section(JsonObjectReader& root, const std::string& origin) {
  std::vector<SupportSpec> supports;
  const json& arr = root.array("supports");
  for (size_t i = 0; i < arr.size(); ++i) {
    JsonObjectReader s(arr[i], origin, "/supports/" + std::to_string(i));
    SupportSpec spec;
    const std::string type = s.string("type", "pinned", kSupportTypes);
    spec.kind = type == "clamped" ? SupportKind::Clamped : type == "symmetry" ? SupportKind::Symmetry : SupportKind::Pinned;
    if (!s.has("select")) s.fail("select", "is required: which vertices are supported");
    spec.select = parse_selector(s.object("select"), Entity::Vertices);
    if (spec.kind == SupportKind::Symmetry) {
      // The plane's normal: the boundary on the plane x = const (y, z) is held along it.
      if (s.has("axes")) s.fail("axes", "is for pinned supports: a symmetry plane names its normal, \"axis\": \"x\"");
      if (!s.has("axis")) s.fail("axis", "is required: the symmetry plane's normal, \"x\", \"y\" or \"z\" (the plane x = const through the selected vertices)");
      const std::string axis = s.string("axis", "x", {"x", "y", "z"});
      spec.axes = std::uint8_t(1u << (axis[0] - 'x'));
    } else if (s.has("axis")) {
      s.fail("axis", "is for symmetry supports (\"type\": \"symmetry\"); a pinned support along some axes names them in \"axes\"");
    }
    if (s.has("axes")) {
      // The global axes held, e.g. "xz" for a diaphragm across y or "z" for a sliding bearing.
      const std::string axes = s.string("axes", "xyz");
      if (spec.kind == SupportKind::Clamped) s.fail("axes", "is for pinned supports: a clamp holds all three axes");
      spec.axes = 0;
      for (const char c : axes) {
        const std::uint8_t bit = c == 'x' ? kHeldX : c == 'y' ? kHeldY : c == 'z' ? kHeldZ : 0;
        if (bit == 0 || (spec.axes & bit))
          s.fail("axes", "must name each of the held axes x, y, z at most once, e.g. \"xz\" (got \"" + axes + "\")");
        spec.axes |= bit;
      }
      if (spec.axes == 0) s.fail("axes", "names no axis: give the held ones, e.g. \"xz\", or leave the key out for all three");
    }
    s.finish();
    supports.push_back(spec);
  }
  return supports;
}

/// One entry of /loads: self-weight, or a force or pressure on the entities its selector picks
/// (which must be of the kind the load acts on).
LoadSpec parse_load(JsonObjectReader& l) {
  LoadSpec spec;
  const std::string type = l.required_string("type", names_of(kLoadKinds));
  spec.kind = value_of(kLoadKinds, type);
  if (spec.kind == LoadKind::SelfWeight) {
    spec.gravity = l.vec3("gravity", Vec3(0, 0, -9.81));
    return spec;
  }
  const Entity def = spec.kind == LoadKind::Point  ? Entity::Vertices
                     : spec.kind == LoadKind::Edge ? Entity::BoundaryEdges
                                                   : Entity::Faces;
  if (spec.kind == LoadKind::Pressure)
    spec.pressure = l.required_number("pressure", -kInf, kInf);
  else
    spec.force = l.required_vec3("force");
  if (!l.has("select")) l.fail("select", "is required: where the load acts");
  spec.select = parse_selector(l.object("select"), def);
  const bool edge_entity = spec.select.entity == Entity::Edges || spec.select.entity == Entity::BoundaryEdges;
  const bool face_entity = spec.select.entity == Entity::Faces;
  if (spec.kind == LoadKind::Edge && !edge_entity)
    l.fail("select", "an edge load selects 'edges' or 'boundary_edges'");
  if ((spec.kind == LoadKind::Area || spec.kind == LoadKind::Pressure) && !face_entity)
    l.fail("select", "an " + type + " load selects 'faces'");
  if (spec.kind == LoadKind::Point && (edge_entity || face_entity))
    l.fail("select", "a point load selects 'vertices' or 'boundary_vertices'");
  return spec;
}

/// /loads.
std::vector<LoadSpec> parse_loads_section(JsonObjectReader& root, const std::string& origin) {
  std::vector<LoadSpec> loads;
  const json& arr = root.array("loads");
  for (size_t i = 0; i < arr.size(); ++i) {
    JsonObjectReader l(arr[i], origin, "/loads/" + std::to_string(i));
    LoadSpec spec = parse_load(l);
    l.finish();
    loads.push_back(spec);
  }
  return loads;
}

/// /stencils: the stencil shapes, each a built-in kind with parameters or a polygon, validated
/// by the stencil library itself.
std::vector<StencilShapeSpec> parse_stencils_section(JsonObjectReader& root, const std::string& origin) {
  std::vector<StencilShapeSpec> shapes;
  const json& arr = root.array("stencils");
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string path = "/stencils/" + std::to_string(i);
    JsonObjectReader s(arr[i], origin, path);
    StencilShapeSpec spec;
    spec.kind = s.string("kind", "circle");
    spec.name = s.string("name", spec.kind);
    for (const auto& other : shapes)
      if (other.name == spec.name) s.fail("name", "duplicate stencil name '" + spec.name + "'");
    if (spec.kind == "polygon") {
      const json& pts = s.array("polygon");
      for (size_t k = 0; k < pts.size(); ++k) {
        const std::string pp = path + "/polygon/" + std::to_string(k);
        if (!pts[k].is_array() || pts[k].size() != 2 || !pts[k][0].is_number() || !pts[k][1].is_number())
          throw InputError(origin + ": " + pp + ": expected [x, y]");
        spec.polygon.emplace_back(pts[k][0].get<double>(), pts[k][1].get<double>());
      }
    } else if (s.has("params")) {
      JsonObjectReader p = s.object("params");
      for (auto it = arr[i]["params"].begin(); it != arr[i]["params"].end(); ++it)
        spec.params[it.key()] = p.number(it.key(), 0, -kInf, kInf);
      p.finish();
    } else {
      s.child("params");
    }
    s.finish();
    // Shape kinds and their parameters are validated by the stencil library itself.
    try {
      if (spec.kind == "polygon")
        make_polygon_stencil(spec.name, spec.polygon);
      else
        make_builtin_stencil(spec.kind, spec.params, spec.name);
    } catch (const InputError& e) {
      throw InputError(origin + ": " + path + ": " + e.what());
    }
    shapes.push_back(spec);
  }
  return shapes;
}

/// /pattern/brushes and /pattern/strokes: the sizing brushes and the sketch strokes.
void parse_brushes_and_strokes(JsonObjectReader& p, const std::string& origin, PatternSettings& o) {
  const json& brushes = p.array("brushes");
  for (size_t i = 0; i < brushes.size(); ++i) {
    JsonObjectReader b(brushes[i], origin, p.path_of("brushes") + "/" + std::to_string(i));
    SizingBrush br;
    br.center = b.required_vec3("center");
    br.radius = b.required_number("radius", 0, kInf, true);
    br.value = b.required_number("value", 0, kInf, true);
    b.finish();
    o.brushes.push_back(br);
  }
  const json& strokes = p.array("strokes");
  for (size_t i = 0; i < strokes.size(); ++i) {
    const std::string sp = p.path_of("strokes") + "/" + std::to_string(i);
    if (!strokes[i].is_array() || strokes[i].size() < 2)
      throw InputError(origin + ": " + sp + ": a stroke is an array of at least 2 points [x, y, z]");
    SketchStroke st;
    for (size_t k = 0; k < strokes[i].size(); ++k)
      st.points.push_back(json_to_vec3(strokes[i][k], origin, sp + "/" + std::to_string(k)));
    o.strokes.push_back(st);
  }
}

/// /pattern: the pattern objective (packing or an exemplar), its weights, sizing and sketch.
PatternSettings parse_pattern_section(JsonObjectReader& root, const std::string& origin,
                                      const fs::path& base_dir) {
  JsonObjectReader p = root.object("pattern");
  const PatternSettings d;
  PatternSettings o;
  o.objective = p.string("objective", "packing", {"packing", "exemplar"}) == "exemplar"
                    ? PatternObjective::Exemplar
                    : PatternObjective::Packing;
  if (const json* ex = p.child("exemplar")) {
    if (ex->is_string()) {
      o.exemplar = p.string("exemplar", "", exemplar_names());
    } else if (ex->is_object()) {
      // Validated here (what `check` runs), mapped onto the stencils by the pattern phase.
      parse_exemplar(*ex, origin, p.path_of("exemplar"));
      o.exemplar_inline = *ex;
    } else {
      p.fail("exemplar", "expected a built-in exemplar name or an exemplar object");
    }
  }
  if (o.objective == PatternObjective::Exemplar && o.exemplar.empty() && o.exemplar_inline.is_null())
    p.fail("exemplar", "is required when objective is 'exemplar'");
  o.w_P = p.number("w_P", d.w_P, 0, kInf);
  o.s = p.number("s", d.s, 0, 10);
  o.r_N = p.number("r_N", d.r_N, 0, 10, true);
  o.epsilon = p.number("epsilon", d.epsilon, 0, 10, true);
  o.xi = p.number("xi", d.xi, 0, kInf);
  o.scale = p.number("scale", d.scale, 0, kInf);
  o.scale_min = p.number("scale_min", 0.5, 0, 1);
  o.scale_max = p.number("scale_max", 1.5, 1, 100);
  o.count = p.integer("count", d.count, 0, 10'000'000);
  o.symmetry = p.integer("symmetry", d.symmetry, 0, 12);
  o.sizing = p.number("sizing", d.sizing, 0, kInf, true);
  if (p.has("sizing_file")) {
    fs::path f(p.string("sizing_file", ""));
    o.sizing_file = f.is_absolute() || base_dir.empty() ? f : base_dir / f;
  } else {
    p.child("sizing_file");
  }
  parse_brushes_and_strokes(p, origin, o);
  o.stroke_weight = p.number("stroke_weight", d.stroke_weight, 0, kInf);
  o.max_iterations = p.integer("max_iterations", d.max_iterations, 0, 1'000'000);
  o.seed = unsigned(p.integer("seed", int(d.seed), 0, 2147483647));
  p.finish();
  return o;
}

/// /structure: the structural objective and the structure phase's settings.
StructureSettings parse_structure_section(JsonObjectReader& root) {
  JsonObjectReader s = root.object("structure");
  const StructureSettings d;
  StructureSettings o;
  o.objective = read_named(s, "objective", d.objective, kStructuralObjectives);
  o.w_S = s.number("w_S", d.w_S, 0, kInf);
  o.beta = s.number("beta", d.beta, 0, 1, true, false);
  o.measure = read_named(s, "measure", d.measure, kDensityMeasures);
  o.adaptive_mode = s.string("adaptive_mode", d.adaptive_mode, {"top_percent", "median"});
  o.adaptive_y = s.number("adaptive_y", d.adaptive_y, 0, 100, true);
  o.max_iterations = s.integer("max_iterations", d.max_iterations, 0, 1'000'000);
  o.max_rounds = s.integer("max_rounds", d.max_rounds, 1, 1000);
  o.fill_holes = s.boolean("fill_holes", d.fill_holes);
  o.max_rotation = s.number("max_rotation", d.max_rotation, 0, 180);
  s.finish();
  return o;
}

/// /fabrication: what the printed part must satisfy.
FabricationSettings parse_fabrication_section(JsonObjectReader& root) {
  JsonObjectReader f = root.object("fabrication");
  FabricationSettings fabrication;
  fabrication.min_feature = f.number("min_feature", FabricationSettings{}.min_feature, 0, 10);
  fabrication.tool_radius = f.number("tool_radius", FabricationSettings{}.tool_radius, 0, 1);
  if (fabrication.tool_radius > 0 && fabrication.tool_radius < kMinToolRadius)
    f.fail("tool_radius", format_number(fabrication.tool_radius) + " m is finer than any tool rounds a corner (at least " +
                              format_number(kMinToolRadius) + " m; 0: sharp corners)");
  f.finish();
  return fabrication;
}

}  // namespace

Scene parse_scene(const json& doc, const std::string& origin, const fs::path& base_dir) {
  JsonObjectReader root(doc, origin, "");
  Scene scene;
  scene.name = root.string("name", "unnamed");
  scene.description = root.string("description", "");
  scene.mesh = parse_mesh_section(root, base_dir);
  scene.material = parse_material_section(root);
  scene.mechanics = parse_mechanics_section(root);
  scene.supports = parse_supports_section(root, origin);
  scene.loads = parse_loads_section(root, origin);
  scene.shapes = parse_stencils_section(root, origin);
  scene.pattern = parse_pattern_section(root, origin, base_dir);
  scene.structure = parse_structure_section(root);
  if (scene.structure.measure == DensityMeasure::Peak && scene.mechanics.stiffness != FillStiffness::Homogenised)
    throw InputError(origin +
                     ": /structure/measure: 'peak' needs mechanics.stiffness 'homogenised' (the concentration factors "
                     "come from its cell problems)");
  for (size_t i = 0; i < scene.supports.size(); ++i)
    if (scene.supports[i].kind == SupportKind::Symmetry && scene.mechanics.bending == BendingModel::Hinge)
      throw InputError(origin + ": /supports/" + std::to_string(i) +
                       ": a symmetry plane needs mechanics.bending 'shape_operator' (the hinge model has no mirrored "
                       "slope across a boundary)");
  scene.fabrication = parse_fabrication_section(root);
  set_tool_radius(scene, scene.fabrication.tool_radius);
  root.finish();
  return scene;
}

void set_tool_radius(Scene& scene, double tool_radius) {
  scene.fabrication.tool_radius = tool_radius;
  scene.mechanics.tool_radius = tool_radius;
  // W_peak reads its factors by corner at the tool's rounds, or without a tool leaves out the rim
  // about singular corners as verify does (load_case.h).
  scene.mechanics.corner_radius = tool_radius > 0 ? tool_radius : scene.fabrication.min_feature;
}

nlohmann::ordered_json scene_to_json(const Scene& s) {
  using json = nlohmann::ordered_json;
  json j;
  j["name"] = s.name;
  j["description"] = s.description;
  if (!s.mesh.generator.empty()) {
    j["mesh"] = {{"generator", s.mesh.generator},
                 {"params", s.mesh.params},
                 {"edge_length", s.mesh.edge_length},
                 {"sim_edge_length", s.mesh.sim_edge_length}};
  } else {
    j["mesh"] = {{"file", s.mesh.file.string()}, {"unit", s.mesh.unit_name}};
    if (s.mesh.sim_subdivisions == kAutoSubdivisions)
      j["mesh"]["sim_subdivisions"] = "auto";
    else
      j["mesh"]["sim_subdivisions"] = s.mesh.sim_subdivisions;
  }
  j["material"] = {{"youngs_modulus", s.material.youngs_modulus},
                   {"poisson_ratio", s.material.poisson_ratio},
                   {"thickness", s.material.thickness},
                   {"density", s.material.density}};
  j["mechanics"] = {{"bending", s.mechanics.bending == BendingModel::Hinge ? "hinge" : "shape_operator"},
                    {"stiffness", s.mechanics.stiffness == FillStiffness::Homogenised ? "homogenised" : "linear"},
                    {"filter", s.mechanics.filter == FillFilter::Cell ? "cell" : "none"},
                    {"loads", s.mechanics.loads == LoadSpread::Area ? "area" : "material"},
                    {"lattice", s.mechanics.lattice_source != LatticeSource::Scene                ? "auto"
                                : s.mechanics.lattice == PerforationLattice::Square ? "square"
                                                                                    : "hexagonal"}};
  if (s.mechanics.lattice_source == LatticeSource::Scene && s.mechanics.lattice == PerforationLattice::Square)
    j["mechanics"]["lattice_axis"] =
        s.mechanics.lattice_follows_field ? json("field") : vec3_json(s.mechanics.lattice_axis);
  j["supports"] = json::array();
  for (const auto& sp : s.supports) {
    json support = {{"type", sp.kind == SupportKind::Clamped    ? "clamped"
                             : sp.kind == SupportKind::Symmetry ? "symmetry"
                                                                : "pinned"},
                    {"select", selector_to_json(sp.select)}};
    if (sp.kind == SupportKind::Symmetry) {
      for (int a = 0; a < 3; ++a)
        if (sp.axes & (1u << a)) support["axis"] = std::string(1, char('x' + a));
    } else if (sp.axes != kHeldAll) {
      std::string axes;
      for (int a = 0; a < 3; ++a)
        if (sp.axes & (1u << a)) axes += char('x' + a);
      support["axes"] = axes;
    }
    j["supports"].push_back(support);
  }
  j["loads"] = json::array();
  for (const auto& l : s.loads) {
    json lj;
    lj["type"] = name_of(kLoadKinds, l.kind);
    switch (l.kind) {
      case LoadKind::SelfWeight: lj["gravity"] = vec3_json(l.gravity); break;
      case LoadKind::Pressure: lj["pressure"] = l.pressure; break;
      default: lj["force"] = vec3_json(l.force); break;
    }
    if (l.kind != LoadKind::SelfWeight) lj["select"] = selector_to_json(l.select);
    j["loads"].push_back(lj);
  }
  j["stencils"] = json::array();
  for (const auto& sh : s.shapes) {
    json sj = {{"name", sh.name}, {"kind", sh.kind}};
    if (sh.kind == "polygon") {
      sj["polygon"] = json::array();
      for (const auto& p : sh.polygon) sj["polygon"].push_back({p[0], p[1]});
    } else {
      sj["params"] = sh.params;
    }
    j["stencils"].push_back(sj);
  }
  const PatternSettings& p = s.pattern;
  json pj = {{"objective", p.objective == PatternObjective::Exemplar ? "exemplar" : "packing"},
             {"w_P", p.w_P},           {"s", p.s},
             {"r_N", p.r_N},           {"epsilon", p.epsilon},
             {"xi", p.xi},             {"scale", p.scale},
             {"scale_min", p.scale_min}, {"scale_max", p.scale_max},
             {"count", p.count},       {"symmetry", p.symmetry},
             {"sizing", p.sizing},     {"stroke_weight", p.stroke_weight},
             {"max_iterations", p.max_iterations}, {"seed", p.seed}};
  if (!p.exemplar.empty()) pj["exemplar"] = p.exemplar;
  if (!p.exemplar_inline.is_null()) pj["exemplar"] = p.exemplar_inline;
  if (!p.sizing_file.empty()) pj["sizing_file"] = p.sizing_file.string();
  pj["brushes"] = json::array();
  for (const auto& b : p.brushes)
    pj["brushes"].push_back({{"center", vec3_json(b.center)}, {"radius", b.radius}, {"value", b.value}});
  pj["strokes"] = json::array();
  for (const auto& st : p.strokes) {
    json pts = json::array();
    for (const auto& q : st.points) pts.push_back(vec3_json(q));
    pj["strokes"].push_back(pts);
  }
  j["pattern"] = pj;
  const StructureSettings& st = s.structure;
  j["structure"] = {{"objective", name_of(kStructuralObjectives, st.objective)},
                    {"w_S", st.w_S},
                    {"beta", st.beta},
                    {"measure", name_of(kDensityMeasures, st.measure)},
                    {"adaptive_mode", st.adaptive_mode},
                    {"adaptive_y", st.adaptive_y},
                    {"max_iterations", st.max_iterations},
                    {"max_rounds", st.max_rounds},
                    {"fill_holes", st.fill_holes},
                    {"max_rotation", st.max_rotation}};
  j["fabrication"] = {{"min_feature", s.fabrication.min_feature}, {"tool_radius", s.fabrication.tool_radius}};
  return j;
}

PlainMeshSupport plain_mesh_support(const SurfaceMesh& mesh) {
  const double zmin = mesh.bbox_min()[2];
  const double extent = (mesh.bbox_max() - mesh.bbox_min()).norm();
  PlainMeshSupport out;
  // A mesh flat in z (every vertex would be "lowest") rests on a frame: its boundary.
  if (mesh.bbox_max()[2] - zmin <= 0.01 * extent && !mesh.boundary_loops().empty()) {
    out.select = {{"entity", "boundary_vertices"}};
    out.description = "a flat mesh, its boundary vertices";
    out.exact = true;
    return out;
  }
  // The part of the surface at its lowest level: a rim, flat feet or a flat bottom. The mesh's
  // facets meet that plane in the same points, lines and faces however finely they are divided,
  // so every refinement (the discretisation estimate's, verify's conforming meshes) holds the same
  // region. It holds the shell if it is not a point or a line.
  const double tolerance = 1e-6 * extent;
  std::vector<Vec3> lowest;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    if (mesh.vertices()(v, 2) <= zmin + tolerance) lowest.push_back(mesh.vertices().row(v).transpose());
  double span = 0, width = 0;  // the largest distance from the first, then from the line through both
  Vec3 far = lowest.front();
  for (const Vec3& p : lowest)
    if ((p - lowest.front()).norm() > span) {
      span = (p - lowest.front()).norm();
      far = p;
    }
  if (span > 0) {
    const Vec3 axis = (far - lowest.front()) / span;
    for (const Vec3& p : lowest) width = std::max(width, (p - lowest.front()).cross(axis).norm());
  }
  if (width > 1e-3 * extent) {
    out.select = {{"entity", "vertices"}, {"z", {{"below", zmin + tolerance}}}};
    out.description = fmt::format("the {} vertices on its lowest plane (z below {})", lowest.size(),
                                  format_number(zmin + tolerance));
    out.exact = true;
    return out;
  }
  // It touches its lowest plane in a point or along a line (a rounded bottom): a band of 1% of the
  // model's size. That band catches more of a finer mesh (a surface rising tangentially out of it),
  // so the discretisation estimate says its levels hold different regions.
  out.select = {{"entity", "vertices"}, {"z", {{"below", zmin + 0.01 * extent}}}};
  out.description = fmt::format("vertices with z below {} (it touches its lowest plane only in a {}: the band of 1% of "
                                "its size holds more of a finer mesh; select the supports in a scene)",
                                format_number(zmin + 0.01 * extent), span > 0 ? "line" : "point");
  return out;
}

std::string metres_hint(const SurfaceMesh& mesh) {
  // Coordinates are metres; a part printed from an STL is usually drawn in millimetres.
  const double size = (mesh.bbox_max() - mesh.bbox_min()).maxCoeff();
  if (!(size > 100)) return {};
  return fmt::format(" (it is {:.3g} m across: coordinates are read as metres; a file drawn in millimetres needs a "
                     "scene with \"mesh\": {{\"file\": ..., \"unit\": \"mm\"}})",
                     size);
}

Scene load_scene(const std::string& what, std::string* notice) {
  fs::path path(what);
  std::error_code ec;
  const bool exists = fs::exists(path, ec);
  // A folder never holds a scene, so a built-in name wins over a folder of that name (such as
  // the output folder of `cutwork design plate --out plate`, made before the scene is read).
  if (!exists || fs::is_directory(path, ec)) {
    for (const auto& b : builtin_scenes())
      if (b.name == what) {
        Scene s = parse_scene(builtin_scene_json(what), "builtin:" + what);
        return s;
      }
    if (exists) throw InputError(what + ": is a directory, expected a scene or mesh file");
    std::string names;
    for (const auto& b : builtin_scenes()) names += (names.empty() ? "" : ", ") + b.name;
    throw InputError(what + ": no such file, and not a built-in scene (built-in: " + names + ")");
  }
  if (is_mesh_file(path)) {
    SurfaceMesh mesh = read_mesh(path);
    const PlainMeshSupport support = plain_mesh_support(mesh);
    json doc = {{"name", path.stem().string()},
                {"description", "mesh file with default supports and loads"},
                {"mesh", {{"file", fs::absolute(path).string()}}},
                {"supports", json::array({{{"type", "pinned"}, {"select", support.select}}})},
                {"loads", json::array({{{"type", "self_weight"}}})},
                {"stencils", json::array({{{"name", "circle"}, {"kind", "circle"}}})}};
    Scene s = parse_scene(doc, path.string());
    s.from_plain_mesh = true;
    s.source = path;
    const std::string unit_hint = metres_hint(mesh);
    if (notice)
      *notice = path.string() + ": a plain mesh; using defaults: self-weight, " + support.description +
                " pinned, circle stencils" + unit_hint;
    return s;
  }
  if (path.extension() != ".json")
    throw InputError(what + ": unknown file type (expected a .json scene or a .obj/.ply/.off/.stl mesh)");
  Scene s = parse_scene(read_json_file(path), path.string(), path.parent_path());
  s.source = path;
  return s;
}

std::string scene_origin(const Scene& scene) {
  return scene.source.empty() ? "builtin:" + scene.name : scene.source.string();
}

SceneMeshes build_scene_meshes(const Scene& scene) {
  SceneMeshes out;
  if (!scene.mesh.generator.empty()) {
    try {
      out.base = generate_shape(scene.mesh.generator, scene.mesh.params, scene.mesh.edge_length,
                                work_limits().max_faces);
    } catch (const InputError& e) {
      throw InputError(scene_origin(scene) + ": /mesh: " + e.what());
    }
    if (scene.mesh.sim_edge_length > 0 && scene.mesh.sim_edge_length != scene.mesh.edge_length) {
      try {
        out.sim = generate_shape(scene.mesh.generator, scene.mesh.params, scene.mesh.sim_edge_length,
                                 work_limits().max_faces, "sim_edge_length");
      } catch (const InputError& e) {
        throw InputError(scene_origin(scene) + ": /mesh: " + e.what());
      }
    }
    if (out.sim.num_faces() == 0) {
      out.sim = out.base;
      out.sim_is_base = true;
    }
  } else {
    out.base = read_mesh(scene.mesh.file);
    if (scene.mesh.unit != 1.0)
      out.base = SurfaceMesh(out.base.vertices() * scene.mesh.unit, out.base.faces(), scene.mesh.file.string());
    // Union-jack patches (a CAD surface's quads split both ways) turned one way for the simulation:
    // the bending element reads them 16-73% too soft (host/mesh/union_jack_flips.h).
    UnionJackFlips flipped = flip_union_jack_diagonals(out.base);
    out.sim_flips = flipped.flips;
    out.sim = std::move(flipped.mesh);
    out.sim_is_base = out.sim_flips == 0;
    out.sim_choice_pending = scene.mesh.sim_subdivisions == kAutoSubdivisions;
    if (scene.mesh.sim_subdivisions > 0) {
      try {
        use_subdivided_simulation_mesh(out, scene.mesh.sim_subdivisions);
      } catch (const InputError& e) {
        throw InputError(scene_origin(scene) + ": /mesh/sim_subdivisions: " + e.what());
      }
      return out;
    }
  }
  out.map = map_meshes(out.base, out.sim);
  return out;
}

void use_subdivided_simulation_mesh(SceneMeshes& meshes, int subdivisions) {
  const double faces = double(meshes.base.num_faces()) * std::pow(4.0, subdivisions);
  if (faces > double(work_limits().max_faces))
    throw InputError(fmt::format("{} subdivisions of {} triangles make {:.0f}, over the limit of {} (--max-faces)",
                                 subdivisions, meshes.base.num_faces(), faces, work_limits().max_faces));
  SurfaceMesh sim = meshes.sim_flips > 0 ? flip_union_jack_diagonals(meshes.base).mesh : meshes.base;
  for (int k = 0; k < subdivisions; ++k) sim = midpoint_subdivision(sim);
  meshes.sim = std::move(sim);
  meshes.sim_is_base = subdivisions == 0 && meshes.sim_flips == 0;
  meshes.sim_subdivisions = subdivisions;
  meshes.map = map_meshes(meshes.base, meshes.sim);
}

std::string union_jack_note(const SceneMeshes& meshes) {
  if (meshes.sim_flips == 0) return {};
  return fmt::format("the file's mesh has union-jack patches (quads split along alternating diagonals), which the "
                     "shape-operator bending reads too soft (a flat plate 73%): {} of their diagonals are turned one "
                     "way in the simulation mesh (the base mesh, cut and exported, keeps them)",
                     meshes.sim_flips);
}

std::vector<std::string> model_notes(const Scene& scene, const SceneMeshes& meshes) {
  std::vector<std::string> notes;
  if (std::string flips = union_jack_note(meshes); !flips.empty()) notes.push_back(std::move(flips));
  if (scene.mechanics.bending == BendingModel::Hinge) {
    const SurfaceMesh& m = meshes.sim;
    Vec3 mean = Vec3::Zero();
    for (int f = 0; f < m.num_faces(); ++f) mean += m.face_areas()[f] * m.face_normals().row(f).transpose();
    double least = 1;
    if (mean.norm() > 0)
      for (int f = 0; f < m.num_faces(); ++f) least = std::min(least, m.face_normals().row(f).dot(mean.normalized()));
    if (mean.norm() == 0 || least < std::cos(10 * std::numbers::pi / 180))
      notes.push_back(
          "mechanics.bending \"hinge\" (the paper's discrete-shell hinges) does not converge to curved shells: on the "
          "references of other shell codes it reads the Scordelis-Lo roof 29% and the pinched hemisphere 60% too stiff "
          "and a pinched ring 28% too soft, where the default shape_operator converges to them (docs/DESIGN.md \"Shell "
          "mechanics\")");
  }
  return notes;
}

namespace {
bool inside(const Selector& s, const Vec3& x) {
  for (int k = 0; k < 3; ++k)
    if (!(x[k] > s.above[k] && x[k] < s.below[k])) return false;
  if (s.near_point && std::isfinite(s.near_radius) && (x - *s.near_point).norm() > s.near_radius)
    return false;
  return true;
}

/// A symmetry support's vertices `vs` onto `lc`: the plane x_a = const they lie on (a the one bit of
/// `axis`), held along x_a, marked in symmetry_axes. Refuses vertices off one plane, inside the
/// surface, or a second plane across the same axis (`where` names the support).
void add_symmetry_plane(LoadCase& lc, const SurfaceMesh& mesh, const std::vector<int>& vs, std::uint8_t axis,
                        const std::string& where) {
  const int a = axis == kHeldX ? 0 : axis == kHeldY ? 1 : 2;
  const char name = char('x' + a);
  const RowMatX3d& V = mesh.vertices();
  const double tol = 1e-6 * (mesh.bbox_max() - mesh.bbox_min()).norm();
  double lo = INFINITY, hi = -INFINITY;
  for (int v : vs) lo = std::min(lo, V(v, a)), hi = std::max(hi, V(v, a));
  if (hi - lo > tol)
    throw InputError(fmt::format("{}: the selected vertices do not lie on one plane {} = const ({} from {} to {}): a "
                                 "symmetry plane is where the surface meets its mirror image; select its vertices on it",
                                 where, name, name, format_number(lo), format_number(hi)));
  for (int v : vs)
    if (!mesh.is_boundary_vertex()[v])
      throw InputError(fmt::format("{}: the vertex at {} lies inside the surface, not on its boundary: a symmetry plane "
                                   "holds the edge where the modelled half ends (select only the boundary on the plane)",
                                   where, fmt::format("({:.4g}, {:.4g}, {:.4g})", V(v, 0), V(v, 1), V(v, 2))));
  const double c = 0.5 * (lo + hi);
  if (std::isfinite(lc.symmetry_planes[a]) && std::abs(lc.symmetry_planes[a] - c) > tol)
    throw InputError(fmt::format("{}: a second symmetry plane across {} ({} = {}, and {} = {} before): a finite "
                                 "structure has at most one mirror plane per direction",
                                 where, name, name, format_number(c), name, format_number(lc.symmetry_planes[a])));
  if (!std::isfinite(lc.symmetry_planes[a])) lc.symmetry_planes[a] = c;
  const std::size_t nv = std::size_t(mesh.num_vertices());
  if (lc.held_axes.empty()) lc.held_axes.assign(nv, 0);
  if (lc.symmetry_axes.empty()) lc.symmetry_axes.assign(nv, 0);
  for (int v : vs) {
    lc.held_axes[std::size_t(v)] |= axis;
    lc.symmetry_axes[std::size_t(v)] |= axis;
  }
}
}  // namespace

std::vector<int> select_entities(const Selector& sel, const SurfaceMesh& mesh, const std::vector<bool>* outer_boundary) {
  const RowMatX3d& V = mesh.vertices();
  auto on_boundary = [&](int v) { return mesh.is_boundary_vertex()[v] && (!outer_boundary || (*outer_boundary)[v]); };
  std::vector<int> out;
  std::vector<double> dist;  // to near_point, for `nearest`
  auto centre_of = [&](std::initializer_list<int> vs) {
    Vec3 c = Vec3::Zero();
    for (int v : vs) c += V.row(v).transpose();
    return Vec3(c / double(vs.size()));
  };
  auto keep = [&](int index, bool ok, const Vec3& where) {
    if (!ok) return;
    out.push_back(index);
    if (sel.near_point) dist.push_back((where - *sel.near_point).norm());
  };
  switch (sel.entity) {
    case Entity::Vertices:
    case Entity::BoundaryVertices:
      for (int v = 0; v < mesh.num_vertices(); ++v) {
        if (sel.entity == Entity::BoundaryVertices && !on_boundary(v)) continue;
        const Vec3 x = V.row(v).transpose();
        keep(v, inside(sel, x), x);
      }
      break;
    case Entity::Edges:
    case Entity::BoundaryEdges:
      for (int e = 0; e < mesh.num_edges(); ++e) {
        const int a = mesh.edges()(e, 0), b = mesh.edges()(e, 1);
        if (sel.entity == Entity::BoundaryEdges && (mesh.edge_faces()(e, 1) >= 0 || !on_boundary(a) || !on_boundary(b)))
          continue;
        keep(e, inside(sel, V.row(a).transpose()) && inside(sel, V.row(b).transpose()), centre_of({a, b}));
      }
      break;
    case Entity::Faces:
      for (int f = 0; f < mesh.num_faces(); ++f) {
        const int a = mesh.faces()(f, 0), b = mesh.faces()(f, 1), c = mesh.faces()(f, 2);
        keep(f,
             inside(sel, V.row(a).transpose()) && inside(sel, V.row(b).transpose()) &&
                 inside(sel, V.row(c).transpose()),
             centre_of({a, b, c}));
      }
      break;
  }
  if (sel.nearest > 0 && int(out.size()) > sel.nearest) {
    std::vector<int> order(out.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = int(i);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return dist[a] < dist[b]; });
    std::vector<int> kept;
    for (int i = 0; i < sel.nearest; ++i) kept.push_back(out[order[i]]);
    std::sort(kept.begin(), kept.end());
    out = kept;
  }
  return out;
}

bool has_symmetry_plane(const Scene& scene) {
  return std::any_of(scene.supports.begin(), scene.supports.end(),
                     [](const SupportSpec& s) { return s.kind == SupportKind::Symmetry; });
}

Vec3 scene_symmetry_planes(const Scene& scene, const SurfaceMesh& mesh) {
  if (!has_symmetry_plane(scene)) return Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  return resolve_load_case(scene, mesh).symmetry_planes;
}

LoadCase resolve_load_case(const Scene& scene, const SurfaceMesh& mesh, const std::vector<bool>* outer_boundary,
                           const LoadCase* match_totals) {
  const std::string origin = scene_origin(scene);
  LoadCase lc;
  const int nv = mesh.num_vertices();
  lc.fixed.assign(nv, false);
  lc.clamped.assign(nv, false);
  lc.forces = RowMatX3d::Zero(nv, 3);
  auto selected = [&](const Selector& sel) {
    std::vector<int> ids = select_entities(sel, mesh, outer_boundary);
    if (ids.empty())
      throw InputError(origin + ": " + sel.json_path + ": selects no " + name_of(kEntities, sel.entity) +
                       " on the simulation mesh (bounding box [" + format_number(mesh.bbox_min()[0]) + ", " +
                       format_number(mesh.bbox_min()[1]) + ", " + format_number(mesh.bbox_min()[2]) + "] to [" +
                       format_number(mesh.bbox_max()[0]) + ", " + format_number(mesh.bbox_max()[1]) + ", " +
                       format_number(mesh.bbox_max()[2]) + "])");
    return ids;
  };
  auto vertices_of = [&](const Selector& sel, const std::vector<int>& ids) {
    std::vector<int> vs;
    for (int id : ids) {
      if (sel.entity == Entity::Vertices || sel.entity == Entity::BoundaryVertices) vs.push_back(id);
      else if (sel.entity == Entity::Faces) for (int k = 0; k < 3; ++k) vs.push_back(mesh.faces()(id, k));
      else for (int k = 0; k < 2; ++k) vs.push_back(mesh.edges()(id, k));
    }
    std::sort(vs.begin(), vs.end());
    vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
    return vs;
  };
  for (size_t i = 0; i < scene.supports.size(); ++i) {
    const SupportSpec& sp = scene.supports[i];
    if (sp.kind == SupportKind::Symmetry) {
      add_symmetry_plane(lc, mesh, vertices_of(sp.select, selected(sp.select)), sp.axes,
                         origin + ": /supports/" + std::to_string(i));
      continue;
    }
    for (int v : vertices_of(sp.select, selected(sp.select))) {
      if (sp.axes != kHeldAll) {  // pinned along some axes: the union of every support's
        if (lc.held_axes.empty()) lc.held_axes.assign(std::size_t(nv), 0);
        lc.held_axes[std::size_t(v)] |= sp.axes;
        continue;
      }
      lc.fixed[v] = true;
      if (sp.kind == SupportKind::Clamped) lc.clamped[v] = true;
    }
  }
  const RowMatX3d& V = mesh.vertices();
  const RowMatX3i& F = mesh.faces();
  const RowMatX2i& E = mesh.edges();
  auto on_boundary = [&](int v) { return mesh.is_boundary_vertex()[v] && (!outer_boundary || (*outer_boundary)[v]); };
  // The edges a line-type load may act on: the (outer) boundary edges, or every edge.
  auto line_edges = [&](bool boundary_only) {
    std::vector<int> es;
    for (int e = 0; e < mesh.num_edges(); ++e)
      if (!boundary_only || (mesh.edge_faces()(e, 1) < 0 && on_boundary(E(e, 0)) && on_boundary(E(e, 1))))
        es.push_back(e);
    return es;
  };
  // Spread a traction (per face, N/m²) over the surface inside the selector's region, or a force
  // per length (N/m) along its (boundary) edges, with consistent nodal weights; add to `out` and
  // return the area or length covered.
  // `record` keeps each face's share (SurfaceLoad).
  auto spread_over_area = [&](const Selector& sel, auto&& traction_of_face, RowMatX3d& out, SurfaceLoad& record) {
    double measure = 0;
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const Vec3 a = V.row(F(f, 0)).transpose(), b = V.row(F(f, 1)).transpose(), c = V.row(F(f, 2)).transpose();
      const RegionMoment m = triangle_in_region(a, b, c, sel);
      if (!(m.measure > 0)) continue;
      measure += m.measure;
      const Vec3 w = triangle_nodal_weights(a, b, c, m);
      const Vec3 t = traction_of_face(f);
      for (int k = 0; k < 3; ++k) out.row(F(f, k)) += w[k] * t.transpose();
      record.faces.push_back(f);
      record.areas.push_back(m.measure);
      record.nodal.push_back({w[0] * t, w[1] * t, w[2] * t});
    }
    return measure;
  };
  auto spread_over_line = [&](const Selector& sel, const Vec3& per_length, RowMatX3d& out) {
    double measure = 0;
    for (int e : line_edges(sel.entity != Entity::Edges)) {
      const Vec3 a = V.row(E(e, 0)).transpose(), b = V.row(E(e, 1)).transpose();
      const RegionMoment m = segment_in_region(a, b, sel);
      if (!(m.measure > 0)) continue;
      measure += m.measure;
      const auto w = segment_nodal_weights(a, b, m);
      out.row(E(e, 0)) += w[0] * per_length.transpose();
      out.row(E(e, 1)) += w[1] * per_length.transpose();
    }
    return measure;
  };
  auto nothing_inside = [&](const Selector& sel, const char* what) {
    std::string where;
    if (sel.near_point) {
      double closest = INFINITY;
      for (int v = 0; v < nv; ++v) closest = std::min(closest, (V.row(v).transpose() - *sel.near_point).norm());
      where = "; its nearest vertex is " + format_number(closest) + " m from near.point";
    }
    return InputError(origin + ": " + sel.json_path + ": its region holds no " + what +
                      " of the simulation mesh (bounding box [" + format_number(mesh.bbox_min()[0]) + ", " +
                      format_number(mesh.bbox_min()[1]) + ", " + format_number(mesh.bbox_min()[2]) + "] to [" +
                      format_number(mesh.bbox_max()[0]) + ", " + format_number(mesh.bbox_max()[1]) + ", " +
                      format_number(mesh.bbox_max()[2]) + "]" + where + ")");
  };
  if (match_totals && match_totals->load_measures.size() != scene.loads.size())
    throw Error("resolve_load_case: the load case to match was resolved from another scene");
  lc.load_measures.assign(scene.loads.size(), 0.0);
  for (size_t i = 0; i < scene.loads.size(); ++i) {
    const LoadSpec& l = scene.loads[i];
    if (l.kind == LoadKind::SelfWeight) {
      lc.gravity += l.gravity;
      continue;
    }
    const Selector& sel = l.select;
    RowMatX3d forces = RowMatX3d::Zero(nv, 3);
    SurfaceLoad surface;  // the faces' shares of a load spread over the surface
    double& measure = lc.load_measures[i];
    bool per_measure = true;  // a load per area or length (scaled to match), not a total
    if (sel.nearest > 0) {
      // `nearest`: the n closest entities, as selected on this mesh (mesh-dependent by nature).
      const std::vector<int> ids = selected(sel);
      switch (l.kind) {
        case LoadKind::Point: {
          const std::vector<int> vs = vertices_of(sel, ids);
          for (int v : vs) forces.row(v) += l.force.transpose() / double(vs.size());
          measure = double(vs.size());
          per_measure = false;
          break;
        }
        case LoadKind::Edge:
          for (int e : ids) {
            const double len = (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
            forces.row(E(e, 0)) += 0.5 * len * l.force.transpose();
            forces.row(E(e, 1)) += 0.5 * len * l.force.transpose();
            measure += len;
          }
          break;
        case LoadKind::Area:
        case LoadKind::Pressure:
          for (int f : ids) {
            const double A = mesh.face_areas()[f];
            const Vec3 t = l.kind == LoadKind::Area ? l.force : Vec3(l.pressure * mesh.face_normals().row(f).transpose());
            for (int k = 0; k < 3; ++k) forces.row(F(f, k)) += (A / 3.0) * t.transpose();
            measure += A;
            surface.faces.push_back(f);
            surface.areas.push_back(A);
            surface.nodal.push_back({A / 3.0 * t, A / 3.0 * t, A / 3.0 * t});
          }
          break;
        case LoadKind::SelfWeight: break;
      }
    } else {
      switch (l.kind) {
        case LoadKind::Point: {
          // A total force spread evenly over the surface (or, for boundary vertices, the boundary
          // line) inside the region: a patch load of the region's physical size.
          per_measure = false;
          const bool line = sel.entity == Entity::BoundaryVertices;
          measure = line ? spread_over_line(sel, l.force, forces)
                         : spread_over_area(sel, [&](int) { return l.force; }, forces, surface);
          if (!(measure > 0)) throw nothing_inside(sel, line ? "boundary length" : "surface area");
          forces /= measure;
          for (auto& n : surface.nodal)
            for (Vec3& v : n) v /= measure;
          break;
        }
        case LoadKind::Edge:
          measure = spread_over_line(sel, l.force, forces);
          if (!(measure > 0)) throw nothing_inside(sel, sel.entity == Entity::Edges ? "edge length" : "boundary length");
          break;
        case LoadKind::Area:
        case LoadKind::Pressure:
          measure = spread_over_area(
              sel,
              [&](int f) {
                return l.kind == LoadKind::Area ? l.force : Vec3(l.pressure * mesh.face_normals().row(f).transpose());
              },
              forces, surface);
          if (!(measure > 0)) throw nothing_inside(sel, "surface area");
          break;
        case LoadKind::SelfWeight: break;
      }
    }
    // A load per area or length carries the total of the load case it matches: on a mesh with
    // holes cut, the share that falls on the holes goes to the material left in the region.
    if (match_totals && per_measure && measure > 0) {
      const double ratio = match_totals->load_measures[i] / measure;
      forces *= ratio;
      for (auto& n : surface.nodal)
        for (Vec3& v : n) v *= ratio;
      measure = match_totals->load_measures[i];
    }
    lc.forces += forces;
    if (!surface.faces.empty() && scene.mechanics.loads == LoadSpread::Material)
      lc.surface_loads.push_back(std::move(surface));
  }
  return lc;
}

namespace {
/// Per face: part of an area support — its three vertices fixed and one of them inside the mesh (a
/// face with all three on the boundary and fixed is a line support turning a corner).
std::vector<bool> area_support_faces(const SurfaceMesh& mesh, const std::vector<bool>& fixed, const char* who) {
  if (int(fixed.size()) != mesh.num_vertices()) throw InternalError(std::string(who) + ": one flag per vertex expected");
  std::vector<bool> face_fixed(std::size_t(mesh.num_faces()), false);
  const std::vector<bool>& boundary = mesh.is_boundary_vertex();
  for (int f = 0; f < mesh.num_faces(); ++f) {
    bool all = true, inner = false;
    for (int c = 0; c < 3; ++c) {
      const auto v = std::size_t(mesh.faces()(f, c));
      all = all && fixed[v];
      inner = inner || !boundary[v];
    }
    face_fixed[std::size_t(f)] = all && inner;
  }
  return face_fixed;
}
}  // namespace

std::vector<int> support_outline_edges(const SurfaceMesh& mesh, const std::vector<bool>& fixed) {
  const std::vector<bool> face_fixed = area_support_faces(mesh, fixed, "support_outline_edges");
  const std::vector<bool>& boundary = mesh.is_boundary_vertex();
  std::vector<int> out;
  for (int k = 0; k < mesh.num_edges(); ++k) {
    const int a = mesh.edges()(k, 0), b = mesh.edges()(k, 1);
    const int f0 = mesh.edge_faces()(k, 0), f1 = mesh.edge_faces()(k, 1);
    if (f1 < 0 || !fixed[std::size_t(a)] || !fixed[std::size_t(b)]) continue;
    const bool in0 = face_fixed[std::size_t(f0)], in1 = face_fixed[std::size_t(f1)];
    const bool chord = boundary[std::size_t(a)] && boundary[std::size_t(b)];
    if (!chord && (in0 != in1 || (!in0 && !in1))) out.push_back(k);
  }
  return out;
}

SupportExtent support_extent(const SurfaceMesh& mesh, const std::vector<bool>& fixed, const std::vector<bool>* outer) {
  const std::vector<bool> face_fixed = area_support_faces(mesh, fixed, "support_extent");
  if (outer && outer->size() != fixed.size())
    throw InputError("support_extent: " + std::to_string(outer->size()) + " outer-boundary flags for " +
                     std::to_string(fixed.size()) + " vertices");
  const std::vector<bool>& boundary = mesh.is_boundary_vertex();
  // With `outer`: the vertices of the boundary loops with no vertex on the outer boundary (the rims
  // of holes inside the surface).
  std::vector<bool> inner_rim(fixed.size(), false);
  if (outer)
    for (const std::vector<int>& loop : mesh.boundary_loops()) {
      const bool touches = std::any_of(loop.begin(), loop.end(), [&](int v) { return (*outer)[std::size_t(v)]; });
      if (!touches)
        for (int v : loop) inner_rim[std::size_t(v)] = true;
    }
  SupportExtent e;
  for (int f = 0; f < mesh.num_faces(); ++f)
    if (face_fixed[std::size_t(f)]) e.area += mesh.face_areas()[f];
  std::vector<bool> on_edge(fixed.size(), false);
  for (int k = 0; k < mesh.num_edges(); ++k) {
    const int a = mesh.edges()(k, 0), b = mesh.edges()(k, 1);
    if (!fixed[std::size_t(a)] || !fixed[std::size_t(b)]) continue;
    on_edge[std::size_t(a)] = on_edge[std::size_t(b)] = true;
    // An edge on the mesh's boundary is a line; an interior edge is one when neither of its faces
    // is in an area support (else it is inside one or on its outline, which the area measures) and
    // it is no chord between two boundary vertices (a line support turning a corner fixes the
    // corner triangle's third edge too).
    const int f0 = mesh.edge_faces()(k, 0), f1 = mesh.edge_faces()(k, 1);
    const bool chord = boundary[std::size_t(a)] && boundary[std::size_t(b)];
    // With `outer`, the rim of a hole inside an area support is the area's own outline, not a line.
    // (Its face's three vertices fixed: an ear of the rim, all three on it, is in the area too.)
    const bool rim_in_area = f1 < 0 && inner_rim[std::size_t(a)] && [&] {
      for (int c = 0; c < 3; ++c)
        if (!fixed[std::size_t(mesh.faces()(f0, c))]) return false;
      return true;
    }();
    const bool line =
        (f1 < 0 && !rim_in_area) || (f1 >= 0 && !chord && !face_fixed[std::size_t(f0)] && !face_fixed[std::size_t(f1)]);
    if (line) e.length += (mesh.vertices().row(a) - mesh.vertices().row(b)).norm();
  }
  for (std::size_t v = 0; v < fixed.size(); ++v)
    if (fixed[v] && !on_edge[v]) ++e.points;
  return e;
}

double support_extent_change(const SupportExtent& a, const SupportExtent& b, double edge_length) {
  auto change = [](double x, double y, double scale) {
    const double m = std::max({std::abs(x), std::abs(y), scale});
    return m > 0 ? std::abs(x - y) / m : 0.0;
  };
  // Beside a line or an area a point support holds about one element, edge_length² of area (the
  // chair's conforming mesh had one stray fixed vertex on its coarsest level beside 7.2 m of line
  // and 0.10 m² of area); on their own, points are counted.
  const bool only_points = a.area == 0 && b.area == 0 && a.length == 0 && b.length == 0;
  if (only_points) return change(a.points, b.points, 0);
  const double h2 = edge_length * edge_length;
  return std::max(change(a.area + h2 * a.points, b.area + h2 * b.points, edge_length * std::max(a.length, b.length)),
                  change(a.length, b.length, 0));
}

}  // namespace cutwork
