// A contact's 3x3 coupling between two nodes into the sparse matrix: K −= ∂f_i/∂x_j, turned
// into the nodes' frames where they have one, at the equations they have (eliminated
// components left out). Shared by the rigid and sheet contact terms.
#pragma once

#include <algorithm>
#include <array>

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

// Asks the memory for the entries of K's columns of these nodes' equations (a node's columns
// are consecutive), which subtract_node_blocks will find and change: called before a pair's
// kernel, the loads run while it computes (a pair's columns are mostly not in cache: scattered
// over the matrix, they made most of the scatter's time).
template <size_t N>
void prefetch_node_columns(const DofMap& dofs, const std::array<int, N>& nodes,
                           const SparseMatrix& K) {
  if (!K.isCompressed()) return;
  const int* eq = dofs.equations();
  const int* outer = K.outerIndexPtr();
  for (int n : nodes) {
    const int* e = eq + 3 * static_cast<size_t>(n);
    const int first = std::max({e[0], e[1], e[2]});  // a node's equations: held ones are -1
    if (first < 0) continue;
    int lo = first, hi = first;
    for (int c = 0; c < 3; ++c)
      if (e[c] >= 0) lo = std::min(lo, e[c]), hi = std::max(hi, e[c]);
    const int begin = outer[lo], end = outer[hi + 1];
    for (int k = begin; k < end; k += 16) __builtin_prefetch(K.innerIndexPtr() + k);
    for (int k = begin; k < end; k += 8) __builtin_prefetch(K.valuePtr() + k);
  }
}

// K −= D, the matrix ∂f/∂X of a pair over its N nodes (3 N coordinates, global axes), as the
// N² node blocks subtract_node_block would add, with one search per pair of nodes instead of
// one per column: the columns of a node's equations hold the same rows (the assembler's
// pattern is built node by node), so where the row node's first entry sits in the first
// column gives it in the others (checked, else searched); its equations are consecutive
// rows there. Nodes with a frame of their own, and a matrix not compressed, take
// subtract_node_block. The entries added are the same in the same order, so K's bits are
// too. `guesses` (per pair of nodes, row node a and column node b at a N + b): where each
// row sat in its column the last time, tried before searching (one comparison checks it: a
// column holds a row once) and kept for the next call; a pair of the same nodes on the same
// pattern then needs no search (the caller's, e.g. per contact slot; -1: unknown).
template <int N>
void subtract_node_blocks(const DofMap& dofs, const std::array<int, N>& nodes,
                          const Eigen::Matrix<double, 3 * N, 3 * N>& D, SparseMatrix& K,
                          std::array<int, N * N>* guesses = nullptr) {
  bool framed = false;
  for (int n : nodes) framed = framed || dofs.frame(n) >= 0;
  if (framed || !K.isCompressed()) {
    for (int a = 0; a < N; ++a)
      for (int b = 0; b < N; ++b)
        subtract_node_block(dofs, nodes[static_cast<size_t>(a)], nodes[static_cast<size_t>(b)],
                            D.template block<3, 3>(3 * a, 3 * b), K);
    return;
  }
  const int* eq = dofs.equations();
  const int* outer = K.outerIndexPtr();
  const int* inner = K.innerIndexPtr();
  double* values = K.valuePtr();
  bool inserted = false;  // an entry was outside the pattern: K is no longer compressed
  // Per node: its first component with an equation (3: none), and whether it is free in every
  // direction with consecutive equations (its rows then three consecutive entries of a column).
  std::array<int, N> firsts;
  std::array<bool, N> wholes;
  for (int a = 0; a < N; ++a) {
    const int* e = eq + 3 * nodes[static_cast<size_t>(a)];
    int f = 0;
    while (f < 3 && e[f] < 0) ++f;
    firsts[static_cast<size_t>(a)] = f;
    wholes[static_cast<size_t>(a)] = f == 0 && e[1] == e[0] + 1 && e[2] == e[0] + 2;
  }
  for (int b = 0; b < N; ++b) {
    if (firsts[static_cast<size_t>(b)] == 3) continue;  // no column
    const int* cols = eq + 3 * nodes[static_cast<size_t>(b)];
    for (int a = 0; a < N; ++a) {
      const int first = firsts[static_cast<size_t>(a)];
      if (first == 3) continue;  // no row
      const int* rows = eq + 3 * nodes[static_cast<size_t>(a)];
      const bool whole = wholes[static_cast<size_t>(a)];
      // Where that row sits from the start of the node's columns.
      int offset = guesses ? (*guesses)[static_cast<size_t>(a * N + b)] : -1;
      for (int cb = 0; cb < 3; ++cb) {
        const int cj = cols[cb];
        if (cj < 0) continue;
        if (inserted) {  // outside the pattern before: the slow way, as subtract_node_block
          for (int ca = first; ca < 3; ++ca)
            if (const double d = D(3 * a + ca, 3 * b + cb); rows[ca] >= 0 && d != 0)
              K.coeffRef(rows[ca], cj) -= d;
          continue;
        }
        const int begin = outer[cj], end = outer[cj + 1];
        int k = begin + offset;
        if (offset < 0 || k >= end || inner[k] != rows[first])
          k = static_cast<int>(std::lower_bound(inner + begin, inner + end, rows[first]) - inner);
        offset = k - begin;
        if (whole && k + 2 < end && inner[k + 2] == rows[2]) {  // sorted: inner[k + 1] too
          const double* d = &D(3 * a, 3 * b + cb);              // the block's column
          values[k] -= d[0], values[k + 1] -= d[1], values[k + 2] -= d[2];
          continue;
        }
        for (int ca = first; ca < 3; ++ca) {
          const int ri = rows[ca];
          if (ri < 0) continue;
          if (k >= end || inner[k] != ri)
            k = static_cast<int>(std::lower_bound(inner + begin, inner + end, ri) - inner);
          const double d = D(3 * a + ca, 3 * b + cb);
          if (k < end && inner[k] == ri) {
            values[k++] -= d;
          } else if (d != 0) {  // not in the pattern (see subtract_node_block): inserted
            K.coeffRef(ri, cj) -= d;
            inserted = true;
            for (int cc = ca + 1; cc < 3; ++cc)  // the rest of this column
              if (const double e = D(3 * a + cc, 3 * b + cb); rows[cc] >= 0 && e != 0)
                K.coeffRef(rows[cc], cj) -= e;
            break;
          }
        }
      }
      if (guesses) (*guesses)[static_cast<size_t>(a * N + b)] = offset;
    }
  }
}

}  // namespace velum
