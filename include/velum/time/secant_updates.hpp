// Quasi-Newton corrections on a factorisation made at an earlier iterate: limited-memory BFGS
// updates of its inverse (Matthies & Strang, "The solution of nonlinear finite element
// equations", IJNME 14, 1979; Nocedal's two-loop recursion, Math. Comp. 35, 1980). Each pair
// (s, y), a correction taken and the change of the residual across it, makes the next
// correction satisfy the secant condition H y = s that the old tangent misses; the factor
// stays H's first guess, so a correction costs one solve and a few vector products, no tangent
// and no factorisation.
#pragma once

#include <vector>

#include "velum/solve/linear_solver.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum {

class SecantUpdates {
 public:
  /// At most `capacity` pairs; the oldest is dropped for a new one beyond that.
  explicit SecantUpdates(int capacity = 10) : capacity_(capacity), alpha_(capacity) {}

  /// Forgets every pair (a fresh factorisation: they described the old one's error).
  /// The slots are taken again from the first (newest_ back to none): a run then holds only
  /// as many vectors as one factorisation's pairs ever reached, not the capacity's (Hencky
  /// n = 64: 17 of 21 vectors of 294 kB, each page of them first touched; heap peak 56.6 to
  /// 55.4 MB).
  void clear() { count_ = 0, open_ = false, newest_ = -1; }
  /// A correction is about to be taken from the state whose residual is r.
  void open(const VecX& r);
  /// Ends the open pair: `s` the correction taken in full, `r` the residual where it led.
  /// A pair without positive curvature (s·y <= 0: no symmetric positive update fits it) is
  /// left out.
  void close(const SecondOrderSystem& sys, const VecX& s, const VecX& r);
  /// A correction not taken in full (cut by a line search, taken back) closes no pair.
  void cancel() { open_ = false; }
  int size() const { return count_; }

  /// x = H b, H the updated inverse of the matrix `solver` factorised, its solve within
  /// `residual` as LinearSolver::solve_within; false when that fails (the caller checks x is
  /// finite, on every process).
  bool solve(const SecondOrderSystem& sys, LinearSolver& solver, const VecX& b, VecX& x,
             double residual);

 private:
  int capacity_;
  int count_ = 0, newest_ = -1;  // pairs held, and the slot of the newest
  bool open_ = false;
  std::vector<VecX> s_, y_;  // allocated once, slot by slot as first used
  std::vector<double> rho_;
  std::vector<double> alpha_;  // the two-loop recursion's, one per slot
  VecX r_open_, q_;
};

}  // namespace velum
