// MUMPS (multifrontal, Debian libmumps-seq-dev) behind the LinearSolver interface: LDLᵀ for
// symmetric matrices, definite or not (one triangle stored; threshold pivoting once a pivot
// comes out negative), LU otherwise. Ordered by METIS nested dissection of the node graph.
#pragma once

#include <memory>

#include "velum/solve/linear_solver.hpp"

namespace velum {

/// Null when this build has no MUMPS. `symmetric`: the caller guarantees numerically
/// symmetric matrices (LDLᵀ always, no symmetry test of its own).
std::unique_ptr<LinearSolver> make_mumps_solver(bool symmetric = false);

}  // namespace velum
