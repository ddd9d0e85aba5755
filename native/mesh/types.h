// Array types at the module boundary: row-major so numpy arrays map without copies.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace paramorph {

using Index = std::int32_t;
/// #V by 3 vertex positions.
using MatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// #V by 2 planar coordinates.
using MatrixX2d = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
/// #F by 3 vertex indices, 0-based, counter-clockwise seen from outside.
using MatrixX3i = Eigen::Matrix<Index, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// #E by 2 vertex indices.
using MatrixX2i = Eigen::Matrix<Index, Eigen::Dynamic, 2, Eigen::RowMajor>;
using VectorXi = Eigen::Matrix<Index, Eigen::Dynamic, 1>;
using Eigen::VectorXd;

}  // namespace paramorph
