#pragma once
/// Shared array vocabulary. Row-major #N×3 matrices so that a row is one point or one triangle
/// and the storage maps 1:1 onto a GPU storage buffer of packed triples.
#include <Eigen/Core>

namespace cutwork {

using RowMatX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using RowMatX3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
using RowMatX2i = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;
using RowMatX2d = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;

}  // namespace cutwork
