// Sparse direct solvers behind one interface (analyse / factorise / solve, as in Eigen):
// CHOLMOD (symmetric positive definite), MUMPS (symmetric LDLᵀ, definite or not, or LU),
// UMFPACK and KLU (unsymmetric). The symbolic analysis is kept while the sparsity pattern
// holds; a failed factorisation returns a status, never throws, so a time step can be cut (a
// wrong choice is not a failure: CHOLMOD given an unsymmetric matrix throws, and the run stops).
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "velum/math/sparse.hpp"

namespace velum {

/// kAuto: while the matrix is numerically symmetric (|A - Aᵀ| <= 1e-10 |A|, checked at every
/// factorisation) a supernodal Cholesky (float panels refined in double from 4e8 flops, as
/// accurate as double's) while it is positive definite and MUMPS's LDLᵀ when
/// it is not (without MUMPS in the build: CHOLMOD while it is positive definite), otherwise the
/// supernodal LU (rows exchanged within supernodes only; KLU or, above 6,000 equations, UMFPACK for
/// a factorisation it refuses) up to 125,000 equations and UMFPACK above. kMumps: LDLᵀ when
/// symmetric, LU otherwise. kCholmod throws std::invalid_argument on an unsymmetric matrix.
/// kPetsc: PETSc (MUMPS by default) on one or several MPI processes (petsc_solver.hpp).
enum class SolverKind { kAuto, kCholmod, kUmfpack, kKlu, kMumps, kPetsc };

/// Whether this build has MUMPS (Debian libmumps-seq-dev, found at configure time).
bool have_mumps();

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;
  virtual std::string_view name() const = 0;
  /// Symbolic analysis (ordering) of the pattern.
  virtual bool analyze(const SparseMatrix& A) = 0;
  /// Numeric factorisation; false when A is singular (or indefinite, for CHOLMOD).
  virtual bool factorize(const SparseMatrix& A) = 0;
  /// Solves A x = b with the last factorisation; false when the result is not finite.
  virtual bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) = 0;
  /// As solve, but a solver that improves its answer in steps (iterative refinement) may stop
  /// once ‖b − A x‖₂ <= `residual`: an inexact Newton correction needs no more. An infinite
  /// `residual` asks for its first step alone, unchecked (one_pass_accuracy). The others solve
  /// as solve does.
  virtual bool solve_within(const Eigen::VectorXd& b, Eigen::VectorXd& x, double residual) {
    (void)residual;
    return solve(b, x);
  }
  /// The relative residual ‖b − A x‖₂ / ‖b‖₂ that the first step of such a solver leaves, as
  /// last measured (NaN before a measure); 0 for a solver that solves in one.
  virtual double one_pass_accuracy() const { return 0; }
  /// Whether the solver needs a symmetric matrix.
  virtual bool symmetric_only() const = 0;
  /// The back-end's own words on its last failure (status codes), or empty.
  virtual std::string status() const { return {}; }
  /// Negative eigenvalues of the last matrix factorised (its inertia, by Sylvester's law from
  /// the pivots of LDLᵀ: MUMPS's INFOG(12); 0 after a Cholesky factorisation that succeeded),
  /// or -1 when this factorisation does not tell (LU).
  virtual int negative_pivots() const { return -1; }

  /// Factorises A, analysing its pattern first only when the pattern changed since the last
  /// analysis: its size, its number of non-zeros or `pattern`, the revision of the pattern the
  /// caller knows (Assembler::pattern_revision, through SecondOrderSystem::pattern_revision:
  /// a contact's couplings change the pattern, maybe not its number of entries).
  bool refactorize(const SparseMatrix& A, long pattern = 0) {
    if (A.rows() != rows_ || A.nonZeros() != nnz_ || pattern != pattern_) {
      if (!analyze(A)) return false;
      rows_ = A.rows();
      nnz_ = A.nonZeros();
      pattern_ = pattern;
      ++analyses_;
    }
    ++factorizations_;
    return factorize(A);
  }
  long analyses() const { return analyses_; }
  long factorizations() const { return factorizations_; }

 private:
  Eigen::Index rows_ = -1, nnz_ = -1;
  long pattern_ = 0;
  long analyses_ = 0, factorizations_ = 0;
};

std::unique_ptr<LinearSolver> make_linear_solver(SolverKind kind);
SolverKind solver_kind_from_name(std::string_view name);  ///< throws std::invalid_argument

}  // namespace velum
