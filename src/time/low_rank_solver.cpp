#include "velum/time/low_rank_solver.hpp"

#include <cmath>

namespace velum {

bool LowRankCorrectedSolver::factorize(const SparseMatrix& A) {
  singular_capacitance_ = false;
  if (!sparse_.refactorize(A, sys_.pattern_revision())) return false;
  const LowRankJacobian& L = sys_.jacobian_low_rank();
  // Only the columns in use (a contact's columns are zero where it has no pair): a zero
  // column adds nothing to U Wᵀ, and leaving it out saves its solve and its capacitance row.
  Eigen::Index k = 0;
  for (Eigen::Index j = 0; j < L.U.cols(); ++j)
    if (!L.U.col(j).isZero(0) && !L.W.col(j).isZero(0)) ++k;
  Z_.resize(A.rows(), k);
  W_.resize(A.rows(), k);
  VecX z;
  for (Eigen::Index j = 0, c = 0; j < L.U.cols(); ++j) {
    if (L.U.col(j).isZero(0) || L.W.col(j).isZero(0)) continue;
    if (!sparse_.solve(L.U.col(j), z)) return false;
    Z_.col(c) = z;
    W_.col(c++) = L.W.col(j);
  }
  if (k == 0) return true;
  const MatX C = MatX::Identity(k, k) + sys_.transposed_product(W_, Z_);
  capacitance_.compute(C);
  // J + U Wᵀ is singular exactly when I + Wᵀ J⁻¹ U is: a pivot lost against the matrix's size.
  const double pivot = capacitance_.matrixLU().diagonal().cwiseAbs().minCoeff();
  singular_capacitance_ = !(pivot > 1e-14 * (1 + C.cwiseAbs().maxCoeff()));
  return !singular_capacitance_;
}

bool LowRankCorrectedSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (!sparse_.solve(b, x)) return false;
  if (Z_.cols() == 0) return true;
  x.noalias() -= Z_ * capacitance_.solve(sys_.transposed_product(W_, x));
  return sys_.all_finite(x);
}

bool LowRankCorrectedSolver::solve_within(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                          double residual) {
  if (Z_.cols() > 0) return solve(b, x);
  return sparse_.solve_within(b, x, residual);
}

std::string LowRankCorrectedSolver::status() const {
  return singular_capacitance_ ? "the gas coupling makes the matrix singular (I + Wᵀ J⁻¹ U)"
                               : sparse_.status();
}

}  // namespace velum
