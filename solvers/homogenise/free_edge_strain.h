#pragma once
/// Stress at a free edge (a hole's rim) recovered from the nodal displacements of a flat membrane
/// of constant-strain triangles (issue 21 item 5).
///
/// Why. A constant-strain triangle reports the mean strain over its area, so the largest face
/// energy density next to a rim lags the rim's own value by the stress gradient times a third of
/// the face's depth (at Kirsch's rim, σ_θθ falls by 7σ∞/a per unit distance: a 2% stress deficit for
/// a face 0.03a deep). The rim itself is better measured along its edges: a free edge carries no
/// normal or shear traction (σ_nn = σ_nt = 0), so its stress is uniaxial along the tangent,
/// σ_tt = E ε_tt, and ε_tt along a boundary edge (a → b) is exact for the linear displacement of its
/// face, ε_tt = t·(u_b − u_a)/|X_b − X_a|, t the unit edge direction: the chord's strain, the mean
/// tangential strain over the edge, one-dimensional averaging over a length h instead of the
/// face's two-dimensional averaging over its depth. The energy density there is then
/// W = σ_tt² h/(2E) = ½ E h ε_tt² (J/m², h the thickness).
///
/// Small-strain (linear) recovery: u is a displacement small against the edge lengths.
#include <vector>

#include "host/core/types.h"
#include "host/scene/load_case.h"

namespace cutwork::solvers {

/// One boundary edge of a mesh and its tangential strain.
struct FreeEdgeStrain {
  int face = -1;     ///< the face the edge bounds
  int a = -1, b = -1;///< its vertices, in the face's order
  double strain = 0; ///< ε_tt (dimensionless)
};

/// The boundary edges (used by exactly one face of F) of the faces [first_face, first_face +
/// num_faces) (num_faces < 0: to the end) and their tangential strains under displacement u.
/// X: #V×3 rest positions (m); F: #F×3; u: #V×3 displacements (m).
std::vector<FreeEdgeStrain> free_edge_strains(const RowMatX3d& X, const RowMatX3i& F, const RowMatX3d& u,
                                              int first_face = 0, int num_faces = -1);

/// The energy density (J/m²) of a free edge with tangential strain ε, normal curvature κ_tt and
/// twist κ_tm (1/m): ½ E h ε² + ½ D (1 − ν²) κ_tt² + D (1 − ν) κ_tm², D = E h³/(12 (1 − ν²)). A free
/// edge carries no N_nn, N_nt, M_nn: the stress is uniaxial along it (σ_tt = E ε_tt, M_tt = D (1 − ν²)
/// κ_tt with κ_nn = −ν κ_tt) and the twist's moment is M_tm = D (1 − ν) κ_tm.
double free_edge_energy_density(const Material& material, double strain, double curvature = 0, double twist = 0);

}  // namespace cutwork::solvers
