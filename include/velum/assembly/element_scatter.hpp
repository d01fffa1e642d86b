#pragma once
// Where an element matrix's entries go in the global matrix's values.
#include <span>
#include <vector>

#include "velum/assembly/dof_map.hpp"
#include "velum/math/sparse.hpp"
#include "velum/math/types.hpp"
#include "velum/model/element_block.hpp"

namespace velum {

/// The positions of the listed elements' matrix entries in a compressed-column matrix whose
/// pattern couples whole nodes. A node's three equations are consecutive and its three
/// columns alike, so the 3 x 3 block of (row node a, column node b) sits at s, s + L, s + 2 L
/// (three consecutive rows each) with L the length of b's columns: an element keeps s for
/// each node pair and L for each node (20 numbers for a quad4 instead of 144 positions, the
/// map being the largest thing the scatter reads after the matrix). Elements with a node that
/// has one or two equations (a symmetry plane) keep every position.
class ElementScatter {
 public:
  ElementScatter() = default;
  /// `elements[k]` is the k-th element; `A` has the pattern (its values are not read).
  ElementScatter(const ElementBlock& b, std::span<const int> elements, const DofMap& dofs,
                 const SparseMatrix& A);

  /// values[position of (i, j)] += Ke(i, j) for element k's entries that have a position
  /// (Ke: dofs x dofs, column-major).
  void add(int k, const double* Ke, double* values) const {
    if (irregular_[k] >= 0) {
      const int* m = full_.data() + irregular_[k];
      for (int q = 0; q < nd_ * nd_; ++q)
        if (m[q] >= 0) values[m[q]] += Ke[q];
      return;
    }
    const int* s = start_.data() + static_cast<std::size_t>(k) * (nn_ * nn_ + nn_);
    const int* L = s + nn_ * nn_;
    for (int b = 0; b < nn_; ++b)
      for (int a = 0; a < nn_; ++a) {
        const int at = s[b * nn_ + a];
        if (at < 0) continue;
        const double* col = Ke + 3 * b * nd_ + 3 * a;
        for (int d = 0; d < 3; ++d) {
          double* v = values + at + d * L[b];
          const double* c = col + d * nd_;
          v[0] += c[0], v[1] += c[1], v[2] += c[2];
        }
      }
  }

  /// Position of element k's entry (i, j) in the values, or -1 (no equation).
  int position(int k, int i, int j) const;
  /// Whether element k keeps the compact form (block starts and strides).
  bool compact(int k) const { return irregular_[k] < 0; }

 private:
  int nn_ = 0, nd_ = 0;
  std::vector<int> start_;      // per element: nn² block starts (column node major), nn strides
  std::vector<int> irregular_;  // per element: its offset in full_, or -1
  std::vector<int> full_;       // the irregular elements' nd² positions (column-major)
};

}  // namespace velum
