// The cut surface against the fill kernel it must agree with: the area of the cut mesh is
// Σ_t α_t A_t (same projection, so any discrepancy is a bug), the removed area of stencils
// inside a flat plate is Σ s² · polygon area, the output is a valid watertight mesh with one
// hole per stencil, new vertices lie on stencil outlines, the degenerate placements (on a
// vertex, on an edge, across the boundary, overlapping) behave, and threads change nothing.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include "host/core/error.h"
#include "host/cut/cut_surface.h"
#include "host/mesh/mesh_io.h"
#include "host/surfaces/generators.h"
#include "host/stencil/fill_ratio.h"
#include "kernels/common/stencil_geometry.h"

namespace cutwork {
namespace {

constexpr double kPlateWidth = 0.2, kPlateHeight = 0.1;

/// A mesh with its BVH (which references it, hence not copyable).
struct Surface {
  SurfaceMesh mesh;
  FaceBvh bvh{mesh};
  explicit Surface(SurfaceMesh m) : mesh(std::move(m)) {}
  Surface(const Surface&) = delete;
  Surface& operator=(const Surface&) = delete;
};

Surface* plate() {
  static Surface s(generate_shape("plate", {{"width", kPlateWidth}, {"height", kPlateHeight}}, 0.005));
  return &s;
}
Surface* bowl() {
  static Surface s(generate_shape("bowl", {}, 0.01));
  return &s;
}
Surface* pavilion() {
  static Surface s(generate_shape("pavilion", {}, 0.2));
  return &s;
}

/// Type ids: 0 circle, 1 star, 2 flower, 3 square, 4 heart (non-convex), 5 leaf.
const StencilLibrary& library() {
  static const StencilLibrary lib = [] {
    StencilLibrary l;
    for (const char* kind : {"circle", "star", "flower", "square", "heart", "leaf"})
      l.add(make_builtin_stencil(kind, {}, kind));
    return l;
  }();
  return lib;
}

const AxisTangentField& field() {
  static const AxisTangentField f;
  return f;
}

StencilParams stencil_at(const Vec3& p, double scale, int type, double angle = 0.3) {
  StencilParams s;
  s.position = p;
  s.scale = scale;
  s.angle = angle;
  s.type = type;
  return s;
}

/// Σ_t α_t A_t from the fill kernel on the same mesh, without the min_fill clamp.
double fill_area(const Surface& s, const std::vector<StencilParams>& stencils) {
  FillRatioOptions opt;
  opt.derivatives = false;
  opt.min_fill = 1e-300;
  FillRatioEvaluator ev(s.bvh, s.bvh, library(), &field(), opt);
  ev.evaluate(stencils);
  return ev.alpha().dot(s.mesh.face_areas());
}

/// Σ s² · polygon area: what stencils lying completely on a flat surface remove.
double stencil_area(const std::vector<StencilParams>& stencils) {
  double a = 0;
  for (const StencilParams& s : stencils) a += s.scale * s.scale * library()[s.type].area;
  return a;
}

bool inside_plate(const Vec3& c, double scale) {
  return std::abs(c.x()) + 1.2 * scale < 0.5 * kPlateWidth &&
         std::abs(c.y()) + 1.2 * scale < 0.5 * kPlateHeight;
}

/// Dart throwing: centres at uniform points of random faces, scales uniform in [lo, hi], types
/// uniform; bounding balls kept 1.3 (s_i + s_j) apart and `admissible` (if given).
std::vector<StencilParams> random_stencils(const SurfaceMesh& mesh, int count, double lo,
                                           double hi, unsigned seed,
                                           const std::function<bool(const Vec3&, double)>&
                                               admissible = nullptr) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> face(0, mesh.num_faces() - 1), type(0, library().size() - 1);
  std::uniform_real_distribution<double> unit(0, 1), scale(lo, hi), angle(-3.2, 3.2);
  std::vector<StencilParams> out;
  for (int tries = 0; tries < 20000 && int(out.size()) < count; ++tries) {
    const int f = face(rng);
    double u = unit(rng), v = unit(rng);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const Vec3 p = (1 - u - v) * mesh.vertices().row(mesh.faces()(f, 0)).transpose() +
                   u * mesh.vertices().row(mesh.faces()(f, 1)).transpose() +
                   v * mesh.vertices().row(mesh.faces()(f, 2)).transpose();
    const double s = scale(rng);
    if (admissible && !admissible(p, s)) continue;
    bool apart = true;
    for (const StencilParams& o : out)
      apart = apart && (o.position - p).norm() > 1.3 * (o.scale + s);
    if (apart) out.push_back(stencil_at(p, s, type(rng), angle(rng)));
  }
  return out;
}

/// Face quality: twice the area over the longest edge squared (√3/2 for an equilateral
/// triangle, 0 for a degenerate one); the worst face of the output.
double worst_quality(const CutSurface& cut) {
  double worst = std::numeric_limits<double>::infinity();
  for (int f = 0; f < cut.faces.rows(); ++f) {
    const Vec3 a = cut.vertices.row(cut.faces(f, 0)).transpose();
    const Vec3 b = cut.vertices.row(cut.faces(f, 1)).transpose();
    const Vec3 c = cut.vertices.row(cut.faces(f, 2)).transpose();
    const double longest2 =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    worst = std::min(worst, (b - a).cross(c - a).norm() / longest2);
  }
  return worst;
}

/// The worst face quality over all outputs this test binary checked (printed by the tests).
double& worst_quality_seen() {
  static double worst = std::numeric_limits<double>::infinity();
  return worst;
}

/// No needles or slivers: every face's twice area exceeds 1e-10 × its longest edge squared, a
/// hundred times the mesh loader's own bound (kZeroAreaRelative = 1e-12).
void check_quality(const CutSurface& cut) {
  const double q = worst_quality(cut);
  worst_quality_seen() = std::min(worst_quality_seen(), q);
  EXPECT_GT(q, 1e-10) << "a face with twice area <= 1e-10 x longest edge^2";
}

/// What `cutwork check DIR/cut.obj` does with the file `cutwork design` writes: the OBJ writer,
/// then the mesh loader (OBJ in double precision) must accept the cut.
void check_loader_accepts(const CutSurface& cut) {
  static std::atomic<int> counter{0};
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("cutwork_cut_surface_test_" + std::to_string(::getpid()) + "_" +
       std::to_string(counter++) + ".obj");
  write_obj(path, cut.vertices, cut.faces);
  try {
    const SurfaceMesh m = read_mesh(path);
    EXPECT_EQ(m.num_faces(), cut.faces.rows());
    EXPECT_EQ(m.num_vertices(), cut.vertices.rows()) << "vertices welded in single precision";
  } catch (const std::exception& e) {
    ADD_FAILURE() << "the mesh loader rejects the written cut: " << e.what();
  }
  std::error_code ec;
  std::filesystem::remove(path, ec);
}

/// Everything test 2 asks of the output mesh. Returns the number of boundary loops.
int check_mesh(const CutSurface& cut, const SurfaceMesh& base) {
  const int nv = int(cut.vertices.rows()), nf = int(cut.faces.rows());
  EXPECT_EQ(cut.source_vertex.size(), nv);
  EXPECT_EQ(cut.source_face.size(), nf);
  // Directed edges: each at most once (manifold, consistently oriented); an undirected edge in
  // two faces is then used once in each direction.
  std::map<std::pair<int, int>, int> directed;
  std::vector<int> referenced(size_t(nv), 0);
  for (int f = 0; f < nf; ++f) {
    for (int k = 0; k < 3; ++k) {
      const int a = cut.faces(f, k), b = cut.faces(f, (k + 1) % 3);
      ++directed[{a, b}];
      ++referenced[size_t(a)];
    }
  }
  int over_used = 0;
  for (const auto& [e, n] : directed) over_used += n > 1;
  EXPECT_EQ(over_used, 0) << "directed edges used twice (non-manifold or flipped)";
  EXPECT_EQ(std::count(referenced.begin(), referenced.end(), 0), 0) << "unreferenced vertices";

  // Boundary loops: boundary edges (no twin) chained head to tail.
  std::multimap<int, int> next;
  for (const auto& [e, n] : directed)
    if (!directed.count({e.second, e.first})) next.emplace(e.first, e.second);
  int pinches = 0;
  for (auto it = next.begin(); it != next.end(); it = next.upper_bound(it->first))
    pinches += next.count(it->first) > 1;
  EXPECT_EQ(pinches, 0) << "boundary vertices with two outgoing boundary edges";
  int loops = 0;
  std::map<int, bool> seen;
  for (const auto& [a, b] : next) {
    if (seen[a]) continue;
    ++loops;
    int v = a;
    int steps = 0;
    while (!seen[v] && steps++ <= int(next.size())) {
      seen[v] = true;
      const auto it = next.find(v);
      if (it == next.end()) {
        ADD_FAILURE() << "open boundary chain at vertex " << v;
        break;
      }
      v = it->second;
    }
  }

  // No duplicate vertices: none closer than 1e-12 × the mesh's size.
  const double tol = 1e-12 * (base.bbox_max() - base.bbox_min()).norm();
  std::vector<int> order(static_cast<size_t>(nv));
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int x, int y) { return cut.vertices(x, 0) < cut.vertices(y, 0); });
  int duplicates = 0;
  for (size_t i = 0; i < order.size(); ++i) {
    for (size_t j = i + 1; j < order.size(); ++j) {
      if (cut.vertices(order[j], 0) - cut.vertices(order[i], 0) > tol) break;
      duplicates += (cut.vertices.row(order[j]) - cut.vertices.row(order[i])).norm() <= tol;
    }
  }
  EXPECT_EQ(duplicates, 0);

  // No sliver below 1e-14 of its source triangle; orientation agrees with the source normal.
  int slivers = 0, flipped = 0;
  for (int f = 0; f < nf; ++f) {
    const Vec3 a = cut.vertices.row(cut.faces(f, 0)).transpose();
    const Vec3 b = cut.vertices.row(cut.faces(f, 1)).transpose();
    const Vec3 c = cut.vertices.row(cut.faces(f, 2)).transpose();
    const Vec3 n = 0.5 * (b - a).cross(c - a);
    const int src = cut.source_face[f];
    slivers += n.norm() < 1e-14 * base.face_areas()[src];
    flipped += n.dot(base.face_normals().row(src).transpose()) <= 0;
  }
  EXPECT_EQ(slivers, 0);
  EXPECT_EQ(flipped, 0);

  // The mesh class's own validation agrees (manifold, oriented, no zero-area faces).
  int mesh_loops = -1;
  EXPECT_NO_THROW({
    const SurfaceMesh m(cut.vertices, cut.faces, "cut");
    mesh_loops = int(m.boundary_loops().size());
  });
  EXPECT_EQ(mesh_loops, loops);
  check_quality(cut);
  return loops;
}

double relative_error(double a, double b) { return std::abs(a - b) / std::abs(b); }

// ---- 1. Exactness against the fill kernel ---------------------------------------------------

TEST(CutSurface, PlateAreaEqualsFillAreaAndStencilArea) {
  const Surface& s = *plate();
  for (unsigned seed : {1u, 2u, 3u}) {
    // From smaller than a triangle (edge 5 mm) to many triangles across.
    const auto stencils = random_stencils(s.mesh, 25, 0.001, 0.015, seed, inside_plate);
    ASSERT_GE(stencils.size(), 10u);
    const CutSurface cut = cut_stencils(s.bvh, library(), field(), stencils);
    const double expected = fill_area(s, stencils);
    const double base = s.mesh.face_areas().sum();
    EXPECT_LT(relative_error(cut.area, expected), 1e-9) << "seed " << seed;
    EXPECT_LT(relative_error(base - cut.area, stencil_area(stencils)), 1e-9) << "seed " << seed;
    std::printf("[ plate seed %u ] %zu stencils: |area - fill| / fill = %.2e, "
                "|removed - sum s^2 A| / sum = %.2e, faces kept/split/removed %d/%d/%d\n",
                seed, stencils.size(), relative_error(cut.area, expected),
                relative_error(base - cut.area, stencil_area(stencils)), cut.kept_faces,
                cut.split_faces, cut.removed_faces);
    EXPECT_GT(cut.split_faces, 0);
    EXPECT_GT(cut.removed_faces, 0);
    EXPECT_EQ(cut.kept_faces + cut.split_faces + cut.removed_faces, s.mesh.num_faces());
    check_quality(cut);
  }
}

// The tool's cut (cut_with_tool): on the plate the cut removes exactly the opened polygons, so the
// cut's area is the plate's less Σ s² A_opened, and the tool leaves Σ s² (A_drawn − A_opened) more
// than the drawn cut; radius 0 is the drawn cut itself.
TEST(CutSurface, AToolsCutRemovesTheOpenedPolygons) {
  const Surface& s = *plate();
  const auto stencils = random_stencils(s.mesh, 25, 0.003, 0.015, 4u, inside_plate);
  ASSERT_GE(stencils.size(), 10u);
  const double tool_radius = 0.0008;
  ToolCutStencils tool;
  const CutSurface cut = cut_with_tool(s.bvh, library(), field(), stencils, tool_radius, &tool);
  ASSERT_EQ(tool.stencils.size(), stencils.size());
  double opened = 0, drawn = 0;
  for (size_t i = 0; i < stencils.size(); ++i) {
    opened += stencils[i].scale * stencils[i].scale * tool.shapes[int(i)].area;
    drawn += stencils[i].scale * stencils[i].scale * library()[stencils[i].type].area;
  }
  EXPECT_GT(tool.rounded, 0);
  EXPECT_GT(drawn - opened, 0);
  const double base = s.mesh.face_areas().sum();
  EXPECT_LT(relative_error(base - cut.area, opened), 1e-9);
  const CutSurface as_drawn = cut_stencils(s.bvh, library(), field(), stencils);
  EXPECT_LT(relative_error(cut.area - as_drawn.area, drawn - opened), 1e-6);
  check_quality(cut);
  const CutSurface zero = cut_with_tool(s.bvh, library(), field(), stencils, 0);
  EXPECT_EQ(zero.vertices, as_drawn.vertices);
  EXPECT_EQ(zero.faces, as_drawn.faces);
  EXPECT_THROW(cut_with_tool(s.bvh, library(), field(), stencils, -1e-3), InputError);
}

TEST(CutSurface, CurvedAreaEqualsFillArea) {
  struct Case {
    const char* name;
    Surface* surface;
  };
  for (const Case& c : {Case{"bowl", bowl()}, Case{"pavilion", pavilion()}}) {
    const Surface& s = *c.surface;
    const double h = s.mesh.mean_edge_length();
    for (unsigned seed : {4u, 5u}) {
      const auto stencils = random_stencils(s.mesh, 60, 0.3 * h, 3 * h, seed);
      ASSERT_GE(stencils.size(), 20u);
      const auto start = std::chrono::steady_clock::now();
      const CutSurface cut = cut_stencils(s.bvh, library(), field(), stencils);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count();
      const double expected = fill_area(s, stencils);
      EXPECT_LT(relative_error(cut.area, expected), 1e-9) << c.name << " seed " << seed;
      std::printf("[ %s seed %u ] %d faces, %zu stencils: |area - fill| / fill = %.2e, "
                  "kept/split/removed %d/%d/%d, output %d faces, %.1f ms\n",
                  c.name, seed, s.mesh.num_faces(), stencils.size(),
                  relative_error(cut.area, expected), cut.kept_faces, cut.split_faces,
                  cut.removed_faces, int(cut.faces.rows()), ms);
      check_mesh(cut, s.mesh);
    }
  }
}

// ---- 2. Watertight where it should be ---------------------------------------------------------

TEST(CutSurface, PlateIsWatertightWithOneHolePerStencil) {
  const Surface& s = *plate();
  for (unsigned seed : {1u, 2u, 3u}) {
    const auto stencils = random_stencils(s.mesh, 25, 0.001, 0.015, seed, inside_plate);
    const CutSurface cut = cut_stencils(s.bvh, library(), field(), stencils);
    const int loops = check_mesh(cut, s.mesh);
    EXPECT_EQ(loops, int(s.mesh.boundary_loops().size() + stencils.size())) << "seed " << seed;
  }
}

// ---- 3. New vertices lie on stencil outlines --------------------------------------------------

double distance_to_outline(const StencilShape& shape, const Vec2& p) {
  double d2 = std::numeric_limits<double>::infinity();
  const auto& poly = shape.polygon;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec2 a = poly[i], b = poly[(i + 1) % poly.size()];
    const Vec2 e = b - a;
    const double t = std::clamp((p - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    d2 = std::min(d2, (a + t * e - p).squaredNorm());
  }
  return std::sqrt(d2);
}

TEST(CutSurface, NewVerticesLieOnStencilOutlines) {
  const Surface& s = *plate();
  const auto stencils = random_stencils(s.mesh, 25, 0.001, 0.015, 7, inside_plate);
  const CutSurface cut = cut_stencils(s.bvh, library(), field(), stencils);
  FillRatioOptions opt;
  opt.derivatives = false;
  FillRatioEvaluator ev(s.bvh, s.bvh, library(), &field(), opt);
  ev.evaluate(stencils);
  double worst = 0;
  int created = 0;
  for (int v = 0; v < cut.vertices.rows(); ++v) {
    if (cut.source_vertex[v] >= 0) {
      EXPECT_EQ(cut.vertices.row(v), s.mesh.vertices().row(cut.source_vertex[v]));
      continue;
    }
    ++created;
    double best = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < stencils.size(); ++i) {
      const kernels::ClipStencil& st = ev.clip_stencils()[i];
      const Vec3 x = cut.vertices.row(v).transpose();
      double w[2];
      kernels::project_equidistant(x.data(), st.origin, st.axis_x, st.axis_y, st.scale, nullptr,
                                   nullptr, nullptr, w, nullptr);
      best = std::min(best, distance_to_outline(library()[st.shape], Vec2(w[0], w[1])));
    }
    worst = std::max(worst, best);
  }
  std::printf("[ outline ] %d new vertices, farthest from an outline: %.2e (reference units)\n",
              created, worst);
  EXPECT_GT(created, 100);
  EXPECT_LE(worst, 1e-9);
}

// ---- 4. Robustness ----------------------------------------------------------------------------

/// Cuts `stencils` from the plate and checks area (fill kernel, and `removed` if given) and the
/// number of boundary loops.
CutSurface cut_plate(const std::vector<StencilParams>& stencils, int expected_loops,
                     double removed = -1) {
  const Surface& s = *plate();
  const CutSurface cut = cut_stencils(s.bvh, library(), field(), stencils);
  const double base = s.mesh.face_areas().sum();
  if (removed < 0) EXPECT_LT(relative_error(cut.area, fill_area(s, stencils)), 1e-9);
  else EXPECT_LT(relative_error(base - cut.area, removed), 1e-9);
  EXPECT_EQ(check_mesh(cut, s.mesh), expected_loops);
  return cut;
}

int nearest_vertex(const SurfaceMesh& mesh, const Vec3& p) {
  int best = 0;
  for (int v = 1; v < mesh.num_vertices(); ++v)
    if ((mesh.vertices().row(v).transpose() - p).norm() <
        (mesh.vertices().row(best).transpose() - p).norm())
      best = v;
  return best;
}

TEST(CutSurface, StencilCentredOnVertexOrEdgeMidpoint) {
  const SurfaceMesh& m = plate()->mesh;
  const int v = nearest_vertex(m, Vec3(0.01, 0.004, 0));
  const Vec3 vertex = m.vertices().row(v).transpose();
  // An edge from that vertex: its midpoint.
  int e = 0;
  while (m.edges()(e, 0) != v && m.edges()(e, 1) != v) ++e;
  const Vec3 mid = 0.5 * (m.vertices().row(m.edges()(e, 0)) + m.vertices().row(m.edges()(e, 1)))
                             .transpose();
  for (const Vec3& centre : {vertex, mid}) {
    for (int type = 0; type < library().size(); ++type) {
      // Angle 0 puts polygon vertices exactly on the horizontal mesh lines through the centre.
      for (double angle : {0.0, 0.25}) {
        for (double scale : {0.002, 0.0075, 0.013}) {
          SCOPED_TRACE(::testing::Message() << "type " << type << " angle " << angle << " scale "
                                            << scale << " centre " << centre.transpose());
          const std::vector<StencilParams> one{stencil_at(centre, scale, type, angle)};
          cut_plate(one, 2);
          cut_plate(one, 2, stencil_area(one));
        }
      }
    }
  }
  // On a curved surface: the bowl's bottom vertex (its hexagonal rings start on the x axis, so
  // angle 0 puts polygon vertices on mesh edges there too) and a vertex a few rings out.
  const Surface& b = *bowl();
  const double h = b.mesh.mean_edge_length();
  for (int vertex : {nearest_vertex(b.mesh, Vec3::Zero()), 40}) {
    for (int type = 0; type < library().size(); ++type) {
      for (double angle : {0.0, 0.25}) {
        SCOPED_TRACE(::testing::Message() << "bowl vertex " << vertex << " type " << type);
        const std::vector<StencilParams> one{
            stencil_at(b.mesh.vertices().row(vertex).transpose(), 1.7 * h, type, angle)};
        const CutSurface cut = cut_stencils(b.bvh, library(), field(), one);
        EXPECT_LT(relative_error(cut.area, fill_area(b, one)), 1e-9);
        EXPECT_EQ(check_mesh(cut, b.mesh), 2);
      }
    }
  }
}

TEST(CutSurface, StencilLargerThanManyTriangles) {
  const std::vector<StencilParams> big{stencil_at(Vec3(0.003, -0.002, 0), 0.04, 2, 0.1)};
  const CutSurface cut = cut_plate(big, 2);
  cut_plate(big, 2, stencil_area(big));
  EXPECT_GT(cut.removed_faces, 100);
}

TEST(CutSurface, StencilInsideOneTriangleMakesAHole) {
  const SurfaceMesh& m = plate()->mesh;
  const int f = m.num_faces() / 2 + 7;
  const Vec3 centroid = (m.vertices().row(m.faces()(f, 0)) + m.vertices().row(m.faces()(f, 1)) +
                         m.vertices().row(m.faces()(f, 2)))
                            .transpose() /
                        3.0;
  for (int type = 0; type < library().size(); ++type) {
    const std::vector<StencilParams> tiny{stencil_at(centroid, 0.0006, type, 0.7)};
    const CutSurface cut = cut_plate(tiny, 2);
    cut_plate(tiny, 2, stencil_area(tiny));
    EXPECT_EQ(cut.split_faces, 1);
    EXPECT_EQ(cut.removed_faces, 0);
    EXPECT_EQ(cut.kept_faces, m.num_faces() - 1);
    for (int i = 0; i < cut.faces.rows(); ++i) {
      const int src = cut.source_face[i];
      if (src == f) continue;
      for (int k = 0; k < 3; ++k) ASSERT_EQ(cut.source_vertex[cut.faces(i, k)], m.faces()(src, k));
    }
  }
}

TEST(CutSurface, StencilAcrossTheOpenBoundary) {
  // Centred on the boundary (x = width/2) and near a corner: the hole merges with the border.
  for (const Vec3& c : {Vec3(0.5 * kPlateWidth, 0.01, 0), Vec3(0.5 * kPlateWidth - 0.004,
                                                                0.5 * kPlateHeight - 0.002, 0)}) {
    for (int type = 0; type < library().size(); ++type) {
      const std::vector<StencilParams> one{stencil_at(c, 0.012, type, 0.4)};
      const CutSurface cut = cut_plate(one, 1);
      EXPECT_LT(plate()->mesh.face_areas().sum() - cut.area, stencil_area(one));
    }
  }
}

TEST(CutSurface, OutlineThroughMeshVerticesAndAlongMeshEdges) {
  // The plate is a staggered lattice: rows of vertices on exact horizontal lines. Around a
  // vertex c: a circle through its two horizontal neighbours (polygon vertices exactly on mesh
  // vertices), a polygon equal to its 1-ring (outline along six mesh edges), and a square whose
  // top side runs along the next lattice row (polygon edges through mesh vertices).
  const SurfaceMesh& m = plate()->mesh;
  const int v = nearest_vertex(m, Vec3(0.01, 0.004, 0));
  const Vec3 c = m.vertices().row(v).transpose();
  std::vector<std::pair<double, Vec2>> ring;
  for (int f = 0; f < m.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (m.faces()(f, k) != v) continue;
      const Vec3 x = m.vertices().row(m.faces()(f, (k + 1) % 3)).transpose() - c;
      ring.push_back({std::atan2(x.y(), x.x()), Vec2(x.x(), x.y())});
    }
  }
  ASSERT_EQ(ring.size(), 6u);
  std::sort(ring.begin(), ring.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Vec2> pts;
  double radius = 0, right = 0, row = 0;
  for (const auto& [angle, p] : ring) {
    pts.push_back(p);
    radius = std::max(radius, p.norm());
    right = std::max(right, p.x());
    row = std::max(row, p.y());
  }
  ASSERT_EQ(pts[2].y(), 0.0) << "expected a horizontal mesh edge";
  StencilLibrary lib;
  lib.add(make_builtin_stencil("circle", {}, "circle"));
  lib.add(make_polygon_stencil("ring", pts));
  lib.add(make_builtin_stencil("square", {}, "square"));
  const double square_top = lib[2].polygon[2].y();
  const double scales[3] = {right, radius, row / square_top};
  for (int type = 0; type < 3; ++type) {
    SCOPED_TRACE(lib[type].name);
    const std::vector<StencilParams> one{stencil_at(c, scales[type], type, 0.0)};
    const CutSurface cut = cut_stencils(plate()->bvh, lib, field(), one);
    FillRatioOptions opt;
    opt.derivatives = false;
    opt.min_fill = 1e-300;
    FillRatioEvaluator ev(plate()->bvh, plate()->bvh, lib, &field(), opt);
    ev.evaluate(one);
    const double removed = m.face_areas().sum() - cut.area;
    EXPECT_LT(relative_error(cut.area, ev.alpha().dot(m.face_areas())), 1e-9);
    EXPECT_LT(relative_error(removed, scales[type] * scales[type] * lib[type].area), 1e-9);
    EXPECT_EQ(check_mesh(cut, m), 2);
    if (type == 1) {  // exactly the six faces of the 1-ring go
      EXPECT_EQ(cut.removed_faces, 6);
      EXPECT_EQ(cut.split_faces, 0);
    }
  }
}

/// Area of the intersection of two convex CCW polygons (Sutherland–Hodgman).
double convex_intersection_area(std::vector<Vec2> subject, const std::vector<Vec2>& clip) {
  for (size_t i = 0; i < clip.size() && !subject.empty(); ++i) {
    const Vec2 a = clip[i], b = clip[(i + 1) % clip.size()];
    auto side = [&](const Vec2& p) { return kernels::orient2(a.x(), a.y(), b.x(), b.y(), p.x(), p.y()); };
    std::vector<Vec2> out;
    for (size_t j = 0; j < subject.size(); ++j) {
      const Vec2 p = subject[(j + subject.size() - 1) % subject.size()], q = subject[j];
      const double sp = side(p), sq = side(q);
      if ((sp >= 0) != (sq >= 0)) out.push_back(p + sp / (sp - sq) * (q - p));
      if (sq >= 0) out.push_back(q);
    }
    subject = std::move(out);
  }
  double twice = 0;
  for (size_t i = 0; i < subject.size(); ++i) {
    const Vec2 a = subject[i], b = subject[(i + 1) % subject.size()];
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * twice;
}

TEST(CutSurface, OverlappingStencilsRemoveTheirUnion) {
  const Surface& s = *plate();
  const std::vector<StencilParams> two{stencil_at(Vec3(-0.011, 0.002, 0), 0.016, 0, 0.2),
                                       stencil_at(Vec3(0.006, -0.004, 0), 0.013, 3, 0.5)};
  FillRatioOptions opt;
  opt.derivatives = false;
  FillRatioEvaluator ev(s.bvh, s.bvh, library(), &field(), opt);
  ev.evaluate(two);
  std::vector<std::vector<Vec2>> world(2);
  for (int i = 0; i < 2; ++i) {
    const kernels::ClipStencil& st = ev.clip_stencils()[size_t(i)];
    for (const Vec2& p : library()[two[size_t(i)].type].polygon) {
      const Vec3 x = Vec3(st.origin[0], st.origin[1], st.origin[2]) +
                     st.scale * (p.x() * Vec3(st.axis_x[0], st.axis_x[1], st.axis_x[2]) +
                                 p.y() * Vec3(st.axis_y[0], st.axis_y[1], st.axis_y[2]));
      world[size_t(i)].emplace_back(x.x(), x.y());
    }
  }
  const double both = convex_intersection_area(world[0], world[1]);
  ASSERT_GT(both, 0.1 * stencil_area({two[1]}));
  const CutSurface cut = cut_plate(two, 2, stencil_area(two) - both);
  std::printf("[ overlap ] union removed, |removed - (A1 + A2 - A12)| / that = %.2e\n",
              relative_error(s.mesh.face_areas().sum() - cut.area, stencil_area(two) - both));
}

TEST(CutSurface, NoStencilsGiveTheInput) {
  const Surface& s = *plate();
  const CutSurface cut = cut_stencils(s.bvh, library(), field(), {});
  EXPECT_EQ(cut.vertices, s.mesh.vertices());
  EXPECT_EQ(cut.faces, s.mesh.faces());
  EXPECT_EQ(cut.kept_faces, s.mesh.num_faces());
  EXPECT_EQ(cut.split_faces + cut.removed_faces, 0);
  EXPECT_NEAR(cut.area, s.mesh.face_areas().sum(), 1e-15);
  // Also with an empty library (nothing to cut with).
  EXPECT_EQ(cut_stencils(s.bvh, StencilLibrary(), field(), {}).faces, s.mesh.faces());
}

TEST(CutSurface, InvalidStencilsThrow) {
  const Surface& s = *plate();
  EXPECT_THROW(cut_stencils(s.bvh, library(), field(),
                            std::vector<StencilParams>{stencil_at(Vec3::Zero(), 0.0, 0)}),
               InputError);
  EXPECT_THROW(cut_stencils(s.bvh, library(), field(),
                            std::vector<StencilParams>{stencil_at(Vec3::Zero(), 0.01, 99)}),
               InputError);
  EXPECT_THROW(cut_stencils(s.bvh, StencilLibrary(), field(),
                            std::vector<StencilParams>{stencil_at(Vec3::Zero(), 0.01, 0)}),
               InputError);
}

// ---- 5. Determinism ---------------------------------------------------------------------------

TEST(CutSurface, SameResultWithOneThreadAndAll) {
  for (Surface* sp : {plate(), bowl(), pavilion()}) {
    const Surface& s = *sp;
    const double h = s.mesh.mean_edge_length();
    const auto stencils = random_stencils(s.mesh, 80, 0.3 * h, 3 * h, 11);
    CutSurface serial;
    {
      tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
      serial = cut_stencils(s.bvh, library(), field(), stencils);
    }
    const CutSurface parallel = cut_stencils(s.bvh, library(), field(), stencils);
    EXPECT_EQ(serial.vertices, parallel.vertices);
    EXPECT_EQ(serial.faces, parallel.faces);
    EXPECT_EQ(serial.source_face, parallel.source_face);
    EXPECT_EQ(serial.area, parallel.area);
    check_mesh(parallel, s.mesh);
  }
}

// ---- 6. Well-shaped faces: near contacts (the sheet of `cutwork design sheet`) ----------------

Surface* sheet() {
  static Surface s(generate_shape("sheet", {}, 0.025));
  return &s;
}

/// Cuts `stencils` from the sheet and checks the area against the fill kernel (and against the
/// stencils' own area when they lie on the sheet), the mesh (watertight, `loops` boundary
/// loops, accepted by SurfaceMesh) and the face quality.
void cut_sheet(const std::vector<StencilParams>& stencils, int loops, bool on_sheet) {
  const Surface& s = *sheet();
  const CutSurface cut = cut_stencils(s.bvh, library(), field(), stencils);
  const double fill = fill_area(s, stencils);
  const double removed = s.mesh.face_areas().sum() - cut.area;
  EXPECT_LT(relative_error(cut.area, fill), 1e-9);
  if (on_sheet) {
    EXPECT_LT(relative_error(removed, stencil_area(stencils)), 1e-9);
  }
  std::printf("[ sheet ] |area - fill| / fill = %.2e, |removed - sum s^2 A| / sum = %.2e, "
              "worst quality %.2e\n",
              relative_error(cut.area, fill), relative_error(removed, stencil_area(stencils)),
              worst_quality(cut));
  EXPECT_EQ(check_mesh(cut, s.mesh), loops);
}

TEST(CutSurface, SheetCutsPassTheMeshValidation) {
  // One circle of scale 0.2 (the scene's): at the centre, on a vertex, at random places. Each
  // cut is well shaped and a valid SurfaceMesh (check_mesh).
  const Surface& s = *sheet();
  for (double angle : {0.0, 0.3}) {
    SCOPED_TRACE(::testing::Message() << "angle " << angle);
    cut_sheet({stencil_at(Vec3::Zero(), 0.2, 0, angle)}, 2, true);
    const Vec3 vertex =
        s.mesh.vertices().row(nearest_vertex(s.mesh, Vec3(0.1, 0.05, 0))).transpose();
    cut_sheet({stencil_at(vertex, 0.2, 0, angle)}, 2, true);
  }
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> place(-0.29, 0.29), angle(-3.2, 3.2);
  for (int i = 0; i < 8; ++i) {
    const Vec3 c(place(rng), place(rng), 0.0);
    SCOPED_TRACE(::testing::Message() << "random centre " << c.transpose());
    cut_sheet({stencil_at(c, 0.2, 0, angle(rng))}, 2, true);
  }
}

TEST(CutSurface, OutlineNearlyTouchingAMeshEdge) {
  // Polygon vertices a hair's breadth from a mesh edge's line are where needles come from. The
  // sheet's lattice has horizontal rows of edges: put the circle's top vertex (angle 0: vertex
  // 16 of 64 points straight up) a distance δ × the mean edge length below or above a row.
  const Surface& s = *sheet();
  const double h = s.mesh.mean_edge_length();
  const int v = nearest_vertex(s.mesh, Vec3(0.05, 0.1, 0));
  const double row = s.mesh.vertices()(v, 1);
  const double r = 0.2;
  const double top = library()[0].polygon[16].y();
  for (double delta : {1e-7, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13}) {
    for (double sign : {-1.0, 1.0}) {
      SCOPED_TRACE(::testing::Message() << "row, delta " << sign * delta << " h");
      const Vec3 c(0.05 + 0.3 * h, row - r * top + sign * delta * h, 0);
      cut_sheet({stencil_at(c, r, 0, 0.0)}, 2, true);
    }
  }
}

TEST(CutSurface, TwoOutlinesNearlyTouchingInsideAFace) {
  // Two circles a hair's breadth apart, touching in a face's interior: a polygon vertex of one
  // close to a polygon vertex of the other (the second turned by π), or close to the middle of
  // one of its edges (turned by π + half a step).
  const Surface& s = *plate();
  const SurfaceMesh& m = s.mesh;
  const int f = m.num_faces() / 2 + 7;
  const Vec3 touch = (m.vertices().row(m.faces()(f, 0)) + m.vertices().row(m.faces()(f, 1)) +
                      m.vertices().row(m.faces()(f, 2)))
                         .transpose() /
                     3.0;
  const double r = 0.01;
  const auto& circle = library()[0].polygon;
  const double step = 2.0 * std::numbers::pi / double(circle.size());
  for (double turn : {0.0, 0.5 * step}) {
    // Distance from the second circle's centre to its outline towards the first.
    const double reach =
        r * circle[0].norm() * (turn == 0.0 ? 1.0 : std::cos(0.5 * step));
    for (double gap : {1e-8, 1e-10, 1e-11, 1e-12, 1e-14, 0.0, -1e-12}) {
      SCOPED_TRACE(::testing::Message() << "turn " << turn << " gap " << gap);
      const Vec3 c1 = touch - Vec3(r * circle[0].x(), 0, 0);
      const Vec3 c2 = touch + Vec3(gap + reach, 0, 0);
      const std::vector<StencilParams> two{stencil_at(c1, r, 0, 0.0),
                                           stencil_at(c2, r, 0, std::numbers::pi + turn)};
      const CutSurface cut = cut_stencils(s.bvh, library(), field(), two);
      EXPECT_LT(relative_error(cut.area, fill_area(s, two)), 1e-9);
      std::printf("[ touching ] turn %.3f gap %8.1e: |area - fill| / fill = %.2e, "
                  "worst quality %.2e\n",
                  turn, gap, relative_error(cut.area, fill_area(s, two)), worst_quality(cut));
      EXPECT_NO_THROW({ const SurfaceMesh mm(cut.vertices, cut.faces, "cut"); });
      check_quality(cut);
    }
  }
}

/// The circle `cutwork design sheet --iterations 4` placed: it touches the fixed border x = 0.5
/// from inside, its rightmost vertex 2.6e-10 m (1.2e-8 of the border edge) inside the sheet.
constexpr double kDesignX = 0.24122221006414024, kDesignY = -0.24022975684563114;
constexpr double kDesignScale = 0.258777789677082;

TEST(CutSurface, OutlineTouchingTheBorder) {
  // The design's circle, and the same with its vertex `gap` m inside the border (negative:
  // outside). Within δ = 1e-9 × the longest mesh edge (~3e-11 m here) the vertex lies on the
  // border and the hole touches it in that vertex (one boundary loop through it twice); farther
  // in, the hole is separate; outside, the hole opens into the border.
  const Surface& s = *sheet();
  struct Case {
    double gap;
    int loops;  // 0: the hole touches the border
  };
  const double design_gap = 0.5 - (kDesignX + kDesignScale * library()[0].polygon[0].x());
  for (const Case& c : {Case{design_gap, 2}, Case{1e-6, 2}, Case{1e-8, 2}, Case{1e-9, 2},
                        Case{1e-10, 2}, Case{1e-11, 0}, Case{1e-13, 0}, Case{0.0, 0},
                        Case{-1e-13, 0}, Case{-1e-11, 0}, Case{-1e-9, 1}}) {
    SCOPED_TRACE(::testing::Message() << "gap " << c.gap << " m");
    const double x = 0.5 - c.gap - kDesignScale * library()[0].polygon[0].x();
    const std::vector<StencilParams> one{stencil_at(Vec3(x, kDesignY, 0), kDesignScale, 0, 0.0)};
    const CutSurface cut = cut_stencils(s.bvh, library(), field(), one);
    const double fill = fill_area(s, one);
    EXPECT_LT(relative_error(cut.area, fill), 1e-9);
    std::printf("[ border ] gap %9.2e m: |area - fill| / fill = %.2e, worst quality %.2e\n", c.gap,
                relative_error(cut.area, fill), worst_quality(cut));
    if (c.loops == 0) {  // touching: one vertex is on both boundaries
      EXPECT_NO_THROW({
        const SurfaceMesh m(cut.vertices, cut.faces, "cut");
        EXPECT_EQ(m.boundary_loops().size(), 1u);
      });
      check_quality(cut);
    } else {
      EXPECT_EQ(check_mesh(cut, s.mesh), c.loops);
    }
  }
}

// Known limitation, not a test of this module: the mesh loader reads OBJ coordinates in single
// precision (assimp's ai_real is float here), so `cutwork check cut.obj` rejects a face whose
// width is below ~1e-7 × the largest coordinate although the cut is valid in double precision
// (design case above: twice area / longest² = 1.2e-8). Snapping at that scale would move the
// outline by up to ~1e-7 m and break the 1e-9 agreement with the fill kernel; run with
// --gtest_also_run_disabled_tests to see the single-precision round trip fail.
TEST(CutSurface, WrittenCutSurvivesTheSinglePrecisionLoader) {
  const std::vector<StencilParams> one{
      stencil_at(Vec3(kDesignX, kDesignY, 0), kDesignScale, 0, 0.0)};
  check_loader_accepts(cut_stencils(sheet()->bvh, library(), field(), one));
  const Surface& b = *bowl();
  const double h = b.mesh.mean_edge_length();
  check_loader_accepts(
      cut_stencils(b.bvh, library(), field(), random_stencils(b.mesh, 60, 0.3 * h, 3 * h, 5)));
}

TEST(CutSurface, WorstFaceQuality) {
  // Runs last (declaration order): the worst face over every output checked above.
  std::printf("[ quality ] worst twice-area / longest^2 over all checked outputs: %.3e\n",
              worst_quality_seen());
  EXPECT_GT(worst_quality_seen(), 1e-10);
}

}  // namespace
}  // namespace cutwork
