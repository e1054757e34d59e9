#include "host/pattern/lattice_order.h"

#include <algorithm>
#include <complex>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "host/core/error.h"
#include "host/pattern/point_grid.h"

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

}  // namespace

LatticeOrder measure_lattice_order(const RowMatX3d& centres, const RowMatX3d& normals, const Vec3& axis) {
  const int n = int(centres.rows());
  if (normals.rows() != n) throw InputError(fmt::format("lattice order: {} normals for {} centres", normals.rows(), n));
  if (!centres.allFinite() || !normals.allFinite() || !axis.allFinite())
    throw InputError("lattice order: the centres, normals and axis must be finite");
  LatticeOrder out;
  if (n < 4) return out;
  // The grid's cells about one spacing of a surface-filling arrangement (exact either way).
  const Vec3 lo = centres.colwise().minCoeff(), hi = centres.colwise().maxCoeff();
  const double spacing = std::max((hi - lo).norm() / std::sqrt(double(n)), 1e-12);
  const PointGrid grid(centres, spacing);
  std::vector<double> square, hexagonal, misfit;
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
    const Vec3 nrm = normals.row(i).transpose().normalized();
    Vec3 t1 = axis - axis.dot(nrm) * nrm;
    const bool has_axis = t1.norm() > 1e-3 * axis.norm();
    t1 = has_axis ? t1.normalized() : any_perpendicular(nrm);
    const Vec3 t2 = nrm.cross(t1);
    std::complex<double> p4 = 0, p6 = 0;
    int k = 0;
    for (int j : near) {
      if (j == i) continue;
      const Vec3 d = centres.row(j).transpose() - c;
      const double theta = std::atan2(d.dot(t2), d.dot(t1));
      p4 += std::polar(1.0, 4 * theta);
      p6 += std::polar(1.0, 6 * theta);
      ++k;
    }
    if (k < 3) continue;
    p4 /= double(k);
    p6 /= double(k);
    square.push_back(std::abs(p4));
    hexagonal.push_back(std::abs(p6));
    if (has_axis && std::abs(p4) >= 0.5) misfit.push_back(std::abs(std::arg(p4)) / 4 * 180 / std::numbers::pi);
  }
  out.stencils = int(square.size());
  out.square = median(square);
  out.hexagonal = median(hexagonal);
  out.axis_misfit = median(misfit);
  return out;
}

}  // namespace cutwork
