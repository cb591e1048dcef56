// Shared numeric types. Everything is double precision; vectors are Eigen column vectors.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <limits>

namespace cbps {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;
/// One 6-block of a constraint row j_c (5.1.3): the coefficients of [v; omega] of one body.
using Row6 = Eigen::Matrix<double, 1, 6>;
/// Sparse matrices (J, Minv, A) are column-major; A is symmetric, so its column k is its row k.
using SpMat = Eigen::SparseMatrix<double>;
/// J is row-major: its row k is constraint k's j_c (6.1), so it is filled row by row.
using SpMatRow = Eigen::SparseMatrix<double, Eigen::RowMajor>;
using Triplet = Eigen::Triplet<double>;

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kPi = 3.14159265358979323846;

}  // namespace cbps
