// Numerical symmetry of an assembled matrix with sorted indices, in one pass that keeps no
// map of transposed positions (such a map costs 4 bytes per entry: 16 MB at 152k DOFs):
// the columns are walked in order with one cursor per column, which meets the transposed
// entries of the upper triangle in order.
#pragma once

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "velum/math/threads.hpp"
#include "velum/solve/linear_solver.hpp"

namespace velum {

class SymmetryCheck {
 public:
  /// Checks the pattern; false when it is structurally unsymmetric.
  bool map(const SparseMatrix& A) {
    double dmax = 0;
    structural_ = walk(A, dmax);
    partner_.clear();
    if (structural_ && A.nonZeros() >= kMapped) map_partners(A);
    return structural_;
  }
  /// |A − Aᵀ| <= 1e-10 |A| (entry-wise maxima) on a structurally symmetric pattern. The
  /// largest |a_ij| first (a pass that vectorises), then the walk over the lower entries stops at
  /// the first pair that decides (on the C9 canopy's unsymmetric Jacobian, near its first
  /// columns).
  bool symmetric(const SparseMatrix& A) {
    if (!structural_) return false;
    if (static_cast<Eigen::Index>(partner_.size()) == A.nonZeros()) return mapped_check(A);
    const double vmax = largest(A);
    if (!(vmax > 0) || !std::isfinite(vmax)) return ratio(A, vmax) <= kTolerance;  // full walk
    double dmax = 0;
    return walk(A, dmax, kTolerance * vmax) && dmax <= kTolerance * vmax;
  }
  /// max |a_ij − a_ji| / max |a_ij| (0 for a zero matrix), infinity on an unsymmetric pattern.
  double asymmetry(const SparseMatrix& A) {
    return structural_ ? ratio(A, largest(A)) : std::numeric_limits<double>::infinity();
  }
  static constexpr double kTolerance = 1e-10;

 private:
  // max |a_ij|. Eigen's maximum vectorises (a loop of std::max carries its result from entry
  // to entry); PropagateNumbers skips a NaN as std::max(vmax, NaN) does.
  static double largest(const SparseMatrix& A) {
    const Eigen::Index nnz = A.nonZeros();
    return nnz > 0 ? Eigen::Map<const Eigen::ArrayXd>(A.valuePtr(), nnz)
                         .abs()
                         .template maxCoeff<Eigen::PropagateNumbers>()
                   : 0.0;
  }

  // asymmetry() with the largest |a_ij| already known.
  double ratio(const SparseMatrix& A, double vmax) {
    double dmax = 0;
    if (!walk(A, dmax)) return std::numeric_limits<double>::infinity();
    return vmax > 0 ? dmax / vmax : 0.0;
  }

  // For every strictly lower entry (i, j), column i's next unvisited upper entry must be
  // (j, i): columns are visited in order, so each column's cursor advances monotonically, and
  // when column j is reached every entry above its diagonal has been met from its own column
  // (i < j): j's cursor stands on the diagonal (or on the first entry below it). So only the
  // lower entries are walked (the upper ones met as their partners), with no branch between
  // the two: on a 0.99M-entry Jacobian of a grid (3 DOFs a node, nine-node stencil) with the
  // caches flushed, 1.8 ms against 3.8 ms for a walk of every entry (with the maximum's pass
  // in both). Folding the maximum into this walk read each value once but took 2.1 ms: its
  // loop-carried maxima, not the memory, set the pace.
  // Gives the largest |a_ij − a_ji|; false on an unsymmetric pattern. With a finite `stop`,
  // returns (true) as soon as dmax exceeds it.
  bool walk(const SparseMatrix& A, double& dmax,
            double stop = std::numeric_limits<double>::infinity()) {
    const int n = static_cast<int>(A.outerSize());
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    const double* v = A.valuePtr();
    cursor_.assign(outer, outer + n);
    for (int j = 0; j < n; ++j) {
      int k = cursor_[j];
      const int end = outer[j + 1];
      if (k < end && inner[k] < j) return false;  // an upper entry no column met
      if (k < end && inner[k] == j) ++k;
      for (; k < end; ++k) {
        const int i = inner[k];
        const int m = cursor_[i]++;
        if (m >= outer[i + 1] || inner[m] != j) return false;
        dmax = std::max(dmax, std::abs(v[k] - v[m]));
        if (dmax > stop) return true;
      }
    }
    return true;
  }

  // Large matrices (millions of entries, where a search for each partner at every
  // factorisation is a walk of cache misses): each lower entry's partner position, found once per
  // pattern (4 bytes an entry), then one pass on the threads there are. The maxima are exact:
  // the same answer on any number of threads.
  void map_partners(const SparseMatrix& A) {
    const int n = static_cast<int>(A.outerSize());
    const int* outer = A.outerIndexPtr();
    const int* inner = A.innerIndexPtr();
    partner_.assign(static_cast<std::size_t>(A.nonZeros()), -1);
    cursor_.assign(outer, outer + n);
    for (int j = 0; j < n; ++j)
      for (int k = outer[j]; k < outer[j + 1]; ++k)
        if (const int i = inner[k]; i > j) partner_[k] = cursor_[i]++;
  }
  bool mapped_check(const SparseMatrix& A) const {
    const double* v = A.valuePtr();
    const int* p = partner_.data();
    const std::ptrdiff_t nnz = A.nonZeros();
    double dmax = 0, vmax = 0;
    auto scan = [&](std::ptrdiff_t k, double& d, double& m) {
      m = std::max(m, std::abs(v[k]));
      if (p[k] >= 0) d = std::max(d, std::abs(v[k] - v[p[k]]));
    };
    if (share_between_threads(nnz > kParallelEntries)) {
#pragma omp parallel for schedule(static) reduction(max : dmax, vmax)
      for (std::ptrdiff_t k = 0; k < nnz; ++k) scan(k, dmax, vmax);
    } else {
      for (std::ptrdiff_t k = 0; k < nnz; ++k) scan(k, dmax, vmax);
    }
    if (vmax == 0) return true;  // a zero matrix
    return std::isfinite(vmax) && dmax <= kTolerance * vmax;
  }
  static constexpr Eigen::Index kMapped = 1'000'000;
  static constexpr std::ptrdiff_t kParallelEntries = 200'000;  ///< below: one thread

  std::vector<int> partner_;  ///< per entry: its partner's position if it is below the diagonal
  std::vector<int> cursor_;
  bool structural_ = false;
};

}  // namespace velum
