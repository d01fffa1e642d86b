// UMFPACK's multifrontal LU (SuiteSparse, through Eigen) behind the LinearSolver interface:
// any square matrix, METIS ordering, no iterative refinement.
#pragma once

#include <memory>

#include "velum/solve/linear_solver.hpp"

namespace velum {

std::unique_ptr<LinearSolver> make_umfpack_solver();

}  // namespace velum
