// Path following for static equilibria r(u, t) = f_int(u) − f_ext(t) = 0 through limit points:
// the load parameter t (the static pseudo-time the loads' time functions see) becomes an
// unknown beside u, and each step adds one constraint on the increment (Δu, Δt):
//   arc length, cylindrical (Crisfield): ‖Δu‖ = Δs, the quadratic solved at each iteration;
//   arc length, Riks: the correction stays in the plane normal to the predictor;
//   displacement control: one equation's increment is prescribed, t follows.
// Bordered Newton: two back-substitutions with one factorisation per iteration, J a = −r and
// J b = −∂r/∂t (by a difference in t), the correction a + δt b with δt from the constraint.
#pragma once

#include <functional>

#include "velum/time/time_loop.hpp"

namespace velum {

struct PathSettings {
  enum class Method { kLoadControl, kArcLength, kDisplacement };
  enum class Constraint { kCylindrical, kRiks };
  Method method = Method::kLoadControl;
  Constraint constraint = Constraint::kCylindrical;  ///< arc length
  double arc_length = 0;  ///< arc length: the first (and largest) Δs; 0: ‖Δu‖ of a load step
  int max_steps = 1000;   ///< arc length: the run ends after this many steps at the latest
  int node = -1, component = 0;  ///< displacement control: the node and component driven
  int equation = -1;             ///< ... their equation (set by the analysis)
  double displacement = 0;       ///< ... its value at the end of the pseudo-time (t0 → t_end)
};

/// Traces the equilibrium path from (s.u, cfg.t0). Arc length: steps of Δs until t reaches
/// cfg.t_end (the last step lands on it by load control) or after path.max_steps steps.
/// Displacement control: a pseudo-time τ from t0 to t_end in steps of cfg.step drives the
/// controlled equation linearly from its start to path.displacement. Failed steps are cut in
/// half (down to cfg.min_step / cfg.step of the first size) and regrow after easy ones. Each
/// accepted step reaches the observer with t the load parameter and output_time set.
TimeLoopResult run_path_following(
    SecondOrderSystem& sys, LinearSolver& solver, const NewtonSettings& newton,
    const TimeLoopSettings& cfg, const PathSettings& path, State& s,
    const std::function<bool(const AcceptedStep&, const State&)>& observer);

}  // namespace velum
