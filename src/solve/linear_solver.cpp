#include "velum/solve/linear_solver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/KLUSupport>
#include <Eigen/UmfPackSupport>
#include <stdexcept>

namespace velum {
namespace {

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

class Cholmod final : public EigenSolver<Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower>> {
 public:
  Cholmod() : EigenSolver("cholmod", true) {}
  bool factorize(const SparseMatrix& A) override {
    impl_.factorize(A);
    // CHOLMOD reports a non-positive pivot through its common status, not through info().
    return impl_.info() == Eigen::Success && impl_.cholmod().status == CHOLMOD_OK;
  }
};

class UmfPack final : public EigenSolver<Eigen::UmfPackLU<SparseMatrix>> {
 public:
  UmfPack() : EigenSolver("umfpack", false) {
    // Newton corrects the solution anyway: iterative refinement only costs time.
    impl_.umfpackControl()(UMFPACK_IRSTEP) = 0;
  }
};

}  // namespace

std::unique_ptr<LinearSolver> make_linear_solver(SolverKind kind) {
  switch (kind) {
    case SolverKind::kCholmod:
      return std::make_unique<Cholmod>();
    case SolverKind::kKlu:
      return std::make_unique<EigenSolver<Eigen::KLU<SparseMatrix>>>("klu", false);
    case SolverKind::kAuto:
    case SolverKind::kUmfpack:
      return std::make_unique<UmfPack>();
  }
  return nullptr;
}

SolverKind solver_kind_from_name(std::string_view n) {
  if (n == "auto") return SolverKind::kAuto;
  if (n == "cholmod") return SolverKind::kCholmod;
  if (n == "umfpack") return SolverKind::kUmfpack;
  if (n == "klu") return SolverKind::kKlu;
  throw std::invalid_argument("unknown linear solver '" + std::string(n) + "'");
}

}  // namespace velum
