#include "auto_solver.hpp"

#include <limits>
#include <string>

#include "back_off.hpp"
#include "cholmod_solver.hpp"
#include "lu_with_fallback.hpp"
#include "mumps_solver.hpp"
#include "supernodal_cholesky.hpp"
#include "symmetry.hpp"
#include "umfpack_solver.hpp"

namespace velum {
namespace {

// Numerically symmetric matrices (|A − Aᵀ| <= 1e-10 |A|, tested at every factorisation): the
// supernodal Cholesky while the matrix is positive definite (much faster than MUMPS's LDLᵀ on
// these matrices: docs/performance.md), MUMPS's LDLᵀ (which gives the inertia) for a matrix it
// refuses and, backing off, for the next 1, 2, 4 ... 64; without MUMPS in the build, CHOLMOD,
// with LU while the matrix is indefinite. Unsymmetric matrices: the supernodal LU (KLU or
// UMFPACK when it refuses a factorisation) up to kSupernodalLimit equations, UMFPACK above.
// The supernodal LU was faster than KLU's refactorisation and UMFPACK at every size measured,
// from the C9 canopy's 2,000 equations to 120,000; the limit is the largest size measured, not
// a crossover. A
// follower-pressure load stiffness is unsymmetric element by element, but on a surface whose
// boundary is held (a clamped or closed membrane) the assembled sum is symmetric, and a symmetric
// factorisation stores one triangle.
class AutoSolver final : public LinearSolver {
 public:
  std::string_view name() const override { return active_ ? active_->name() : "auto"; }
  bool symmetric_only() const override { return false; }
  bool analyze(const SparseMatrix& A) override {
    check_.map(A);
    sym_analyzed_ = chol_analyzed_ = lu_analyzed_ = spd_analyzed_ = false;
    spd_backoff_ = BackOff{};
    small_ = A.rows() <= kSupernodalLimit;
    lu_ = make_lu();
    return true;
  }
  bool factorize(const SparseMatrix& A) override {
    if (check_.symmetric(A)) {
      if (sym_) {
        if (supernodal_cholesky(A)) return true;
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
  bool solve_within(const Eigen::VectorXd& b, Eigen::VectorXd& x, double residual) override {
    return active_ && active_->solve_within(b, x, residual);
  }
  double one_pass_accuracy() const override {
    return active_ ? active_->one_pass_accuracy() : std::numeric_limits<double>::quiet_NaN();
  }
  std::string status() const override { return active_ ? active_->status() : std::string(); }
  int negative_pivots() const override { return active_ ? active_->negative_pivots() : -1; }

 private:
  // The supernodal Cholesky while the matrix is positive definite; after a refusal (a pivot not
  // positive: indefinite or singular), MUMPS's LDLᵀ, which gives the inertia, for the next 1,
  // 2, 4 ... 64 factorisations before the Cholesky is tried again (a success resets the count).
  bool supernodal_cholesky(const SparseMatrix& A) {
    if (spd_backoff_.skip()) return false;
    if (!spd_analyzed_) spd_analyzed_ = spd_.analyze(A);
    active_ = &spd_;
    if (spd_analyzed_ && spd_.factorize(A)) {
      spd_backoff_.succeeded();
      release_lu();
      if (sym_analyzed_) {  // one factorisation in memory at a time
        sym_ = make_mumps_solver(true);
        sym_analyzed_ = false;
      }
      return true;
    }
    spd_backoff_.refused();
    return false;
  }
  // Without MUMPS: after an indefinite matrix, CHOLMOD is tried again after 1, 2, 4 ... 64
  // factorisations with LU (a static inflation is indefinite while the sheet is slack).
  bool cholesky(const SparseMatrix& A) {
    if (backoff_.skip()) return false;
    if (!chol_analyzed_) chol_analyzed_ = chol_->analyze(A);
    if (chol_analyzed_ && chol_->factorize(A)) {
      active_ = chol_.get();
      backoff_.succeeded();
      release_lu();
      return true;
    }
    backoff_.refused();
    chol_ = make_cholmod_solver(false);
    chol_analyzed_ = false;
    return false;
  }
  void release_lu() {
    if (!lu_analyzed_) return;
    lu_ = make_lu();
    lu_analyzed_ = false;
  }
  std::unique_ptr<LinearSolver> make_lu() const {
    if (small_) return make_supernodal_lu_with_fallback();
    return make_umfpack_solver();
  }
  static constexpr Eigen::Index kSupernodalLimit = 125000;

  SymmetryCheck check_;
  std::unique_ptr<LinearSolver> sym_ = make_mumps_solver(true);  ///< null without MUMPS
  /// With MUMPS in the build; CHOLMOD's role without. Float panels refined in double above
  /// SupernodalCholesky::kMixedFlops: less CPU for a large run with the same iterations (the
  /// float factor is cheaper and a refined solve costs less than the factorisation saves).
  SupernodalCholesky spd_{
      {}, SupernodalCholesky::kSplitFlops, SupernodalCholesky::Precision::kAuto};
  bool spd_analyzed_ = false;
  BackOff spd_backoff_;  ///< MUMPS factorisations before spd_ is tried again
  std::unique_ptr<LinearSolver> chol_ = make_cholmod_solver(false);
  std::unique_ptr<LinearSolver> lu_;
  bool small_ = true;  ///< LU by the supernodal LU (else UMFPACK)
  LinearSolver* active_ = nullptr;
  bool sym_analyzed_ = false, chol_analyzed_ = false, lu_analyzed_ = false;
  BackOff backoff_;  ///< LU factorisations before CHOLMOD is tried again
};

}  // namespace

std::unique_ptr<LinearSolver> make_auto_solver() {
  return std::make_unique<AutoSolver>();
}

}  // namespace velum
