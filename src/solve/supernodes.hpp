// The symbolic part of a supernodal LU of a structurally symmetric matrix: the fill-reducing
// order (METIS nested dissection of the node graph, then a postorder of the elimination tree),
// the column counts of L, the supernodes (columns whose L structure nests, relaxed by
// amalgamation), their dense panels for L and Uᵀ (the same structure; L alone for a Cholesky
// factorisation), the place in the panels of each stored entry of A, and where each
// supernode's update goes. Made once per pattern; the numeric factorisations
// (supernodal_lu.hpp, supernodal_cholesky.hpp) allocate nothing.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <vector>

#include "velum/solve/linear_solver.hpp"

namespace velum {

/// When a supernode absorbs its child (CHOLMOD's rule, nrelax / zrelax): always up to
/// `always` columns, up to `small` columns while under `small_zeros` of its panel are
/// explicit zeros, up to `medium` under `medium_zeros`, any width under `zeros`; never wider
/// than `widest`.
struct Amalgamation {
  int always = 4, small = 16, medium = 48, widest = 256;
  double small_zeros = 0.8, medium_zeros = 0.1, zeros = 0.05;
};

struct SupernodalStructure {
  struct Target {        ///< a supernode that one supernode's update reaches
    int supernode;       ///< the target
    int begin, end;      ///< the source's below rows [begin, end) are the target's columns
    std::ptrdiff_t rel;  ///< relative[rel + i - begin]: row position in the target's L panel
  };                     ///< of the source's below row i, for i in [begin, below count)

  int n = 0;
  std::vector<int> order;               ///< order[k] = the equation eliminated k-th
  std::vector<int> first;               ///< columns of supernode s: [first[s], first[s+1])
  std::vector<int> below_begin;         ///< rows below s: rows[below_begin[s] .. below_begin[s+1])
  std::vector<int> rows;                ///< in elimination order, ascending
  std::vector<std::ptrdiff_t> l_panel;  ///< (width + below) x width, column-major: L and the
                                        ///< whole diagonal block
  std::vector<std::ptrdiff_t> u_panel;  ///< below x width, column-major: U's rows, transposed
                                        ///< (empty for a Cholesky factorisation)
  std::ptrdiff_t values = 0;            ///< size of the panels together
  std::vector<std::ptrdiff_t> entry;    ///< LU: A's k-th stored value -> its place in the
                                        ///< panels
  struct Load {                         ///< Cholesky: the value at `a` in A's lower triangle
    int a, at;                          ///< (lower_begin), at its place in its supernode's L
  };                                    ///< panel
  /// Cholesky: A's lower triangle apart, column by column: column j's rows at or below j (the
  /// last ones it stores: rows sorted) at [lower_begin[j], lower_begin[j + 1]).
  std::vector<int> lower_begin;
  std::vector<int> load_begin;    ///< Cholesky: A's values in t's panel: loads[load_begin[t] ..
  std::vector<Load> loads;        ///< [t + 1]) (the permuted lower triangle's, each once; both
                                  ///< empty when a panel holds more than 2^31 values or A's
                                  ///< pattern is not symmetric)
  std::ptrdiff_t entries = 0;     ///< A's stored values
  std::vector<int> target_begin;  ///< targets of s: targets[target_begin[s] .. [s+1])
  std::vector<Target> targets;
  std::vector<int> relative;
  int widest = 0, most_below = 0;  ///< largest width and below count (work sizes)
  double flops = 0;                ///< of one numeric factorisation (LU or Cholesky)

  int supernodes() const { return static_cast<int>(first.size()) - 1; }
  int width(int s) const { return first[s + 1] - first[s]; }
  /// Whether A has the analysed pattern (its size and its number of stored entries: a
  /// factorisation reads A's values through `entry` or `loads`, or its own lists made from
  /// them).
  bool matches(const SparseMatrix& A) const { return A.rows() == n && A.nonZeros() == entries; }
  /// Cholesky flops of supernode s: its diagonal block, the rows below, its update's lower
  /// triangle.
  double cholesky_flops(int s) const {
    const double w = width(s), m = below(s);
    return w * w * w / 3.0 + m * w * w + m * (m + 1) * w;
  }
  int below(int s) const { return below_begin[s + 1] - below_begin[s]; }
};

/// position[i] = the pivot position of equation i (nested_dissection), or empty for the
/// natural order. The pattern read is that of A + Aᵀ. Factor::kCholesky: L's panels only (A's
/// entries above the diagonal blocks are not read), and Cholesky's flop count. by_nodes: the
/// elimination tree and L's structure found on the graph of A's nodes (runs of columns with one
/// pattern, a membrane node's equations) where A has them, the same structure as from the graph
/// of its equations (false: always from that, to check against) in a ninth of the work.
enum class Factor { kLu, kCholesky };
SupernodalStructure analyse_supernodes(const SparseMatrix& A, const std::vector<int>& position,
                                       const Amalgamation& relax = {}, Factor factor = Factor::kLu,
                                       bool by_nodes = true);

// Eigen splits a matrix product over OpenMP threads when the program has several: on panels
// this small (a few dozen rows) that costs more than it saves (on a small model's Jacobian,
// with two threads allowed, several times the CPU of one thread, most of it in libgomp's
// barriers). The supernodal factorisations and solves run on the calling thread
// while one of these lives; Eigen's default (follow OpenMP) is restored after it.
class SerialEigen {
 public:
  SerialEigen() { Eigen::setNbThreads(1); }
  ~SerialEigen() { Eigen::setNbThreads(0); }
  SerialEigen(const SerialEigen&) = delete;
  SerialEigen& operator=(const SerialEigen&) = delete;
};

}  // namespace velum
