#include "velum/solve/linear_solver.hpp"

#include <stdexcept>
#include <string>

#include "auto_solver.hpp"
#include "cholmod_solver.hpp"
#include "klu_solver.hpp"
#include "mumps_solver.hpp"
#include "umfpack_solver.hpp"
#include "velum/solve/petsc_solver.hpp"

namespace velum {

std::unique_ptr<LinearSolver> make_linear_solver(SolverKind kind) {
  switch (kind) {
    case SolverKind::kCholmod:
      return make_cholmod_solver();
    case SolverKind::kKlu:
      return make_klu_solver();
    case SolverKind::kAuto:
      return make_auto_solver();
    case SolverKind::kUmfpack:
      return make_umfpack_solver();
    case SolverKind::kMumps:
      return make_mumps_solver();
    case SolverKind::kPetsc:
      return make_petsc_solver({});
  }
  return nullptr;
}

SolverKind solver_kind_from_name(std::string_view n) {
  if (n == "auto") return SolverKind::kAuto;
  if (n == "cholmod") return SolverKind::kCholmod;
  if (n == "umfpack") return SolverKind::kUmfpack;
  if (n == "klu") return SolverKind::kKlu;
  if (n == "mumps") return SolverKind::kMumps;
  if (n == "petsc") return SolverKind::kPetsc;
  throw std::invalid_argument("unknown linear solver '" + std::string(n) + "'");
}

}  // namespace velum
