#pragma once
/// The discrete shell of §5.1–§5.2 on one simulation mesh: elements, supports, loads, DOF numbering
/// and the assembly pattern — everything that is fixed while fill ratios and positions change.
///
/// Elements (indexed in this order by the assembly: membranes, then the bending elements of the
/// scene's bending model — MechanicsSettings::bending):
///   - one CST membrane per face (membrane_energy.h), scaled by g_m(α_f) (9);
///   - shape_operator (default): one bending element per face over the face and its edge neighbours
///     (shape_operator_energy.h), Kirchhoff's energy with the material's ν, scaled by g_b(α_f);
///   - hinge (the paper's model): one hinge per interior edge (hinge_energy.h), scaled by
///     √(g_b(α_i) g_b(α_j)) (10), and one clamp hinge per (face, edge) whose two edge vertices are
///     both clamped.
/// g_m, g_b are the fill stiffness rules of fill_stiffness_map.h: g(α) = α (the paper's, default) or
/// the homogenised stiffness of perforated material (mechanics.stiffness = Homogenised).
/// Under the isotropic split (FillStiffnessMap::split()) each membrane and each shape-operator bend
/// is two elements over the same nodes, its bulk part and its shear part, each with its own fill
/// factor: the first blocks of membranes and bends then hold the bulk parts, and the shear parts
/// follow the clamp hinges (membranes, then bends). Hinges and clamp hinges are never split.
/// On a square lattice (FillStiffnessMap::anisotropic()) each membrane and bend has a third part,
/// the anisotropic one of fill_stiffness_map.h, in the lattice's orientation at the face
/// (lattice_orientation()); those parts follow the shear parts (membranes, then bends).
///
/// Supports. A pinned vertex is fixed in space: its three DOFs are eliminated (the assembled system
/// is the reduced one over the free vertices); a pinned edge is a simple support (moment-free: a
/// face's patch across it is condensed like a free edge's). A clamp must also stop the surface from
/// rotating about the support line: for every face f with an edge (a, b) whose two vertices are
/// clamped, a ghost point continues the surface across the edge. With the shape operator, the ghost
/// takes the place of the neighbour node across (a, b) in f's patch and mirrors f's third vertex c
/// evenly across the edge (shape_operator_energy.h), so the patch holds the rest tangent plane along
/// the edge. With hinges, a one-sided clamp hinge (a, b, c, g) bends f against the fixed ghost g —
/// the mirror image of c across the edge in f's rest plane — with
/// the hinge area Ā = A_f/3 (the physical third of the hinge's diamond): with a fixed ghost, the
/// dihedral angle at a clamped edge is half that of the mirror-symmetric (w(−s) = w(s))
/// continuation, which carries twice the physical energy over twice the area, hence
/// k = (D/6)|ē|²/(A_f/3). An interior edge with both vertices clamped is a clamped boundary on each
/// side (ghosts on both sides; no ordinary hinge). A clamped vertex without a clamped neighbour along
/// an edge cannot hold a rotation and acts as a pin. The plate tests
/// (tests/solvers/equilibrium/plate_theory_test.cpp) check both constructions against Kirchhoff.
/// A clamp hinge is scaled by its face's α_f (its ghost half carries no material).
/// A symmetry plane (LoadCase::symmetry_axes) holds its vertices along the plane's normal only (they
/// slide in it, as held_axes do) and mirrors the slope: across a boundary edge whose two vertices lie
/// on one plane, the shape-operator patch takes the mirror image of f's third vertex in the plane as
/// its ghost — the current position reflected, so the ghost moves with the structure — which is the
/// neighbour the whole, symmetric structure would have there under a symmetric deformation: a half
/// model on a mesh whose mirror image completes it solves the whole to round-off
/// (tests/solvers/equilibrium/symmetry_plane_test.cpp). The hinge model refuses symmetry planes.
/// The rigid-motion check counts a mirrored edge as holding the rotations about the two axes in its
/// plane.
///
/// Loads: LoadCase::forces are dead loads (N per vertex, constant in x and α); self-weight of face
/// t is α_t ρ h A_t g, lumped equally to its three vertices (a stencil removes mass as well as
/// stiffness). Loads on supported vertices go to the support and do no work.
///
/// DOF numbering: the free vertices, in vertex order, are nodes 0..n−1; node k owns free DOFs
/// 3k, 3k+1, 3k+2 (x, y, z). Positions are #V×3 row-major arrays (metres) in vertex order.
#include <array>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "host/mesh/surface_mesh.h"
#include "host/scene/load_case.h"
#include "solvers/linear/block_assembly.h"
#include "solvers/shell/fill_stiffness_map.h"
#include "solvers/shell/hinge_energy.h"
#include "solvers/shell/membrane_energy.h"
#include "solvers/shell/shape_operator_energy.h"
#include "solvers/shell/shell_material.h"

namespace cutwork::solvers {

/// Ordinary bending hinge between faces face[0] and face[1] (vertex order of cutwork::Hinge).
struct ShellHinge {
  int v[4] = {-1, -1, -1, -1};
  int face[2] = {-1, -1};
  HingeRest rest;
};

/// One-sided clamp hinge: face `face` = (v[0], v[1], v[2]) in face order, bending about the clamped
/// edge (v[0], v[1]) against the fixed ghost point `ghost`.
struct ClampHinge {
  int v[3] = {-1, -1, -1};
  int face = -1;
  Vec3 ghost = Vec3::Zero();
  HingeRest rest;
};

/// Shape-operator bending element of face `face`: patch vertices in the DOF order of
/// shape_operator_energy.h (v[3+i] = −1 across a free or clamped edge: rest.across says which).
struct ShellBend {
  int v[6] = {-1, -1, -1, -1, -1, -1};
  int face = -1;
  ShapeOperatorRest rest;
};

enum class ElementKind { Membrane, Bend, Hinge, Clamp };

/// An element of the model: its kind, its index among the elements of that kind, and the part of
/// it that the element is (the whole, or its bulk or shear part under the isotropic split).
struct ElementRef {
  ElementKind kind;
  int index;
  FillPart part = FillPart::Whole;
};

/// Per-element energies at unit fill ratio (J), indexed like the model's elements: A Ψ per membrane,
/// the bending energy per shape-operator element, k(θ−θ̄)² per hinge and clamp hinge. The stencilled
/// energies are these times the element's fill factor (element_fill_factor in shell_energy.h).
using ElementEnergies = Eigen::VectorXd;

class ShellModel {
 public:
  /// Builds the shell. `load_case` must have #V entries in fixed/clamped (or be empty: none) and
  /// #V×3 forces (or 0 rows: none); a clamped vertex is fixed as well.
  /// Throws InputError for a load case that does not match the mesh or a bad material, and
  /// SolveError, with a message naming the problem, for:
  ///   - an unconstrained model: no fixed vertex at all, or a connected part of the mesh without
  ///     support or with only collinear, unclamped supports (a rigid motion is possible);
  ///   - non-finite forces or gravity;
  ///   - a load case that loads no free vertex (zero load) or loads a vertex of no face.
  ShellModel(const SurfaceMesh& mesh, const Material& material, const LoadCase& load_case,
             const MechanicsSettings& mechanics = {});

  const SurfaceMesh& mesh() const { return *m_mesh; }
  const Material& material() const { return m_material; }
  const ShellStiffness& stiffness() const { return m_stiffness; }
  const MechanicsSettings& mechanics() const { return m_mechanics; }
  /// How membrane and bending stiffness follow a face's fill ratio (mechanics.stiffness).
  const FillStiffnessMap& fill_stiffness() const { return m_fill_stiffness; }
  /// Replaces the homogenised rule's calibrated curve (StencilledShell: the shapes reweighted by a
  /// new set of stencils); the next assembly uses it. Throws InputError for a curve
  /// FillStiffnessMap refuses, leaving the model unchanged.
  void set_stiffness_curve(FillStiffnessCurve curve);
  /// Ĉ of shape_operator_energy.h for the material's ν, or its bulk or shear part:
  /// ((1 + ν)/2) [1 1 0; 1 1 0; 0 0 0] and (1 − ν) [½ −½ 0; −½ ½ 0; 0 0 2], which add up to Ĉ.
  const Eigen::Matrix3d& bending_constitutive(FillPart part = FillPart::Whole) const {
    return m_bending_constitutive[int(part == FillPart::Anisotropy ? FillPart::Whole : part)];
  }
  /// Ĉ of one part of face f's bend: bending_constitutive(part), or for the anisotropic part
  /// (1 − ν) [c/2 −c/2 s; −c/2 c/2 −s; s −s −2c], (c, s) = lattice_orientation()[f]
  /// (kᵀĈ_A k = 2(1 − ν)[c(e₁² − e₂²) + 2s e₁e₂], e₁ = (k₁₁ − k₂₂)/2, e₂ = k₁₂).
  Eigen::Matrix3d bending_part_constitutive(FillPart part, int face) const;
  /// Voigt matrix (N/m; strains E₁₁, E₂₂, 2E₁₂ in face f's rest frame) of one part of f's membrane:
  /// whole membrane_constitutive(μ, λ); bulk (μ + λ)[1 1 0; 1 1 0; 0 0 0]; shear μ[1 −1 0; −1 1 0;
  /// 0 0 1]; anisotropic μ[c −c s; −c c −s; s −s −c] (Ψ_A = 2μ[c(e₁² − e₂²) + 2s e₁e₂]).
  Eigen::Matrix3d membrane_part_constitutive(FillPart part, int face) const;
  /// #F: (cos 4φ, sin 4φ) with φ the angle of the square lattice's axis (mechanics.lattice_axis,
  /// projected onto the face) from the first axis of the face's rest frame (X1 − X0, the frame of
  /// both elements); zero where the axis is normal to the face (within 1e-3) and without anisotropy.
  const std::vector<Eigen::Vector2d>& lattice_orientation() const { return m_lattice_orientation; }
  /// The membrane's (μ, λ) (N/m) of ShellStiffness, or of its bulk part (0, μ + λ): ((μ + λ)/2) tr(E)²,
  /// or its shear part (μ, −μ): μ |dev E|². The anisotropic part has no Lamé form
  /// (membrane_part_constitutive): asking for one throws InternalError.
  std::array<double, 2> membrane_lame(FillPart part = FillPart::Whole) const;
  const LoadCase& load_case() const { return m_load_case; }

  int num_vertices() const { return m_mesh->num_vertices(); }
  int num_faces() const { return m_mesh->num_faces(); }
  /// Free vertices (nodes) and free DOFs (3 per node).
  int num_nodes() const { return int(m_node_vertex.size()); }
  int num_dofs() const { return 3 * num_nodes(); }
  /// #V: node of each vertex, −1 for a fixed or unreferenced vertex.
  const std::vector<int>& vertex_node() const { return m_vertex_node; }
  /// #nodes: vertex of each node.
  const std::vector<int>& node_vertex() const { return m_node_vertex; }
  /// #V: true where the vertex is fixed (pinned or clamped, or held along all three axes).
  const std::vector<bool>& fixed() const { return m_fixed; }
  /// Free DOFs held at rest by supports along some axes only (LoadCase::held_axes), ascending. Such a
  /// vertex is a node; its held DOFs stay in the system decoupled: assemble_shell zeroes their
  /// gradient entries and their Hessian rows and columns but the diagonal (hold_in_hessian), and
  /// every right-hand side (loads, adjoint) is zeroed there (zero_held), so Newton steps and adjoint
  /// solutions are zero along them — the exact constraint, as elimination would give.
  const std::vector<int>& held_dofs() const { return m_held_dofs; }
  /// Zeroes the held DOFs of a free-DOF vector (a force, a residual, an adjoint right-hand side).
  void zero_held(Eigen::VectorXd& free) const;
  /// Decouples the held DOFs in Hessian values of assembly(): rows and columns zero, the diagonal
  /// kept (1 where it is not positive).
  void hold_in_hessian(std::vector<double>& values) const;

  /// Rest positions X (#V×3, m).
  const RowMatX3d& rest_positions() const { return m_mesh->vertices(); }
  /// Diagonal of the rest bounding box (m): the model size of the displacement limit.
  double model_size() const { return m_model_size; }

  const std::vector<MembraneRest>& membranes() const { return m_membranes; }
  const std::vector<ShellBend>& bends() const { return m_bends; }
  const std::vector<ShellHinge>& hinges() const { return m_hinges; }
  const std::vector<ClampHinge>& clamp_hinges() const { return m_clamps; }
  int num_elements() const {
    const std::size_t parts = m_membranes.size() + m_bends.size();
    const std::size_t extra = (m_fill_stiffness.split() ? parts : 0) + (m_fill_stiffness.anisotropic() ? parts : 0);
    return int(m_membranes.size() + m_bends.size() + m_hinges.size() + m_clamps.size() + extra);
  }
  /// Kind, index and part of element e ∈ [0, num_elements()): membranes, bends, hinges, clamp
  /// hinges; under the split, the membranes' and the bends' shear parts after them, then (square
  /// lattice) their anisotropic parts.
  ElementRef element(int e) const {
    const int nf = int(m_membranes.size()), nb = int(m_bends.size()), nh = int(m_hinges.size()),
              nc = int(m_clamps.size());
    const FillPart first = m_fill_stiffness.split() ? FillPart::Bulk : FillPart::Whole;
    if (e < nf) return {ElementKind::Membrane, e, first};
    if (e < nf + nb) return {ElementKind::Bend, e - nf, first};
    if (e < nf + nb + nh) return {ElementKind::Hinge, e - nf - nb};
    if (e < nf + nb + nh + nc) return {ElementKind::Clamp, e - nf - nb - nh};
    e -= nf + nb + nh + nc;
    if (e < nf) return {ElementKind::Membrane, e, FillPart::Shear};
    if (e < nf + nb) return {ElementKind::Bend, e - nf, FillPart::Shear};
    e -= nf + nb;
    if (e < nf) return {ElementKind::Membrane, e, FillPart::Anisotropy};
    return {ElementKind::Bend, e - nf, FillPart::Anisotropy};
  }

  /// Pattern, scatter map and colouring of the reduced Hessian (built once).
  const BlockAssembly& assembly() const { return m_assembly; }

  /// External forces f_ext(α) (#V×3, N): dead loads plus α-scaled self-weight, with the loads
  /// spread over the surface (LoadCase::surface_loads) carried by the material: each face's share
  /// in proportion to α_t a_t, each load's total unchanged. Rows of fixed vertices included (they do
  /// no work).
  RowMatX3d external_forces(const Eigen::VectorXd& alpha) const;
  /// Adds v · ∂f_ext/∂α_t to out[t] (#F) for a #V×3 array v (pass zeros in rows that should not
  /// count): self-weight's ρ h A_t g / 3 per vertex, and each surface load's
  /// ∂f/∂α_t = s F_t − (a_t / Σ α a) f (not local: a face that loses material moves its share of
  /// the load onto the others).
  void add_load_alpha_product(const RowMatX3d& v, const Eigen::VectorXd& alpha, Eigen::VectorXd& out) const;
  /// s = Σ a_t / Σ α_t a_t of a surface load at fill ratios α: f = s Σ α_t F_t.
  static double surface_load_scale(const SurfaceLoad& load, const Eigen::VectorXd& alpha);
  /// ∂f_ext/∂α_t per face: the self-weight ρ h A_t g / 3 that face t puts on each of its vertices
  /// (N per unit fill ratio). Zero without gravity.
  Vec3 self_weight_per_vertex_and_alpha(int face) const;

  /// Free-DOF vector (#DOF) of the free rows of a #V×3 array, and back (fixed rows untouched).
  Eigen::VectorXd gather_free(const RowMatX3d& values) const;
  void scatter_free(const Eigen::VectorXd& free, RowMatX3d& values) const;

  /// Throws InputError unless alpha has #F finite entries > 0 (the fill kernel clamps at 1e-4).
  void check_fill_ratios(const Eigen::VectorXd& alpha) const;

 private:
  bool edge_clamped(int a, int b) const;
  /// The axis of a symmetry plane both a and b lie on (LoadCase::symmetry_axes), or −1.
  int edge_mirror_axis(int a, int b) const;
  void build_bends();
  void build_hinges();

  std::shared_ptr<const SurfaceMesh> m_mesh;
  Material m_material;
  ShellStiffness m_stiffness;
  MechanicsSettings m_mechanics;
  FillStiffnessMap m_fill_stiffness;
  std::array<Eigen::Matrix3d, 3> m_bending_constitutive;  ///< by FillPart
  LoadCase m_load_case;
  std::vector<bool> m_fixed;
  std::vector<int> m_held_dofs;
  std::vector<long> m_held_diagonal, m_held_coupling;  ///< value slots of assembly() (hold_in_hessian)
  std::vector<int> m_vertex_node;
  std::vector<int> m_node_vertex;
  double m_model_size = 0;
  std::vector<MembraneRest> m_membranes;
  std::vector<ShellBend> m_bends;
  std::vector<ShellHinge> m_hinges;
  std::vector<ClampHinge> m_clamps;
  std::vector<Eigen::Vector2d> m_lattice_orientation;
  BlockAssembly m_assembly;
};

}  // namespace cutwork::solvers
