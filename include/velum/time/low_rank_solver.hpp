// A linear solver for J + U Wᵀ (SecondOrderSystem::jacobian_low_rank): the sparse J factorised
// by the wrapped solver, the k dense columns applied by the Sherman-Morrison-Woodbury formula
// (J + U Wᵀ)⁻¹ b = y − Z (I + Wᵀ Z)⁻¹ Wᵀ y with y = J⁻¹ b, Z = J⁻¹ U (k extra
// back-substitutions per factorisation, none per solve). Without low-rank columns it is the
// wrapped solver.
#pragma once

#include <Eigen/LU>

#include "velum/solve/linear_solver.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum {

class LowRankCorrectedSolver final : public LinearSolver {
 public:
  /// Borrows both; the low-rank part is read from `sys` at each factorisation.
  LowRankCorrectedSolver(LinearSolver& sparse, const SecondOrderSystem& sys)
      : sparse_(sparse), sys_(sys) {}

  std::string_view name() const override { return sparse_.name(); }
  /// The wrapped solver analyses (and counts) in its own refactorize.
  bool analyze(const SparseMatrix&) override { return true; }
  bool factorize(const SparseMatrix& A) override;
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override;
  /// Within `residual` where there is no low-rank part; exactly where there is (the Woodbury
  /// correction holds for exact solves).
  bool solve_within(const Eigen::VectorXd& b, Eigen::VectorXd& x, double residual) override;
  /// The wrapped solver's while there is no low-rank part (with one, solves are exact).
  double one_pass_accuracy() const override {
    return Z_.cols() > 0 ? 0.0 : sparse_.one_pass_accuracy();
  }
  bool symmetric_only() const override { return sparse_.symmetric_only(); }
  /// The wrapped solver's while there is no low-rank part (with one: not known).
  int negative_pivots() const override { return Z_.cols() > 0 ? -1 : sparse_.negative_pivots(); }
  std::string status() const override;
  const LinearSolver& wrapped() const { return sparse_; }
  const SecondOrderSystem& system() const { return sys_; }

 private:
  LinearSolver& sparse_;
  const SecondOrderSystem& sys_;
  MatX Z_, W_;  ///< J⁻¹ U and W of the factorisation at hand (no columns: none)
  Eigen::PartialPivLU<MatX> capacitance_;  ///< I + Wᵀ Z
  bool singular_capacitance_ = false;
};

}  // namespace velum
