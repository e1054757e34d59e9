#pragma once
/// Cell filtering of fill ratios (issue 21, item 4): what a face's stiffness sees when the
/// simulation triangles are as large as the stencils or larger.
///
/// A face's own fill ratio α_t is the fraction of that triangle the stencils leave. Where a
/// triangle is about the size of a stencil, α_t jumps between nearly 0 and nearly 1 from face
/// to face along a regular perforation, and a mesh of stiff and soft faces side by side carries
/// load around the soft ones: it is stiffer than the perforated sheet whose material fraction it
/// has (the issue measured a cantilever perforated by 12 mm holes on a 20 mm lattice: 11–19% too
/// stiff at 10–20 mm triangles, even with the homogenised g(α) of cell_homogenisation.h, which is
/// exact for a uniform perforation). The homogenised stiffness is a property of the stencil's
/// cell — the stencil plus its share of the ligaments — so the fill ratio it is evaluated at must
/// be the cell's porosity, not the triangle's.
///
/// The filter. ᾱ = B α with B a fixed sparse #F×#F matrix, built once per simulation mesh:
///
///     (B α)_t = (1 − b_t) α_t + b_t Σ_s w_ts α_s / Σ_s w_ts,
///     w_ts = A_s (1 − |c_s − c_t| / R_t)₊,      R_t = max(a_t, h_t),
///     b_t = smoothstep((h_t/d_t − ¼) / ¾)   (0 for h_t ≤ d_t/4, 1 for h_t ≥ d_t),
///
/// c_t the centroid and A_t the area of face t, h_t = √(4 A_t/√3) its equilateral edge length,
/// a_t the local stencil spacing (centre to centre) and d_t the local stencil's hydraulic
/// diameter 4A/P at the face (A its area, P its perimeter: its diameter for a circle, 0.44 of its
/// bounding diameter for the default five-pointed star; scene_cell_filter takes the library's
/// narrowest shape). The sum runs over the faces reached from t across edges whose centroids lie within R_t
/// (the neighbourhood is connected on the surface: two sheets close in space do not mix). The
/// cone of radius one spacing averages over about one cell (its support holds π a² ≈ 3.6 cells
/// of a hexagonal lattice, weighted towards the centre); R_t ≥ h_t makes the average reach the
/// neighbouring faces when triangles are larger than a cell. Where triangles resolve the
/// stencils (four or more across d_t) b_t = 0 and the face keeps its own α_t: the mesh then
/// resolves the holes and the ligaments itself. Why 4A/P and not the bounding diameter: the faces
/// a stencil's outline cuts, whose own α is neither hole nor material, lie in a band about h wide
/// along its perimeter, a fraction ~4h/(4A/P) of its area; a star has the perimeter of a much
/// smaller circle. Measured (perforated-lattice suite, hexagonal stars at α 0.67, cell-filtered
/// at ¼ / ½ / 0.8 bounding diameters): 0.854 / 0.981 / 0.964 against the bounding diameter's
/// 0.776 / 0.841 / 0.947 (0.877 / 1.006 / 0.995 with the star's calibration sampled at its lowest
/// α too, fill_stiffness_calibration.h); circles are unchanged (4A/P of the 64-gon is 0.9988 of
/// its diameter). Below ¼ bounding diameter the star's triangles are still too stiff (0.877 at ¼,
/// the per-face rule 0.843 at ⅛): a face's own α needs triangles narrower than the ligaments between the
/// tips, which depend on the layout, not on the shape (docs/DESIGN.md, "Below one diameter").
///
/// At a clamped support the filter stops, both ways (scene_cell_filter marks the faces with a
/// clamped vertex): a marked face keeps its own α, and no other face's cone counts a marked face.
/// Homogenisation assumes each cell free to deform periodically; a clamp holds the cells next to
/// it, and the material between the clamp and the first holes is solid. So (1) the cone's average
/// over the cells inside — softer — is the wrong stiffness for the faces at the clamp, exactly where
/// a clamped plate or a cantilever's root stores most of its energy, and (2) the clamp's solid
/// margin is no part of the lattice's cells further in: the faces at the clamp carry it already,
/// and counted again in the cones of the faces next to them it made the first cells in from the
/// clamp stiffer than the lattice is. Measured on the perforated-lattice suite (circles, hexagonal,
/// α 0.5; coarse / conforming over the uncut plate's own coarse error, ½ d / 1 d / 2 d): the plate
/// clamped all round 0.987 / 1.050 / 1.066 filtered through the clamps, 0.948 / 0.929 / 0.988 with
/// (1) alone, 0.972 / 0.966 / 0.993 with both; the cantilever 0.993 / 1.022 / 1.010, 0.990 / 1.007 /
/// 1.003, 0.993 / 1.013 / 1.007 (docs/DESIGN.md, "At a clamp the filter stops"). Filtering across
/// free or pinned borders is left as it is: stopped there as at clamps, own α alone moved the
/// cantilever to 0.980 / 1.001, and both ways it helped the square lattice pulled at 45° by 4% and
/// cost the bent hexagonal plates 1–2% (measured, not adopted).
///
/// Across a symmetry plane (the mesh a half model's, LoadCase::symmetry_axes) the filter does not
/// stop: the cone reaches into the mirror image, whose faces are the half's own reflected (the
/// design is symmetric), so the faces beside the plane average over the same cell as the whole's
/// do (CellFilter.AHalfOnASymmetryPlaneFiltersAsTheWhole, to round-off).
///
/// B is a convex combination per row, so ᾱ ∈ [min α, max α] and B·1 = 1 (an uncut shell is
/// unchanged). It does not depend on the stencils (a_t, d_t are the pattern's nominal spacing
/// and size, not the current stencils'), so dᾱ/dp = B dα/dp exactly and a gradient pulls back
/// through Bᵀ. B does not conserve Σ A α exactly near borders and where the faces' sizes change
/// (the row weights are normalised per row); the area a design removes is measured with the
/// unfiltered α.
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "host/mesh/surface_mesh.h"

namespace cutwork::solvers {

class CellFilter {
 public:
  /// The identity (no filtering).
  CellFilter() = default;
  /// The filter of the file comment on `mesh`, with the local stencil spacing `spacing` (#F, m,
  /// > 0) and the stencil's hydraulic diameter `diameter` (#F, m, > 0: d_t of the file comment)
  /// at each face; the faces marked in
  /// `keep_own` (#F, optional) keep their own α (b_t = 0) and are left out of every other face's
  /// average (a column of B with its diagonal entry only). Throws InputError for sizes that do not
  /// match or values that are not finite and positive.
  /// `mirror_planes` (LoadCase::symmetry_planes: x = .x(), …; NaN where none): the mesh is the half
  /// (or quarter) of a whole completed by its mirror images in those planes, and a face's cone counts
  /// the images of the faces as the whole's own (each face s weighed once for itself and once per
  /// image of the cone's centre its centroid lies near), so the half filters as the whole does.
  CellFilter(const SurfaceMesh& mesh, const Eigen::VectorXd& spacing, const Eigen::VectorXd& diameter,
             const std::vector<bool>* keep_own = nullptr,
             const Vec3& mirror_planes = Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));

  bool identity() const { return m_matrix.rows() == 0; }
  /// ᾱ = B α (a copy of α for the identity).
  Eigen::VectorXd apply(const Eigen::VectorXd& alpha) const;
  /// Bᵀ g: a gradient with respect to ᾱ pulled back to α.
  Eigen::VectorXd pull_back(const Eigen::VectorXd& gradient) const;
  /// B (#F×#F; empty for the identity).
  const Eigen::SparseMatrix<double, Eigen::RowMajor>& matrix() const { return m_matrix; }
  /// b_t (#F; empty for the identity): 0 where the face keeps its own α, 1 where it takes the cell's.
  const Eigen::VectorXd& blend() const { return m_blend; }
  /// 1 − smoothstep((h_t/d_t − ¼)/¾) (#F; empty for the identity): how far the face's triangle
  /// resolves the stencils, 1 where four or more span d_t, 0 where it is d_t across or larger —
  /// b_t's complement before a clamp's mark (a face at a clamp keeps its own α whatever its size).
  const Eigen::VectorXd& resolution() const { return m_resolution; }
  /// Mean number of faces per row (the filter's width), 1 for the identity.
  double mean_row_size() const;

 private:
  Eigen::SparseMatrix<double, Eigen::RowMajor> m_matrix;
  Eigen::SparseMatrix<double, Eigen::RowMajor> m_transpose;
  Eigen::VectorXd m_blend;
  Eigen::VectorXd m_resolution;
};

/// b(h/d) of the file comment.
double cell_filter_blend(double edge_over_diameter);

}  // namespace cutwork::solvers
