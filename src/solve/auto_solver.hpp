// The `auto` linear solver: chooses per factorisation between the supernodal Cholesky, MUMPS's
// LDLᵀ (or CHOLMOD) and an LU, from the matrix's symmetry, definiteness and size.
#pragma once

#include <memory>

#include "velum/solve/linear_solver.hpp"

namespace velum {

std::unique_ptr<LinearSolver> make_auto_solver();

}  // namespace velum
