// A supernodal Cholesky factorisation (LLᵀ) for symmetric positive definite matrices (the
// statics of a prestressed membrane, Hencky's problem): the symbolic analysis of the supernodal
// LU (supernodes.hpp) with L's panels only, dense kernels (Eigen) for the diagonal block's
// Cholesky, the triangular solve of the rows below and the symmetric update, no pivoting. A
// pivot that is not positive and finite, or pivots (l_kk²) spanning more than
// 1/kSmallestPivotRatio, and the factorisation reports failure: the caller factorises with
// MUMPS's LDLᵀ, which also gives the inertia (`auto`).
#pragma once

#include <string>
#include <vector>

#include "supernodes.hpp"
#include "velum/solve/linear_solver.hpp"

namespace velum {

class SupernodalCholesky final : public LinearSolver {
 public:
  static constexpr double kSmallestPivotRatio = 1e-12;

  explicit SupernodalCholesky(const Amalgamation& relax = {}) : relax_(relax) {}
  std::string_view name() const override { return "supernodal-cholesky"; }
  bool symmetric_only() const override { return true; }
  bool analyze(const SparseMatrix& A) override;
  /// Reads the lower triangle of A (and the upper within diagonal blocks: A must be symmetric).
  bool factorize(const SparseMatrix& A) override;
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;
  std::string status() const override { return status_; }
  /// Definite: no negative pivot after a factorisation that succeeded.
  int negative_pivots() const override { return factorized_ ? 0 : -1; }

  const SupernodalStructure& structure() const { return st_; }
  /// min l_kk² / max l_kk² of the last factorisation.
  double pivot_ratio() const { return pivot_ratio_; }

 private:
  bool factor_supernode(int s);
  void scatter_update(int s);

  Amalgamation relax_;
  SupernodalStructure st_;
  std::vector<double> values_, update_, gather_, y_;
  bool factorized_ = false;
  double pivot_ratio_ = 0, smallest_pivot_ = 0, largest_pivot_ = 0;
  std::string status_;
};

}  // namespace velum
