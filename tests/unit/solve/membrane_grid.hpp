// The pattern of a membrane Jacobian for the sparse-solver tests: an nx x ny grid of nodes,
// quad4 elements, 3 equations per node (every `drop`-th equation removed when drop > 0, as
// constraints remove components), each equation coupled with every equation of its node and of
// the neighbouring nodes. The tests fill it with their own values. Also how they judge a solve.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "velum/math/sparse.hpp"

namespace velum {

struct MembraneGrid {
  MembraneGrid(int nx, int ny, int drop) : nx(nx), ny(ny), index(3 * nx * ny, -1) {
    for (int e = 0; e < 3 * nx * ny; ++e)
      if (drop == 0 || e % drop != drop - 1) index[e] = n++;
  }
  /// Calls couple(r, c) for every ordered pair of distinct coupled equations, in a fixed order.
  template <class Couple>
  void for_each_coupling(Couple&& couple) const {
    for (int a = 0; a < nx * ny; ++a)
      for (int d = 0; d < 9; ++d) {
        const int bx = a % nx + d % 3 - 1, by = a / nx + d / 3 - 1;
        if (bx < 0 || bx >= nx || by < 0 || by >= ny) continue;
        const int b = bx + nx * by;
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            const int r = index[3 * a + i], c = index[3 * b + j];
            if (r >= 0 && c >= 0 && r != c) couple(r, c);
          }
      }
  }

  int nx, ny;
  std::vector<int> index;  ///< equation of each node component, -1 when removed
  int n = 0;               ///< equations
};

/// |A x - b| relative to |A| |x|.
inline double relative_residual(const SparseMatrix& A, const Eigen::VectorXd& x,
                                const Eigen::VectorXd& b) {
  return (A * x - b).norm() / (A.norm() * x.norm());
}

/// The right-hand side the sparse-solver tests solve for: n values from -1 to 2.
inline Eigen::VectorXd rhs(Eigen::Index n) {
  return Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
}

}  // namespace velum
