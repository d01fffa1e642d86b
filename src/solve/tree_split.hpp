// How a supernodal factorisation shares its work between two threads: the elimination tree's
// supernodes fall into two groups of whole subtrees (each group factorised by one thread, no
// write shared with the other group) and the top (the ancestors of those subtrees, the largest
// separators of the nested dissection), factorised after both groups with the dense work of
// each supernode split between the threads. The split depends on the structure alone, never
// on the number of threads: a factorisation on one thread does the same arithmetic in the
// same order, so its result is the same to the bit.
#pragma once

#include <cstddef>
#include <vector>

#include "supernodes.hpp"

namespace velum {

struct TreeSplit {
  static constexpr int kTop = 2;
  std::vector<int> group;                  ///< per supernode: 0, 1 or kTop
  std::vector<int> members[2];             ///< each group's supernodes, ascending (a postorder)
  std::vector<int> top;                    ///< the top's supernodes, ascending
  std::vector<std::ptrdiff_t> top_offset;  ///< per supernode: its L panel's place in a copy
                                           ///< of the top's panels (-1 outside the top)
  std::ptrdiff_t top_values = 0;           ///< size of the top's panels together
  double flops[3] = {0, 0, 0};             ///< groups 0 and 1 and the top (Cholesky count)
};

/// Grows the top from the roots down, always opening its heaviest subtree, and keeps the split
/// whose estimated time (the heavier group plus the top at `top_speedup` on two threads) is
/// shortest; the subtrees go to the groups heaviest first, each to the lighter group.
TreeSplit split_tree(const SupernodalStructure& st, double top_speedup = 1.8);

}  // namespace velum
