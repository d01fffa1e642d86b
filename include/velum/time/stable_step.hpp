// The stable step of central difference at the current state (docs/theory.md, explicit
// dynamics): 2/ω_max, ω_max² the largest eigenvalue of M⁻¹K with M the lumped mass and K the
// stiffness of everything the residual holds (membranes, cables, follower pressures, the gas
// of a chamber, the contacts in touch), plus the penalties not in touch yet
// (load_stiffness_over_mass). The power iteration is carried through the run: at the start on
// the assembled tangent, then at each trust check on the forces' directional differences
// from the vector it reached last (docs/performance.md, explicit dynamics: its cost).
#pragma once

#include <vector>

#include "velum/math/sparse.hpp"
#include "velum/math/types.hpp"
#include "velum/time/integrators.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum {

class StableStepEstimate {
 public:
  /// At (t, s): power iteration on M⁻¹(K + U Wᵀ), the Jacobian assembled with c_u = 1 and its
  /// low-rank part (gas), from a uniform vector, until the estimate moves less than 1e-4 (at
  /// most 50 iterations). Returns the stable step (INFINITY when nothing moves or nothing is
  /// stiff). The iteration's ratio ‖M⁻¹Kx‖_M / ‖x‖_M never exceeds ω_max² for a symmetric K:
  /// the estimate approaches it from below (the safety factor covers the rest).
  double start(SecondOrderSystem& sys, double t, const State& s);
  /// start() again on the stiffness start() assembled (after the mass changed: mass scaling).
  double restart(SecondOrderSystem& sys);
  /// At (t, s), a central-difference state reached by a step of h (so that the residual at
  /// (u, v½ = v − h/2 a) is −M a): power iterations on (r(u + εx, v½) − r(u, v½))/ε, one force
  /// evaluation each, from the last vector: one, and up to kMaxIterations while the estimate
  /// moves by more than 2%. Without a start, start() instead.
  double update(SecondOrderSystem& sys, double t, double h, const State& s);
  /// The last ω_max² (beside the penalties not in touch).
  double omega_squared() const { return lambda_; }
  /// The stiffness start() assembled (c_u = 1), and its low-rank part, on this process.
  const SparseMatrix& stiffness() const { return K_; }
  /// Force evaluations of the updates so far.
  long evaluations() const { return evaluations_; }
  /// What a restart needs to go on estimating as the run would have: appended to `m` (the
  /// vector whole, on the first process: a collective call); read back from m[at...]
  /// (returns the position after it; an empty tail: nothing saved, start afresh).
  void save(const SecondOrderSystem& sys, std::vector<double>& m) const;
  size_t restore(const SecondOrderSystem& sys, const std::vector<double>& m, size_t at);
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

/// Per equation, a bound of the stiffness its row may put against its mass: Σ_j |J_ij| +
/// Σ_k |U_ik| Σ_j |W_jk| (Gershgorin: ω_max² ≤ max_i of it over m_i). One process only
/// (the rows of a share are not the whole rows).
VecX stiffness_row_bounds(const SparseMatrix& J, const LowRankJacobian& low_rank);

}  // namespace velum
