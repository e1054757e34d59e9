#include "solvers/objective/ligament_peak.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "host/core/error.h"
#include "solvers/shell/fill_stiffness_map.h"

namespace cutwork::solvers {
namespace {

// The header's tables: x = R/w and the neck's rim stress (membrane) or rim moment (bending) over
// the far field's.
constexpr double kLastX = 64;
// Goodier's single hole in uniaxial bending, (5 + 3ν)/(3 + ν), at the measurement's ν = 0.4.
constexpr double kGoodierBending = (5 + 3 * 0.4) / (3 + 0.4);

const MonotoneCurve& membrane_curve() {
  static const MonotoneCurve curve({0, 1, 2, 4, 8, 16, 32, kLastX},
                                   {3.00, 3.39, 4.20, 5.71, 8.08, 11.59, 16.80, 24.34});
  return curve;
}

const MonotoneCurve& bending_curve() {
  static const MonotoneCurve curve({0, 1, 2, 4, 8, 16, 32, kLastX},
                                   {kGoodierBending, 2.47, 3.06, 4.08, 5.53, 7.62, 10.71, 14.84});
  return curve;
}

double read(const MonotoneCurve& c, double x) {
  if (!(x >= 0)) return c(0);
  if (x > kLastX) return c(kLastX) * std::sqrt(x / kLastX);
  return c(x);
}

}  // namespace

double two_hole_concentration(double x) { return read(membrane_curve(), x); }

double two_hole_bending_concentration(double x) { return read(bending_curve(), x); }

double lattice_ligament_parameter(double alpha, PerforationLattice lattice) {
  if (alpha >= 1) return 0;
  const double cell = lattice == PerforationLattice::Square ? 1.0 : std::sqrt(3.0) / 2;  // per spacing²
  const double r = std::sqrt((1 - alpha) * cell / std::numbers::pi);  // R/p
  if (r >= 0.5) return std::numeric_limits<double>::infinity();
  return r / (1 - 2 * r);
}

double pair_parameter(const Ligament& l) {
  const double R_h = l.neck_radius(), S = l.pair_radius();
  if (!(R_h > 0)) return 0;
  return l.width > 0 ? S * S / (R_h * l.width) : std::numeric_limits<double>::infinity();
}

double bending_pair_parameter(const Ligament& l) {
  const double R_h = l.neck_radius();
  if (!(R_h > 0)) return 0;
  return l.width > 0 ? R_h / l.width : std::numeric_limits<double>::infinity();
}

std::vector<LigamentPeak> ligament_peaks(const SurfaceMesh& sim, const Eigen::VectorXd& alpha,
                                         const Eigen::VectorXd& W_peak, std::span<const Ligament> ligaments,
                                         double alpha_floor, PerforationLattice lattice) {
  const int nf = sim.num_faces();
  if (alpha.size() != nf || W_peak.size() != nf)
    throw InputError(fmt::format("ligament peaks: {} fill ratios and {} peak densities for {} faces", alpha.size(),
                                 W_peak.size(), nf));
  const RowMatX3d& V = sim.vertices();
  const RowMatX3i& F = sim.faces();
  RowMatX3d centroid(nf, 3);
  for (int f = 0; f < nf; ++f) centroid.row(f) = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))) / 3.0;
  // The faces by centroid x: a ligament looks at the slab |x − m_x| ≤ r only.
  std::vector<int> by_x(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f) by_x[std::size_t(f)] = f;
  std::sort(by_x.begin(), by_x.end(), [&](int a, int b) { return centroid(a, 0) < centroid(b, 0); });
  std::vector<double> xs(by_x.size());
  for (std::size_t i = 0; i < by_x.size(); ++i) xs[i] = centroid(by_x[i], 0);
  // The nearest centroid of a point on the surface lies within about one edge of it.
  const double near_reach = 2 * sim.mean_edge_length();
  std::vector<LigamentPeak> out;
  out.reserve(ligaments.size());
  for (std::size_t i = 0; i < ligaments.size(); ++i) {
    const Ligament& l = ligaments[i];
    LigamentPeak p;
    p.ligament = int(i);
    p.neck_radius = l.neck_radius();
    p.pair_radius = l.pair_radius();
    p.x = pair_parameter(l);
    p.x_bending = bending_pair_parameter(l);
    const double Km = two_hole_concentration(p.x), Kb = two_hole_bending_concentration(p.x_bending);
    const Vec3 m = l.midpoint();
    int nearest = -1;
    double nearest_d2 = std::numeric_limits<double>::infinity();
    auto consider = [&](int f) {
      if (!std::isfinite(W_peak(f))) return;
      const double a = std::clamp(alpha(f), alpha_floor, 1.0);
      const double x_lat = lattice_ligament_parameter(a, lattice);
      const double rm = Km / two_hole_concentration(x_lat), rb = Kb / two_hole_bending_concentration(x_lat);
      const double factor = std::max({1.0, rm * rm, rb * rb});
      const double W = factor * W_peak(f);
      if (p.face < 0 || W > p.W) {
        p.W = W;
        p.factor = factor;
        p.x_lattice = x_lat;
        p.face = f;
        p.W_peak_face = W_peak(f);
        p.alpha = alpha(f);
      }
    };
    auto scan = [&](double reach, bool within_pair) {
      const auto first = std::lower_bound(xs.begin(), xs.end(), m.x() - reach);
      const auto last = std::upper_bound(xs.begin(), xs.end(), m.x() + reach);
      for (auto it = first; it != last; ++it) {
        const int f = by_x[std::size_t(it - xs.begin())];
        const double d2 = (centroid.row(f).transpose() - m).squaredNorm();
        if (d2 < nearest_d2) nearest_d2 = d2, nearest = f;
        if (within_pair && d2 <= p.pair_radius * p.pair_radius) consider(f);
      }
    };
    const double reach = std::max(p.pair_radius, near_reach);
    scan(reach, true);
    // A face outside the slab is farther than `reach`: the nearest found is the nearest unless it is
    // farther still (a mesh coarser there than its mean edge), when every face is looked at.
    if (nearest < 0 || nearest_d2 > reach * reach) scan(std::numeric_limits<double>::infinity(), false);
    if (nearest >= 0) consider(nearest);
    out.push_back(p);
  }
  return out;
}

LigamentPeakSummary summarize_ligament_peaks(const CutSurface& cut, const SurfaceMesh& base, const SurfaceMesh& sim,
                                             const Eigen::VectorXd& alpha, const Eigen::VectorXd& W_peak,
                                             double alpha_floor, double thickness, PerforationLattice lattice,
                                             const Vec3& mirror_planes) {
  LigamentPeakSummary s;
  s.ligaments = find_ligaments(cut, base, kLigamentSearchWidth, mirror_planes);
  s.peaks = ligament_peaks(sim, alpha, W_peak, s.ligaments, alpha_floor, lattice);
  for (std::size_t i = 0; i < s.peaks.size(); ++i) {
    if (s.worst < 0 || s.peaks[i].W > s.W_max) {
      s.W_max = s.peaks[i].W;
      s.worst = int(i);
    }
    if (s.ligaments[i].width < thickness) ++s.narrower_than_thickness;
  }
  return s;
}

}  // namespace cutwork::solvers
