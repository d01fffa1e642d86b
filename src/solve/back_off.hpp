// When to try a fast factorisation again after it refused a matrix: the count of
// factorisations that skip it doubles after each refusal, up to 64.
#pragma once

#include <algorithm>

namespace velum {

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

}  // namespace velum
