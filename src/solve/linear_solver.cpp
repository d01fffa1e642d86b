#include "velum/solve/linear_solver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/KLUSupport>
#include <Eigen/UmfPackSupport>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

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
  // A non-positive pivot is reported through the status (and `auto` falls back to LU), not
  // printed on the user's console by CHOLMOD itself.
  // METIS nested dissection: at 118,803 DOF (200x200 quad4) 2% faster factorisations and 3%
  // less memory than CHOLMOD's default AMD, for an analysis of 0.29 s instead of 0.07 s once
  // per run (bench BM_Factorize/200).
  Cholmod() : EigenSolver("cholmod", true) {
    impl_.cholmod().print = 0;
    impl_.cholmod().nmethods = 1;
    impl_.cholmod().method[0].ordering = CHOLMOD_METIS;
  }
  bool factorize(const SparseMatrix& A) override {
    impl_.factorize(A);
    // CHOLMOD reports a non-positive pivot through its common status, not through info().
    return impl_.info() == Eigen::Success && impl_.cholmod().status == CHOLMOD_OK;
  }
};

// Eigen's UmfPackLU keeps the numeric factorisation's return code protected (its accessor
// asserts on a factorisation that failed to allocate): expose it.
class UmfPackLUWithStatus : public Eigen::UmfPackLU<SparseMatrix> {
 public:
  int return_code() const { return static_cast<int>(m_fact_errorCode); }
};

class UmfPack final : public EigenSolver<UmfPackLUWithStatus> {
 public:
  std::string status() const override {
    // UMFPACK_WARNING_singular_matrix (1) versus out of memory (-1) and the like.
    const int code = impl_.return_code();
    return code == UMFPACK_OK                        ? std::string()
           : code == UMFPACK_WARNING_singular_matrix ? "UMFPACK: singular matrix"
           : code == UMFPACK_ERROR_out_of_memory     ? "UMFPACK: out of memory (status -1)"
                                                     : "UMFPACK status " + std::to_string(code);
  }
  // UMFPACK's iterative refinement is kept: it costs about 10% of a small run, but without
  // it Newton stalled at 1.2x the tolerance on a 152k-DOF static membrane.
  // METIS ordering: 10% faster factorisations than the default AMD at 118,803 DOF (768 ->
  // 692 ms, bench BM_Factorize/200), for 0.24 s more analysis once per run.
  UmfPack() : EigenSolver("umfpack", false) {
    impl_.umfpackControl()(UMFPACK_ORDERING) = UMFPACK_ORDERING_METIS;
  }
};

// CHOLMOD while the assembled matrix is numerically symmetric and positive definite, UMFPACK
// otherwise (structurally unsymmetric patterns: UMFPACK only). A follower-pressure load stiffness
// is unsymmetric element by element, but on a surface whose boundary is held (a clamped or closed
// membrane) the assembled sum is symmetric: there the Cholesky factorisation is exact and several
// times cheaper than LU.
class AutoSolver final : public LinearSolver {
 public:
  std::string_view name() const override { return active_ ? active_->name() : "auto"; }
  bool symmetric_only() const override { return false; }
  bool analyze(const SparseMatrix& A) override {
    // Index of the transposed entry of every stored entry (the pattern is structurally
    // symmetric), so the symmetry test costs one pass without allocating.
    mirror_.assign(A.nonZeros(), -1);
    for (int j = 0; j < A.outerSize(); ++j)
      for (int k = A.outerIndexPtr()[j]; k < A.outerIndexPtr()[j + 1]; ++k) {
        const int i = A.innerIndexPtr()[k];
        const int* lo = A.innerIndexPtr() + A.outerIndexPtr()[i];
        const int* hi = A.innerIndexPtr() + A.outerIndexPtr()[i + 1];
        const int* pos = std::lower_bound(lo, hi, j);
        if (pos == hi || *pos != j) {  // structurally unsymmetric: LU only
          cholmod_ok_ = false;
          return lu_analyzed_ = lu_->analyze(A);
        }
        mirror_[k] = static_cast<int>(pos - A.innerIndexPtr());
      }
    chol_analyzed_ = lu_analyzed_ = false;
    return true;
  }
  // After an indefinite matrix, CHOLMOD is tried again after 1, 2, 4 ... 64 factorisations
  // with LU: a static inflation is indefinite while the sheet is slack and definite once it
  // carries the load, and a failed Cholesky costs at most one factorisation.
  bool factorize(const SparseMatrix& A) override {
    if (cholmod_ok_ && skip_ > 0)
      --skip_;
    else if (cholmod_ok_ && symmetric(A)) {
      if (!chol_analyzed_) chol_analyzed_ = chol_->analyze(A);
      if (chol_analyzed_ && chol_->factorize(A)) {
        active_ = chol_.get();
        backoff_ = 1;
        if (lu_analyzed_) {  // one factor in memory at a time: the peak is the larger one
          lu_ = std::make_unique<UmfPack>();
          lu_analyzed_ = false;
        }
        return true;
      }
      skip_ = backoff_;
      backoff_ = std::min(2 * backoff_, 64);
      chol_ = std::make_unique<Cholmod>();
      chol_analyzed_ = false;
    }
    if (!lu_analyzed_) lu_analyzed_ = lu_->analyze(A);
    active_ = lu_.get();
    return lu_analyzed_ && lu_->factorize(A);
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    return active_ && active_->solve(b, x);
  }
  std::string status() const override { return active_ ? active_->status() : std::string(); }

 private:
  bool symmetric(const SparseMatrix& A) const {
    const double* v = A.valuePtr();
    double vmax = 0, dmax = 0;
    for (size_t k = 0; k < mirror_.size(); ++k) {
      vmax = std::max(vmax, std::abs(v[k]));
      dmax = std::max(dmax, std::abs(v[k] - v[mirror_[k]]));
    }
    return dmax <= 1e-10 * vmax;
  }

  std::unique_ptr<LinearSolver> chol_ = std::make_unique<Cholmod>();
  std::unique_ptr<LinearSolver> lu_ = std::make_unique<UmfPack>();
  LinearSolver* active_ = nullptr;
  std::vector<int> mirror_;
  bool cholmod_ok_ = true, chol_analyzed_ = false, lu_analyzed_ = false;
  int skip_ = 0, backoff_ = 1;  ///< LU factorisations before CHOLMOD is tried again
};

}  // namespace

std::unique_ptr<LinearSolver> make_linear_solver(SolverKind kind) {
  switch (kind) {
    case SolverKind::kCholmod:
      return std::make_unique<Cholmod>();
    case SolverKind::kKlu:
      return std::make_unique<EigenSolver<Eigen::KLU<SparseMatrix>>>("klu", false);
    case SolverKind::kAuto:
      return std::make_unique<AutoSolver>();
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
