#include "host/pattern/lattice_order.h"

#include <algorithm>
#include <complex>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "host/core/error.h"
#include "host/pattern/point_grid.h"
#include "host/stencil/frame.h"

namespace cutwork {

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  const std::size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(m), v.end());
  return v[m];
}

/// A unit vector perpendicular to n.
Vec3 any_perpendicular(const Vec3& n) {
  const Vec3 a = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return (a - a.dot(n) * n).normalized();
}

/// One stencil's bond order, its angles measured in its tangent frame (t1, t2): t1 the axis
/// projected (any tangent where the axis is normal to it, has_axis false).
struct StencilOrder {
  std::complex<double> p4, p6;
  Vec3 normal, t1, t2;
  bool has_axis = false;
};

/// Every stencil with three or more neighbours within 1.3 times its nearest one's distance, its
/// angles from `axis`, or from its own row of `axes` (#S×3) where given.
std::vector<StencilOrder> stencil_orders(const RowMatX3d& centres, const RowMatX3d& normals, const Vec3& axis,
                                         const RowMatX3d* axes = nullptr) {
  const int n = int(centres.rows());
  if (normals.rows() != n) throw InputError(fmt::format("lattice order: {} normals for {} centres", normals.rows(), n));
  if (!centres.allFinite() || !normals.allFinite() || !axis.allFinite() || (axes && !axes->allFinite()))
    throw InputError("lattice order: the centres, normals and axis must be finite");
  if (axes && axes->rows() != n) throw InputError(fmt::format("lattice order: {} axes for {} centres", axes->rows(), n));
  std::vector<StencilOrder> out;
  if (n < 4) return out;
  // The grid's cells about one spacing of a surface-filling arrangement (exact either way).
  const Vec3 lo = centres.colwise().minCoeff(), hi = centres.colwise().maxCoeff();
  const double spacing = std::max((hi - lo).norm() / std::sqrt(double(n)), 1e-12);
  const PointGrid grid(centres, spacing);
  std::vector<int> near;
  for (int i = 0; i < n; ++i) {
    const Vec3 c = centres.row(i).transpose();
    // The nearest neighbour: widen the ball until it holds another centre.
    double r = spacing, d1 = INFINITY;
    for (int tries = 0; tries < 40 && !std::isfinite(d1); ++tries, r *= 2) {
      grid.in_ball(c, r, near);
      for (int j : near)
        if (j != i) d1 = std::min(d1, (centres.row(j).transpose() - c).norm());
    }
    if (!std::isfinite(d1) || !(d1 > 0)) continue;
    grid.in_ball(c, 1.3 * d1, near);
    StencilOrder o;
    o.normal = normals.row(i).transpose().normalized();
    const Vec3 a = axes ? Vec3(axes->row(i).transpose()) : axis;
    Vec3 t1 = a - a.dot(o.normal) * o.normal;
    o.has_axis = t1.norm() > 1e-3 * a.norm();
    o.t1 = o.has_axis ? t1.normalized() : any_perpendicular(o.normal);
    o.t2 = o.normal.cross(o.t1);
    int k = 0;
    for (int j : near) {
      if (j == i) continue;
      const Vec3 d = centres.row(j).transpose() - c;
      const double theta = std::atan2(d.dot(o.t2), d.dot(o.t1));
      o.p4 += std::polar(1.0, 4 * theta);
      o.p6 += std::polar(1.0, 6 * theta);
      ++k;
    }
    if (k < 3) continue;
    o.p4 /= double(k);
    o.p6 /= double(k);
    out.push_back(o);
  }
  return out;
}

}  // namespace

LatticeOrder measure_lattice_order(const RowMatX3d& centres, const RowMatX3d& normals, const Vec3& axis,
                                   const RowMatX3d* axes) {
  std::vector<double> square, hexagonal, misfit;
  for (const StencilOrder& o : stencil_orders(centres, normals, axis, axes)) {
    square.push_back(std::abs(o.p4));
    hexagonal.push_back(std::abs(o.p6));
    if (o.has_axis && std::abs(o.p4) >= 0.5) misfit.push_back(std::abs(std::arg(o.p4)) / 4 * 180 / std::numbers::pi);
  }
  LatticeOrder out;
  out.stencils = int(square.size());
  out.square = median(square);
  out.hexagonal = median(hexagonal);
  out.axis_misfit = median(misfit);
  return out;
}

MeasuredLattice measure_lattice(const RowMatX3d& centres, const RowMatX3d& normals, const RowMatX3d* tangents) {
  // The reference axis: of x, y, z the one whose projections onto the tangent planes are largest.
  Vec3 reference = Vec3::UnitX();
  double best_projection = -1;
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = Vec3::Unit(k);
    double s = 0;
    for (Eigen::Index i = 0; i < normals.rows(); ++i) {
      const Vec3 nrm = normals.row(i).transpose().normalized();
      s += 1 - std::pow(e.dot(nrm), 2);
    }
    if (s > best_projection + 1e-9) best_projection = s, reference = e;
  }
  const std::vector<StencilOrder> orders = stencil_orders(centres, normals, reference);
  // Each ordered stencil's own axis (arg ψ₄ / 4 from the reference in its plane) and its quarter turn.
  std::vector<const StencilOrder*> ordered;
  for (const StencilOrder& o : orders)
    if (o.has_axis && std::abs(o.p4) >= 0.5) ordered.push_back(&o);
  MeasuredLattice out;
  if (!ordered.empty()) {
    double best_score = -INFINITY;
    const std::size_t tries = std::min<std::size_t>(32, ordered.size());
    for (std::size_t t = 0; t < tries; ++t) {
      const StencilOrder& o = *ordered[t * ordered.size() / tries];
      const double phi = std::arg(o.p4) / 4;
      const Vec3 local = std::cos(phi) * o.t1 + std::sin(phi) * o.t2;
      for (const Vec3& candidate : {local, Vec3(o.normal.cross(local))}) {
        // Σ Re(ψ₄ e^{−4iβ}): each stencil's order measured from the candidate's projection (angle β
        // from its t1), |ψ₄| cos 4Δ.
        double score = 0;
        for (const StencilOrder& s : orders) {
          const Vec3 p = candidate - candidate.dot(s.normal) * s.normal;
          if (p.norm() < 1e-3) continue;
          const double beta = std::atan2(p.dot(s.t2), p.dot(s.t1));
          score += (s.p4 * std::polar(1.0, -4 * beta)).real();
        }
        if (score > best_score + 1e-12) best_score = score, out.axis = candidate.normalized();
      }
    }
  }
  out.order = measure_lattice_order(centres, normals, out.axis);
  const bool ordered_square = out.order.stencils > 0 && out.order.square >= 0.7 && out.order.hexagonal < 0.5;
  out.turning = ordered_square && !(out.order.axis_misfit <= 10);
  out.square = ordered_square && !out.turning;
  if (out.turning && tangents) {
    // Does the lattice follow the field? Each stencil's axes from its own field direction t: a
    // constant angle δ₀ (arg Σ ψ₄ / 4, the |ψ₄|-weighted circular mean) within a median 10°.
    const std::vector<StencilOrder> by_field = stencil_orders(centres, normals, Vec3::UnitX(), tangents);
    std::complex<double> sum = 0;
    for (const StencilOrder& o : by_field)
      if (o.has_axis && std::abs(o.p4) >= 0.5) sum += o.p4;
    if (std::abs(sum) > 0) {
      out.field_angle = std::arg(sum) / 4;
      std::vector<double> misfit;
      for (const StencilOrder& o : by_field)
        if (o.has_axis && std::abs(o.p4) >= 0.5)
          misfit.push_back(std::abs(std::arg(o.p4 * std::polar(1.0, -4 * out.field_angle))) / 4 * 180 / std::numbers::pi);
      out.field_misfit = median(misfit);
      if (out.field_misfit <= 10) {
        out.follows_field = true;
        out.square = true;
        out.turning = false;
      }
    }
  }
  return out;
}

void stencil_frames(const FaceBvh& bvh, const TangentField& field, std::span<const StencilParams> stencils,
                    RowMatX3d& centres, RowMatX3d& normals, RowMatX3d* tangents) {
  centres.resize(Eigen::Index(stencils.size()), 3);
  normals.resize(Eigen::Index(stencils.size()), 3);
  if (tangents) tangents->resize(Eigen::Index(stencils.size()), 3);
  for (std::size_t i = 0; i < stencils.size(); ++i) {
    const Frame f = compute_frame(bvh, field, stencils[i].position, nullptr);
    centres.row(Eigen::Index(i)) = f.origin.transpose();
    normals.row(Eigen::Index(i)) = f.normal.transpose();
    if (tangents) tangents->row(Eigen::Index(i)) = f.tangent.transpose();
  }
}

void attach_lattice_field(MechanicsSettings& mechanics, const FaceBvh& bvh, const TangentField& field) {
  if (!mechanics.lattice_follows_field) {
    mechanics.lattice_axis_at = nullptr;
    return;
  }
  const double c = std::cos(mechanics.lattice_field_angle), s = std::sin(mechanics.lattice_field_angle);
  mechanics.lattice_axis_at = [&bvh, &field, c, s](const Vec3& point) {
    const Frame f = compute_frame(bvh, field, point, nullptr);
    return Vec3(c * f.tangent + s * f.bitangent);
  };
}

}  // namespace cutwork
