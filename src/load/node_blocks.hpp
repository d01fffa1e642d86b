// A contact's 3x3 coupling between two nodes into the sparse matrix: K −= ∂f_i/∂x_j, turned
// into the nodes' frames where they have one, at the equations they have (eliminated
// components left out). Shared by the rigid and sheet contact terms.
#pragma once

#include "velum/assembly/dof_map.hpp"

namespace velum {

inline void subtract_node_block(const DofMap& dofs, int i, int j, const Mat3& D, SparseMatrix& K) {
  const int fi = dofs.frame(i), fj = dofs.frame(j);
  Mat3 A = -D;
  if (fi >= 0) A = dofs.rotation(fi) * A;
  if (fj >= 0) A = A * dofs.rotation(fj).transpose();
  for (int b = 0; b < 3; ++b) {
    const int cj = dofs.equation(j, b);
    if (cj < 0) continue;
    for (int a = 0; a < 3; ++a)
      if (const int ri = dofs.equation(i, a); ri >= 0 && A(a, b) != 0)
        K.coeffRef(ri, cj) += A(a, b);
  }
}

}  // namespace velum
