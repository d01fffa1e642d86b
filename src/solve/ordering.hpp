// Fill-reducing ordering of a structurally symmetric matrix: METIS nested dissection on the
// graph of its nodes. A membrane matrix has one column per degree of freedom and up to three
// of them per node with the same pattern; ordering the node graph (a ninth of the edges)
// keeps a node's equations together and takes a third of the time of ordering the equations.
#pragma once

#include <vector>

#include "velum/solve/linear_solver.hpp"

namespace velum {

/// Whether columns a and b of A hold the same rows (a node's equations do).
bool same_rows(const SparseMatrix& A, int a, int b);

/// position[i] = the pivot position (0-based) of equation i; empty when METIS fails (the
/// caller then lets its solver choose).
std::vector<int> nested_dissection(const SparseMatrix& A);

}  // namespace velum
