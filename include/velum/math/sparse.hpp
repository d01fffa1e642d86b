// The sparse matrix every layer passes (assembled Jacobians, mass, patterns): compressed
// columns, int indices.
#pragma once

#include <Eigen/SparseCore>

namespace velum {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

}  // namespace velum
