// A dense LU of the matrix handed to it, as a LinearSolver: the base of the Newton tests'
// solvers that each change one behaviour (what a first step returns, what a solve is asked
// for, the inertia reported).
#pragma once

#include <Eigen/Dense>
#include <string_view>

#include "velum/solve/linear_solver.hpp"

namespace velum::test {

class DenseSolver : public LinearSolver {
 public:
  std::string_view name() const override { return "dense"; }
  bool analyze(const SparseMatrix&) override { return true; }
  bool factorize(const SparseMatrix& A) override {
    lu_.compute(Eigen::MatrixXd(A));
    return true;
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    x = lu_.solve(b);
    return true;
  }
  bool symmetric_only() const override { return false; }

 protected:
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
};

}  // namespace velum::test
