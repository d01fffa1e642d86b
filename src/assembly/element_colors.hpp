#pragma once
// The colours of a parallel assembly: which elements' sums may run at once.
#include <vector>

#include "velum/model/element_block.hpp"

namespace velum {

/// Greedy colouring of groups of `group` consecutive elements of `elems`: a group takes the
/// smallest colour none of its nodes has seen, so that the groups of one colour share no node
/// and threads may take them at once. Each colour lists whole groups, in order, the short last
/// group (if any) at its end: slices of `group` entries of a colour's list are its groups.
/// A group's elements, neighbours in a mesh's order, share nodes and matrix entries and run one
/// after the other on one thread: their scatter finds the matrix's lines in cache (coloured
/// element by element, each colour's pass went through the whole matrix, a visible share of
/// a large run).
std::vector<std::vector<int>> color_element_groups(const ElementBlock& b,
                                                   const std::vector<int>& elems, int num_nodes,
                                                   int group);

}  // namespace velum
