#include "klu_solver.hpp"

#include <klu.h>

#include <cmath>
#include <string>
#include <vector>

#include "ordering.hpp"

namespace velum {
namespace {

// KLU keeping its pivot order between factorisations of one pattern: klu_refactor reuses the
// rows chosen by the last full klu_factor (no pivot search, no symbolic work: a fraction of
// klu_factor's cost). A Newton tangent changes little from one
// iteration to the next, so the old pivots usually stay good; when they do not (the estimate
// of the reciprocal condition number min |u_kk| / max |u_kk| fell below kWorse times the last
// full factorisation's, or the refactorisation met a zero pivot), the matrix is factorised
// again with pivoting and its new order is kept. (KLU's reciprocal pivot growth, klu_rgrowth,
// would be the finer test, but it costs a sizeable part of a refactorisation.)
class Klu final : public LinearSolver {
 public:
  // No row scaling and no check of the matrix (scale = -1; KLU's default divides every row by
  // its largest entry, and scale = 0 still walks the matrix to check it, at every
  // refactorisation, a visible share of a small matrix's refactorisation). The rows, all
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
  // Ordering: METIS nested dissection of the node graph (ordering.hpp): on membrane meshes
  // fewer flops and entries in L + U than KLU's AMD, and faster refactorisations. KLU's AMD
  // when METIS fails.
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

}  // namespace

std::unique_ptr<LinearSolver> make_klu_solver() {
  return std::make_unique<Klu>();
}

}  // namespace velum
