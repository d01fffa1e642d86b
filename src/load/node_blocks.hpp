// A contact's 3x3 coupling between two nodes into the sparse matrix: K −= ∂f_i/∂x_j, turned
// into the nodes' frames where they have one, at the equations they have (eliminated
// components left out). Shared by the rigid and sheet contact terms.
#pragma once

#include <algorithm>

#include "velum/assembly/dof_map.hpp"

namespace velum {

// The entries are found in K's pattern (one search per column: a node's equations are
// consecutive rows); an entry outside it is inserted (slow: K is then uncompressed), which
// only a matrix made without the term's couplings needs (Assembler::set_couplings).
inline void subtract_node_block(const DofMap& dofs, int i, int j, const Mat3& D, SparseMatrix& K) {
  const int fi = dofs.frame(i), fj = dofs.frame(j);
  Mat3 A = -D;
  if (fi >= 0) A = dofs.rotation(fi) * A;
  if (fj >= 0) A = A * dofs.rotation(fj).transpose();
  const int rows[3] = {dofs.equation(i, 0), dofs.equation(i, 1), dofs.equation(i, 2)};
  for (int b = 0; b < 3; ++b) {
    const int cj = dofs.equation(j, b);
    if (cj < 0) continue;
    int a = 0;
    if (K.isCompressed()) {
      const int* inner = K.innerIndexPtr();
      const int end = K.outerIndexPtr()[cj + 1];
      int k = K.outerIndexPtr()[cj];
      for (; a < 3; ++a) {
        const int ri = rows[a];
        if (ri < 0 || A(a, b) == 0) continue;
        if (k >= end || inner[k] != ri)
          k = static_cast<int>(std::lower_bound(inner + k, inner + end, ri) - inner);
        if (k >= end || inner[k] != ri) break;  // not in the pattern
        K.valuePtr()[k++] += A(a, b);
      }
    }
    for (; a < 3; ++a)
      if (const int ri = rows[a]; ri >= 0 && A(a, b) != 0) K.coeffRef(ri, cj) += A(a, b);
  }
}

}  // namespace velum
