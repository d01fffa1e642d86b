#include "velum/time/low_rank_solver.hpp"

#include <cmath>

namespace velum {

bool LowRankCorrectedSolver::factorize(const SparseMatrix& A) {
  singular_capacitance_ = false;
  if (!sparse_.refactorize(A)) return false;
  const LowRankJacobian& L = sys_.jacobian_low_rank();
  const Eigen::Index k = L.U.cols();
  Z_.resize(A.rows(), k);
  W_ = L.W;
  VecX z;
  for (Eigen::Index j = 0; j < k; ++j) {
    if (!sparse_.solve(L.U.col(j), z)) return false;
    Z_.col(j) = z;
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
