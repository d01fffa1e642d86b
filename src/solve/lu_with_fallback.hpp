// `auto`'s LU of unsymmetric matrices: the supernodal LU, and a factorisation with full
// pivoting (KLU or UMFPACK) for the matrices it refuses.
#pragma once

#include <memory>

#include "velum/solve/linear_solver.hpp"

namespace velum {

std::unique_ptr<LinearSolver> make_supernodal_lu_with_fallback();

}  // namespace velum
