#include "solvers/objective/peak_energy_density.h"

#include "host/core/internal_error.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "host/core/error.h"
#include "solvers/objective/energy_density.h"
#include "solvers/shell/shell_energy.h"

namespace cutwork::solvers {

namespace {

MonotoneCurve checked_concentration(const std::vector<double>& alpha, const std::vector<double>& k, const char* what) {
  if (k.size() != alpha.size())
    throw InputError(fmt::format("{} concentration curve: {} factors for {} fill ratios", what, k.size(), alpha.size()));
  for (size_t i = 0; i < k.size(); ++i)
    if (!(k[i] >= 1 - 1e-9))
      throw InputError(fmt::format("{} concentration curve: factor {} at α = {} is below 1", what, k[i], alpha[i]));
  return MonotoneCurve(alpha, k);
}

/// One curve in α per biaxiality node; empty for an empty table.
std::vector<MonotoneCurve> checked_by_biaxiality(const std::vector<double>& alpha,
                                                 const std::vector<std::vector<double>>& table, const char* what) {
  std::vector<MonotoneCurve> nodes;
  if (table.empty()) return nodes;
  if (table.size() != alpha.size())
    throw InputError(fmt::format("{} concentration by biaxiality: {} rows for {} fill ratios", what, table.size(),
                                 alpha.size()));
  for (const std::vector<double>& row : table)
    if (row.size() != size_t(kBiaxialityNodes))
      throw InputError(fmt::format("{} concentration by biaxiality: a row of {} factors, not {}", what, row.size(),
                                   kBiaxialityNodes));
  for (int j = 0; j < kBiaxialityNodes; ++j) {
    std::vector<double> k;
    for (const std::vector<double>& row : table) k.push_back(row[size_t(j)]);
    nodes.push_back(checked_concentration(alpha, k, what));
  }
  return nodes;
}

/// K_b blended towards K_m in stress by φ (the header's "Thick plates").
double thick_blend(double bending, double membrane, double phi) {
  const double root = (1 - phi) * std::sqrt(std::max(bending, 0.0)) + phi * std::sqrt(std::max(membrane, 0.0));
  return root * root;
}

/// `curve` with every shape's bending factors by corner blended at each node's φ_c =
/// thick_round_transition(2 scale / e_c) (e_c the node, scale = corner radius / thickness; φ = 0 at
/// e_c = 0), and the worst shape's bending factors, which are the largest over the shapes of each
/// shape's node 0, recomputed from the blended ones.
FillStiffnessCurve with_thick_plate(const FillStiffnessCurve& curve, double scale) {
  FillStiffnessCurve c = curve;
  const int n_nodes = c.tool_cut ? kToolNodes : kCornerNodes;
  std::vector<double> phi;
  for (int node = 0; node < n_nodes; ++node) {
    const double e = c.tool_cut ? tool_node(node) : corner_node(node);
    phi.push_back(e > 0 ? thick_round_transition(2 * scale / e) : 0.0);
  }
  for (FillStiffnessCurve::ShapeConcentration& shape : c.shape_concentration) {
    if (shape.empty() || shape.bending_by_corner.empty()) continue;
    if (shape.bending_by_corner.size() != c.alpha.size() || shape.membrane_by_corner.size() != c.alpha.size() ||
        shape.bending_by_biaxiality.size() != c.alpha.size() || shape.membrane_by_biaxiality.size() != c.alpha.size())
      return curve;  // malformed: the map's own checks say what is wrong
    for (size_t k = 0; k < c.alpha.size(); ++k) {
      std::vector<double>& bending = shape.bending_by_corner[k];
      const std::vector<double>& membrane = shape.membrane_by_corner[k];
      if (bending.size() != size_t(n_nodes * kBiaxialityNodes) || membrane.size() != bending.size()) return curve;
      for (int node = 0; node < n_nodes; ++node)
        for (int j = 0; j < kBiaxialityNodes; ++j) {
          const size_t i = size_t(node * kBiaxialityNodes + j);
          bending[i] = thick_blend(bending[i], membrane[i], phi[size_t(node)]);
        }
      // Node 0 is also the shape's plain table by biaxiality and its worst state.
      shape.bending_by_biaxiality[k].assign(bending.begin(), bending.begin() + kBiaxialityNodes);
      shape.bending[k] = *std::max_element(bending.begin(), bending.begin() + kBiaxialityNodes);
    }
  }
  if (!(phi[0] > 0)) return c;
  const bool states = !c.bending_concentration_by_biaxiality.empty();
  for (size_t k = 0; k < c.alpha.size(); ++k) {
    double worst = 1;
    std::vector<double> worst_states(size_t(kBiaxialityNodes), 1.0);
    for (const FillStiffnessCurve::ShapeConcentration& shape : c.shape_concentration) {
      if (shape.empty()) continue;
      worst = std::max(worst, shape.bending[k]);
      if (states && shape.bending_by_biaxiality.size() == c.alpha.size())
        for (int j = 0; j < kBiaxialityNodes; ++j)
          worst_states[size_t(j)] = std::max(worst_states[size_t(j)], shape.bending_by_biaxiality[k][size_t(j)]);
    }
    c.bending_concentration[k] = worst;
    if (states) c.bending_concentration_by_biaxiality[k] = worst_states;
  }
  return c;
}

}  // namespace

double thick_round_transition(double x) {
  if (!(x >= 0)) throw InternalError("thick_round_transition: 2ρ/h must be at least 0");
  // Roark's K_t(x) − 1.79 over Kirsch's 3 − 1.79: the blend of Goodier's 1.79 and Kirsch's 3 is then
  // the fit itself (whose x = 0 end is 2.981, so φ(0) = 0.984).
  if (std::isinf(x)) return 0;
  return (0.25 / (0.39 + x) + 0.81 / (1 + x * x) - 0.26 / (1 + x * x * x)) / (3 - 1.79);
}

ConcentrationMap ConcentrationMap::for_mechanics(const MechanicsSettings& mechanics, const Material& material) {
  const bool thick = mechanics.corner_radius > 0 && material.thickness > 0;
  return ConcentrationMap(mechanics.stiffness_curve, thick ? mechanics.corner_radius / material.thickness : 0.0);
}

ConcentrationMap::ConcentrationMap(const FillStiffnessCurve& curve, double thick_scale) {
  if (curve.membrane_concentration.empty() && curve.bending_concentration.empty()) return;
  if (!(thick_scale >= 0 && std::isfinite(thick_scale)))
    throw InputError(fmt::format("concentration: thick-plate scale {} is not finite and at least 0", thick_scale));
  // The blended copy where the curve has factors by corner to blend (`c` is `curve` otherwise, to the bit).
  const bool by_corner = std::any_of(curve.shape_concentration.begin(), curve.shape_concentration.end(),
                                     [](const auto& s) { return !s.empty() && !s.bending_by_corner.empty(); });
  m_thick_scale = by_corner ? thick_scale : 0.0;
  const FillStiffnessCurve blended = m_thick_scale > 0 ? with_thick_plate(curve, m_thick_scale) : FillStiffnessCurve{};
  const FillStiffnessCurve& c = m_thick_scale > 0 ? blended : curve;
  m_worst.membrane = checked_concentration(c.alpha, c.membrane_concentration, "membrane");
  m_worst.bending = checked_concentration(c.alpha, c.bending_concentration, "bending");
  m_membrane_ratio = MonotoneCurve(c.alpha, c.membrane);
  m_bending_ratio = MonotoneCurve(c.alpha, c.bending);
  m_worst.membrane_states = checked_by_biaxiality(c.alpha, c.membrane_concentration_by_biaxiality, "membrane");
  m_worst.bending_states = checked_by_biaxiality(c.alpha, c.bending_concentration_by_biaxiality, "bending");
  if (m_worst.membrane_states.empty() != m_worst.bending_states.empty())
    throw InputError("concentration by biaxiality: membrane and bending tables must come together");
  int calibrated = 0;
  bool corners = false;  // a shape whose factors change under the corner rule (or the tool)
  m_tool = c.tool_cut;
  for (int k = 0; k < (m_tool ? kToolNodes : kCornerNodes); ++k)
    m_corner_nodes.push_back(m_tool ? tool_node(k) : corner_node(k));
  for (const FillStiffnessCurve::ShapeConcentration& shape : c.shape_concentration) {
    ShapeFactors& by_corner = m_shapes.emplace_back();
    if (shape.empty()) continue;
    Factors& f = by_corner.emplace_back();
    f.membrane = checked_concentration(c.alpha, shape.membrane, "a shape's membrane");
    f.bending = checked_concentration(c.alpha, shape.bending, "a shape's bending");
    f.membrane_states = checked_by_biaxiality(c.alpha, shape.membrane_by_biaxiality, "a shape's membrane");
    f.bending_states = checked_by_biaxiality(c.alpha, shape.bending_by_biaxiality, "a shape's bending");
    if (f.membrane_states.size() != m_worst.membrane_states.size() ||
        f.bending_states.size() != m_worst.bending_states.size())
      throw InputError("concentration by shape: a shape's tables by biaxiality do not match the curve's");
    ++calibrated;
    if (shape.membrane_by_corner.empty() && shape.bending_by_corner.empty()) continue;
    if (f.membrane_states.empty())
      throw InputError("concentration by corner: a shape's tables by corner need its tables by biaxiality");
    // Nodes 1 … n − 1 from the tables by corner (node 0 is the tables above); the worst state's K
    // at a node is its largest over the biaxiality nodes.
    const auto node_table = [&](const std::vector<std::vector<double>>& table, int node, const char* what) {
      if (table.size() != c.alpha.size())
        throw InputError(fmt::format("{} concentration by corner: {} rows for {} fill ratios", what, table.size(),
                                     c.alpha.size()));
      std::vector<std::vector<double>> rows;
      for (const std::vector<double>& row : table) {
        if (row.size() != m_corner_nodes.size() * kBiaxialityNodes)
          throw InputError(fmt::format("{} concentration by corner: a row of {} factors, not {}", what, row.size(),
                                       m_corner_nodes.size() * kBiaxialityNodes));
        rows.emplace_back(row.begin() + node * kBiaxialityNodes, row.begin() + (node + 1) * kBiaxialityNodes);
      }
      return rows;
    };
    const auto worst_of = [](const std::vector<std::vector<double>>& rows) {
      std::vector<double> worst;
      for (const std::vector<double>& row : rows) worst.push_back(*std::max_element(row.begin(), row.end()));
      return worst;
    };
    for (int node = 1; node < int(m_corner_nodes.size()); ++node) {
      const auto membrane = node_table(shape.membrane_by_corner, node, "a shape's membrane");
      const auto bending = node_table(shape.bending_by_corner, node, "a shape's bending");
      Factors g;
      g.membrane = checked_concentration(c.alpha, worst_of(membrane), "a shape's membrane");
      g.bending = checked_concentration(c.alpha, worst_of(bending), "a shape's bending");
      g.membrane_states = checked_by_biaxiality(c.alpha, membrane, "a shape's membrane");
      g.bending_states = checked_by_biaxiality(c.alpha, bending, "a shape's bending");
      by_corner.push_back(std::move(g));
    }
    const auto varies = [](const std::vector<std::vector<double>>& table) {
      for (const std::vector<double>& row : table)
        for (size_t i = kBiaxialityNodes; i < row.size(); ++i)
          if (row[i] != row[i % kBiaxialityNodes]) return true;
      return false;
    };
    corners = corners || varies(shape.membrane_by_corner) || varies(shape.bending_by_corner);
  }
  m_by_shape = calibrated >= 2 || (calibrated == 1 && corners);
  if (c.split()) {
    m_membrane_bulk = MonotoneCurve(c.alpha, c.membrane_bulk);
    m_membrane_shear = MonotoneCurve(c.alpha, c.membrane_shear);
    m_bending_bulk = MonotoneCurve(c.alpha, c.bending_bulk);
    m_bending_shear = MonotoneCurve(c.alpha, c.bending_shear);
  }
}

bool concentration_by_shape(const MechanicsSettings& mechanics, const Material& material) {
  return !mechanics.stiffness_curve.shape_concentration.empty() &&
         ConcentrationMap::for_mechanics(mechanics, material).by_shape();
}

double ConcentrationMap::single(const Factors& f, bool bending, double alpha, const double* rho, double* d_alpha,
                                double* d_rho) {
  const MonotoneCurve& worst = bending ? f.bending : f.membrane;
  if (!rho) {
    if (d_rho) *d_rho = 0;
    return apply(worst, alpha, d_alpha, false);
  }
  return by_state(bending ? f.bending_states : f.membrane_states, worst, alpha, *rho, d_alpha, d_rho, false);
}

double ConcentrationMap::shape_factor(int shape, bool bending, double alpha, const double* rho, double epsilon,
                                      double* d_alpha, double* d_rho, double* d_epsilon) const {
  if (d_epsilon) *d_epsilon = 0;
  const bool own = shape >= 0 && shape < num_shapes() && !m_shapes[size_t(shape)].empty();
  if (!own) return single(m_worst, bending, alpha, rho, d_alpha, d_rho);
  const ShapeFactors& nodes = m_shapes[size_t(shape)];
  if (nodes.size() == 1) return single(nodes[0], bending, alpha, rho, d_alpha, d_rho);
  // Between the nodes ε_j ≤ ε < ε_(j+1) (clamped to the first and last; the slope in ε one-sided,
  // the right interval's, at a node and zero outside them): the corner rule's linear in ε, of the
  // factors and their α- and ρ-slopes at the two nodes; the tool's a power law through the two,
  // K = K_j^(1−t) K_(j+1)^t with t = ln(ε/ε_j) / ln(ε_(j+1)/ε_j), exact for K ∝ ε^p (a round's
  // peak energy grows about as 1/ε), which linear over-reads by up to 12% mid-interval. Below the
  // tool's first node the first interval's power law goes on, K = K_0 (τ/τ_0)^(−p), its exponent
  // held to 0 ≤ p ≤ 1: a notch's peak stress grows at most as 1/√ρ (a crack's), and a round whose
  // K fell as it shrank would be read as the first node's.
  const std::vector<double>& e = m_corner_nodes;
  const int n = int(nodes.size());
  const bool below = m_tool && epsilon < e.front() && epsilon > 0;
  const double x = below ? epsilon : std::clamp(epsilon, e.front(), e[size_t(n - 1)]);
  int j = 0;
  while (j < n - 2 && x >= e[size_t(j + 1)]) ++j;
  const double e0 = e[size_t(j)], e1 = e[size_t(j + 1)];
  const bool inside = epsilon > e.front() && epsilon < e[size_t(n - 1)];
  double a0 = 0, r0 = 0, a1 = 0, r1 = 0;
  const double v0 = single(nodes[size_t(j)], bending, alpha, rho, &a0, &r0);
  const double v1 = single(nodes[size_t(j + 1)], bending, alpha, rho, &a1, &r1);
  double value, da, dr, de;
  if (m_tool) {
    // K = K_j exp(t l), l = ln(K_(j+1)/K_j); below the first node l held to [−span, 0] (p in [0, 1]),
    // and where it is held K is K_0 times a constant: its α- and ρ-slopes are K_0's scaled.
    const double span = std::log(e1 / e0);
    const double t = below ? std::log(x / e0) / span : std::clamp(std::log(x / e0) / span, 0.0, 1.0);
    const double l_free = std::log(v1 / v0), l = below ? std::clamp(l_free, -span, 0.0) : l_free;
    const bool through_both = l == l_free;  // the power law through both nodes (not held)
    value = through_both ? std::pow(v0, 1 - t) * std::pow(v1, t) : v0 * std::exp(t * l);
    da = value * ((through_both ? 1 - t : 1) * a0 / v0 + (through_both ? t * a1 / v1 : 0));
    dr = value * ((through_both ? 1 - t : 1) * r0 / v0 + (through_both ? t * r1 / v1 : 0));
    de = inside || below ? value * l / (span * x) : 0.0;
  } else {
    const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    value = (1 - t) * v0 + t * v1, da = (1 - t) * a0 + t * a1, dr = (1 - t) * r0 + t * r1;
    de = inside ? (v1 - v0) / (e1 - e0) : 0.0;
  }
  if (d_alpha) *d_alpha = da;
  if (d_rho) *d_rho = dr;
  if (d_epsilon) *d_epsilon = de;
  return value;
}

double ConcentrationMap::by_state(const std::vector<MonotoneCurve>& nodes, const MonotoneCurve& worst, double alpha,
                                  double rho, double* d_alpha, double* d_rho, bool ramp) {
  if (d_rho) *d_rho = 0;
  if (nodes.empty()) return apply(worst, alpha, d_alpha, ramp);
  if (d_alpha) *d_alpha = 0;
  if (alpha >= 1) return 1;
  // Catmull–Rom over the nodes j − 1 … j + 2 around ρ (clamped to the table), tangents by central
  // differences, one-sided at the end nodes; linear in the node values, so the α-slope is the same
  // spline of the nodes' α-slopes.
  constexpr int n = kBiaxialityNodes;
  constexpr double h = 2.0 / (n - 1);
  const double r = std::clamp(rho, -1.0, 1.0);
  const int j = std::clamp(int((r + 1) / h), 0, n - 2);
  const double t = std::clamp((r - biaxiality_node(j)) / h, 0.0, 1.0);
  std::array<double, 4> v{}, dv{};
  for (int i = 0; i < 4; ++i)
    v[size_t(i)] = apply(nodes[size_t(std::clamp(j - 1 + i, 0, n - 1))], alpha, &dv[size_t(i)], ramp);
  const auto tangent = [&](const std::array<double, 4>& y, int i) {  // at node j − 1 + i, i = 1, 2
    const int node = j - 1 + i;
    if (node == 0) return y[size_t(i + 1)] - y[size_t(i)];
    if (node == n - 1) return y[size_t(i)] - y[size_t(i - 1)];
    return 0.5 * (y[size_t(i + 1)] - y[size_t(i - 1)]);
  };
  const double t2 = t * t, t3 = t2 * t;
  const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
  const auto hermite = [&](const std::array<double, 4>& y) {
    return h00 * y[1] + h10 * tangent(y, 1) + h01 * y[2] + h11 * tangent(y, 2);
  };
  if (d_alpha) *d_alpha = hermite(dv);
  if (d_rho && rho > -1 && rho < 1) {
    const double g00 = 6 * t2 - 6 * t, g10 = 3 * t2 - 4 * t + 1, g01 = -g00, g11 = 3 * t2 - 2 * t;
    *d_rho = (g00 * v[1] + g10 * tangent(v, 1) + g01 * v[2] + g11 * tangent(v, 2)) / h;
  }
  return hermite(v);
}

Eigen::Vector2d ConcentrationMap::split_ratios(bool bending, double alpha, Eigen::Vector2d* slope) const {
  if (slope) slope->setZero();
  const MonotoneCurve& bulk = bending ? m_bending_bulk : m_membrane_bulk;
  const MonotoneCurve& shear = bending ? m_bending_shear : m_membrane_shear;
  if (bulk.empty() || alpha >= 1) return {1, 1};
  Eigen::Vector2d d;
  const Eigen::Vector2d r(bulk(alpha, &d[0]), shear(alpha, &d[1]));
  if (slope) *slope = d;
  return r;
}

double ConcentrationMap::apply(const MonotoneCurve& k, double alpha, double* slope, bool ramp) {
  if (slope) *slope = 0;
  if (k.empty() || alpha >= 1) return 1;
  double dk = 0;
  const double K = k(alpha, slope ? &dk : nullptr);
  const double t = (1 - alpha) / kConcentrationRamp;
  if (t >= 1 || !ramp) {
    if (slope) *slope = dk;
    return K;
  }
  // K ← 1 + (K − 1) s(t), s(t) = 3t² − 2t³, dt/dα = −1/δ.
  const double s = t * t * (3 - 2 * t), ds_dalpha = -6 * t * (1 - t) / kConcentrationRamp;
  if (slope) *slope = dk * s + (K - 1) * ds_dalpha;
  return 1 + (K - 1) * s;
}

double ConcentrationMap::ratio(const MonotoneCurve& r, double alpha, double* slope) {
  if (slope) *slope = 0;
  if (r.empty() || alpha >= 1) return 1;
  return r(alpha, slope);
}

namespace {

/// ρ of one part (the header's rule) from its bulk and shear energies U_K, U_G at unit fill, with
/// dρ/dα (through the split's ratios) and dρ/dU_K, dρ/dU_G.
struct Biaxiality {
  double rho = 0, d_alpha = 0, d_bulk = 0, d_shear = 0;
};

Biaxiality biaxiality(double UK, double UG, double cK, double cG, const Eigen::Vector2d& r, const Eigen::Vector2d& dr) {
  Biaxiality b;
  const double rootK = std::sqrt(cK * std::max(UK, 0.0)), rootG = std::sqrt(cG * std::max(UG, 0.0));
  const double P = r[0] * rootK, S = r[1] * rootG, T = P + S;
  if (!(T > 0)) return b;
  b.rho = (P - S) / T;
  // ∂ρ/∂P = 2S/T², ∂ρ/∂S = −2P/T²; ∂P/∂U_K = P/(2 U_K), ∂S/∂U_G = S/(2 U_G).
  const double T2 = T * T;
  b.d_alpha = 2 * (S * dr[0] * rootK - P * dr[1] * rootG) / T2;
  if (UK > 0) b.d_bulk = P * S / (T2 * UK);
  if (UG > 0) b.d_shear = -P * S / (T2 * UG);
  return b;
}

/// A face's two states: its membrane's and its bend's (bend false: no shape-operator bend, the
/// worst state's K_b applies), and, when asked for, the gradients of their ρ over the membrane's
/// 3 and the bend's 6 vertices (the bend's slots across a free or clamped edge zero).
struct FaceState {
  Biaxiality membrane, bending;
  bool bend = false;
  Eigen::Matrix<double, 9, 1> membrane_gradient = Eigen::Matrix<double, 9, 1>::Zero();
  Eigen::Matrix<double, 18, 1> bending_gradient = Eigen::Matrix<double, 18, 1>::Zero();
};

/// Index of each face's shape-operator bend, −1 where it has none.
std::vector<int> bend_of_face(const ShellModel& model) {
  std::vector<int> bend(size_t(model.num_faces()), -1);
  for (size_t i = 0; i < model.bends().size(); ++i) bend[size_t(model.bends()[i].face)] = int(i);
  return bend;
}

/// The states of every face, with the gradients of their ρ when `gradients`.
std::vector<FaceState> face_states(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                   const ConcentrationMap& K, bool gradients = false) {
  const int nf = model.num_faces();
  const double nu = model.material().poisson_ratio;
  const std::vector<int> bend = bend_of_face(model);
  const ElementNeed need = gradients ? ElementNeed::Gradient : ElementNeed::Energy;
  std::vector<FaceState> states(static_cast<size_t>(nf));
  tbb::parallel_for(0, nf, [&](int t) {
    FaceState& st = states[size_t(t)];
    Eigen::Vector2d dr;
    {
      const Eigen::Vector2d r = K.split_ratios(false, alpha[t], &dr);
      double U[2];
      Eigen::Matrix<double, 9, 1> g[2];
      int p = 0;
      for (const FillPart part : {FillPart::Bulk, FillPart::Shear}) {
        detail::visit_membrane(model, x, t, model.membrane_lame(part), 1.0, need, [&](const ElementLocal<3>& l) {
          U[p] = l.energy;
          if (gradients) g[p] = l.gradient;
        });
        ++p;
      }
      st.membrane = biaxiality(U[0], U[1], 1 / (1 - nu), 1 / (1 + nu), r, dr);
      if (gradients) st.membrane_gradient = st.membrane.d_bulk * g[0] + st.membrane.d_shear * g[1];
    }
    if (bend[size_t(t)] >= 0) {
      st.bend = true;
      const Eigen::Vector2d r = K.split_ratios(true, alpha[t], &dr);
      double U[2];
      Eigen::Matrix<double, 18, 1> g[2];
      int p = 0;
      for (const FillPart part : {FillPart::Bulk, FillPart::Shear}) {
        detail::visit_bend(model, x, bend[size_t(t)], model.bending_constitutive(part), 1.0, need,
                           [&](const ElementLocal<6>& l) {
                             U[p] = l.energy;
                             if (gradients) g[p] = l.gradient;
                           });
        ++p;
      }
      st.bending = biaxiality(U[0], U[1], 1 + nu, 1 - nu, r, dr);
      if (gradients) st.bending_gradient = st.bending.d_bulk * g[0] + st.bending.d_shear * g[1];
    }
  });
  return states;
}

/// Σ_t weights(t, 0) ∂ρ_t^m/∂x + weights(t, 1) ∂ρ_t^b/∂x (#V×3; rows of fixed vertices zero) from
/// states with gradients.
RowMatX3d scatter_state_gradients(const ShellModel& model, const std::vector<FaceState>& states,
                                  const Eigen::MatrixX2d& weights) {
  RowMatX3d out = RowMatX3d::Zero(model.num_vertices(), 3);
  const RowMatX3i& F = model.mesh().faces();
  const std::vector<int> bend = bend_of_face(model);
  for (int t = 0; t < model.num_faces(); ++t) {
    const FaceState& st = states[size_t(t)];
    for (int a = 0; a < 3; ++a) out.row(F(t, a)) += weights(t, 0) * st.membrane_gradient.segment<3>(3 * a).transpose();
    if (!st.bend) continue;
    const ShellBend& b = model.bends()[size_t(bend[size_t(t)])];
    for (int a = 0; a < 6; ++a)
      if (b.v[a] >= 0) out.row(b.v[a]) += weights(t, 1) * st.bending_gradient.segment<3>(3 * a).transpose();
  }
  for (int v = 0; v < model.num_vertices(); ++v)
    if (model.fixed()[size_t(v)]) out.row(v).setZero();
  return out;
}

/// W_peak_t = a W_t + b M_t (M_t the membrane part of W_t) at α_t = alpha with blend weight w, and
/// da/dα, db/dα (the header's rule); by state, the α-derivatives include ρ's, and rho_m, rho_b are
/// ∂(k_m q_m)/∂ρ^m and ∂(k_b q_b)/∂ρ^b (W_peak = k_b q_b (W − M) + k_m q_m M). By shape, da_dh,
/// db_dh hold ∂a/∂h_s, ∂b/∂h_s, and da_de, db_de ∂a/∂e_s, ∂b/∂e_s (e the cover's corner moments).
struct PeakCoefficients {
  double a = 1, b = 0, da = 0, db = 0, rho_m = 0, rho_b = 0;
  std::vector<double> da_dh, db_dh, da_de, db_de;
};

/// One part's factor k and its slopes: dk/dα (at fixed ρ), dk/dρ, and by shape dk/dh_s, dk/de_s.
struct PartFactor {
  double k = 1, d_alpha = 0, d_rho = 0;
  std::vector<double> d_h, d_e;
};

/// A face's cover by shape: covered fractions h and corner moments e (empty: ε = 0).
struct FaceCover {
  Eigen::RowVectorXd h, e;
};

/// The part's factor by shape (the header's rule): K − 1 = ‖x‖_p over the shapes, x_s = s(h_s/δ)(K_s − 1)
/// with K_s unramped at ε̄_s = e_s/h_s.
PartFactor shape_mix(const ConcentrationMap& K, bool bending, double alpha, const double* rho, const FaceCover& cover) {
  const Eigen::RowVectorXd& h = cover.h;
  const bool corner = cover.e.size() == h.size();
  const int n = int(h.size());
  PartFactor f;
  f.d_h.assign(size_t(n), 0.0);
  f.d_e.assign(size_t(n), 0.0);
  std::vector<double> x(size_t(n), 0.0), dx_alpha(size_t(n), 0.0), dx_rho(size_t(n), 0.0), dx_h(size_t(n), 0.0),
      dx_e(size_t(n), 0.0);
  double max_x = 0;
  for (int s = 0; s < n; ++s) {
    if (!(h[s] > 0)) continue;
    const double epsilon = corner ? cover.e[s] / h[s] : 0.0;
    double dk = 0, dk_rho = 0, dk_eps = 0;
    const double k = K.shape_factor(s, bending, alpha, rho, epsilon, &dk, &dk_rho, &dk_eps);
    const double t = h[s] / kConcentrationRamp;
    // The ramp in the shape's covered fraction: s(t) = 3t² − 2t³ below t = 1.
    const double ramp = t >= 1 ? 1 : t * t * (3 - 2 * t), d_ramp = t >= 1 ? 0 : 6 * t * (1 - t) / kConcentrationRamp;
    x[size_t(s)] = ramp * (k - 1);
    dx_alpha[size_t(s)] = ramp * dk;
    dx_rho[size_t(s)] = ramp * dk_rho;
    // ε̄ = e/h: ∂ε̄/∂h = −ε̄/h, ∂ε̄/∂e = 1/h.
    dx_h[size_t(s)] = d_ramp * (k - 1) - ramp * dk_eps * epsilon / h[s];
    dx_e[size_t(s)] = ramp * dk_eps / h[s];
    max_x = std::max(max_x, x[size_t(s)]);
  }
  if (!(max_x > 0)) return f;
  // ‖x‖_p scaled by the largest x against overflow; ∂‖x‖_p/∂x_s = (x_s/‖x‖_p)^(p−1).
  double sum = 0;
  for (const double xs : x) sum += std::pow(xs / max_x, kShapeNorm);
  const double norm = max_x * std::pow(sum, 1 / kShapeNorm);
  f.k = 1 + norm;
  for (int s = 0; s < n; ++s) {
    const double g = std::pow(x[size_t(s)] / norm, kShapeNorm - 1);
    f.d_alpha += g * dx_alpha[size_t(s)];
    f.d_rho += g * dx_rho[size_t(s)];
    f.d_h[size_t(s)] = g * dx_h[size_t(s)];
    f.d_e[size_t(s)] = g * dx_e[size_t(s)];
  }
  return f;
}

/// The part's factor from the worst shape's curves (the rule without shapes).
PartFactor worst_factor(const ConcentrationMap& K, bool bending, double alpha, const double* rho) {
  PartFactor f;
  if (rho)
    f.k = bending ? K.bending(alpha, *rho, &f.d_alpha, &f.d_rho) : K.membrane(alpha, *rho, &f.d_alpha, &f.d_rho);
  else
    f.k = bending ? K.bending(alpha, &f.d_alpha) : K.membrane(alpha, &f.d_alpha);
  return f;
}

/// `cover`: the face's cover by shape (null: the worst shape's factors).
PeakCoefficients peak_coefficients(const FillStiffnessMap& g, const ConcentrationMap& K, double alpha, double w,
                                   const FaceState* state, const FaceCover* cover = nullptr) {
  PeakCoefficients c;
  if (alpha >= 1) return c;
  const double* rho_m = state && K.by_biaxiality() ? &state->membrane.rho : nullptr;
  const double* rho_b = state && state->bend && K.by_biaxiality() ? &state->bending.rho : nullptr;
  const bool by_shape = cover && K.by_shape() && cover->h.sum() > 0;
  PartFactor m = by_shape ? shape_mix(K, false, alpha, rho_m, *cover) : worst_factor(K, false, alpha, rho_m);
  PartFactor b = by_shape ? shape_mix(K, true, alpha, rho_b, *cover) : worst_factor(K, true, alpha, rho_b);
  // ρ's own α-dependence (through the split's ratios).
  if (rho_m) m.d_alpha += m.d_rho * state->membrane.d_alpha;
  if (rho_b) b.d_alpha += b.d_rho * state->bending.d_alpha;
  const double km = 1 + w * (m.k - 1), kb = 1 + w * (b.k - 1);
  const double dkm = w * m.d_alpha, dkb = w * b.d_alpha;
  // q: perforated material's mean energy density over the model's (1 where the model's elements
  // are the homogenised ones; the calibrated ratio ρ under the linear rule, whose r is 1).
  double qm = 1, qb = 1, dqm = 0, dqb = 0;
  if (g.linear()) qm = K.membrane_ratio(alpha, &dqm), qb = K.bending_ratio(alpha, &dqb);
  c.a = kb * qb;
  c.da = dkb * qb + kb * dqb;
  c.b = km * qm - c.a;
  c.db = dkm * qm + km * dqm - c.da;
  c.rho_m = w * m.d_rho * qm;
  c.rho_b = w * b.d_rho * qb;
  if (by_shape) {
    const size_t n = m.d_h.size();
    c.da_dh.resize(n), c.db_dh.resize(n), c.da_de.resize(n), c.db_de.resize(n);
    for (size_t s = 0; s < n; ++s) {
      c.da_dh[s] = w * b.d_h[s] * qb;
      c.db_dh[s] = w * m.d_h[s] * qm - c.da_dh[s];
      c.da_de[s] = w * b.d_e[s] * qb;
      c.db_de[s] = w * m.d_e[s] * qm - c.da_de[s];
    }
  }
  return c;
}

void check_weight(const ShellModel& model, const Eigen::VectorXd* weight) {
  if (weight && weight->size() != model.num_faces())
    throw InternalError("peak_energy_density: the weights do not match the faces");
}

/// `cover` when the rule by shape applies (K.by_shape()), null otherwise.
const ShapeCover* checked_cover(const ShellModel& model, const ConcentrationMap& K, const ShapeCover* cover) {
  if (!cover || cover->empty() || !K.by_shape()) return nullptr;
  const auto fits = [&](const Eigen::MatrixXd& m) { return m.rows() == model.num_faces() && m.cols() == K.num_shapes(); };
  if (!fits(cover->covered) || (cover->corner.size() > 0 && !fits(cover->corner)))
    throw InternalError("peak_energy_density: the cover does not match the faces and the shapes");
  return cover;
}

/// Face t's row of the cover.
FaceCover face_cover(const ShapeCover& cover, int t) {
  FaceCover f;
  f.h = cover.covered.row(t);
  if (cover.corner.size() > 0) f.e = cover.corner.row(t);
  return f;
}

}  // namespace

Eigen::MatrixX2d stress_biaxiality(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                   const ConcentrationMap& K) {
  const std::vector<FaceState> states = face_states(model, x, alpha, K);
  Eigen::MatrixX2d rho(model.num_faces(), 2);
  for (int t = 0; t < model.num_faces(); ++t) {
    rho(t, 0) = states[size_t(t)].membrane.rho;
    rho(t, 1) = states[size_t(t)].bend ? states[size_t(t)].bending.rho : std::numeric_limits<double>::quiet_NaN();
  }
  return rho;
}

Eigen::VectorXd peak_energy_density(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                    const ConcentrationMap& K, const Eigen::VectorXd* weight,
                                    const ShapeCover* cover) {
  check_weight(model, weight);
  cover = checked_cover(model, K, cover);
  const Eigen::VectorXd W = energy_density(model, x, alpha);
  const Eigen::VectorXd M = energy_density(model, x, alpha, DensityElements::Membrane);
  const std::vector<FaceState> states = K.by_biaxiality() ? face_states(model, x, alpha, K) : std::vector<FaceState>{};
  Eigen::VectorXd peak(model.num_faces());
  tbb::parallel_for(0, model.num_faces(), [&](int t) {
    const FaceCover f = cover ? face_cover(*cover, t) : FaceCover{};
    const PeakCoefficients c = peak_coefficients(model.fill_stiffness(), K, alpha[t], weight ? (*weight)[t] : 1.0,
                                                 states.empty() ? nullptr : &states[size_t(t)], cover ? &f : nullptr);
    peak[t] = c.a * W[t] + c.b * M[t];
  });
  return peak;
}

void peak_energy_density_vjp(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                             const ConcentrationMap& K, const Eigen::VectorXd* weight, const Eigen::VectorXd& c,
                             RowMatX3d* d_positions, Eigen::VectorXd* d_alpha, const ShapeCover* cover,
                             ShapeCover* d_cover) {
  check_weight(model, weight);
  const ShapeCover* mix = checked_cover(model, K, cover);
  const int nf = model.num_faces();
  if (d_cover) {
    d_cover->covered.setZero(nf, cover ? cover->covered.cols() : 0);
    d_cover->corner.setZero(cover && cover->corner.size() > 0 ? nf : 0, cover ? cover->corner.cols() : 0);
  }
  if (c.size() != nf) throw InternalError("peak_energy_density_vjp: the weights c do not match the faces");
  const bool by_state = K.by_biaxiality();
  const std::vector<FaceState> states =
      by_state ? face_states(model, x, alpha, K, d_positions != nullptr) : std::vector<FaceState>{};
  const Eigen::VectorXd W = energy_density(model, x, alpha);
  const Eigen::VectorXd M = energy_density(model, x, alpha, DensityElements::Membrane);
  Eigen::VectorXd ca(nf), cb(nf), dca(nf), dcb(nf);
  Eigen::MatrixX2d c_rho = Eigen::MatrixX2d::Zero(nf, 2);  // c_t ∂W_peak_t/∂ρ_t^m, ∂ρ_t^b
  tbb::parallel_for(0, nf, [&](int t) {
    const FaceCover f = mix ? face_cover(*mix, t) : FaceCover{};
    const PeakCoefficients k = peak_coefficients(model.fill_stiffness(), K, alpha[t], weight ? (*weight)[t] : 1.0,
                                                 by_state ? &states[size_t(t)] : nullptr, mix ? &f : nullptr);
    ca[t] = c[t] * k.a, cb[t] = c[t] * k.b, dca[t] = c[t] * k.da, dcb[t] = c[t] * k.db;
    c_rho(t, 0) = c[t] * k.rho_m * M[t];
    c_rho(t, 1) = c[t] * k.rho_b * (W[t] - M[t]);
    if (d_cover)
      for (size_t s = 0; s < k.da_dh.size(); ++s) {
        d_cover->covered(t, Eigen::Index(s)) = c[t] * (k.da_dh[s] * W[t] + k.db_dh[s] * M[t]);
        if (d_cover->corner.size() > 0)
          d_cover->corner(t, Eigen::Index(s)) = c[t] * (k.da_de[s] * W[t] + k.db_de[s] * M[t]);
      }
  });
  // Σ c a W + Σ c b M: through the densities' own vector–Jacobian products, plus the coefficients'
  // own α-derivatives (ρ's included), plus, by state, the factors' dependence on x through ρ.
  energy_density_vjp(model, x, alpha, ca, d_positions, d_alpha);
  RowMatX3d membrane_x;
  Eigen::VectorXd membrane_alpha;
  energy_density_vjp(model, x, alpha, cb, d_positions ? &membrane_x : nullptr, d_alpha ? &membrane_alpha : nullptr,
                     DensityElements::Membrane);
  if (d_positions) {
    *d_positions += membrane_x;
    if (by_state) *d_positions += scatter_state_gradients(model, states, c_rho);
  }
  if (d_alpha) {
    *d_alpha += membrane_alpha;
    for (int t = 0; t < nf; ++t) (*d_alpha)[t] += dca[t] * W[t] + dcb[t] * M[t];
  }
}

}  // namespace cutwork::solvers
