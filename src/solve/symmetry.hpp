// Numerical symmetry of an assembled matrix whose pattern is fixed: the position of every
// entry's transpose is found once per pattern, so each test is one pass that allocates nothing.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "velum/solve/linear_solver.hpp"

namespace velum {

class SymmetryCheck {
 public:
  /// Maps the pattern; false when it is structurally unsymmetric.
  bool map(const SparseMatrix& A) {
    mirror_.assign(A.nonZeros(), -1);
    for (int j = 0; j < A.outerSize(); ++j)
      for (int k = A.outerIndexPtr()[j]; k < A.outerIndexPtr()[j + 1]; ++k) {
        const int i = A.innerIndexPtr()[k];
        const int* lo = A.innerIndexPtr() + A.outerIndexPtr()[i];
        const int* hi = A.innerIndexPtr() + A.outerIndexPtr()[i + 1];
        const int* pos = std::lower_bound(lo, hi, j);
        if (pos == hi || *pos != j) return structural_ = false;
        mirror_[k] = static_cast<int>(pos - A.innerIndexPtr());
      }
    return structural_ = true;
  }
  /// |A − Aᵀ| <= 1e-10 |A| (entry-wise maxima) on a structurally symmetric pattern.
  bool symmetric(const SparseMatrix& A) const {
    if (!structural_) return false;
    const double* v = A.valuePtr();
    double vmax = 0, dmax = 0;
    for (size_t k = 0; k < mirror_.size(); ++k) {
      vmax = std::max(vmax, std::abs(v[k]));
      dmax = std::max(dmax, std::abs(v[k] - v[mirror_[k]]));
    }
    return dmax <= 1e-10 * vmax;
  }

 private:
  std::vector<int> mirror_;
  bool structural_ = false;
};

}  // namespace velum
