#include "velum/solve/linear_solver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/KLUSupport>
#include <Eigen/UmfPackSupport>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "mumps_solver.hpp"
#include "symmetry.hpp"
#include "velum/solve/petsc_solver.hpp"

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
    factorized_ = impl_.info() == Eigen::Success && impl_.cholmod().status == CHOLMOD_OK;
    return factorized_;
  }
  int negative_pivots() const override { return factorized_ ? 0 : -1; }  // definite

 private:
  bool factorized_ = false;
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

// Numerically symmetric matrices (|A − Aᵀ| <= 1e-10 |A|, tested at every factorisation): MUMPS's
// LDLᵀ, definite or not (pivoting only once a pivot comes out negative); without MUMPS in the
// build, CHOLMOD, with LU while the matrix is indefinite. Unsymmetric matrices: UMFPACK. A
// follower-pressure load stiffness is unsymmetric element by element, but on a surface whose
// boundary is held (a clamped or closed membrane) the assembled sum is symmetric, and a symmetric
// factorisation stores one triangle.
class AutoSolver final : public LinearSolver {
 public:
  std::string_view name() const override { return active_ ? active_->name() : "auto"; }
  bool symmetric_only() const override { return false; }
  bool analyze(const SparseMatrix& A) override {
    check_.map(A);
    sym_analyzed_ = chol_analyzed_ = lu_analyzed_ = false;
    return true;
  }
  bool factorize(const SparseMatrix& A) override {
    if (check_.symmetric(A)) {
      if (sym_) {
        if (!sym_analyzed_) sym_analyzed_ = sym_->analyze(A);
        release_lu();
        active_ = sym_.get();
        return sym_analyzed_ && sym_->factorize(A);
      }
      if (cholesky(A)) return true;
    }
    if (sym_ && sym_analyzed_) {  // one factorisation in memory at a time
      sym_ = make_mumps_solver(true);
      sym_analyzed_ = false;
    }
    if (!lu_analyzed_) lu_analyzed_ = lu_->analyze(A);
    active_ = lu_.get();
    return lu_analyzed_ && lu_->factorize(A);
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    return active_ && active_->solve(b, x);
  }
  std::string status() const override { return active_ ? active_->status() : std::string(); }
  int negative_pivots() const override { return active_ ? active_->negative_pivots() : -1; }

 private:
  // Without MUMPS: after an indefinite matrix, CHOLMOD is tried again after 1, 2, 4 ... 64
  // factorisations with LU (a static inflation is indefinite while the sheet is slack).
  bool cholesky(const SparseMatrix& A) {
    if (skip_ > 0) {
      --skip_;
      return false;
    }
    if (!chol_analyzed_) chol_analyzed_ = chol_->analyze(A);
    if (chol_analyzed_ && chol_->factorize(A)) {
      active_ = chol_.get();
      backoff_ = 1;
      release_lu();
      return true;
    }
    skip_ = backoff_;
    backoff_ = std::min(2 * backoff_, 64);
    chol_ = std::make_unique<Cholmod>();
    chol_analyzed_ = false;
    return false;
  }
  void release_lu() {
    if (!lu_analyzed_) return;
    lu_ = std::make_unique<UmfPack>();
    lu_analyzed_ = false;
  }

  SymmetryCheck check_;
  std::unique_ptr<LinearSolver> sym_ = make_mumps_solver(true);  ///< null without MUMPS
  std::unique_ptr<LinearSolver> chol_ = std::make_unique<Cholmod>();
  std::unique_ptr<LinearSolver> lu_ = std::make_unique<UmfPack>();
  LinearSolver* active_ = nullptr;
  bool sym_analyzed_ = false, chol_analyzed_ = false, lu_analyzed_ = false;
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
    case SolverKind::kMumps:
      return make_mumps_solver();
    case SolverKind::kPetsc:
      return make_petsc_solver({});
  }
  return nullptr;
}

SolverKind solver_kind_from_name(std::string_view n) {
  if (n == "auto") return SolverKind::kAuto;
  if (n == "cholmod") return SolverKind::kCholmod;
  if (n == "umfpack") return SolverKind::kUmfpack;
  if (n == "klu") return SolverKind::kKlu;
  if (n == "mumps") return SolverKind::kMumps;
  if (n == "petsc") return SolverKind::kPetsc;
  throw std::invalid_argument("unknown linear solver '" + std::string(n) + "'");
}

}  // namespace velum
