// `linear_solver: petsc`: the distributed linear solve of a run on one or several MPI
// processes (docs/parallel.md). Every process passes its share of the assembled matrix (its
// own elements' entries); the shares are added into one PETSc MPIAIJ matrix (block size 3
// where every node has three equations), preallocated from the union of their patterns at the
// analysis and refilled at every factorisation, and the solution is gathered back to every
// process.
//
// Direct by default: MUMPS through PETSc, LDLᵀ (PCCHOLESKY) while the matrix is numerically
// symmetric (|A − Aᵀ| <= 1e-10 |A|, as `auto`), LU otherwise; its symbolic analysis is kept
// while the pattern holds. Iterative on request (analysis.petsc_options, e.g.
// "-ksp_type gmres -pc_type gamg"): right preconditioning, the rigid-body near-null space for
// GAMG, and the true residual checked after PETSc says it converged.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "velum/math/types.hpp"
#include "velum/parallel/equation_layout.hpp"
#include "velum/solve/linear_solver.hpp"

namespace velum {

struct PetscSolverSettings {
  /// PETSc options in its own syntax ("-ksp_type gmres -pc_type gamg"), applied over the
  /// defaults (MUMPS, direct).
  std::string options;
  /// Rigid-body modes over the equations (columns; any number, orthonormalised here): the
  /// near-null space an algebraic multigrid preconditioner builds its coarse spaces from.
  /// Called at the analysis of an iterative solve only (a direct solve needs none: 48 bytes
  /// per equation not held on every process); may be empty.
  std::function<MatX()> near_null_space;
  /// 3 when equations 3k, 3k+1, 3k+2 are one node's for every k; otherwise 1.
  int block_size = 1;
  /// Several processes: the matrices and vectors handed to the solver are over this
  /// process's local equations (owned, then ghosts); the solver maps them to the global
  /// numbering and owns the rows the layout says. Null or not distributed: global.
  const EquationLayout* layout = nullptr;
};

/// Throws std::runtime_error when this build has no PETSc.
std::unique_ptr<LinearSolver> make_petsc_solver(const PetscSolverSettings& settings);

}  // namespace velum
