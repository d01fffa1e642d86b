// A random symmetric positive definite matrix for the dense kernels' benchmark and tests
// (tests/unit/solve/dense_kernels_test.cpp): B Bᵀ / n + I / 2 with B uniform in [−1, 1], whose
// factor has entries of both signs and a spread of pivots.
#pragma once

#include <Eigen/Core>

namespace velum {

template <class T>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> random_spd(int n) {
  using Matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;
  const Matrix B = Matrix::Random(n, n);
  Matrix A = B * B.transpose() / T(n);
  A.diagonal().array() += T(0.5);
  return A;
}

}  // namespace velum
