#include "velum/time/secant_updates.hpp"

#include <cmath>

namespace velum {

void SecantUpdates::open(const VecX& r) {
  r_open_ = r;
  open_ = true;
}

void SecantUpdates::close(const SecondOrderSystem& sys, const VecX& s, const VecX& r) {
  if (!open_) return;
  open_ = false;
  r_open_ = r - r_open_;  // y, in place
  const double sy = sys.dot(s, r_open_);
  // Curvature lost against the vectors' sizes makes 1/(s·y) meaningless: such a pair is left
  // out (Nocedal & Wright, section 6.1), as one of negative curvature is.
  if (!(sy > 1e-10 * sys.norm(s) * sys.norm(r_open_))) return;
  const int slot = (newest_ + 1) % capacity_;
  if (static_cast<int>(s_.size()) <= slot) {
    s_.emplace_back();
    y_.emplace_back();
    rho_.push_back(0);
  }
  s_[slot] = s;
  y_[slot].swap(r_open_);
  rho_[slot] = 1 / sy;
  newest_ = slot;
  if (count_ < capacity_) ++count_;
}

bool SecantUpdates::solve(const SecondOrderSystem& sys, LinearSolver& solver, const VecX& b,
                          VecX& x, double residual) {
  if (count_ == 0) return solver.solve_within(b, x, residual);
  // Two loops over the pairs, newest first, then oldest first, around the factor's solve.
  q_ = b;
  auto slot = [&](int k) { return (newest_ - k + capacity_) % capacity_; };  // k-th newest
  for (int k = 0; k < count_; ++k) {
    const int i = slot(k);
    alpha_[i] = rho_[i] * sys.dot(s_[i], q_);
    q_.noalias() -= alpha_[i] * y_[i];
  }
  if (!solver.solve_within(q_, x, residual)) return false;
  for (int k = count_ - 1; k >= 0; --k) {
    const int i = slot(k);
    const double beta = rho_[i] * sys.dot(y_[i], x);
    x.noalias() += (alpha_[i] - beta) * s_[i];
  }
  return true;
}

}  // namespace velum
