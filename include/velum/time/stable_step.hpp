// The stable step of central difference at the current state (docs/theory.md, explicit
// dynamics): 2/ω_max, ω_max² the largest eigenvalue of M⁻¹K with M the lumped mass and K the
// stiffness of everything the residual holds (membranes, cables, follower pressures, gas, the
// contacts in touch), plus the penalties not in touch yet (load_stiffness_over_mass). The
// power iteration is carried through the run: at the start on the assembled tangent, then at
// each trust check on the forces' directional differences from the vector it reached last.
#pragma once

#include "velum/math/sparse.hpp"
#include "velum/math/types.hpp"
#include "velum/time/integrators.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum {

class StableStepEstimate {
 public:
  /// At (t, s): power iteration on M⁻¹(K + U Wᵀ), the Jacobian assembled with c_u = 1 and its
  /// low-rank part (gas), from a uniform vector, to 1e-4 (at most 50 iterations). Returns the
  /// stable step (INFINITY when nothing moves or nothing is stiff).
  double start(SecondOrderSystem& sys, double t, const State& s);
  /// At (t, s), a central-difference state reached by a step of h (so that the residual at
  /// (u, v½ = v − h/2 a) is −M a): power iterations on (r(u + εx, v½) − r(u, v½))/ε, one force
  /// evaluation each, from the last vector, until the estimate moves less than 1% (at least
  /// one, at most kMaxIterations). Without a start, start() instead.
  double update(SecondOrderSystem& sys, double t, double h, const State& s);
  /// The last ω_max² (beside the penalties not in touch).
  double omega_squared() const { return lambda_; }
  /// Force evaluations of the updates so far.
  long evaluations() const { return evaluations_; }
  static constexpr int kMaxIterations = 4;

 private:
  double step(const SecondOrderSystem& sys) const;
  VecX x_, y_, r_, r0_, u_, vhalf_, zero_;  ///< x_: ‖x‖_M = 1
  SparseMatrix K_;
  double lambda_ = 0;
  long evaluations_ = 0;
};

/// The stable step at (t, s) from a fresh estimate (StableStepEstimate::start).
double stable_time_step(SecondOrderSystem& sys, double t, const State& s);

}  // namespace velum
