#pragma once
/// Total elastic energy (11) of a ShellModel, Ŵ(x, α) = Σ_e s_e(α) U_e(x), with U_e the energy of
/// element e at unit fill ratio and s_e its fill factor (g_m(α_f) for membranes, g_b(α_f) for
/// shape-operator bends and clamp hinges, √(g_b(α_i) g_b(α_j)) for hinges (10); g(α) = α under the
/// paper's linear rule; under the isotropic split the bulk and shear parts of membranes and bends
/// — and on a square lattice their anisotropic parts, whose U_e can be negative — are elements of
/// their own with their own g, see fill_stiffness_map.h), with its gradient and Hessian over the
/// free DOFs, assembled in parallel (TBB) into the fixed pattern of ShellModel::assembly(). Results
/// do not depend on the number of threads.
///
/// Every consumer of elements (assembly, energy density, fill-ratio partials) goes through one
/// dispatch, visit_element(), and one fill-factor rule, element_fill_factor() /
/// for_each_fill_dependence(), so a new element kind is added in one place.
///
/// x: #V×3 positions (m), rows of fixed vertices equal to their rest positions; alpha: #F fill
/// ratios. Energies in J, gradients in N, Hessian entries in N/m.
#include <array>
#include <vector>

#include <Eigen/Core>

#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

/// What an element evaluation must produce.
enum class ElementNeed { Energy, Gradient, Hessian };

/// One element's local quantities in its DOF order (K nodes): energy, and, as requested, gradient
/// and Hessian. vertex[a] is the mesh vertex of local node a, −1 for a ghost or unused node.
template <int K>
struct ElementLocal {
  std::array<int, K> vertex;
  double energy = 0;
  Eigen::Matrix<double, 3 * K, 1> gradient;
  Eigen::Matrix<double, 3 * K, 3 * K> hessian;
};

/// Evaluates element e of `model` at positions x with the energy multiplied by `scale` (1: unit fill
/// ratio), and calls visit(const ElementLocal<K>&) once, K = 3 (membrane), 6 (shape-operator bend)
/// or 4 (hinge, clamp hinge).
template <typename Visit>
void visit_element(const ShellModel& model, const RowMatX3d& x, int e, double scale, ElementNeed need,
                   Visit&& visit);

/// Under the isotropic split: the membrane or bend whose bulk part is element e, whole, with each
/// part (bulk, shear and, on a square lattice, anisotropic) scaled by its fill factor at `alpha` —
/// one evaluation of all parts (the energy is linear in the constitutive constants), which the
/// assembly uses in place of the part elements.
template <typename Visit>
void visit_split_element(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha, int e,
                         ElementNeed need, Visit&& visit);

/// s_e(α) of element e.
double element_fill_factor(const ShellModel& model, const Eigen::VectorXd& alpha, int e);
/// Calls visit(face, ∂s_e/∂α_face) for every face whose fill ratio s_e depends on, in a fixed order.
template <typename Visit>
void for_each_fill_dependence(const ShellModel& model, const Eigen::VectorXd& alpha, int e, Visit&& visit);

/// Ŵ(x, α) (J). When `unit` is given it receives U_e for every element (ShellModel's element order).
/// Returns +inf when an element is degenerate (a collapsed triangle makes its normal undefined),
/// which a line search treats as a rejected step.
double shell_energy(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                    ElementEnergies* unit = nullptr);

/// Buffers of one assembly, reused between calls to avoid reallocation.
struct ShellAssembly {
  double energy = 0;              ///< Ŵ (J)
  Eigen::VectorXd gradient;       ///< #DOF: ∂Ŵ/∂x on the free DOFs (N)
  std::vector<double> hessian;    ///< nnz: upper triangle of ∂²Ŵ/∂x² (N/m), in assembly() order
  std::vector<double> element_energy;  ///< per element, scaled by its fill factor
};

/// Energy and gradient, plus the Hessian values when with_hessian.
void assemble_shell(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                    bool with_hessian, ShellAssembly& out);

/// Σ_e weight_e ∂U_e/∂x over the free DOFs (#DOF): a weighted sum of unit element gradients, as the
/// energy-density objectives and the adjoint's ∂f/∂α products need. Deterministic.
Eigen::VectorXd weighted_element_gradient(const ShellModel& model, const RowMatX3d& x,
                                          const Eigen::VectorXd& weight);

/// Local position vectors of the elements.
Vec9 membrane_positions(const ShellModel& model, const RowMatX3d& x, int face);
Vec18 bend_positions(const ShellBend& bend, const RowMatX3d& x);
Vec12 hinge_positions(const ShellHinge& hinge, const RowMatX3d& x);
Vec12 clamp_positions(const ClampHinge& clamp, const RowMatX3d& x);
/// √(g_b(α_i) g_b(α_j)) of a hinge (√(α_i α_j) under the linear rule).
double hinge_fill_factor(const ShellModel& model, const ShellHinge& hinge, const Eigen::VectorXd& alpha);

// ---- implementation of the templates -------------------------------------------------------------

namespace detail {

/// Membrane `index` with Lamé parameters (N/m) `lame`, energy times `scale`.
template <typename Visit>
void visit_membrane(const ShellModel& model, const RowMatX3d& x, int index, const std::array<double, 2>& lame,
                    double scale, ElementNeed need, Visit&& visit) {
  ElementLocal<3> l;
  for (int a = 0; a < 3; ++a) l.vertex[a] = model.mesh().faces()(index, a);
  membrane_energy_gradient_hessian(membrane_positions(model, x, index), model.membranes()[index], lame[0], lame[1],
                                   scale, &l.energy, need != ElementNeed::Energy ? &l.gradient : nullptr,
                                   need == ElementNeed::Hessian ? &l.hessian : nullptr);
  visit(l);
}

/// Membrane `index` with a general Voigt constitutive matrix C (N/m) in its rest frame.
template <typename Visit>
void visit_membrane_general(const ShellModel& model, const RowMatX3d& x, int index, const Eigen::Matrix3d& C,
                            double scale, ElementNeed need, Visit&& visit) {
  ElementLocal<3> l;
  for (int a = 0; a < 3; ++a) l.vertex[a] = model.mesh().faces()(index, a);
  membrane_energy_gradient_hessian(membrane_positions(model, x, index), model.membranes()[index], C, scale, &l.energy,
                                   need != ElementNeed::Energy ? &l.gradient : nullptr,
                                   need == ElementNeed::Hessian ? &l.hessian : nullptr);
  visit(l);
}

/// Shape-operator bend `index` with constitutive matrix C (dimensionless), energy times scale · D.
template <typename Visit>
void visit_bend(const ShellModel& model, const RowMatX3d& x, int index, const Eigen::Matrix3d& C, double scale,
                ElementNeed need, Visit&& visit) {
  const ShellBend& b = model.bends()[index];
  ElementLocal<6> l;
  for (int a = 0; a < 6; ++a) l.vertex[a] = b.v[a];
  shape_operator_energy_gradient_hessian(bend_positions(b, x), b.rest, C, scale * model.stiffness().bending, &l.energy,
                                         need != ElementNeed::Energy ? &l.gradient : nullptr,
                                         need == ElementNeed::Hessian ? &l.hessian : nullptr);
  visit(l);
}

}  // namespace detail

template <typename Visit>
void visit_split_element(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha, int e,
                         ElementNeed need, Visit&& visit) {
  const ElementRef ref = model.element(e);
  const bool bend = ref.kind == ElementKind::Bend;
  const double a = alpha[bend ? model.bends()[size_t(ref.index)].face : ref.index];
  const FillStiffnessMap& g = model.fill_stiffness();
  const double bulk = g.factor(bend, FillPart::Bulk, a), shear = g.factor(bend, FillPart::Shear, a);
  const bool aniso = g.anisotropic();
  if (!bend && !aniso) {
    const std::array<double, 2> b = model.membrane_lame(FillPart::Bulk), s = model.membrane_lame(FillPart::Shear);
    detail::visit_membrane(model, x, ref.index, {bulk * b[0] + shear * s[0], bulk * b[1] + shear * s[1]}, 1.0, need,
                           visit);
  } else if (!bend) {
    const int f = ref.index;
    const Eigen::Matrix3d C = bulk * model.membrane_part_constitutive(FillPart::Bulk, f) +
                              shear * model.membrane_part_constitutive(FillPart::Shear, f) +
                              g.factor(false, FillPart::Anisotropy, a) *
                                  model.membrane_part_constitutive(FillPart::Anisotropy, f);
    detail::visit_membrane_general(model, x, f, C, 1.0, need, visit);
  } else {
    Eigen::Matrix3d C =
        bulk * model.bending_constitutive(FillPart::Bulk) + shear * model.bending_constitutive(FillPart::Shear);
    if (aniso) {
      const int f = model.bends()[size_t(ref.index)].face;
      C += g.factor(true, FillPart::Anisotropy, a) * model.bending_part_constitutive(FillPart::Anisotropy, f);
    }
    detail::visit_bend(model, x, ref.index, C, 1.0, need, visit);
  }
}

template <typename Visit>
void visit_element(const ShellModel& model, const RowMatX3d& x, int e, double scale, ElementNeed need,
                   Visit&& visit) {
  const bool want_g = need != ElementNeed::Energy, want_h = need == ElementNeed::Hessian;
  const ElementRef ref = model.element(e);
  switch (ref.kind) {
    case ElementKind::Membrane:
      if (ref.part == FillPart::Anisotropy)
        detail::visit_membrane_general(model, x, ref.index, model.membrane_part_constitutive(ref.part, ref.index), scale,
                                       need, visit);
      else
        detail::visit_membrane(model, x, ref.index, model.membrane_lame(ref.part), scale, need, visit);
      return;
    case ElementKind::Bend:
      detail::visit_bend(model, x, ref.index,
                         model.bending_part_constitutive(ref.part, model.bends()[size_t(ref.index)].face), scale, need,
                         visit);
      return;
    case ElementKind::Hinge: {
      const ShellHinge& h = model.hinges()[ref.index];
      ElementLocal<4> l;
      for (int a = 0; a < 4; ++a) l.vertex[a] = h.v[a];
      hinge_energy_gradient_hessian(hinge_positions(h, x), h.rest, scale, &l.energy, want_g ? &l.gradient : nullptr,
                                    want_h ? &l.hessian : nullptr);
      visit(l);
      return;
    }
    case ElementKind::Clamp: {
      const ClampHinge& c = model.clamp_hinges()[ref.index];
      ElementLocal<4> l;
      l.vertex = {c.v[0], c.v[1], c.v[2], -1};
      hinge_energy_gradient_hessian(clamp_positions(c, x), c.rest, scale, &l.energy, want_g ? &l.gradient : nullptr,
                                    want_h ? &l.hessian : nullptr);
      visit(l);
      return;
    }
  }
}

template <typename Visit>
void for_each_fill_dependence(const ShellModel& model, const Eigen::VectorXd& alpha, int e, Visit&& visit) {
  const ElementRef ref = model.element(e);
  const FillStiffnessMap& g = model.fill_stiffness();
  double d = 0;
  switch (ref.kind) {
    case ElementKind::Membrane: g.factor(false, ref.part, alpha[ref.index], &d); visit(ref.index, d); return;
    case ElementKind::Bend: {
      const int f = model.bends()[ref.index].face;
      g.factor(true, ref.part, alpha[f], &d);
      visit(f, d);
      return;
    }
    case ElementKind::Hinge: {
      // s = √(g_i g_j): ∂s/∂α_i = s g_i' / (2 g_i).
      const ShellHinge& h = model.hinges()[ref.index];
      const double s = hinge_fill_factor(model, h, alpha);
      for (int side = 0; side < 2; ++side) {
        const double gi = g.bending(alpha[h.face[side]], &d);
        visit(h.face[side], s * d / (2.0 * gi));
      }
      return;
    }
    case ElementKind::Clamp: {
      const int f = model.clamp_hinges()[ref.index].face;
      g.bending(alpha[f], &d);
      visit(f, d);
      return;
    }
  }
}

}  // namespace cutwork::solvers
