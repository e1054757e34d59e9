#pragma once
/// Peak energy density at the ligaments between holes (issue 21 item 5, beyond the paper).
///
/// A coarse face's W (energy_density.h) is a mean over the face's material: a hole's rim carries
/// more. The cell problems (solvers/homogenise/cell_homogenisation.h) measure, per stencil shape and
/// fill ratio, the concentration factor K = peak W / mean W over a periodic cell's material (the
/// largest over the macroscopic stress states: uniaxial at every angle, equibiaxial, pure shear;
/// separately for membrane and bending). The calibrated curve (FillStiffnessCurve's
/// membrane_concentration, bending_concentration) carries K at its sample fill ratios.
///
/// The rule. Per face t,
///     W_peak_t = K_m(α_t) W_t^memb + K_b(α_t) W_t^bend,
/// the mean energy densities of perforated material at the face's macroscopic strain and curvature:
///     W_t^memb = q_m(α_t) M_t,   W_t^bend = q_b(α_t) (W_t − M_t),
/// M_t the membrane part of the model's W_t (r_m^model U_t^memb / A_t, U_t^memb the face's membrane
/// element energy at unit fill, summed over the bulk and shear parts under the isotropic split of
/// fill_stiffness_map.h) and W_t − M_t its bending part, whatever the bending model. Under the
/// homogenised rule the model's elements are perforated material's, so q = 1 and the two parts add
/// up to W_t. Under the linear rule they do not: q = ρ, the calibrated ratio of the curve (the
/// linear rule's r is 1). The linear rule's faces are stiffer than perforated material, and at the
/// strain the linear model computes, perforated material stores ρ U/A per area of material (not
/// U/A) — the rule takes the model's strain as given; where the load, not the strain, is
/// prescribed, the linear model's strain and so its W_peak are too small by about ρ. K_m and K_b
/// apply to their own parts: a plate's membrane and bending peaks sit at the same rim points, so
/// adding them bounds the peak of the sum from above (up to the cross term). A face with α_t = 1
/// exactly is uncut: K = 1, q = 1, W_peak_t = W_t.
///
/// K(α) between samples: the shape-preserving cubic of fill_stiffness_map.h (PCHIP; K need not be
/// monotone, PCHIP does not overshoot the samples and is C¹), held constant outside the samples.
/// The last sample (α = 1) holds the dilute limit (a vanishing hole still concentrates stress, as
/// Kirsch's hole does), not the uncut value 1. Between 1 − δ and 1 (δ = kConcentrationRamp) the
/// factor ramps to 1, K ← 1 + (K − 1) s((1 − α)/δ) with the C¹ smoothstep s(t) = 3t² − 2t³: a face
/// that a stencil barely touches (or, under the cell filter, whose cone barely reaches a hole) holds
/// no rim of its own — the faces that hold the hole report its peak — and the objective built on
/// W_peak stays C¹ where a stencil first enters a face (a jump from 1 to the dilute K there would
/// stall the line search). Units: W in J/m².
///
/// K by the state (FillStiffnessCurve's concentration by biaxiality, when the calibration carries
/// it). A hole concentrates a uniaxial stress most (Kirsch: rim 3σ, K = 9) and an equibiaxial one
/// far less (2σ, K = 2/(1 − ν) = 3.3 at ν = 0.4), so the worst state's K overstates the peak of a
/// shell whose faces are stretched or bent in two directions. Each part's factor is then read at the
/// face's own state: K_m(α_t, ρ_t^m), K_b(α_t, ρ_t^b), with ρ the biaxiality of the perforated
/// material's macroscopic stress (membrane) or moment (bending) — principal values (1, ρ) up to
/// scale, ρ ∈ [−1, 1]: −1 pure shear, 0 uniaxial, 1 equibiaxial — under the isotropic split:
///     ρ = (P − S)/(P + S),   P = r_K √(c_K U_K),   S = r_G √(c_G U_G),
/// U_K, U_G the face's bulk and shear element energies at unit fill (membrane: ((μ + λ)/2) A tr(E)²
/// and μ A |dev E|²; bending: the shape-operator bend's parts, D A (1 + ν)/4 tr(k)² and
/// D A (1 − ν)/2 |dev k|²), r_K, r_G the curve's bulk and shear ratios at α_t (1 without the
/// split), c_K = 1/(1 − ν), c_G = 1/(1 + ν) (membrane) and c_K = 1 + ν, c_G = 1 − ν (bending):
/// P is the mean principal stress's magnitude and S half the principal difference, up to one
/// factor. K between the biaxiality nodes: Catmull–Rom (C¹, linear in the nodes' values, which the
/// PCHIP in α gives with their α-slopes). The orientation of the state against the lattice and the
/// stencils is not known per face: each node holds the worst over the angles (exact for the
/// hexagonal lattice of circles, isotropic). Hinge bending has no per-face curvature tensor: its
/// K_b stays the worst state's. ρ is Lipschitz in the strain, not smooth: at a pure shear or an
/// equibiaxial state the rim's peak moves between points (a max of two smooth functions), and a
/// face at exactly tr = 0 or dev = 0 takes the subgradient 0.
///
/// K by shape (a design of two or more shapes whose curve carries each shape's own factors, when
/// the caller gives the shapes' covered fractions h_ts of each face: the part of face t that the
/// stencils of shape s cover, FillRatioEvaluator::covered_by_shape, filtered as α is). A face's fill
/// ratio does not say which shape cut it — the worst shape's K above then applies to every face,
/// which on the bowl gave a face cut by a small circle the flower's factor — its covered fractions
/// do. The peak over a face's material is at the rim of the worst hole it holds, so per part
///     K_t − 1 = (Σ_s x_ts^p)^(1/p),   x_ts = s(h_ts/δ) (K_s(α_t, ρ_t) − 1),   p = kShapeNorm,
/// K_s the shape's own factor without the ramp in α and s the ramp's smoothstep (1 for h ≥ δ): a
/// shape that barely reaches a face holds no rim there, as a stencil that barely touches it above.
/// The p-norm is a smooth maximum: the largest x where one dominates, at most 2^(1/p) above it
/// where two are equal (4.4% for p = 16); its gradient is bounded, so with s'(0) = 0 the rule stays
/// C¹ where a shape first enters a face. A face of one shape has that shape's ramped factor — the
/// rule above with 1 − α → h_t — and a design of one shape keeps the rule above exactly (its worst
/// shape is its only one). W_peak then depends on the stencils through h too: ∂W_peak_t/∂h_ts
/// (peak_energy_density_vjp's d_cover), pulled back through the clipping
/// (FillRatioEvaluator::pullback_by_shape).
///
/// K by corner. A shape with sharp corners turning into the material (a star's tips, a flower's
/// notches) has an unbounded stress there; `cutwork verify` leaves the rim within the fabrication
/// minimum feature g of such corners out of its conforming peak (a printed corner is rounded at
/// about that size), and the cell's rim, resolved at R/16, reads a tip's value that grows as it is
/// refined. The cells read K at corner nodes ε_c (cell_homogenisation.h: the rim within ε_c bounding
/// radii of a singular corner left out, the corners found as verify finds them); a face reads
/// K_s(α, ρ, ε̄_ts) with ε̄_ts = Σ f ε / Σ f over the pieces of shape s in it, ε = g / (the
/// stencil's scale) — the rule's radius in that stencil's own size, so a small star's tips are
/// left out over more of its rim than a large one's. Linear in ε between the nodes, held at
/// ε ≥ 1: the corner rule itself jumps in ε (a round becomes a corner once it turns 30° within
/// ε/4: the default flower's uniaxial K_m at α = 0.75 reads 20.0 up to ε = 0.25 and 3.0 from
/// 0.375), and a C¹ spline through such a step over- and undershoots (Catmull–Rom dipped to 1.7
/// between 0.375 and 0.5); linear is Lipschitz with kinks at the nodes, as ρ is at its
/// subgradient points, and its ε-slope at a node is the right interval's. ε̄ moves with the
/// stencils' scales and pieces: its derivatives join d_cover. A design of one shape with corners reads its factors this way too (a face of it,
/// by the rule above, is that shape's); a shape without corners (a circle) has the same K at
/// every node.
///
/// K by the tool. A part cut by a tool of radius r (MechanicsSettings::tool_radius) has no sharp
/// corner that turns into the material: each is a round of radius r, whose peak is finite, read
/// at every rim point, and falls about as 1/r (a notch's peak stress about as 1/√ρ: the default
/// star's uniaxial K_m at α = 0.75 is 294, 145, 73, 35, 16 at τ = 1/64 … 1/4). The curve's factors
/// by corner are then the tool's (FillStiffnessCurve::tool_cut): the cells of the holes the tool
/// cuts at τ_c = tool_node(c) = 1/64 … 1/2 bounding radii, and a face reads them at
/// τ̄_ts = Σ f τ / Σ f, τ = r / (the stencil's scale) (corner_radius = r), by the same machinery
/// as ε above. Between two nodes a power law through them, K = K_j^(1−t) K_(j+1)^t with
/// t = ln(τ/τ_j)/ln(τ_(j+1)/τ_j) (exact for K ∝ τ^p; linear in τ over-read 1/τ by up to 12% between
/// doubling nodes). Below the first node (a round under 1/64 of its stencil: a 0.5 mm tool on
/// stencils above 32 mm) the first interval's power law goes on, K = K_0 (τ/τ_0)^(−p), with p held to
/// [0, 1] (a notch's peak stress grows at most as a crack's, 1/√ρ; a first interval that rises is
/// held at the first node): the star's and the cross's cells at 1/128 and 1/256 read within 4.2% of
/// it, but the cross's bending at α 0.9, whose exponent grows as its rounds shrink, 5% and 13% above
/// it (held at the first node, they read 1.5–4× above; DESIGN.md "W_peak by the tool"). Beyond 1/2 the last node is held (where no disc of the tool fits in the default
/// star: kept as drawn, as verify keeps it).
///
/// Thick plates. The factors are a Kirchhoff plate's. Where a hole is not large against the
/// shell's thickness h, the 3-D part's bending peak is higher: with a hole far smaller than h, each
/// layer of the plate carries its share of the moment in plane stress, so the rim's bending stress
/// concentrates as the membrane's does in the same hole (Reissner's theory: for a circular hole of
/// radius a in uniaxial bending the factor rises from Goodier's (5 + 3ν)/(3 + ν) = 1.79 at a ≫ h
/// towards Kirsch's 3). Roark's fit of Reissner's circular hole (Young & Budynas, Table 17.1;
/// ν = 0.3), K_t(x) = 1.79 + 0.25/(0.39 + x) + 0.81/(1 + x²) − 0.26/(1 + x³), x = 2a/h, gives the
/// transition
///     φ(x) = (K_t(x) − 1.79) / (3 − 1.79),   0.98 at x = 0, 0.38 at 1, 0.12 at 2.6, 0 as x → ∞
/// (thick_round_transition), and the bending factors become, in stress (√K) as the fit is,
///     K_b ← ((1 − φ) √K_b + φ √K_m)²,
/// K_m the membrane factor of the same cell at the same biaxiality node (a layer's in-plane stress
/// state is the moment's); the circle's fit by construction (K_b = Goodier², K_m = 9 give K_t(x)²).
/// For another hole, x = 2s/h with s the stencil's bounding radius — the hole's size, not the
/// radius of its rounds: 3-D elasticity (solvers/solid/solid_plate.h, quadratic tetrahedra) of the
/// default star cut by a tool of s/8, at 2s/h = 16, 8, 4, 2: the rule by 2s/h reads the face's peak
/// 1.8–6.1% low, the rule by 2r/h (r the rounds' radius) 15–47% high: the factor nears the
/// membrane's only once the plate is thick against the whole star. Rounds of s/16 and s/32 at
/// 2s/h = 2, 1, 0.5: the rule within −6% and +19% of the face's peak (high where the plate is
/// thicker), where Kirchhoff's factor read 23–39% low; their largest σ_tt through the depth is up
/// to 32% above the face's, and the rule up to 21% under it. On the circle the 3-D face reads 2–11%
/// below Roark's fit (its free face lowers the peak, which Reissner's plate theory does not see).
/// The worst over orientations and rim points of the blend is at most the blend of the worsts.
/// A face's stencils' scale is known through the factors by corner: at node e_c (the corner rule's
/// ε_c = g/s or the tool's τ_c = r/s, the corner radius ρ = g or r) the stencils are of bounding
/// radius s_c = ρ/e_c, so each node's bending factors are blended at φ_c = φ(2ρ/(e_c h)) (0 at
/// ε = 0, a stencil without bound), on the calibrated samples, and the map's slopes are those of
/// the blended curves; between nodes the factors interpolate as before (linear in ε between the
/// corner rule's nodes over-reads φ there: at most φ(2ρ/(ε_1 h)) ε/ε_1 against φ(2ρ/(ε h))).
/// Without factors by corner, or without a corner radius, the factors stay Kirchhoff's.
///
/// As an objective (structure.measure "peak", structural_objective.h): per face,
///     W_peak_t = a(α_t) W_t + b(α_t) M_t,   a = k_b q_b,   b = k_m q_m − k_b q_b,
/// with k the blended factors; a = 1, b = 0 at α = 1. The weights w (the cell filter's blend) do not
/// depend on the stencils, so ∂W_peak/∂α is the α-derivative of a and b plus a ∂W/∂α + b ∂M/∂α
/// (peak_energy_density_vjp); by state, k also depends on x and α through ρ:
/// ∂W_peak/∂(x, α) gains q_m w ∂K_m/∂ρ M ∂ρ^m + q_b w ∂K_b/∂ρ (W − M) ∂ρ^b.
#include <Eigen/Core>

#include "host/scene/load_case.h"
#include "solvers/objective/objective_terms.h"
#include "solvers/shell/fill_stiffness_map.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

/// The rule above in a line, for reports.
inline constexpr const char* kPeakEnergyDensityRule =
    "W_peak = K_m(alpha, rho_m) W_membrane + K_b(alpha, rho_b) W_bending per face, K = peak/mean energy density over "
    "a periodic cell's material from the cell problems (worst over orientations; with several shapes, per face a smooth "
    "maximum (16-norm) over the shapes that cover part of it, each ramped to 1 as its covered fraction goes to 0 over "
    "[0, 0.05]; at the face's biaxiality rho "
    "of stress and of moment: -1 pure shear, 0 uniaxial, 1 equibiaxial; the worst state's K for hinge bending and "
    "uncalibrated states; K ramps to 1 over alpha in [0.95, 1] "
    "and is 1 at alpha = 1; blended towards 1 where the cell filter says a face resolves its stencils; a shape with "
    "sharp corners read at mechanics.corner_radius over each stencil's scale: without a tool the rim within the "
    "minimum feature of its corners left out, with one (fabrication.tool_radius) the holes as the tool rounds them; "
    "the bending K raised towards the membrane K for the thick plate, K_b <- ((1 - phi) sqrt(K_b) + phi sqrt(K_m))^2, "
    "phi(2 s / thickness) from Roark's fit of Reissner's circular hole, s the stencils' bounding radius); max over "
    "material faces";
/// What reports say instead when the mechanics carries no concentration samples (W_peak null).
inline constexpr const char* kPeakEnergyDensityAbsent =
    "not computed: no concentration factors (mechanics.stiffness is not homogenised)";

/// δ of the ramp of K to 1 near α = 1 (above), and of a shape's covered fraction (K by shape).
inline constexpr double kConcentrationRamp = 0.05;
/// p of the smooth maximum over the shapes in a face (K by shape).
inline constexpr double kShapeNorm = 16;

/// K_m(α), K_b(α) of a calibrated curve.
class ConcentrationMap {
 public:
  /// No calibration: empty().
  ConcentrationMap() = default;
  /// From the curve's concentration samples; empty() when it has none. `thick_scale`: ρ/h, the
  /// corner radius the factors by corner are read at (MechanicsSettings::corner_radius) over the
  /// shell's thickness, for the thick-plate transition ("Thick plates" above; 0: Kirchhoff's
  /// factors). Throws InputError for samples of the wrong size or below 1, or a scale that is not
  /// finite and at least 0.
  explicit ConcentrationMap(const FillStiffnessCurve& curve, double thick_scale = 0);
  /// The map a model of `mechanics` and `material` reads W_peak with: its curve's factors, blended
  /// for the thick plate at ρ/h = corner_radius / thickness.
  static ConcentrationMap for_mechanics(const MechanicsSettings& mechanics, const Material& material);
  /// ρ/h of the thick-plate transition (0: Kirchhoff's factors: none asked for, or no factors by
  /// corner to blend).
  double thick_scale() const { return m_thick_scale; }

  bool empty() const { return m_worst.membrane.empty(); }
  /// True when the curve carries K by biaxiality (membrane and bending).
  bool by_biaxiality() const { return !m_worst.membrane_states.empty(); }
  /// True when the curve carries the factors of two or more shapes of its own
  /// (FillStiffnessCurve::shape_concentration), or of one whose factors change under the corner
  /// rule (a shape with singular corners): W_peak then reads them per face when it is given the
  /// shapes' cover (the rules by shape and by corner above).
  bool by_shape() const { return m_by_shape; }
  /// Number of shapes the factors by shape are indexed by (the library's; 0 without them).
  int num_shapes() const { return int(m_shapes.size()); }
  /// The worst state's K_m(α) with the ramp to 1 above (1 for α ≥ 1, and when empty()); dK_m/dα
  /// into `slope`.
  double membrane(double alpha, double* slope = nullptr) const { return apply(m_worst.membrane, alpha, slope); }
  double bending(double alpha, double* slope = nullptr) const { return apply(m_worst.bending, alpha, slope); }
  /// K_m(α, ρ) at biaxiality ρ ∈ [−1, 1] (clamped) with the ramp; the worst state's K_m(α) when
  /// !by_biaxiality(). dK/dα, dK/dρ into the slopes (either may be null).
  double membrane(double alpha, double rho, double* d_alpha, double* d_rho) const {
    return by_state(m_worst.membrane_states, m_worst.membrane, alpha, rho, d_alpha, d_rho, true);
  }
  double bending(double alpha, double rho, double* d_alpha, double* d_rho) const {
    return by_state(m_worst.bending_states, m_worst.bending, alpha, rho, d_alpha, d_rho, true);
  }
  /// Shape `shape`'s own factor, membrane or bending, *without* the ramp in α (the rule by shape
  /// ramps by the shape's covered fraction instead), at biaxiality `rho` (null: the worst state's)
  /// and the corner rule's radius `epsilon` (bounding radii, clamped to [0, 1]; the shape's ε = 0
  /// factors when the curve has none by corner), linear between the corner nodes — or, on a curve
  /// by the tool, the tool's radius τ (a power law between the nodes, the first interval's below
  /// 1/64 with its exponent held to [0, 1], held beyond 1/2); the worst over the shapes for a shape
  /// the curve has no factors of. Slopes as above, dK/dε into `d_epsilon` (the right interval's at
  /// a node, 0 beyond the last node and, on the corner rule, below the first); any may be null.
  double shape_factor(int shape, bool bending, double alpha, const double* rho, double epsilon, double* d_alpha,
                      double* d_rho, double* d_epsilon = nullptr) const;
  /// r_K(α), r_G(α) of the split (1 each without it, and for α ≥ 1), the α-slopes into `slope`.
  Eigen::Vector2d split_ratios(bool bending, double alpha, Eigen::Vector2d* slope = nullptr) const;
  /// The calibrated ratios ρ = g/α of the curve the factors came with (1 for α ≥ 1).
  double membrane_ratio(double alpha, double* slope = nullptr) const { return ratio(m_membrane_ratio, alpha, slope); }
  double bending_ratio(double alpha, double* slope = nullptr) const { return ratio(m_bending_ratio, alpha, slope); }

 private:
  /// One set of factors: the worst state's curves in α and, by biaxiality, one curve per node.
  struct Factors {
    MonotoneCurve membrane, bending;
    std::vector<MonotoneCurve> membrane_states, bending_states;
  };
  static double apply(const MonotoneCurve& k, double alpha, double* slope, bool ramp = true);
  static double ratio(const MonotoneCurve& r, double alpha, double* slope);
  static double by_state(const std::vector<MonotoneCurve>& nodes, const MonotoneCurve& worst, double alpha, double rho,
                         double* d_alpha, double* d_rho, bool ramp);
  /// One set per corner node (one, ε = 0, without the tables by corner); empty for a shape the
  /// curve has no factors of.
  using ShapeFactors = std::vector<Factors>;
  static double single(const Factors& f, bool bending, double alpha, const double* rho, double* d_alpha, double* d_rho);
  Factors m_worst;
  std::vector<ShapeFactors> m_shapes;  ///< by shape type
  std::vector<double> m_corner_nodes;   ///< ε of the nodes: corner_node(c), or tool_node(c) with m_tool
  bool m_tool = false;                  ///< the factors by corner are the tool's (FillStiffnessCurve::tool_cut)
  double m_thick_scale = 0;             ///< ρ/h of the thick-plate transition
  bool m_by_shape = false;
  MonotoneCurve m_membrane_ratio, m_bending_ratio;
  MonotoneCurve m_membrane_bulk, m_membrane_shear, m_bending_bulk, m_bending_shear;  ///< the split's r
};

/// φ(x) of the thick-plate transition ("Thick plates" above) at x = 2s/h ≥ 0: Roark's fit of
/// Reissner's circular hole, (K_t(x) − 1.79)/(3 − 1.79): 0.984 at x = 0, 0 as x → ∞; decreasing.
double thick_round_transition(double x);

/// True when the map of `mechanics` and `material` (ConcentrationMap::for_mechanics) reads its
/// factors by shape: W_peak then wants the shapes' covered fractions (ConcentrationMap::by_shape();
/// a thick plate's transition makes any factors by corner vary with the node).
bool concentration_by_shape(const MechanicsSettings& mechanics, const Material& material);

/// W_peak (#F, J/m²) of the rule above at positions x (#V×3) and fill ratios alpha (#F).
/// `weight` (#F in [0, 1], optional; null: all ones): how far each face is from resolving its
/// stencils. The factors are blended, K ← 1 + w_t (K − 1), so that a face that resolves the rim
/// of a hole itself (w = 0: the cell filter's blend b of solvers/shell/cell_filter.h, 0 where four
/// or more triangles span a stencil) is not concentrated a second time. Only K is blended: the
/// ratios r convert the model's W into perforated material's mean W and stay as they are.
/// `cover` (optional; #F × K.num_shapes() each): the stencils' cover of the faces by shape (K by
/// shape and by corner, above); used when K.by_shape(), and a face whose covered row sums to 0
/// takes the worst shape's factors. Precondition: !K.empty().
Eigen::VectorXd peak_energy_density(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                    const ConcentrationMap& K, const Eigen::VectorXd* weight = nullptr,
                                    const ShapeCover* cover = nullptr);

/// Per face the biaxiality ρ (above) of its membrane state (column 0) and of its bending state
/// (column 1; NaN without a shape-operator bend), #F×2, at fill ratios alpha; 0 for a face without
/// strain (curvature).
Eigen::MatrixX2d stress_biaxiality(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                   const ConcentrationMap& K);

/// For weights c (#F): Σ_t c_t ∂W_peak_t/∂x into d_positions (#V×3; rows of fixed vertices zero)
/// and Σ_t c_t ∂W_peak_t/∂α into d_alpha (#F), at fixed `weight`, and with `cover` (K by shape)
/// Σ_t c_t ∂W_peak_t/∂(cover) into d_cover (the same sizes as cover's; zeros where the rule by
/// shape does not apply). Any output may be null. The twin of energy_density_vjp for an objective
/// built on W_peak.
void peak_energy_density_vjp(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                             const ConcentrationMap& K, const Eigen::VectorXd* weight, const Eigen::VectorXd& c,
                             RowMatX3d* d_positions, Eigen::VectorXd* d_alpha, const ShapeCover* cover = nullptr,
                             ShapeCover* d_cover = nullptr);

}  // namespace cutwork::solvers
