// Eigen's sparse solvers (analyzePattern / factorize / solve / info) behind the LinearSolver
// interface: the common base of the CHOLMOD and UMFPACK adapters.
#pragma once

#include <Eigen/Core>
#include <string_view>

#include "velum/solve/linear_solver.hpp"

namespace velum {

template <class Impl>
class EigenSolver : public LinearSolver {
 public:
  EigenSolver(std::string_view name, bool sym) : name_(name), sym_(sym) {}
  std::string_view name() const override { return name_; }
  bool symmetric_only() const override { return sym_; }
  bool analyze(const SparseMatrix& A) override {
    impl_.analyzePattern(A);
    return impl_.info() == Eigen::Success;
  }
  bool factorize(const SparseMatrix& A) override {
    impl_.factorize(A);
    return impl_.info() == Eigen::Success;
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    x = impl_.solve(b);
    return impl_.info() == Eigen::Success && x.allFinite();
  }

 protected:
  Impl impl_;

 private:
  std::string_view name_;
  bool sym_;
};

}  // namespace velum
