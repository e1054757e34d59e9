#pragma once
/// A triangle mesh completed by its mirror image in a coordinate plane: what a model of a structure's
/// half on a symmetry plane (LoadCase::symmetry_axes) stands for. The printable solid of such a
/// design is the whole (host/export/design_files.h).
#include <vector>

#include "host/core/types.h"

namespace cutwork {

struct MirroredMesh {
  RowMatX3d vertices;      ///< the input's, then the images of those off the plane
  RowMatX3i faces;         ///< the input's, then their images, turned to face the same side
  std::vector<int> image;  ///< #V of the input: each vertex's image (itself on the plane)
};

/// `vertices` and `faces` and their mirror image in the plane x_axis = c. Vertices within
/// `tolerance` (m) of the plane are put on it exactly and shared by both halves, so a half whose
/// boundary lies on the plane becomes one surface across it.
MirroredMesh mirror_across_plane(const RowMatX3d& vertices, const RowMatX3i& faces, int axis, double c,
                                 double tolerance);

}  // namespace cutwork
