#include "velum/solve/linear_solver.hpp"

#include <fmt/format.h>
#include <klu.h>
#include <omp.h>
#include <Eigen/CholmodSupport>
#include <Eigen/UmfPackSupport>
#include <limits>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "mumps_solver.hpp"
#include "ordering.hpp"
#include "supernodal_cholesky.hpp"
#include "supernodal_lu.hpp"
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

// CHOLMOD 3.0 (SuiteSparse 5.12) runs loops of its supernodal factorisation in OpenMP regions
// with num_threads(CHOLMOD_OMP_NUM_THREADS), a constant 4, whatever the program's thread count:
// on Hencky quad4 n = 130 with --threads 1, three extra threads took 28 % of the run's CPU
// samples, most of it spinning in libgomp and the kernel, on this 2-core machine (24.4 s CPU
// with OMP_THREAD_LIMIT=1, 35.7 s without). Those loops copy and clear; the BLAS (dgemm,
// dsyrk), which does the work, has its own threads (--threads). While CHOLMOD runs, no
// OpenMP region may be active (max-active-levels 0): its regions run on the calling thread.
class SerialOpenMp {
 public:
  SerialOpenMp() : levels_(omp_get_max_active_levels()) { omp_set_max_active_levels(0); }
  ~SerialOpenMp() { omp_set_max_active_levels(levels_); }
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;

 private:
  int levels_;
};

class Cholmod final : public EigenSolver<Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower>> {
 public:
  // A non-positive pivot is reported through the status (and `auto` falls back to LU), not
  // printed on the user's console by CHOLMOD itself.
  // METIS nested dissection: at 118,803 DOF (200x200 quad4) 2% faster factorisations and 3%
  // less memory than CHOLMOD's default AMD, for an analysis of 0.29 s instead of 0.07 s once
  // per run (bench BM_Factorize/200).
  // check_symmetry: CHOLMOD reads the lower triangle only, so a matrix chosen by the user is
  // checked at every factorisation (one pass over the entries, against a factorisation's many):
  // an unsymmetric one (a follower pressure on a surface with a free edge, drag) would be
  // factorised as a different, symmetric matrix. `auto` checks before it calls CHOLMOD.
  explicit Cholmod(bool check_symmetry = true)
      : EigenSolver("cholmod", true), check_symmetry_(check_symmetry) {
    impl_.cholmod().print = 0;
    impl_.cholmod().nmethods = 1;
    impl_.cholmod().method[0].ordering = CHOLMOD_METIS;
  }
  bool analyze(const SparseMatrix& A) override {
    if (check_symmetry_) check_.map(A);
    SerialOpenMp serial;
    return EigenSolver::analyze(A);
  }
  bool factorize(const SparseMatrix& A) override {
    if (check_symmetry_) {
      const double asym = check_.asymmetry(A);
      if (!(asym <= SymmetryCheck::kTolerance))
        throw std::invalid_argument(fmt::format(
            "linear_solver: cholmod factorises symmetric matrices only (it reads the lower "
            "triangle), but this Jacobian is unsymmetric (max |a_ij - a_ji| = {:.2e} max "
            "|a_ij|; a follower pressure on a surface with a free edge or drag make it so): "
            "use linear_solver: auto, klu, umfpack or mumps",
            asym));
    }
    SerialOpenMp serial;
    impl_.factorize(A);
    // CHOLMOD reports a non-positive pivot through its common status, not through info().
    factorized_ = impl_.info() == Eigen::Success && impl_.cholmod().status == CHOLMOD_OK;
    return factorized_;
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    SerialOpenMp serial;
    return EigenSolver::solve(b, x);
  }
  int negative_pivots() const override { return factorized_ ? 0 : -1; }  // definite

 private:
  bool check_symmetry_;
  SymmetryCheck check_;
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
  // No iterative refinement (UMFPACK_IRSTEP = 0; UMFPACK's default is up to 2 steps): Newton
  // corrects what a step of refinement would, and on the C9 canopy's Jacobian a refined solve
  // cost 1.5 ms against 0.18 ms without (the refinement's residual pass and its second
  // solve), 15% of a Newton iteration, for residuals of 2e-13 against 4e-13.
  // METIS ordering: 10% faster factorisations than the default AMD at 118,803 DOF (768 ->
  // 692 ms, bench BM_Factorize/200), for 0.24 s more analysis once per run.
  UmfPack() : EigenSolver("umfpack", false) {
    impl_.umfpackControl()(UMFPACK_ORDERING) = UMFPACK_ORDERING_METIS;
    impl_.umfpackControl()(UMFPACK_IRSTEP) = 0;
  }
};

// KLU keeping its pivot order between factorisations of one pattern: klu_refactor reuses the
// rows chosen by the last full klu_factor (no pivot search, no symbolic work: about half the
// cost of klu_factor on the C9 canopy's Jacobian). A Newton tangent changes little from one
// iteration to the next, so the old pivots usually stay good; when they do not (the estimate
// of the reciprocal condition number min |u_kk| / max |u_kk| fell below kWorse times the last
// full factorisation's, or the refactorisation met a zero pivot), the matrix is factorised
// again with pivoting and its new order is kept. (KLU's reciprocal pivot growth, klu_rgrowth,
// would be the finer test, but it costs a fifth of a refactorisation on the C9's Jacobian.)
class Klu final : public LinearSolver {
 public:
  // No row scaling and no check of the matrix (scale = -1; KLU's default divides every row by
  // its largest entry, and scale = 0 still walks the matrix to check it, at every
  // refactorisation: 6 % of a refactorisation of the C9 canopy's Jacobian). The rows, all
  // translational equations in one set of units, need no equilibration, and the matrix comes
  // from Eigen compressed, sorted, without duplicates: there is nothing to check.
  Klu() {
    klu_defaults(&common_);
    common_.scale = -1;
  }
  ~Klu() override { release(); }
  Klu(const Klu&) = delete;
  Klu& operator=(const Klu&) = delete;
  std::string_view name() const override { return "klu"; }
  bool symmetric_only() const override { return false; }
  // Ordering: METIS nested dissection of the node graph (ordering.hpp): on the C9 canopy's
  // Jacobian 10.8 MFlop and 186k entries in L + U against 13.1 MFlop and 197k with KLU's AMD,
  // and refactorisations 18% faster. KLU's AMD when METIS fails.
  bool analyze(const SparseMatrix& A) override {
    release();
    n_ = static_cast<int>(A.rows());
    int* outer = const_cast<int*>(A.outerIndexPtr());
    int* inner = const_cast<int*>(A.innerIndexPtr());
    const std::vector<int> position = nested_dissection(A);
    if (static_cast<int>(position.size()) == n_) {
      std::vector<int> order(n_);  // order[k] = the equation pivoted k-th
      for (int i = 0; i < n_; ++i) order[position[i]] = i;
      symbolic_ = klu_analyze_given(n_, outer, inner, order.data(), order.data(), &common_);
    } else {
      symbolic_ = klu_analyze(n_, outer, inner, &common_);
    }
    return symbolic_ != nullptr;
  }
  bool factorize(const SparseMatrix& A) override {
    if (!symbolic_) return false;
    int* outer = const_cast<int*>(A.outerIndexPtr());
    int* inner = const_cast<int*>(A.innerIndexPtr());
    double* values = const_cast<double*>(A.valuePtr());
    if (numeric_ && klu_refactor(outer, inner, values, symbolic_, numeric_, &common_) &&
        common_.status == KLU_OK && quality() && common_.rcond >= kWorse * rcond_)
      return true;
    if (numeric_) klu_free_numeric(&numeric_, &common_);
    numeric_ = klu_factor(outer, inner, values, symbolic_, &common_);
    ++full_factorizations_;
    if (!numeric_ || common_.status != KLU_OK || !quality()) {
      if (numeric_) klu_free_numeric(&numeric_, &common_);
      return false;
    }
    rcond_ = common_.rcond;
    return rcond_ > 0;
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    if (!numeric_) return false;
    x = b;
    return klu_solve(symbolic_, numeric_, n_, 1, x.data(), &common_) && x.allFinite();
  }
  std::string status() const override {
    if (common_.status == KLU_SINGULAR) return "KLU: singular matrix";
    if (common_.status == KLU_OUT_OF_MEMORY) return "KLU: out of memory";
    return common_.status == KLU_OK ? std::string()
                                    : "KLU status " + std::to_string(common_.status);
  }
  /// Factorisations with a pivot search (the others reused the pivot order).
  long full_factorizations() const { return full_factorizations_; }

 private:
  static constexpr double kWorse = 1e-2;
  bool quality() {
    return klu_rcond(symbolic_, numeric_, &common_) && std::isfinite(common_.rcond);
  }
  void release() {
    if (numeric_) klu_free_numeric(&numeric_, &common_);
    if (symbolic_) klu_free_symbolic(&symbolic_, &common_);
  }
  klu_common common_{};
  klu_symbolic* symbolic_ = nullptr;
  klu_numeric* numeric_ = nullptr;
  int n_ = 0;
  double rcond_ = 0;  ///< of the last full factorisation
  long full_factorizations_ = 0;
};

// A fast path that may refuse a matrix (a Cholesky meeting an indefinite one, an LU whose
// pivots must leave their block): a refusal costs the fast attempt on top of the fallback's
// factorisation, so after one the next 1, 2, 4 ... 64 factorisations skip it; a success
// resets the count.
class BackOff {
 public:
  /// Whether this factorisation skips the fast path (counting it).
  bool skip() {
    if (skip_ == 0) return false;
    --skip_;
    return true;
  }
  void succeeded() { backoff_ = 1; }
  void refused() {
    skip_ = backoff_;
    backoff_ = std::min(2 * backoff_, 64);
  }

 private:
  int skip_ = 0, backoff_ = 1;
};

// `auto`'s LU of unsymmetric matrices: the supernodal LU (dense kernels, rows exchanged only
// within a supernode's diagonal block) and, for a factorisation it refuses (a zero pivot, a
// multiplier over 1e3, pivots spanning over 1e12: supernodal_lu.hpp), a factorisation with
// full pivoting: KLU up to kKluLimit equations, UMFPACK above. A refused factorisation costs
// one supernodal factorisation on top of the fallback's, so after a refusal the next 1, 2, 4
// ... 64 factorisations go to the fallback directly before the supernodal LU is tried again;
// a success resets the count.
class SupernodalLuWithFallback final : public LinearSolver {
 public:
  static constexpr Eigen::Index kKluLimit = 6000;

  std::string_view name() const override { return active_ ? active_->name() : fast_.name(); }
  bool symmetric_only() const override { return false; }
  bool analyze(const SparseMatrix& A) override {
    fast_analyzed_ = fast_.analyze(A);
    if (A.rows() <= kKluLimit)
      fallback_ = std::make_unique<Klu>();
    else
      fallback_ = std::make_unique<UmfPack>();
    fallback_analyzed_ = false;
    backoff_ = BackOff{};
    active_ = nullptr;
    return true;
  }
  bool factorize(const SparseMatrix& A) override {
    if (!backoff_.skip() && fast_analyzed_) {
      active_ = &fast_;
      if (fast_.factorize(A)) {
        backoff_.succeeded();
        return true;
      }
      ++refusals_;
      backoff_.refused();
    }
    if (!fallback_analyzed_) fallback_analyzed_ = fallback_->analyze(A);
    active_ = fallback_.get();
    return fallback_analyzed_ && fallback_->factorize(A);
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    return active_ && active_->solve(b, x);
  }
  std::string status() const override {
    if (!active_ || active_ == &fast_) return fast_.status();
    const std::string s = fallback_->status();
    return s.empty() || fast_.status().empty() ? s : fast_.status() + "; then " + s;
  }
  long refusals() const { return refusals_; }

 private:
  SupernodalLu fast_;
  std::unique_ptr<LinearSolver> fallback_;
  LinearSolver* active_ = nullptr;
  bool fast_analyzed_ = false, fallback_analyzed_ = false;
  BackOff backoff_;
  long refusals_ = 0;
};

// Numerically symmetric matrices (|A − Aᵀ| <= 1e-10 |A|, tested at every factorisation): the
// supernodal Cholesky while the matrix is positive definite, MUMPS's LDLᵀ (which gives the
// inertia) for a matrix it refuses and, backing off, for the next 1, 2, 4 ... 64 (Hencky quad4
// n = 130, 151,970 equations: 10.4 to 11.6 s CPU for the run against 15.9 to 18.9 with MUMPS
// alone, docs/performance.md section 14); without MUMPS in the build, CHOLMOD, with LU while
// the matrix is indefinite. Unsymmetric matrices: the supernodal
// LU (KLU or UMFPACK when it refuses a factorisation) up to kSupernodalLimit equations, UMFPACK
// above. CPU ms per factorisation of C9 canopy Jacobians (docs/performance.md, section 13):
// 2,021 equations 0.98 (KLU's refactorisation 3.4, UMFPACK 4.9); 7,980: 6.3 (KLU 31, UMFPACK
// 25); 30,492: 46 (KLU 262, UMFPACK 132); 119,868: 281 (UMFPACK 1,050); the limit is the
// largest size measured, not a crossover. A
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
    chol_ = std::make_unique<Cholmod>(false);
    chol_analyzed_ = false;
    return false;
  }
  void release_lu() {
    if (!lu_analyzed_) return;
    lu_ = make_lu();
    lu_analyzed_ = false;
  }
  std::unique_ptr<LinearSolver> make_lu() const {
    if (small_) return std::make_unique<SupernodalLuWithFallback>();
    return std::make_unique<UmfPack>();
  }
  static constexpr Eigen::Index kSupernodalLimit = 125000;

  SymmetryCheck check_;
  std::unique_ptr<LinearSolver> sym_ = make_mumps_solver(true);  ///< null without MUMPS
  /// With MUMPS in the build; CHOLMOD's role without. Float panels refined in double above
  /// SupernodalCholesky::kMixedFlops (Hencky quad4 n = 130: 7% less CPU for the run, 11% less
  /// memory; n = 220: 6% less CPU, 9% more memory; the same iterations; docs/performance.md
  /// section 20).
  SupernodalCholesky spd_{
      {}, SupernodalCholesky::kSplitFlops, SupernodalCholesky::Precision::kAuto};
  bool spd_analyzed_ = false;
  BackOff spd_backoff_;  ///< MUMPS factorisations before spd_ is tried again
  std::unique_ptr<LinearSolver> chol_ = std::make_unique<Cholmod>(false);
  std::unique_ptr<LinearSolver> lu_;
  bool small_ = true;  ///< LU by the supernodal LU (else UMFPACK)
  LinearSolver* active_ = nullptr;
  bool sym_analyzed_ = false, chol_analyzed_ = false, lu_analyzed_ = false;
  BackOff backoff_;  ///< LU factorisations before CHOLMOD is tried again
};

}  // namespace

std::unique_ptr<LinearSolver> make_linear_solver(SolverKind kind) {
  switch (kind) {
    case SolverKind::kCholmod:
      return std::make_unique<Cholmod>();
    case SolverKind::kKlu:
      return std::make_unique<Klu>();
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
