// Built-in procedural shapes: validity, topology, triangle quality, resolution, geometry of each
// shape as its parameters say, orientation, determinism and rejection of bad input.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "host/core/error.h"
#include "host/surfaces/generators.h"

namespace cutwork {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

/// Minimum-angle guarantee per shape at its default parameters (degrees), the measured
/// behaviour of each mesher: the staggered lattice (plate, sheet, and the isometric table and
/// chair) has all angles ≥ 30° (boundary right triangles 30-60-90, interior ones near 60°);
/// the hex disk's six corner faces are the worst (~43°) on the bowl; the pavilion's steep
/// flanks near the feet bring it to ~35°, and respacing each foot's rim vertices so that both
/// foot ends are vertices to 33.2° at its coarse default simulation size (0.35 m).
double min_angle_guarantee_deg(const std::string& shape) {
  if (shape == "bowl") return 42.0;
  if (shape == "pavilion") return 33.0;
  return 30.0;
}

/// The mean edge is the requested h within 15%, except on the extruded shapes (table, chair), whose
/// fillets get a row every 10° of their turn whatever h is (plan_rows): at coarse h those extra rows
/// pull the mean down, to 0.72 h on the chair at 0.2 m.
void expect_mean_edge(const SurfaceMesh& m, const std::string& shape, double h) {
  const double ratio = m.mean_edge_length() / h;
  if (shape == "table" || shape == "chair") {
    EXPECT_GE(ratio, 0.7) << shape << " h " << h;
    EXPECT_LE(ratio, 1.15) << shape << " h " << h;
  } else {
    EXPECT_NEAR(ratio, 1.0, 0.15) << shape << " h " << h;
  }
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no InputError thrown)";
}

/// Connected components of the vertices selected by `keep`, through mesh edges.
std::vector<std::vector<int>> clusters(const SurfaceMesh& mesh, const std::vector<bool>& keep) {
  std::vector<int> parent(std::size_t(mesh.num_vertices()));
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = int(i);
  std::function<int(int)> root = [&](int v) {
    while (parent[std::size_t(v)] != v) v = parent[std::size_t(v)] = parent[std::size_t(parent[std::size_t(v)])];
    return v;
  };
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const int a = mesh.edges()(e, 0), b = mesh.edges()(e, 1);
    if (keep[std::size_t(a)] && keep[std::size_t(b)]) parent[std::size_t(root(a))] = root(b);
  }
  std::map<int, std::vector<int>> groups;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (keep[std::size_t(v)]) groups[root(v)].push_back(v);
  }
  std::vector<std::vector<int>> out;
  for (auto& [r, g] : groups) out.push_back(g);
  return out;
}

std::vector<bool> below(const SurfaceMesh& mesh, double z) {
  std::vector<bool> keep(std::size_t(mesh.num_vertices()));
  for (int v = 0; v < mesh.num_vertices(); ++v) keep[std::size_t(v)] = mesh.vertices()(v, 2) < z;
  return keep;
}

/// The checks every generated mesh must pass: a valid manifold disk (the SurfaceMesh
/// constructor rejects non-manifold or inconsistently oriented input), χ = 1, one boundary
/// loop, one component, every vertex used.
void expect_valid_disk(const SurfaceMesh& m, const std::string& label) {
  SCOPED_TRACE(label);
  EXPECT_EQ(m.euler_characteristic(), 1);
  EXPECT_EQ(m.boundary_loops().size(), 1u);
  EXPECT_EQ(m.num_components(), 1);
  std::vector<bool> used(std::size_t(m.num_vertices()), false);
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) used[std::size_t(m.faces()(f, c))] = true;
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << "unreferenced vertices";
}

double coarsest_edge_length(const std::string& shape, const ShapeParameters& params) {
  const std::string msg = message_of([&] { generate_shape(shape, params, 1e9); });
  std::smatch match;
  const std::regex pattern(R"(edge_length must be a length in \(0, ([0-9.eE+-]+)\] m)");
  EXPECT_TRUE(std::regex_search(msg, match, pattern)) << msg;
  return match.empty() ? 0.0 : std::stod(match[1].str());
}

// ---------------------------------------------------------------------------------------------

TEST(Shapes, RegistryListsEveryShapeWithDefaults) {
  std::vector<std::string> names;
  for (const auto& info : builtin_shapes()) {
    names.push_back(info.name);
    EXPECT_FALSE(info.description.empty()) << info.name;
    EXPECT_FALSE(info.defaults.empty()) << info.name;
    // The simulation mesh is the coarser one, by the ratio the scenes rely on.
    const double ratio = info.sim_edge_length / info.base_edge_length;
    EXPECT_GE(ratio, 2.0) << info.name;
    EXPECT_LE(ratio, 2.5) << info.name;
    EXPECT_EQ(find_shape(info.name), &info);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"plate", "sheet", "bowl", "pavilion", "table", "chair"}));
  EXPECT_EQ(find_shape("teapot"), nullptr);
}

struct Resolution {
  std::string shape;
  std::string which;  // base | sim | fine
};

void PrintTo(const Resolution& r, std::ostream* os) { *os << r.shape << " at " << r.which; }

class ShapeAtResolution : public ::testing::TestWithParam<Resolution> {
 protected:
  static double edge_length(const Resolution& r) {
    const ShapeInfo* info = find_shape(r.shape);
    if (r.which == "sim") return info->sim_edge_length;
    if (r.which == "fine") return 0.5 * info->base_edge_length;
    return info->base_edge_length;
  }
};

TEST_P(ShapeAtResolution, IsAWellShapedDiskAtTheRequestedResolution) {
  const Resolution& r = GetParam();
  const double h = edge_length(r);
  const SurfaceMesh m = generate_shape(r.shape, {}, h);
  expect_valid_disk(m, r.shape + " " + r.which);
  const double angle = min_angle(m) / kDeg;
  EXPECT_GE(angle, min_angle_guarantee_deg(r.shape) - 1e-9);
  expect_mean_edge(m, r.shape, h);
  RecordProperty("min_angle_deg", std::to_string(angle));
  RecordProperty("vertices", m.num_vertices());
  RecordProperty("faces", m.num_faces());
}

INSTANTIATE_TEST_SUITE_P(
    AllShapes, ShapeAtResolution,
    ::testing::ValuesIn([] {
      std::vector<Resolution> all;
      for (const char* shape : {"plate", "sheet", "bowl", "pavilion", "table", "chair"}) {
        for (const char* which : {"base", "sim", "fine"}) all.push_back({shape, which});
      }
      return all;
    }()),
    [](const ::testing::TestParamInfo<Resolution>& info) {
      return info.param.shape + "_" + info.param.which;
    });

TEST(Shapes, FaceCountScalesWithInverseSquareEdgeLength) {
  for (const auto& info : builtin_shapes()) {
    SCOPED_TRACE(info.name);
    const double h[3] = {info.sim_edge_length, info.base_edge_length, 0.5 * info.base_edge_length};
    double faces[3];
    for (int k = 0; k < 3; ++k) faces[k] = generate_shape(info.name, {}, h[k]).num_faces();
    // The extruded shapes' fillets get a row every 10° of their turn whatever h is (plan_rows'
    // max_row_spacing), rows that only refinement past r·π/18 adds to: their counts grow more
    // slowly than h⁻² at coarse h (table 2449 faces at 0.04 m, where the lattice alone has 2139).
    const bool fillet_rows = info.name == "table" || info.name == "chair";
    for (int k = 0; k + 1 < 3; ++k) {
      const double expected = (h[k] / h[k + 1]) * (h[k] / h[k + 1]);
      const double ratio = faces[k + 1] / faces[k] / expected;
      if (fillet_rows) {
        EXPECT_GE(ratio, 0.6) << "h " << h[k] << " -> " << h[k + 1] << ": " << faces[k] << " -> " << faces[k + 1];
        EXPECT_LE(ratio, 1.15) << "h " << h[k] << " -> " << h[k + 1] << ": " << faces[k] << " -> " << faces[k + 1];
      } else {
        EXPECT_NEAR(ratio, 1.0, 0.15) << "h " << h[k] << " -> " << h[k + 1] << ": " << faces[k] << " -> " << faces[k + 1];
      }
    }
  }
}

TEST(Shapes, CoarsestAllowedResolutionStillGivesAValidMesh) {
  for (const auto& info : builtin_shapes()) {
    const double h = coarsest_edge_length(info.name, {});
    ASSERT_GT(h, 0) << info.name;
    const SurfaceMesh m = generate_shape(info.name, {}, h);
    expect_valid_disk(m, info.name + " at its coarsest");
    // Coarse isometric shapes cut their rounded corners with chords, a little below 30°.
    EXPECT_GE(min_angle(m) / kDeg, info.name == "pavilion" ? 25.0 : 29.0) << info.name;
  }
}

TEST(Shapes, GenerationIsDeterministicAndIndependentOfThreads) {
  for (const auto& info : builtin_shapes()) {
    const SurfaceMesh a = generate_shape(info.name, {}, info.base_edge_length);
    const SurfaceMesh b = generate_shape(info.name, {}, info.base_edge_length);
    EXPECT_TRUE(a.vertices() == b.vertices()) << info.name;
    EXPECT_TRUE(a.faces() == b.faces()) << info.name;
    // The curved shapes relax their vertices in parallel; one thread must give the same bits.
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    const SurfaceMesh c = generate_shape(info.name, {}, info.base_edge_length);
    EXPECT_TRUE(a.vertices() == c.vertices()) << info.name;
  }
}

// --- per-shape geometry and orientation ------------------------------------------------------

TEST(Shapes, PlateAndSheetAreFlatRectanglesFacingUp) {
  struct Case {
    std::string shape;
    ShapeParameters params;
    double half_x, half_y;
  };
  for (const Case& c : {Case{"plate", {}, 0.1, 0.05}, Case{"plate", {{"width", 0.3}, {"height", 0.07}}, 0.15, 0.035},
                        Case{"sheet", {}, 0.5, 0.5}, Case{"sheet", {{"size", 2.0}}, 1.0, 1.0}}) {
    SCOPED_TRACE(c.shape);
    const SurfaceMesh m = generate_shape(c.shape, c.params, 0.25 * c.half_y);
    EXPECT_EQ(m.bbox_min(), Vec3(-c.half_x, -c.half_y, 0));
    EXPECT_EQ(m.bbox_max(), Vec3(c.half_x, c.half_y, 0));
    for (int f = 0; f < m.num_faces(); ++f) ASSERT_NEAR(m.face_normals()(f, 2), 1.0, 1e-12);
    EXPECT_GE(min_angle(m) / kDeg, 30.0 - 1e-9);
  }
}

TEST(Shapes, BowlIsASphericalCapWithNormalsOnItsConvexSide) {
  const double radius = 0.15, depth = 0.07;
  const double sphere_radius = (radius * radius + depth * depth) / (2 * depth);
  const Vec3 centre(0, 0, sphere_radius);
  for (double h : {0.008, 0.018}) {
    const SurfaceMesh m = generate_shape("bowl", {}, h);
    for (int v = 0; v < m.num_vertices(); ++v) {
      const Vec3 x = m.vertices().row(v).transpose();
      ASSERT_NEAR((x - centre).norm(), sphere_radius, 1e-12) << "vertex off the sphere";
      if (m.is_boundary_vertex()[std::size_t(v)]) {
        ASSERT_NEAR(std::hypot(x.x(), x.y()), radius, 1e-12);
        ASSERT_EQ(x.z(), depth);
      }
    }
    EXPECT_EQ(m.bbox_min().z(), 0.0);  // the bottom vertex stays at the origin
    EXPECT_EQ(m.bbox_max().z(), depth);
    EXPECT_GE(m.bbox_max().x(), 0.99 * radius);
    EXPECT_LE(m.bbox_max().x(), radius + 1e-12);
    EXPECT_GE(-m.bbox_min().y(), 0.99 * radius);
    for (int f = 0; f < m.num_faces(); ++f) {
      const Vec3 c = (m.vertices().row(m.faces()(f, 0)) + m.vertices().row(m.faces()(f, 1)) +
                      m.vertices().row(m.faces()(f, 2))).transpose() / 3.0;
      ASSERT_GT(m.face_normals().row(f).dot((c - centre).normalized()), 0.99) << "face " << f;
    }
  }
  // A hemisphere is the deepest bowl allowed and still meshes well.
  const SurfaceMesh deep = generate_shape("bowl", {{"depth", radius}}, 0.01);
  expect_valid_disk(deep, "hemisphere");
  EXPECT_NEAR(deep.bbox_max().z(), radius, 1e-12);
  EXPECT_GE(min_angle(deep) / kDeg, 35.0);
}

TEST(Shapes, PavilionStandsOnItsFeetWithCrownAtTheCentre) {
  const double radius = 3.0, height = 1.8;
  for (double h : {0.35, 0.15, 0.075}) {
    SCOPED_TRACE(h);
    const SurfaceMesh m = generate_shape("pavilion", {}, h);
    EXPECT_EQ(m.vertices().row(0), Eigen::RowVector3d(0, 0, height).eval());
    EXPECT_EQ(m.bbox_max().z(), height);
    EXPECT_EQ(m.bbox_min().z(), 0.0);
    for (int v = 0; v < m.num_vertices(); ++v) {
      const double r = std::hypot(m.vertices()(v, 0), m.vertices()(v, 1));
      ASSERT_LE(r, radius * (1 + 1e-12));
      if (m.is_boundary_vertex()[std::size_t(v)]) {
        ASSERT_NEAR(r, radius, 1e-12);
      }
    }
    // Normals up/outward: the vault is a height field over the disk.
    for (int f = 0; f < m.num_faces(); ++f) ASSERT_GT(m.face_normals()(f, 2), 0.0);
    // Supports select "z below 1e-6": one cluster per leg, each a strip of the rim exactly on
    // z = 0 (a looser bound also takes the rim rising tangentially past the foot's ends: with
    // "below 0.01", up to 0.11 m more on each side of a fine mesh's foot).
    const auto feet = clusters(m, below(m, 1e-6));
    EXPECT_EQ(feet.size(), 4u);
    for (const auto& foot : feet) {
      int on_floor = 0;
      double first = INFINITY, last = -INFINITY;  // angles along the rim, about the foot's centre
      const double centre = std::atan2(m.vertices()(foot[0], 1), m.vertices()(foot[0], 0));
      for (int v : foot) {
        EXPECT_TRUE(m.is_boundary_vertex()[std::size_t(v)]);
        on_floor += m.vertices()(v, 2) == 0.0;
        EXPECT_LE(m.vertices()(v, 2), 1e-12);
        const double a = std::remainder(std::atan2(m.vertices()(v, 1), m.vertices()(v, 0)) - centre, 2 * std::numbers::pi);
        first = std::min(first, a), last = std::max(last, a);
      }
      EXPECT_GE(on_floor, 2);
      // Both ends of the foot are vertices: the strip on the floor is the whole foot_length
      // (0.8 m) at every edge length, so the supports do not change with the mesh.
      EXPECT_NEAR(radius * (last - first), 0.8, 1e-9);
    }
  }
}

TEST(Shapes, PavilionMeshesWellOverItsParameterRange) {
  // Corners of the admissible box (steepest crown, highest arches allowed for the legs and
  // foot length), each with one foot cluster per leg; also at the coarsest resolution.
  for (int legs : {3, 5, 6, 8}) {
    for (double foot_fraction : {0.5, 1.0}) {
      const double radius = 3.0, height = 0.6 * radius;
      const double foot = foot_fraction * 0.6 * std::numbers::pi * radius / legs;
      const double span = std::numbers::pi / legs - 0.5 * foot / radius;
      const double arch = std::min(0.8 * height, 2 / std::numbers::pi * radius * span);
      const ShapeParameters p{{"radius", radius}, {"height", height}, {"arch_height", arch},
                              {"legs", double(legs)}, {"foot_length", foot}};
      const double coarsest = coarsest_edge_length("pavilion", p);
      for (double h : {std::min(0.35, coarsest), coarsest}) {
        const std::string label = "legs " + std::to_string(legs) + " foot " +
                                  std::to_string(foot) + " h " + std::to_string(h);
        SCOPED_TRACE(label);
        const SurfaceMesh m = generate_shape("pavilion", p, h);
        expect_valid_disk(m, label);
        EXPECT_GE(min_angle(m) / kDeg, 25.0);
        EXPECT_EQ(clusters(m, below(m, 1e-6)).size(), std::size_t(legs));
      }
    }
  }
}

TEST(Shapes, TableStandsOnTheFloorWithAFlatTop) {
  const double half_length = 0.5, half_depth = 0.3, height = 0.7;
  for (double h : {0.08, 0.035}) {
    SCOPED_TRACE(h);
    const SurfaceMesh m = generate_shape("table", {}, h);
    EXPECT_EQ(m.bbox_min(), Vec3(-half_length, -half_depth, 0));
    EXPECT_EQ(m.bbox_max(), Vec3(half_length, half_depth, height));
    // On the floor: exactly the two panels' bottom rows, spanning the full depth.
    const auto floor = clusters(m, below(m, 1e-12));
    ASSERT_EQ(floor.size(), 2u);
    for (const auto& row : floor) {
      double y_min = 1e9, y_max = -1e9;
      for (int v : row) {
        EXPECT_EQ(std::abs(m.vertices()(v, 0)), half_length);
        EXPECT_EQ(m.vertices()(v, 2), 0.0);
        y_min = std::min(y_min, m.vertices()(v, 1));
        y_max = std::max(y_max, m.vertices()(v, 1));
      }
      EXPECT_EQ(y_min, -half_depth);
      EXPECT_EQ(y_max, half_depth);
    }
    // Normals: top up, side panels outward.
    int top = 0, sides = 0;
    for (int f = 0; f < m.num_faces(); ++f) {
      const Vec3 n = m.face_normals().row(f).transpose();
      bool on_top = true, on_left = true, on_right = true;
      for (int c = 0; c < 3; ++c) {
        const Vec3 x = m.vertices().row(m.faces()(f, c)).transpose();
        on_top &= x.z() == height;
        on_left &= x.x() == -half_length;
        on_right &= x.x() == half_length;
      }
      if (on_top) {
        EXPECT_NEAR(n.z(), 1.0, 1e-12);
        ++top;
      }
      if (on_left || on_right) {
        EXPECT_NEAR(n.x(), on_left ? -1.0 : 1.0, 1e-12);
        ++sides;
      }
    }
    EXPECT_GT(top, 0);
    EXPECT_GT(sides, 0);
  }
}

TEST(Shapes, ChairRunnerLiesOnTheFloorAndTheSeatFacesUp) {
  for (double h : {0.05, 0.022}) {
    SCOPED_TRACE(h);
    const SurfaceMesh m = generate_shape("chair", {}, h);
    EXPECT_EQ(m.bbox_min(), Vec3(-0.08, -0.225, 0));
    EXPECT_EQ(m.bbox_max(), Vec3(0.5, 0.225, 0.9));
    // The runner (x from the end of the fillet at (0.1, 0) to 0.5) is exactly on z = 0, and
    // nothing else lies low there: the diagonal is ≥ 0.25 m up at x ≥ 0.3.
    double floor_x_min = 1e9, floor_x_max = -1e9;
    for (int v = 0; v < m.num_vertices(); ++v) {
      const double x = m.vertices()(v, 0), z = m.vertices()(v, 2);
      ASSERT_GE(z, 0.0);
      if (z == 0.0) {
        floor_x_min = std::min(floor_x_min, x);
        floor_x_max = std::max(floor_x_max, x);
      }
      if (x >= 0.3 && z < 0.2) {
        ASSERT_EQ(z, 0.0) << "vertex " << v;
      }
    }
    EXPECT_LE(floor_x_min, 0.25);
    EXPECT_EQ(floor_x_max, 0.5);
    EXPECT_EQ(clusters(m, below(m, 1e-12)).size(), 1u);
    // Seat (z = 0.45, 0.1 < x < 0.3: clear of the fillets) and runner face up; the back rest
    // faces forward (+x), towards the sitter.
    int seat = 0, back = 0;
    for (int f = 0; f < m.num_faces(); ++f) {
      const Vec3 n = m.face_normals().row(f).transpose();
      bool on_seat = true, on_runner = true, on_back = true;
      for (int c = 0; c < 3; ++c) {
        const Vec3 x = m.vertices().row(m.faces()(f, c)).transpose();
        on_seat &= x.z() == 0.45 && x.x() > 0.1 && x.x() < 0.3;
        on_runner &= x.z() == 0.0;
        on_back &= x.z() > 0.6;
      }
      if (on_seat || on_runner) {
        EXPECT_NEAR(n.z(), 1.0, 1e-12);
        ++seat;
      }
      if (on_back) {
        EXPECT_GT(n.x(), 0.9);
        ++back;
      }
    }
    EXPECT_GT(seat, 0);
    EXPECT_GT(back, 0);
  }
}

TEST(Shapes, ChairRunnerOnTheFloorIsTheSameStripOnEveryMesh) {
  // The runner is flat on z = 0 from where its fillet ends to runner_end, extruded over the width:
  // a row of the extruded lattice lies on the fillet's end (plan_rows), so the faces with all
  // vertices on the floor cover
  // exactly that strip at every edge length (before, the strip stopped at the last row short of
  // the fillet: 0.1115 m² at 0.043 m, 0.1224 m² at 0.0107 m).
  const double width = 0.45, runner_end = 0.5, radius = 0.06;
  // The corner at (runner_start, 0) between the diagonal from the seat front (0.45, 0.45) and the
  // runner turns by π − atan2(0.45, 0.35); the fillet takes radius·tan(turn/2) of the runner.
  const double turn = std::numbers::pi - std::atan2(0.45, 0.45 - 0.1);
  const double flat = runner_end - (0.1 + radius * std::tan(0.5 * turn));
  for (double h : {0.043, 0.0215, 0.01075, 0.005}) {
    SCOPED_TRACE(h);
    const SurfaceMesh m = generate_shape("chair", {}, h);
    double area = 0;
    for (int f = 0; f < m.num_faces(); ++f) {
      bool on_floor = true;
      for (int c = 0; c < 3; ++c) on_floor &= m.vertices()(m.faces()(f, c), 2) < 1e-6;
      if (on_floor) area += m.face_areas()[f];
    }
    EXPECT_NEAR(area, width * flat, 1e-9);
  }
}

TEST(Shapes, ExtrudedShapesStayWellShapedForOtherParameters) {
  const std::vector<std::pair<std::string, ShapeParameters>> cases = {
      {"table", {{"length", 2.0}, {"depth", 0.9}, {"height", 0.45}, {"corner_radius", 0.2}}},
      {"table", {{"length", 0.4}, {"depth", 0.3}, {"height", 1.0}, {"corner_radius", 0.02}}},
      {"chair", {{"width", 0.6}, {"seat_height", 0.4}, {"back_height", 1.1}, {"back_recline", 0.2},
                 {"runner_start", 0.0}, {"runner_end", 0.7}, {"corner_radius", 0.1}}},
      {"chair", {{"seat_depth", 0.6}, {"runner_start", 0.5}, {"runner_end", 0.8}}}};
  for (const auto& [shape, params] : cases) {
    for (double fraction : {1.0, 0.3}) {
      const double h = fraction * coarsest_edge_length(shape, params);
      const SurfaceMesh m = generate_shape(shape, params, h);
      expect_valid_disk(m, shape);
      EXPECT_GE(min_angle(m) / kDeg, 29.0) << shape << " h " << h;
      expect_mean_edge(m, shape, h);
      EXPECT_EQ(m.bbox_min().z(), 0.0) << shape;
    }
  }
}

// --- bad input -------------------------------------------------------------------------------

TEST(Shapes, RejectsBadParametersWithTheAdmissibleRange) {
  auto plate = [](const ShapeParameters& p) { return [p] { generate_shape("plate", p, 0.01); }; };
  EXPECT_EQ(message_of(plate({{"width", 20}})),
            "shape 'plate': parameter 'width' must be in [0.01, 10] (got 20)");
  EXPECT_EQ(message_of(plate({{"height", -1}})),
            "shape 'plate': parameter 'height' must be in [0.01, 10] (got -1)");
  EXPECT_EQ(message_of(plate({{"width", std::nan("")}})),
            "shape 'plate': parameter 'width' must be in [0.01, 10] (got nan)");
  EXPECT_EQ(message_of(plate({{"widht", 0.2}})),
            "shape 'plate': unknown parameter 'widht' (accepted: height, width)");
  // Bounds that depend on other parameters are stated as numbers.
  EXPECT_EQ(message_of([] { generate_shape("bowl", {{"depth", 0.2}}, 0.01); }),
            "shape 'bowl': parameter 'depth' must be in [0.0075, 0.15] (got 0.2)");
  EXPECT_EQ(message_of([] { generate_shape("pavilion", {{"legs", 4.5}}, 0.2); }),
            "shape 'pavilion': parameter 'legs' must be an integer in [3, 8] (got 4.5)");
  EXPECT_EQ(message_of([] { generate_shape("pavilion", {{"legs", 2}}, 0.2); }),
            "shape 'pavilion': parameter 'legs' must be an integer in [3, 8] (got 2)");
  EXPECT_EQ(message_of([] { generate_shape("table", {{"corner_radius", 0.6}}, 0.05); }),
            "shape 'table': parameter 'corner_radius' must be in [0.01, 0.5] (got 0.6)");
  EXPECT_EQ(message_of([] { generate_shape("chair", {{"runner_start", 0.45}}, 0.05); }),
            "shape 'chair': parameter 'runner_start' must be in [0, 0.405] (got 0.45)");
  EXPECT_EQ(message_of([] { generate_shape("teapot", {}, 0.01); }),
            "unknown shape 'teapot' (built-in shapes: plate, sheet, bowl, pavilion, table, chair)");
  // Every default set is itself valid.
  for (const auto& info : builtin_shapes()) {
    EXPECT_NO_THROW(generate_shape(info.name, info.defaults, info.sim_edge_length)) << info.name;
  }
}

TEST(Shapes, RejectsBadResolutionsAndSaysWhatFits) {
  for (double bad : {0.0, -0.01, std::nan(""), std::numeric_limits<double>::infinity(), 0.06}) {
    const std::string msg = message_of([&] { generate_shape("plate", {}, bad); });
    EXPECT_EQ(msg.rfind("shape 'plate': edge_length must be a length in (0, 0.05] m for these "
                        "parameters (got ", 0),
              0u)
        << msg;
  }
  // Too fine for max_faces: the message names an edge length that fits, and it is close.
  const int max_faces = 10'000;
  for (const auto& info : builtin_shapes()) {
    SCOPED_TRACE(info.name);
    const std::string msg =
        message_of([&] { generate_shape(info.name, {}, 0.1 * info.base_edge_length, max_faces); });
    std::smatch match;
    ASSERT_TRUE(std::regex_search(
        msg, match, std::regex(R"(more than max_faces = 10000; use edge_length >= ([0-9.eE+-]+) m$)")))
        << msg;
    const double fit = std::stod(match[1].str());
    const SurfaceMesh m = generate_shape(info.name, {}, fit, max_faces);
    EXPECT_LE(m.num_faces(), max_faces);
    EXPECT_GE(m.num_faces(), 0.75 * max_faces);
  }
  // Absurd resolutions are refused before anything is allocated.
  EXPECT_NE(message_of([] { generate_shape("pavilion", {}, 1e-300); }).find("max_faces = 4000000"),
            std::string::npos);
  EXPECT_NE(message_of([] { generate_shape("sheet", {}, 0.02, 10); }).find("max_faces = 10 is too small"),
            std::string::npos);
  EXPECT_NE(message_of([] { generate_shape("sheet", {}, 0.02, 0); }).find("max_faces must be positive"),
            std::string::npos);
}

}  // namespace
}  // namespace cutwork
