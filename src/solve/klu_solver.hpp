// KLU (SuiteSparse) behind the LinearSolver interface: a sparse LU with partial pivoting that
// keeps its pivot order between factorisations of one pattern while the pivots stay good.
#pragma once

#include <memory>

#include "velum/solve/linear_solver.hpp"

namespace velum {

std::unique_ptr<LinearSolver> make_klu_solver();

}  // namespace velum
