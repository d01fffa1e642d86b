#include "lu_with_fallback.hpp"

#include <string>

#include "back_off.hpp"
#include "klu_solver.hpp"
#include "supernodal_lu.hpp"
#include "umfpack_solver.hpp"

namespace velum {
namespace {

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
      fallback_ = make_klu_solver();
    else
      fallback_ = make_umfpack_solver();
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

}  // namespace

std::unique_ptr<LinearSolver> make_supernodal_lu_with_fallback() {
  return std::make_unique<SupernodalLuWithFallback>();
}

}  // namespace velum
