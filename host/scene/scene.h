#pragma once
/// A design scene: one JSON document (see docs/SCENES.md) parsed into plain structs. Parsing and
/// validation live in scene.cpp; everything downstream (shapes, mechanics, patterns) reads these
/// structs, never JSON.
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/mesh/mesh_mapping.h"
#include "host/scene/load_case.h"

namespace cutwork {

/// Where the base mesh comes from: a built-in generator or a file.
struct MeshSpec {
  std::string generator;                 ///< built-in shape name, or empty when `file` is set
  std::map<std::string, double> params;  ///< generator parameters (validated by host/surfaces)
  std::filesystem::path file;            ///< mesh file (resolved relative to the scene file)
  double edge_length = 0;                ///< base-mesh target edge length (m), generators only
  double sim_edge_length = 0;            ///< simulation-mesh edge length (m); 0: same as base
  /// Files only: the simulation mesh is the file's mesh divided this many times at its edges'
  /// midpoints (the same flat facets, finer), or kAutoSubdivisions: as many as the uncut shell
  /// needs to be within the discretisation tolerance (solvers/conforming/simulation_mesh_choice.h).
  int sim_subdivisions = -1;
  /// Files only: the length of one of the file's coordinate units in metres (`unit`: "m" 1, "cm"
  /// 0.01, "mm" 0.001, "in" 0.0254); the mesh is scaled by it when read.
  double unit = 1.0;
  std::string unit_name = "m";
};

/// MeshSpec::sim_subdivisions "auto", and the most a scene may ask for (256× the triangles).
inline constexpr int kAutoSubdivisions = -1;
inline constexpr int kMaxSimSubdivisions = 4;

/// Which mesh entities a selector picks. An edge or face is selected when all its vertices
/// satisfy every condition.
enum class Entity { Vertices, BoundaryVertices, Edges, BoundaryEdges, Faces };

/// A geometric predicate: the conjunction of per-axis bounds and an optional ball.
struct Selector {
  Entity entity = Entity::Vertices;
  std::array<double, 3> above{-INFINITY, -INFINITY, -INFINITY};  ///< coordinate > above[k]
  std::array<double, 3> below{INFINITY, INFINITY, INFINITY};     ///< coordinate < below[k]
  std::optional<Vec3> near_point;   ///< with near_radius: |x − near_point| ≤ near_radius
  double near_radius = 0;
  /// Keep only the `nearest` entities closest to `near_point` (0: keep all that match).
  int nearest = 0;
  std::string json_path;            ///< where it was written, for error messages
};

struct SupportSpec {
  SupportKind kind = SupportKind::Pinned;
  Selector select;
  /// The global axes a pinned support holds (LoadCase::held_axes bits; `"axes": "xz"`): all three by
  /// default; fewer let the vertices slide along the others. A clamp holds all three.
  std::uint8_t axes = kHeldAll;
};

enum class LoadKind {
  Point,        ///< `force` (N) in total, spread evenly over the surface inside the region
  Edge,         ///< `force` per length (N/m) along the (boundary) edges inside the region
  Area,         ///< `force` per area (N/m²) over the surface inside the region
  Pressure,     ///< `pressure` (Pa) along the faces' rest normals, over the surface inside the region
  SelfWeight,   ///< `gravity` (m/s²) times ρ h α A per face
};

struct LoadSpec {
  LoadKind kind = LoadKind::SelfWeight;
  Selector select;
  Vec3 force = Vec3::Zero();
  double pressure = 0;
  Vec3 gravity{0, 0, -9.81};
};

/// One stencil shape: a built-in kind with parameters, or a polygon.
struct StencilShapeSpec {
  std::string name;                       ///< unique within the scene
  std::string kind;                       ///< circle, ellipse, star, flower, leaf, apple, polygon…
  std::map<std::string, double> params;   ///< kind parameters (validated by host/stencil)
  std::vector<Vec2> polygon;              ///< vertices, for kind "polygon"
};

enum class PatternObjective { Packing, Exemplar };

struct SizingBrush {
  Vec3 center = Vec3::Zero();
  double radius = 0;
  double value = 1;
};

struct SketchStroke {
  std::vector<Vec3> points;  ///< a polyline on (or near) the surface
};

struct PatternSettings {
  PatternObjective objective = PatternObjective::Packing;
  std::string exemplar;                 ///< built-in exemplar name (objective = exemplar)
  nlohmann::json exemplar_inline;       ///< or an inline exemplar document (null if none)
  double w_P = 1.0;                     ///< pattern weight
  double s = 0.2;                       ///< collision safety factor
  double r_N = 0.3;                     ///< DET neighbourhood radius, relative to the exemplar size
  double epsilon = 0.25;                ///< packing neighbourhood, fraction of the object's length
  double xi = 1.0;                      ///< DET type-mismatch penalty
  double scale = 0.0;                   ///< stencil scale (bounding radius, m); 0: automatic
  double scale_min = 0.0;               ///< lower bound (fraction of `scale`)
  double scale_max = 0.0;               ///< upper bound (fraction of `scale`)
  int count = 0;                        ///< target stencil count for initialisation; 0: automatic
  int symmetry = 0;                     ///< orientation field N-fold symmetry; 0: from the shapes
  double sizing = 1.0;                  ///< constant sizing field value
  std::filesystem::path sizing_file;    ///< per-vertex sizing (one value per line), optional
  std::vector<SizingBrush> brushes;
  std::vector<SketchStroke> strokes;
  double stroke_weight = 10.0;          ///< soft alignment weight of sketch strokes
  int max_iterations = 200;
  unsigned seed = 1;
};

enum class StructuralObjective { None, EnergyDensity, Adaptive, Compliance };
/// What the energy-density objectives threshold: the face's mean energy density W (16), or the
/// ligament peak W_peak = K_m W^memb + K_b W^bend (solvers/objective/peak_energy_density.h; needs
/// mechanics.stiffness "homogenised", whose cell problems give K).
enum class DensityMeasure { Mean, Peak };

struct StructureSettings {
  StructuralObjective objective = StructuralObjective::EnergyDensity;
  double w_S = 500.0;                   ///< structural weight
  double beta = 0.2;                    ///< threshold as a fraction of the uncut shell's W_q (2% area quantile of W)
  DensityMeasure measure = DensityMeasure::Mean;  ///< W or W_peak against β (energy_density, adaptive)
  std::string adaptive_mode = "top_percent";  ///< "top_percent" or "median"
  double adaptive_y = 5.0;              ///< y (%) for top_percent
  int max_iterations = 200;
  int max_rounds = 10;                  ///< adaptive β updates / type-vote rounds
  bool fill_holes = false;              ///< §6.3 hole filling between rounds
  double max_rotation = 15.0;           ///< how far (degrees) the structure may turn a stencil
                                        ///< away from the orientation field's direction
};

/// What the printed part must satisfy (cut_solid.stl / .3mf, the minimum-feature check).
struct FabricationSettings {
  double min_feature = 0.001;  ///< narrowest printable ligament between stencils or to the border (m)
  /// Radius of the tool that cuts the holes (m; 0: the outlines as drawn): cutwork verify checks
  /// the outline as such a tool cuts it (host/stencil/stencil_opening.h).
  double tool_radius = 0;
};

struct Scene {
  std::string name;
  std::string description;
  std::filesystem::path source;         ///< scene file, or empty for a built-in
  bool from_plain_mesh = false;         ///< a mesh file given in place of a scene (defaults used)
  MeshSpec mesh;
  Material material;
  MechanicsSettings mechanics;
  std::vector<SupportSpec> supports;
  std::vector<LoadSpec> loads;
  std::vector<StencilShapeSpec> shapes;
  PatternSettings pattern;
  StructureSettings structure;
  FabricationSettings fabrication;
};

/// Parses and validates a scene document. `origin` names it in messages (a file name or
/// "builtin:NAME"); relative paths inside resolve against `base_dir`.
/// Throws InputError("<origin>: <json path>: <problem> (<accepted range>)").
Scene parse_scene(const nlohmann::json& doc, const std::string& origin,
                  const std::filesystem::path& base_dir = {});

/// The smallest radius (m) of a cutting tool: 10 µm. No cutter rounds a corner more finely (a laser's
/// kerf is some 0.1 mm wide); below it the factors by the tool would read rounds of thousandths of a
/// stencil's size, far past their cells (1/64 … 1/2 of it) and the extrapolation checked to 1/256
/// (W_peak 8e9 J/m² on the chair at 1 nm, against 212.5 drawn). 0 is no tool: sharp corners.
inline constexpr double kMinToolRadius = 1e-5;

/// Sets the radius (m, ≥ 0) of the tool the holes are cut with (fabrication.tool_radius) and what
/// the mechanics reads from it (MechanicsSettings::tool_radius, and corner_radius: the tool's radius,
/// or the minimum feature without a tool). parse_scene calls it; so does a command that overrides
/// the scene's tool (cutwork verify --tool-radius).
void set_tool_radius(Scene& scene, double tool_radius);

/// The complete document of a scene, every default filled in, keys in the documented order:
/// parsing it again gives the same scene.
nlohmann::ordered_json scene_to_json(const Scene& scene);

/// The supports a plain mesh gets by default (load_scene): a flat mesh's boundary; else the part of
/// the surface on its lowest plane (z within 1e-6 of the model's size of the lowest vertex) where
/// that holds the shell (not a point or a line); else the vertices within 1% of the model's size of
/// the lowest, a region that grows as the mesh is refined (`exact` false).
struct PlainMeshSupport {
  nlohmann::json select;    ///< the support's selector (docs/SCENES.md)
  std::string description;  ///< for the note load_scene gives
  bool exact = false;       ///< the same region on every refinement of the mesh
};
PlainMeshSupport plain_mesh_support(const SurfaceMesh& mesh);

/// For a mesh over 100 m across: " (it is … m across: coordinates are read as metres; a file drawn in
/// millimetres needs a scene with "unit": "mm")", said of a plain mesh (its note, and a solve's
/// error: a part drawn in millimetres read as metres cannot carry its own weight); "" otherwise.
std::string metres_hint(const SurfaceMesh& mesh);

/// Loads `what`: a built-in scene name, a scene file (.json), or a mesh file (defaults: self
/// weight, the lowest vertices supported; `notice` receives a line saying so).
Scene load_scene(const std::string& what, std::string* notice = nullptr);

/// How messages name a scene: its file, or "builtin:NAME".
std::string scene_origin(const Scene& scene);

struct BuiltinScene {
  std::string name;
  std::string description;
};
const std::vector<BuiltinScene>& builtin_scenes();
/// The JSON document of a built-in scene, or throws InputError listing the known names.
nlohmann::json builtin_scene_json(const std::string& name);

/// The meshes of a scene: base (cut and exported), simulation, and the map between them.
struct SceneMeshes {
  SurfaceMesh base;
  SurfaceMesh sim;
  MeshMapping map;
  bool sim_is_base = false;
  /// A file's mesh: how many times `sim` divides it (MeshSpec::sim_subdivisions, resolved).
  int sim_subdivisions = 0;
  /// "auto" not yet resolved: `sim` is the file's mesh until solvers::choose_simulation_mesh
  /// (solvers/conforming/simulation_mesh_choice.h) has solved the uncut shell on its subdivisions.
  bool sim_choice_pending = false;
  /// What that choice found (report.json mesh.sim_choice); null where nothing was chosen.
  nlohmann::json sim_choice;
  /// A file's mesh: diagonals of union-jack patches turned one way in `sim` (before it is divided;
  /// host/mesh/union_jack_flips.h), so the bending element does not read them too soft.
  int sim_flips = 0;
};
/// The run's note on a file's union-jack diagonals flipped for the simulation ("" when none).
std::string union_jack_note(const SceneMeshes& meshes);
/// The notes a run gives on how its shell model reads this scene: union_jack_note, and where the
/// scene asks for the paper's hinge bending on a curved surface (a face normal more than 10° from
/// the mean), what that model gets wrong on curved shells.
std::vector<std::string> model_notes(const Scene& scene, const SceneMeshes& meshes);
/// The scene's meshes. A file's mesh with sim_subdivisions "auto" comes back with sim the file's
/// mesh and sim_choice_pending set (the choice needs the mechanics: solvers::choose_simulation_mesh).
SceneMeshes build_scene_meshes(const Scene& scene);

/// Makes the base mesh of `meshes` (a file's), its union-jack diagonals flipped where
/// meshes.sim_flips says so, divided `subdivisions` times (midpoint) the simulation mesh, with the
/// map between them. Throws InputError when it would exceed the work limit.
void use_subdivided_simulation_mesh(SceneMeshes& meshes, int subdivisions);

/// Resolves supports and loads onto `mesh` (normally the simulation mesh).
/// Supports fix the vertices their selector picks. Loads are integrated over their selector's
/// region (host/scene/load_regions.h), so that they do not depend on the mesh: an area or
/// pressure load over the surface inside the region, an edge load along the (boundary) edges
/// inside it, and a point load — a total force — spread evenly over the surface inside the region
/// (along the boundary inside it for `boundary_vertices`), i.e. a patch load of the region's size.
/// A selector with `nearest` keeps the mesh-dependent rule: the n closest entities, whole.
/// `outer_boundary` (#V, optional): the boundary vertices that boundary selectors may pick —
/// for a mesh with stencils cut out, those on the uncut surface's boundary, so that a support
/// "on the boundary" does not land on the rims of the holes. Default: every boundary vertex.
/// `match_totals` (optional; the same scene resolved on another mesh): every load per area or
/// length is scaled so that its total equals the one it has there — on a mesh with holes cut,
/// the share of a dead load that falls on the holes is carried by the material left in the
/// region (the rule of docs/SCENES.md "Loads over holes").
/// Throws InputError naming the selector's JSON path when it selects nothing.
LoadCase resolve_load_case(const Scene& scene, const SurfaceMesh& mesh,
                           const std::vector<bool>* outer_boundary = nullptr,
                           const LoadCase* match_totals = nullptr);

/// Whether the scene models a half (quarter, eighth) on symmetry planes (supports of type "symmetry").
bool has_symmetry_plane(const Scene& scene);

/// The scene's symmetry planes resolved on `mesh` (LoadCase::symmetry_planes: x = .x(), …; NaN where
/// none; all NaN without a symmetry support, without resolving anything). Throws as resolve_load_case.
Vec3 scene_symmetry_planes(const Scene& scene, const SurfaceMesh& mesh);

/// How much of a mesh a set of fixed vertices holds, as measures that converge under refinement
/// when the supports select a fixed physical region:
///  - area: the faces whose three vertices are fixed, one of them inside the mesh (an area
///    support; a face with all three on the boundary is a line support turning a corner);
///  - length: the edges with both ends fixed that are on the mesh's boundary, or inside it with
///    neither face in the area and not a chord between two boundary vertices (a line support, and
///    the part of an area support's outline on the boundary);
///  - points: the fixed vertices on no fixed edge (point supports).
/// With `outer` (per vertex: on the uncut surface's boundary, boundary_vertices_on_boundary_of), the
/// rim of a hole inside the surface (a boundary loop with no vertex on that boundary) where it
/// bounds an area support's face is the area's outline and no line: its length follows how finely
/// each mesh writes the hole, while the area it bounds converges. (The chair's base, clamped with
/// stars cut in it, their tips a tool's 0.5 mm arcs that each level writes with edges of at least
/// L/10: 6.63, 6.78, 6.92 m of line over three levels, 4% apart, with the rims; 0.1045, 0.1043,
/// 0.1042 m² of area.) Holes that cross the outer boundary are part of its loop and still count.
struct SupportExtent {
  double area = 0;    ///< m²
  double length = 0;  ///< m
  int points = 0;
};
SupportExtent support_extent(const SurfaceMesh& mesh, const std::vector<bool>& fixed,
                             const std::vector<bool>* outer = nullptr);

/// The interior edges (indices into mesh.edges()) that outline what `fixed` holds, as
/// support_extent measures it: both ends fixed, not both on the boundary (a chord, beside a hole's
/// rim or across a corner), and either on an area support's outline (one face in the area, one
/// not) or a line support inside the mesh (neither face in an area). A remesh that keeps these lines (host/mesh/isotropic_remesh.h
/// RemeshOptions::feature_edges) holds the same region on every mesh: the conforming verification's
/// levels, where a clamped area's outline would otherwise be cut anew by each level's triangles.
std::vector<int> support_outline_edges(const SurfaceMesh& mesh, const std::vector<bool>& fixed);

/// The largest relative difference between two extents' area, length and point count (each
/// |a − b| / max(a, b), 0 where both are 0). Areas are compared against at least
/// edge_length × length, the area a line support's outline can differ by between meshes. Points
/// beside a line or an area count as edge_length² of area each; only where both extents are
/// points alone is their number compared.
double support_extent_change(const SupportExtent& a, const SupportExtent& b, double edge_length);

/// The largest support_extent_change between meshes of one surface under which the supports count
/// as holding the same region (the discretisation estimate's and the conforming verification's).
inline constexpr double kSupportExtentTolerance = 0.01;

/// Indices of the entities `sel` selects on `mesh` (vertex, edge or face indices by entity).
/// Boundary entities are restricted to `outer_boundary` when given (see resolve_load_case; a
/// boundary edge counts when both its vertices are in it).
std::vector<int> select_entities(const Selector& sel, const SurfaceMesh& mesh,
                                 const std::vector<bool>* outer_boundary = nullptr);

}  // namespace cutwork
