// CHOLMOD's supernodal Cholesky (SuiteSparse, through Eigen) behind the LinearSolver interface:
// symmetric positive definite matrices, METIS ordering, a non-positive pivot reported as a
// failed factorisation.
#pragma once

#include <memory>

#include "velum/solve/linear_solver.hpp"

namespace velum {

/// `check_symmetry`: test every matrix for numerical symmetry and throw on an unsymmetric one
/// (CHOLMOD reads the lower triangle only); false when the caller has already tested it.
std::unique_ptr<LinearSolver> make_cholmod_solver(bool check_symmetry = true);

}  // namespace velum
