#include "host/surfaces/generators.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/surfaces/domain_mesh.h"
#include "host/surfaces/rounded_polyline.h"

namespace cutwork {

namespace {

using shapes_detail::DomainMesh;
using shapes_detail::RoundedPolyline;

constexpr double kPi = std::numbers::pi;
/// Area of an equilateral triangle of unit edge.
constexpr double kEquilateralArea = 0.43301270189221932338;
/// Smoothing sweeps on the curved disk shapes. Fixed (not resolution-dependent): the sweeps
/// only repair local distortion of the initial map, so a few suffice at every resolution.
constexpr int kRelaxSweeps = 20;

/// One accepted parameter with its admissible closed interval. The interval may depend on
/// parameters listed before it (which are validated first).
struct Bound {
  std::string key;
  double lo = 0, hi = 0;
  bool integer = false;
};

struct Definition {
  ShapeInfo info;
  /// Bounds of every accepted parameter, in validation order.
  std::function<std::vector<Bound>(const ShapeParameters&)> bounds;
  /// Coarsest edge length that still gives a meaningful mesh (metres).
  std::function<double(const ShapeParameters&)> max_edge_length;
  /// Exact number of faces generate() makes at edge length h (a double: requests for absurd
  /// resolutions must be refused before anything is allocated or any int overflows).
  std::function<double(const ShapeParameters&, double h)> num_faces;
  std::function<SurfaceMesh(const ShapeParameters&, double h, const std::string& what)> generate;
};

// ---------------------------------------------------------------------------------------------
// Building blocks

/// Flat rectangle [-width/2, width/2] × [-height/2, height/2] in z = 0, normals +z.
SurfaceMesh flat_rectangle(double width, double height, double h, const std::string& what) {
  const auto plan = shapes_detail::plan_rectangle(width, height, h);
  const DomainMesh domain = shapes_detail::mesh_rectangle(width, height, plan);
  RowMatX3d vertices(domain.uv.rows(), 3);
  for (Eigen::Index i = 0; i < domain.uv.rows(); ++i) {
    vertices.row(i) << domain.uv(i, 0) - 0.5 * width, domain.uv(i, 1) - 0.5 * height, 0.0;
  }
  return SurfaceMesh(std::move(vertices), domain.faces, what);
}

/// Row spacing in a stretch of an extruded profile: a fillet gets a row at least every
/// kFilletRowAngle of its turn, so its curvature — where a monocoque bends most — is resolved
/// whatever h is.
constexpr double kFilletRowAngle = kPi / 18;
std::function<double(double, double)> arc_rows(const RoundedPolyline& profile) {
  return [&profile](double begin, double end) { return profile.radius_at(0.5 * (begin + end)) * kFilletRowAngle; };
}

/// The profile (in the x-z plane) extruded along y over [-width/2, width/2], meshed on the
/// (y × arc length) rectangle with rows along y (plan_rows). Normal = tangent × ŷ: +z where the
/// profile runs along +x.
SurfaceMesh extruded_profile(const RoundedPolyline& profile, double width, double h,
                             const std::string& what) {
  // u runs along the extrusion and v along the profile's arc length, with a row of vertices on
  // every corner and fillet end of the profile (plan_rows): a region that ends there (a foot on
  // the floor up to where its fillet rises) is the same region on every mesh.
  const auto plan = shapes_detail::plan_rows(width, profile.breaks(), h, arc_rows(profile));
  const DomainMesh domain = shapes_detail::mesh_rectangle(width, profile.length(), plan);
  RowMatX3d vertices(domain.uv.rows(), 3);
  for (Eigen::Index i = 0; i < domain.uv.rows(); ++i) {
    const Vec2 p = profile.point(domain.uv(i, 1));
    vertices.row(i) << p.x(), domain.uv(i, 0) - 0.5 * width, p.y();
  }
  // (u, v) ↦ (y, arc length) reverses the orientation of (arc length, y): swap to keep the
  // normals on the profile's left.
  RowMatX3i faces = domain.faces;
  faces.col(1).swap(faces.col(2));
  return SurfaceMesh(std::move(vertices), std::move(faces), what);
}

double extruded_num_faces(const RoundedPolyline& profile, double width, double h) {
  return shapes_detail::plan_rows(width, profile.breaks(), h, arc_rows(profile)).num_faces();
}

/// Ring count of a hex disk whose near-equilateral triangles of edge h cover `area`.
double disk_rings(double area, double h) {
  return std::max(2.0, std::round(std::sqrt(area / (6 * kEquilateralArea)) / h));
}

Vec2 onto_unit_circle(const Vec2& p) { return p.normalized(); }
Vec2 unit_circle_tangent(const Vec2& p) { return Vec2(-p.y(), p.x()).normalized(); }

// ---------------------------------------------------------------------------------------------
// Parameter access

double get(const ShapeParameters& p, const std::string& key) { return p.at(key); }

// ---------------------------------------------------------------------------------------------
// plate and sheet

Definition plate_definition() {
  Definition d;
  d.info = {"plate",
            "flat rectangular plate in z = 0, centred at the origin (Fig. 5: clamp one short "
            "side, load the middle of the other)",
            {{"width", 0.2}, {"height", 0.1}},
            0.004,
            0.009};
  d.bounds = [](const ShapeParameters&) {
    return std::vector<Bound>{{"width", 0.01, 10.0}, {"height", 0.01, 10.0}};
  };
  d.max_edge_length = [](const ShapeParameters& p) {
    return 0.5 * std::min(get(p, "width"), get(p, "height"));
  };
  d.num_faces = [](const ShapeParameters& p, double h) {
    return shapes_detail::plan_rectangle(get(p, "width"), get(p, "height"), h).num_faces();
  };
  d.generate = [](const ShapeParameters& p, double h, const std::string& what) {
    return flat_rectangle(get(p, "width"), get(p, "height"), h, what);
  };
  return d;
}

Definition sheet_definition() {
  Definition d;
  d.info = {"sheet",
            "flat square sheet in z = 0, centred at the origin (Fig. 4: unit square under "
            "self-weight, outer boundary fixed)",
            {{"size", 1.0}},
            0.02,
            0.045};
  d.bounds = [](const ShapeParameters&) { return std::vector<Bound>{{"size", 0.01, 20.0}}; };
  d.max_edge_length = [](const ShapeParameters& p) { return 0.5 * get(p, "size"); };
  d.num_faces = [](const ShapeParameters& p, double h) {
    return shapes_detail::plan_rectangle(get(p, "size"), get(p, "size"), h).num_faces();
  };
  d.generate = [](const ShapeParameters& p, double h, const std::string& what) {
    return flat_rectangle(get(p, "size"), get(p, "size"), h, what);
  };
  return d;
}

// ---------------------------------------------------------------------------------------------
// bowl: spherical cap, bottom at the origin, rim circle of radius `radius` at z = depth.

struct BowlGeometry {
  double rim_radius, depth;
  double sphere_radius, cap_angle, geodesic_radius;

  BowlGeometry(double radius, double depth_) : rim_radius(radius), depth(depth_) {
    sphere_radius = (radius * radius + depth * depth) / (2 * depth);
    cap_angle = std::asin(std::min(1.0, radius / sphere_radius));  // depth ≤ radius: ≤ π/2
    geodesic_radius = sphere_radius * cap_angle;
  }
  double area() const { return kPi * (rim_radius * rim_radius + depth * depth); }

  /// Azimuthal equidistant map of the unit disk onto the cap: distance from the centre of the
  /// disk is geodesic distance from the bottom (scaled), direction is azimuth.
  Vec3 point(const Vec2& uv) const {
    const double rho = uv.norm();
    if (rho == 0) return Vec3::Zero();
    const Vec2 dir = uv / rho;
    const double phi = rho * cap_angle;
    const double r = sphere_radius * std::sin(phi);
    return Vec3(r * dir.x(), r * dir.y(), sphere_radius * (1 - std::cos(phi)));
  }
  /// Exact rim point (radius and depth reproduced without rounding).
  Vec3 rim_point(const Vec2& uv) const {
    const Vec2 dir = uv.normalized();
    return Vec3(rim_radius * dir.x(), rim_radius * dir.y(), depth);
  }
};

Definition bowl_definition() {
  Definition d;
  d.info = {"bowl",
            "spherical cap opening up: bottom at the origin, rim circle of radius 'radius' at "
            "z = 'depth' (fruit bowl, Fig. 9)",
            {{"radius", 0.15}, {"depth", 0.07}},
            0.008,
            0.018};
  d.bounds = [](const ShapeParameters& p) {
    const double r = get(p, "radius");
    return std::vector<Bound>{{"radius", 0.02, 5.0}, {"depth", 0.05 * r, r}};
  };
  d.max_edge_length = [](const ShapeParameters& p) {
    const BowlGeometry g(get(p, "radius"), get(p, "depth"));
    return 0.5 * std::sqrt(g.area() / (6 * kEquilateralArea));  // at least 2 rings
  };
  d.num_faces = [](const ShapeParameters& p, double h) {
    const double rings = disk_rings(BowlGeometry(get(p, "radius"), get(p, "depth")).area(), h);
    return 6 * rings * rings;
  };
  d.generate = [](const ShapeParameters& p, double h, const std::string& what) {
    const BowlGeometry g(get(p, "radius"), get(p, "depth"));
    DomainMesh domain = shapes_detail::mesh_hex_disk(int(disk_rings(g.area(), h)));
    std::vector<bool> pinned(std::size_t(domain.uv.rows()), false);
    pinned[0] = true;  // the bottom stays at the origin
    shapes_detail::relax_on_surface(
        domain, [&g](const Vec2& uv) { return g.point(uv); }, kRelaxSweeps, onto_unit_circle,
        unit_circle_tangent, pinned);
    RowMatX3d vertices(domain.uv.rows(), 3);
    for (Eigen::Index i = 0; i < domain.uv.rows(); ++i) {
      const Vec2 uv = domain.uv.row(i).transpose();
      vertices.row(i) = (domain.on_boundary[std::size_t(i)] ? g.rim_point(uv) : g.point(uv)).transpose();
    }
    // The domain's CCW faces have normals towards the sphere's centre (into the bowl); flip
    // them so normals point to the convex outside like every other curved shape.
    RowMatX3i faces = domain.faces;
    faces.col(1).swap(faces.col(2));
    return SurfaceMesh(std::move(vertices), std::move(faces), what);
  };
  return d;
}

// ---------------------------------------------------------------------------------------------
// pavilion: vault over the disk of radius R,
//   z(r, θ) = H (1 − ρ²) + ρ² A g(θ),  ρ = r / R,
// with g = 0 on an angular band at each leg (the foot, a strip of the rim on z = 0) and
// g = sin²(π t / 2) rising to 1 midway between legs (the arches).

struct PavilionGeometry {
  double radius, height, arch_height, foot_length;
  int legs;
  double half_period, half_foot;  // radians

  explicit PavilionGeometry(const ShapeParameters& p)
      : radius(get(p, "radius")),
        height(get(p, "height")),
        arch_height(get(p, "arch_height")),
        foot_length(get(p, "foot_length")),
        legs(int(get(p, "legs"))) {
    half_period = kPi / legs;
    half_foot = 0.5 * foot_length / radius;
  }

  /// Legs are centred at θ = (2k + 1)·π/legs (for 4 legs: the diagonals, arches facing ±x, ±y).
  /// Returns g and dg/dθ.
  std::pair<double, double> arch(double theta) const {
    const double from_leg = std::remainder(theta - half_period, 2 * half_period);
    const double distance = std::abs(from_leg);
    if (distance <= half_foot) return {0.0, 0.0};
    const double span = half_period - half_foot;
    const double t = (distance - half_foot) / span;
    const double s = std::sin(0.5 * kPi * t);
    const double dg = 0.5 * kPi / span * std::sin(kPi * t) * (from_leg < 0 ? -1.0 : 1.0);
    return {s * s, dg};
  }

  /// Height at normalised radius rho ∈ [0, 1] and angle theta.
  double z(double rho, double theta) const {
    return height * (1 - rho * rho) + rho * rho * arch_height * arch(theta).first;
  }

  /// Map of the unit disk: (u, v) ↦ (R u, R v, z). On the rim pass on_rim = true so the feet
  /// are reproduced exactly on z = 0.
  Vec3 point(const Vec2& uv, bool on_rim = false) const {
    const double theta = std::atan2(uv.y(), uv.x());
    if (on_rim) {
      return Vec3(radius * std::cos(theta), radius * std::sin(theta),
                  arch_height * arch(theta).first);
    }
    return Vec3(radius * uv.x(), radius * uv.y(), z(uv.norm(), theta));
  }

  /// Midpoint-rule area: dA = R·sqrt(z_θ² + ρ² z_ρ² + R² ρ²) dρ dθ.
  double area() const {
    const int nr = 200, nt = 64 * legs;
    double sum = 0;
    for (int j = 0; j < nt; ++j) {
      const double theta = 2 * kPi * (j + 0.5) / nt;
      const auto [g, dg] = arch(theta);
      for (int i = 0; i < nr; ++i) {
        const double rho = (i + 0.5) / nr;
        const double z_rho = 2 * rho * (arch_height * g - height);
        const double z_theta = rho * rho * arch_height * dg;
        sum += radius * std::sqrt(z_theta * z_theta + rho * rho * z_rho * z_rho +
                                  radius * radius * rho * rho);
      }
    }
    return sum * (1.0 / nr) * (2 * kPi / nt);
  }

  bool in_foot(double theta) const {
    return std::abs(std::remainder(theta - half_period, 2 * half_period)) <= half_foot;
  }
};

/// Initial placement for the pavilion: along each ray from the centre, the hex disk's rings
/// are spaced evenly in 3-D arc length (not in plan), so the steep flanks near the feet are
/// not stretched radially. Tabulated on a (θ, ρ) grid and interpolated.
class RayArcLength {
 public:
  explicit RayArcLength(const PavilionGeometry& g) : m_s((kAngles + 1) * (kSteps + 1)) {
    for (int m = 0; m <= kAngles; ++m) {
      const double theta = 2 * kPi * m / kAngles;
      const double a = g.arch_height * g.arch(theta).first - g.height;
      auto speed = [&](double rho) {  // |dX/dρ| along the ray
        const double z_rho = 2 * rho * a;
        return std::sqrt(g.radius * g.radius + z_rho * z_rho);
      };
      double* s = &m_s[std::size_t(m) * (kSteps + 1)];
      s[0] = 0;
      for (int k = 1; k <= kSteps; ++k) {
        s[k] = s[k - 1] + 0.5 * (speed((k - 1.0) / kSteps) + speed(double(k) / kSteps)) / kSteps;
      }
    }
  }

  /// Plan position of the point a fraction `fraction` ∈ [0, 1] of the ray's arc length out
  /// along direction theta ∈ [0, 2π].
  double radius_at(double fraction, double theta) const {
    const double x = theta / (2 * kPi) * kAngles;
    const int m = std::clamp(int(x), 0, kAngles - 1);
    const double t = x - m;
    return (1 - t) * invert(m, fraction) + t * invert(m + 1, fraction);
  }

 private:
  static constexpr int kAngles = 1024, kSteps = 256;
  double invert(int m, double fraction) const {
    const double* s = &m_s[std::size_t(m) * (kSteps + 1)];
    const double target = fraction * s[kSteps];
    const int k = int(std::upper_bound(s, s + kSteps + 1, target) - s);
    if (k > kSteps) return 1.0;
    return (k - 1 + (target - s[k - 1]) / (s[k] - s[k - 1])) / kSteps;
  }
  std::vector<double> m_s;
};

Definition pavilion_definition() {
  Definition d;
  d.info = {"pavilion",
            "doubly curved vault over a disk standing on 'legs' feet: crown of 'height' at the "
            "centre, rim arches of 'arch_height' between feet; each foot is a strip of the rim "
            "of 'foot_length' on z = 0, exactly (select supports with z below 1e-6: past a foot's "
            "end the rim rises out of z = 0 tangentially, so a looser bound fixes a longer strip of a "
            "finer mesh)",
            {{"radius", 3.0}, {"height", 1.8}, {"arch_height", 1.2}, {"legs", 4},
             {"foot_length", 0.8}},
            0.15,
            0.35};
  d.bounds = [](const ShapeParameters& p) {
    const double r = get(p, "radius");
    const double h = get(p, "height");
    const double legs = get(p, "legs");
    // Slopes are capped so the hex disk's triangles stay well-shaped (min angle ≥ 25° over
    // the whole admissible box): the crown's slope at the feet is 2·height/radius ≤ 1.2, and
    // the rim's steepest slope on an arch flank, arch_height·(π/2)/(radius·span) with span the
    // angle from a foot's edge to the arch top, is ≤ 1.
    const double span = kPi / legs - 0.5 * get(p, "foot_length") / r;
    return std::vector<Bound>{{"radius", 0.5, 50.0},
                              {"height", 0.05 * r, 0.6 * r},
                              {"legs", 3, 8, true},
                              {"foot_length", 0.02 * r, 0.6 * kPi * r / legs},
                              {"arch_height", 0.0, std::min(0.8 * h, 2 / kPi * r * span)}};
  };
  d.max_edge_length = [](const ShapeParameters& p) {
    const PavilionGeometry g(p);
    // Half a foot keeps ≥ 1 (typically 2) rim vertices on every foot; 3 rings at least.
    return std::min(0.5 * g.foot_length,
                    std::sqrt(g.area() / (6 * kEquilateralArea)) / 3);
  };
  d.num_faces = [](const ShapeParameters& p, double h) {
    const double rings = disk_rings(PavilionGeometry(p).area(), h);
    return 6 * rings * rings;
  };
  d.generate = [](const ShapeParameters& p, double h, const std::string& what) {
    const PavilionGeometry g(p);
    DomainMesh domain = shapes_detail::mesh_hex_disk(int(disk_rings(g.area(), h)));
    const RayArcLength rays(g);
    std::vector<bool> pinned(std::size_t(domain.uv.rows()), false);
    pinned[0] = true;  // the crown stays at the centre
    // Both ends of every foot are rim vertices, and the foot's rim vertices are spread evenly
    // between them. Otherwise the strip on z = 0 that the supports select is
    // shorter than foot_length by up to one rim spacing on each side, by an amount that changes
    // with the edge length (the default pavilion's compliance was 2.5 times the fine meshes').
    std::vector<bool> on_foot(std::size_t(domain.uv.rows()), false);
    {
      std::vector<std::pair<double, Eigen::Index>> rim;  // (angle in [0, 2π), vertex)
      for (Eigen::Index i = 1; i < domain.uv.rows(); ++i) {
        if (!domain.on_boundary[std::size_t(i)]) continue;
        double theta = std::atan2(domain.uv(i, 1), domain.uv(i, 0));
        rim.emplace_back(theta < 0 ? theta + 2 * kPi : theta, i);
      }
      std::sort(rim.begin(), rim.end());
      const long n = long(rim.size());
      for (int leg = 0; leg < g.legs; ++leg) {
        const double centre = (2 * leg + 1) * g.half_period;
        auto offset = [&](long k) {  // signed angle of rim vertex k from the leg's centre
          return std::remainder(rim[std::size_t(((k % n) + n) % n)].first - centre, 2 * kPi);
        };
        // As many rim spacings on the foot as keep the spacing nearest the rim's own (≥ 1), on the
        // consecutive rim vertices centred on the leg.
        const long gaps = std::max(1L, std::lround(2 * g.half_foot / (2 * kPi / double(n))));
        long middle = 0;
        for (long k = 1; k < n; ++k)
          if (std::abs(offset(k)) < std::abs(offset(middle))) middle = k;
        long lo = middle - gaps / 2;
        if (gaps % 2 == 1 && offset(middle) > 0) --lo;  // an odd count: the middle vertex's side
        const long hi = lo + gaps;
        for (long k = lo; k <= hi; ++k) {
          const double theta = centre - g.half_foot + 2 * g.half_foot * double(k - lo) / double(hi - lo);
          const Eigen::Index i = rim[std::size_t(((k % n) + n) % n)].second;
          domain.uv.row(i) = Vec2(std::cos(theta), std::sin(theta)).transpose();
          on_foot[std::size_t(i)] = true;
        }
      }
    }
    for (Eigen::Index i = 1; i < domain.uv.rows(); ++i) {
      const Vec2 uv = domain.uv.row(i).transpose();
      double theta = std::atan2(uv.y(), uv.x());
      if (theta < 0) theta += 2 * kPi;
      if (domain.on_boundary[std::size_t(i)]) {
        // Rim vertices on a foot (its ends included) stay put, so every foot keeps its vertices
        // on z = 0.
        pinned[std::size_t(i)] = on_foot[std::size_t(i)];
        continue;
      }
      const double rho = uv.norm();
      domain.uv.row(i) = (uv * (rays.radius_at(rho, theta) / rho)).transpose();
    }
    shapes_detail::relax_on_surface(
        domain, [&g](const Vec2& uv) { return g.point(uv); }, kRelaxSweeps, onto_unit_circle,
        unit_circle_tangent, pinned);
    RowMatX3d vertices(domain.uv.rows(), 3);
    for (Eigen::Index i = 0; i < domain.uv.rows(); ++i) {
      vertices.row(i) =
          g.point(domain.uv.row(i).transpose(), domain.on_boundary[std::size_t(i)]).transpose();
    }
    return SurfaceMesh(std::move(vertices), domain.faces, what);
  };
  return d;
}

// ---------------------------------------------------------------------------------------------
// Shapes extruded from a rounded profile (table, chair): the coarsest edge length, the face
// count and the mesh, from the profile and the parameter `extent_key` (the extrusion length).

void set_extruded(Definition& d, RoundedPolyline (*profile)(const ShapeParameters&), const char* extent_key) {
  d.max_edge_length = [=](const ShapeParameters& p) {
    return std::min({0.5 * get(p, extent_key), 2 * get(p, "corner_radius"), 0.25 * profile(p).length()});
  };
  d.num_faces = [=](const ShapeParameters& p, double h) {
    return extruded_num_faces(profile(p), get(p, extent_key), h);
  };
  d.generate = [=](const ShapeParameters& p, double h, const std::string& what) {
    return extruded_profile(profile(p), get(p, extent_key), h, what);
  };
}

// ---------------------------------------------------------------------------------------------
// table: ∩-shaped monocoque, profile (−L/2, 0) ↑ (−L/2, H) → (L/2, H) ↓ (L/2, 0), extruded
// over y ∈ [−depth/2, depth/2].

std::vector<Vec2> table_corners(const ShapeParameters& p) {
  const double half = 0.5 * get(p, "length"), top = get(p, "height");
  return {Vec2(-half, 0), Vec2(-half, top), Vec2(half, top), Vec2(half, 0)};
}

RoundedPolyline table_profile(const ShapeParameters& p) {
  return RoundedPolyline(table_corners(p), get(p, "corner_radius"));
}

Definition table_definition() {
  Definition d;
  d.info = {"table",
            "monocoque table: two vertical side panels standing on z = 0 and a flat top at "
            "z = 'height', joined by rounded corners; 'length' along x, 'depth' along y",
            {{"length", 1.0}, {"depth", 0.6}, {"height", 0.7}, {"corner_radius", 0.08}},
            0.035,
            0.08};
  d.bounds = [](const ShapeParameters& p) {
    return std::vector<Bound>{
        {"length", 0.2, 5.0},
        {"depth", 0.1, 3.0},
        {"height", 0.1, 2.0},
        {"corner_radius", 0.01, RoundedPolyline::max_radius(table_corners(p))}};
  };
  set_extruded(d, table_profile, "depth");
  return d;
}

// ---------------------------------------------------------------------------------------------
// chair: cantilever "Z" profile (x forward, z up) back-rest top → seat back (0, seat_height)
// → seat front → diagonal down to the floor → floor runner, extruded over y ∈ [−w/2, w/2].

std::vector<Vec2> chair_corners(const ShapeParameters& p) {
  const double seat = get(p, "seat_height");
  return {Vec2(-get(p, "back_recline"), get(p, "back_height")), Vec2(0, seat),
          Vec2(get(p, "seat_depth"), seat), Vec2(get(p, "runner_start"), 0),
          Vec2(get(p, "runner_end"), 0)};
}

RoundedPolyline chair_profile(const ShapeParameters& p) {
  return RoundedPolyline(chair_corners(p), get(p, "corner_radius"));
}

Definition chair_definition() {
  Definition d;
  d.info = {"chair",
            "monocoque cantilever chair: back rest from (-back_recline, back_height) down to "
            "the seat (0..seat_depth at seat_height), a diagonal down to the floor at "
            "runner_start and a floor runner on z = 0 to runner_end (x forward, z up), "
            "corners rounded, extruded over 'width' along y",
            {{"width", 0.45},
             {"seat_height", 0.45},
             {"seat_depth", 0.45},
             {"back_height", 0.9},
             {"back_recline", 0.08},
             {"runner_start", 0.1},
             {"runner_end", 0.5},
             {"corner_radius", 0.06}},
            0.022,
            0.05};
  d.bounds = [](const ShapeParameters& p) {
    const double seat = get(p, "seat_height"), depth = get(p, "seat_depth");
    const double back = get(p, "back_height"), start = get(p, "runner_start");
    return std::vector<Bound>{
        {"width", 0.1, 3.0},
        {"seat_height", 0.1, 1.5},
        {"seat_depth", 0.1, 1.5},
        {"back_height", seat + 0.05, seat + 1.5},
        {"back_recline", 0.0, 0.5 * (back - seat)},
        {"runner_start", 0.0, 0.9 * depth},
        {"runner_end", start + 0.05, start + 2.0},
        {"corner_radius", 0.01, RoundedPolyline::max_radius(chair_corners(p))}};
  };
  set_extruded(d, chair_profile, "width");
  return d;
}

// ---------------------------------------------------------------------------------------------

const std::vector<Definition>& definitions() {
  static const std::vector<Definition> all = {plate_definition(),    sheet_definition(),
                                              bowl_definition(),     pavilion_definition(),
                                              table_definition(),    chair_definition()};
  return all;
}

const Definition* find_definition(const std::string& name) {
  for (const auto& d : definitions()) {
    if (d.info.name == name) return &d;
  }
  return nullptr;
}

std::string shape_names() {
  std::string names;
  for (const auto& d : definitions()) names += (names.empty() ? "" : ", ") + d.info.name;
  return names;
}

/// Defaults overlaid with `params`, every key known and every value within its bounds.
ShapeParameters validated(const Definition& d, const ShapeParameters& params) {
  const std::string shape = "shape '" + d.info.name + "'";
  for (const auto& [key, value] : params) {
    if (!d.info.defaults.contains(key)) {
      std::string accepted;
      for (const auto& entry : d.info.defaults) accepted += (accepted.empty() ? "" : ", ") + entry.first;
      throw InputError(fmt::format("{}: unknown parameter '{}' (accepted: {})", shape, key, accepted));
    }
  }
  ShapeParameters merged = d.info.defaults;
  for (const auto& [key, value] : params) merged[key] = value;
  // Bounds are re-derived after each check so that a bound depending on an earlier parameter
  // is computed only once that parameter is known to be valid.
  const std::size_t count = d.bounds(merged).size();
  for (std::size_t k = 0; k < count; ++k) {
    const Bound b = d.bounds(merged)[k];
    const double v = merged.at(b.key);
    // Bounds are printed with 6 significant digits; accept values that round to them.
    const double slack = 1e-5 * std::max(std::abs(b.lo), std::abs(b.hi));
    const bool inside = std::isfinite(v) && v >= b.lo - slack && v <= b.hi + slack &&
                        (!b.integer || v == std::round(v));
    if (!inside) {
      throw InputError(fmt::format("{}: parameter '{}' must be {}in [{:g}, {:g}] (got {:g})",
                                   shape, b.key, b.integer ? "an integer " : "", b.lo, b.hi, v));
    }
  }
  return merged;
}

/// Rounds up to 3 significant digits, so a printed suggestion is not below the real value.
double round_up_3_digits(double x) {
  const double unit = std::pow(10.0, std::floor(std::log10(x)) - 2);
  return std::ceil(x / unit) * unit;
}

/// The finest edge length (to ~1%, printed with 3 significant digits) whose mesh has at most
/// max_faces faces. Pre: the mesh at `coarsest` fits. The first guess scales the requested
/// resolution by the ~1/h² face count (from the coarsest mesh when the requested count
/// overflowed); lattice rounding makes the count only roughly monotone, hence the 1% walk.
double fitting_edge_length(const Definition& d, const ShapeParameters& p, double h,
                           double faces, double coarsest, double max_faces) {
  auto fits = [&](double x) { return d.num_faces(p, x) <= max_faces; };
  double fit = faces < 1e12 ? h * std::sqrt(faces / max_faces)
                            : coarsest * std::sqrt(d.num_faces(p, coarsest) / max_faces);
  fit = std::min(coarsest, round_up_3_digits(fit));
  for (int step = 0; step < 1000 && !fits(fit); ++step) {
    fit = std::min(coarsest, round_up_3_digits(fit * 1.01));
  }
  for (int step = 0; step < 1000; ++step) {
    const double finer = round_up_3_digits(fit * 0.99);
    if (finer >= fit || !fits(finer)) break;
    fit = finer;
  }
  return fit;
}

}  // namespace

const std::vector<ShapeInfo>& builtin_shapes() {
  static const std::vector<ShapeInfo> infos = [] {
    std::vector<ShapeInfo> out;
    for (const auto& d : definitions()) out.push_back(d.info);
    return out;
  }();
  return infos;
}

const ShapeInfo* find_shape(const std::string& name) {
  for (const auto& info : builtin_shapes()) {
    if (info.name == name) return &info;
  }
  return nullptr;
}

SurfaceMesh generate_shape(const std::string& name, const ShapeParameters& params,
                           double edge_length, int max_faces, const std::string& length_key) {
  const Definition* d = find_definition(name);
  if (!d) {
    throw InputError(fmt::format("unknown shape '{}' (built-in shapes: {})", name, shape_names()));
  }
  const std::string shape = "shape '" + name + "'";
  const ShapeParameters p = validated(*d, params);
  if (max_faces <= 0) {
    throw InputError(fmt::format("{}: max_faces must be positive (got {})", shape, max_faces));
  }
  const double coarsest = d->max_edge_length(p);
  // The bound is printed with 6 significant digits; accept values that round to it.
  if (!std::isfinite(edge_length) || edge_length <= 0 || edge_length > coarsest * (1 + 1e-5)) {
    throw InputError(fmt::format(
        "{}: {} must be a length in (0, {:g}] m for these parameters (got {:g})", shape, length_key,
        coarsest, edge_length));
  }
  const double faces = d->num_faces(p, edge_length);
  if (faces > max_faces) {
    if (d->num_faces(p, coarsest) > max_faces) {
      throw InputError(fmt::format(
          "{}: max_faces = {} is too small: even the coarsest mesh ({} {:g} m) has {:g} "
          "faces",
          shape, max_faces, length_key, coarsest, d->num_faces(p, coarsest)));
    }
    // (absurd requests overflow the count to infinity: say "over 1e12" rather than "inf")
    const std::string count = faces < 1e12 ? fmt::format("{:.0f}", faces) : "over 1e12";
    throw InputError(fmt::format(
        "{}: {} {:g} m would give {} faces, more than max_faces = {}; use "
        "{} >= {:g} m",
        shape, length_key, edge_length, count, max_faces, length_key, fitting_edge_length(*d, p, edge_length, faces, coarsest, max_faces)));
  }
  return d->generate(p, edge_length, shape);
}

}  // namespace cutwork
