// A supernodal LU for structurally symmetric, numerically unsymmetric matrices (the membrane
// Jacobians with a follower pressure): dense panels per supernode (supernodes.hpp), dense
// kernels (Eigen) for the diagonal block's LU, the two triangular solves and the update, and
// a static pivot order: rows are exchanged only within a supernode's diagonal block. That is
// fast and usually enough (a Newton tangent's pivot order is stable), but not always: when a
// pivot is zero, a multiplier exceeds kMultiplierLimit (the threshold KLU's own pivoting
// applies, 1/0.001) or the pivots span more than 1/kSmallestPivotRatio, the factorisation
// reports failure and the caller factorises with full pivoting instead (KLU, in `auto`).
#pragma once

#include <string>
#include <vector>

#include "supernodes.hpp"
#include "velum/solve/linear_solver.hpp"

namespace velum {

class SupernodalLu final : public LinearSolver {
 public:
  static constexpr double kMultiplierLimit = 1e3;
  static constexpr double kSmallestPivotRatio = 1e-12;

  explicit SupernodalLu(const Amalgamation& relax = {}) : relax_(relax) {}
  std::string_view name() const override { return "supernodal-lu"; }
  bool symmetric_only() const override { return false; }
  bool analyze(const SparseMatrix& A) override;
  bool factorize(const SparseMatrix& A) override;
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;
  std::string status() const override { return status_; }

  const SupernodalStructure& structure() const { return st_; }
  /// min |u_kk| / max |u_kk| and the largest |l_ij| of the last factorisation.
  double pivot_ratio() const { return pivot_ratio_; }
  double largest_multiplier() const { return largest_multiplier_; }

 private:
  bool factor_supernode(int s);
  void scatter_update(int s);

  Amalgamation relax_;
  SupernodalStructure st_;
  std::vector<double> values_, update_, gather_, y_;
  std::vector<double> triangles_;  ///< a diagonal block's U11ᵀ and unit L11, apart
  std::vector<int> swap_;          ///< swap_[k]: the row exchanged with row k (same supernode)
  bool factorized_ = false;
  double pivot_ratio_ = 0, largest_multiplier_ = 0, smallest_pivot_ = 0, largest_pivot_ = 0;
  std::string status_;
};

}  // namespace velum
