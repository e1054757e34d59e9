// `cutwork scenes`, `cutwork show NAME`, `cutwork check FILE`.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <iostream>
#include <optional>
#include <numbers>

#include "host/cli/cli_common.h"
#include "host/cli/commands.h"
#include "host/core/input_file.h"
#include "host/core/timer.h"
#include "host/pattern/pattern_context.h"
#include "host/pattern/stencils_json.h"
#include "host/scene/work_estimate.h"
#include "host/mesh/surface_mesh.h"
#include "host/scene/scene.h"
#include "solvers/conforming/simulation_mesh_choice.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/structural_quantities.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::cli {

void add_scenes_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("scenes", "List the built-in scenes, one line each");
  cmd->callback([] {
    for (const auto& s : builtin_scenes()) std::cout << fmt::format("{:<22} {}\n", s.name, s.description);
  });
}

void add_show_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "show", "Print a built-in scene's complete JSON (every default filled in), ready to copy and edit");
  auto name = std::make_shared<std::string>();
  cmd->add_option("NAME", *name, "built-in scene name (see `cutwork scenes`)")->required();
  cmd->callback([name] {
    const Scene scene = parse_scene(builtin_scene_json(*name), "builtin:" + *name);
    std::cout << scene_to_json(scene).dump(2) << "\n";
  });
}

namespace {
const char* entity_word(Entity e) {
  switch (e) {
    case Entity::Vertices: return "vertices";
    case Entity::BoundaryVertices: return "boundary vertices";
    case Entity::Edges: return "edges";
    case Entity::BoundaryEdges: return "boundary edges";
    case Entity::Faces: return "faces";
  }
  return "";
}
const char* load_word(LoadKind k) {
  switch (k) {
    case LoadKind::Point: return "point";
    case LoadKind::Edge: return "edge";
    case LoadKind::Area: return "area";
    case LoadKind::Pressure: return "pressure";
    case LoadKind::SelfWeight: return "self-weight";
  }
  return "";
}

void print_mesh(const std::string& label, const SurfaceMesh& m) {
  const Vec3 lo = m.bbox_min(), hi = m.bbox_max();
  std::cout << fmt::format(
      "{}: {} vertices, {} faces, {} edges, {} boundary loop(s), Euler characteristic {}, {} component(s)\n"
      "  bounding box [{:.4g}, {:.4g}, {:.4g}] to [{:.4g}, {:.4g}, {:.4g}], mean edge {:.4g} m, min angle {:.1f} deg\n",
      label, m.num_vertices(), m.num_faces(), m.num_edges(), m.boundary_loops().size(),
      m.euler_characteristic(), m.num_components(), lo[0], lo[1], lo[2], hi[0], hi[1], hi[2],
      m.mean_edge_length(), min_angle(m) * 180.0 / std::numbers::pi);
}
}  // namespace

void add_check_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "check", "Validate a scene (.json), a built-in scene name or a mesh file and print a summary");
  auto what = std::make_shared<std::string>();
  auto stencils = std::make_shared<std::string>();
  cmd->add_option("FILE", *what, "scene file, built-in scene name, or mesh (.obj .ply .off .stl)")->required();
  cmd->add_option("--stencils", *stencils,
                  "also validate a design's stencils.json against the scene, as `cutwork simulate --stencils` does");
  auto no_equilibrium = std::make_shared<bool>(false);
  cmd->add_flag("--no-equilibrium", *no_equilibrium,
                "only read and validate: skip the uncut shell's equilibrium under the scene's loads (which says "
                "whether the shell can carry them at all, as design and simulate would)");
  add_limit_options(*cmd);
  cmd->callback([what, stencils, no_equilibrium] {
    std::string notice;
    const Scene scene = load_scene(*what, &notice);
    SceneMeshes meshes = build_scene_meshes(scene);
    if (scene.from_plain_mesh) set_solve_error_hint(metres_hint(meshes.base));
    // A file's simulation mesh "auto" is chosen by solving the uncut shell: with the equilibrium.
    const bool choice_pending = meshes.sim_choice_pending && *no_equilibrium;
    const std::string choice = *no_equilibrium ? std::string() : solvers::choose_simulation_mesh(scene, meshes);
    const LoadCase lc = resolve_load_case(scene, meshes.sim);
    // Everything design and simulate check before they start is checked here, before anything is
    // printed: supports that hold every part and loads that are finite and not zero (the shell
    // model), the work the pattern asks for, the exemplar against the stencils, the sizing file
    // and the strokes (the pattern context), and a design's stencils.
    const solvers::ShellModel model(meshes.sim, scene.material, lc, solvers::uncut_scene_mechanics(scene));
    solvers::EquilibriumSolver analysis(model);  // CHOLMOD's symbolic analysis: the factor's size
    check_factor_work(scene, meshes, analysis.linear_solver().factor_nonzeros());
    check_stencil_work(scene, meshes);
    const PatternContext ctx(scene, meshes);
    // The uncut shell under the scene's loads, as design solves it first: a load it cannot carry
    // fails here (SolveError, "the structure can carry only …% of the load", exit 2) in one
    // equilibrium instead of after the pattern phase. Stencils only weaken the shell.
    Stopwatch uncut_clock;
    const Eigen::VectorXd solid = Eigen::VectorXd::Ones(meshes.sim.num_faces());
    std::optional<solvers::EquilibriumStats> uncut_stats;
    solvers::EquilibriumSummary uncut;
    if (!*no_equilibrium) {
      uncut_stats = analysis.solve(solid);
      uncut = solvers::summarize_equilibrium(model, analysis.positions(), solid);
    }
    const double uncut_seconds = uncut_clock.seconds();
    size_t stencil_count = 0;
    std::string lattice_line;  // what simulate and verify would model these stencils' lattice as
    if (!stencils->empty()) {
      const StencilBounds bounds{meshes.base.bbox_min(), meshes.base.bbox_max()};
      const std::vector<StencilParams> read = read_stencils_json(*stencils, ctx.shapes(), &bounds).stencils;
      stencil_count = read.size();
      std::vector<std::string> lattice_notes;
      const MechanicsSettings m = solvers::measured_lattice(scene.mechanics, ctx.surface().bvh(), ctx.surface().field(),
                                                            read, lattice_notes);
      lattice_line = m.lattice == PerforationLattice::Hexagonal ? "hexagonal (isotropic)"
                     : m.lattice_follows_field
                         ? fmt::format("square, along the orientation field turned by {:.1f} degrees",
                                       m.lattice_field_angle * 180 / std::numbers::pi)
                         : fmt::format("square, along ({:.3f}, {:.3f}, {:.3f})", m.lattice_axis.x(), m.lattice_axis.y(),
                                       m.lattice_axis.z());
      lattice_line += m.lattice_source == LatticeSource::Stencils ? ", read from the stencils" : ", as the scene states";
      for (const std::string& n : lattice_notes) lattice_line += "; note: " + n;
    }
    if (!notice.empty()) std::cout << "note: " << notice << "\n";
    std::cout << "scene " << excerpt(scene.name) << (scene.description.empty() ? "" : ": " + excerpt(scene.description, 200))
              << "\n";
    print_mesh("base mesh", meshes.base);
    for (const std::string& n : model_notes(scene, meshes)) std::cout << "note: " << n << "\n";
    if (!choice.empty()) std::cout << "note: " << choice << "\n";
    if (choice_pending)
      std::cout << "simulation mesh: the file's mesh or a subdivision of it, chosen by the uncut shell's "
                   "equilibrium when a run starts (mesh.sim_subdivisions auto)\n";
    else if (meshes.sim_is_base)
      std::cout << "simulation mesh: the base mesh\n";
    else if (meshes.sim_subdivisions == 0)
      print_mesh("simulation mesh (the base mesh, its union-jack diagonals turned one way)", meshes.sim);
    else
      print_mesh(fmt::format("simulation mesh (the base mesh{} divided {} times)",
                             meshes.sim_flips > 0 ? ", its union-jack diagonals turned one way," : "",
                             meshes.sim_subdivisions),
                 meshes.sim);
    int fixed = 0, clamped = 0, held = 0;
    for (size_t v = 0; v < lc.fixed.size(); ++v) {
      fixed += lc.fixed[v];
      clamped += lc.clamped[v];
      held += !lc.fixed[v] && !lc.held_axes.empty() && lc.held_axes[v] != 0;
    }
    std::cout << fmt::format("supports: {} fixed vertices ({} clamped){}\n", fixed, clamped,
                             held ? fmt::format(", {} held along some axes", held) : "");
    for (const auto& sp : scene.supports) {
      std::string axes;
      for (int a = 0; a < 3 && sp.axes != kHeldAll; ++a)
        if (sp.axes & (1u << a)) axes += char('x' + a);
      const std::string what =
          sp.kind == SupportKind::Symmetry
              ? fmt::format("symmetry plane {} = {:.4g}", axes, lc.symmetry_planes[axes[0] - 'x'])
              : (sp.kind == SupportKind::Clamped ? "clamped" : "pinned") + (axes.empty() ? "" : " along " + axes);
      std::cout << fmt::format("  {} at {} ({} {})\n", what, sp.select.json_path,
                               select_entities(sp.select, meshes.sim).size(), entity_word(sp.select.entity));
    }
    std::cout << "loads:\n";
    for (const auto& l : scene.loads) {
      if (l.kind == LoadKind::SelfWeight)
        std::cout << fmt::format("  self-weight, g = [{:.4g}, {:.4g}, {:.4g}] m/s^2\n", l.gravity[0],
                                 l.gravity[1], l.gravity[2]);
      else
        std::cout << fmt::format("  {} load at {} ({} {})\n", load_word(l.kind), l.select.json_path,
                                 select_entities(l.select, meshes.sim).size(), entity_word(l.select.entity));
    }
    const Vec3 total = lc.forces.colwise().sum().transpose();
    std::cout << fmt::format("  total of the fixed loads: [{:.4g}, {:.4g}, {:.4g}] N\n", total[0], total[1],
                             total[2]);
    std::cout << fmt::format("simulation: {} DOFs, stiffness factor {} nonzeros (about {:.3g} GB)\n", model.num_dofs(),
                             analysis.linear_solver().factor_nonzeros(),
                             factor_bytes(analysis.linear_solver().factor_nonzeros()) / 1e9);
    if (uncut_stats)
      std::cout << fmt::format("uncut equilibrium: carries the whole load; compliance {:.4g} J, largest displacement "
                               "{:.3g} m ({:.2g}% of the model size), W_max {:.4g} J/m^2 ({} Newton iterations{}, "
                               "{:.2g} s)\n",
                               uncut.compliance, uncut.max_displacement,
                               100 * uncut.max_displacement / model.model_size(), uncut.W_max,
                               uncut_stats->newton_iterations,
                               uncut_stats->load_steps > 0 ? fmt::format(", {} load steps", uncut_stats->load_steps) : "",
                               uncut_seconds);
    else
      std::cout << "uncut equilibrium: not solved (--no-equilibrium)\n";
    std::cout << fmt::format("stencil shapes: {}; pattern: about {:.0f} stencils (estimated)\n", scene.shapes.size(),
                             estimate_stencil_count(scene.pattern, meshes.base));
    if (!stencils->empty())
      std::cout << fmt::format("stencils file: {} stencils; perforation lattice {}\n", stencil_count, lattice_line);
    std::cout << "ok\n";
  });
}

}  // namespace cutwork::cli
