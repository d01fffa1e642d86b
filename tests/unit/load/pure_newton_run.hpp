// A static run with pure Newton (the tangent rebuilt at every iteration, so that the residuals
// show the tangent), for the contact tests that press and then slide a strip: Newton's
// residuals of the step at `t_first` and of the last step.
#pragma once

#include <cmath>
#include <iostream>
#include <vector>

#include "velum/analysis/mechanical_system.hpp"
#include "velum/solve/linear_solver.hpp"
#include "velum/time/integrators.hpp"
#include "velum/time/time_loop.hpp"

namespace velum::test {

struct PureNewtonRun {
  bool completed = false;
  std::vector<double> first, last;  ///< Newton's residuals at t_first, at the last step
};

/// pure_newton false: Newton as runs use it (the tangent reused where it converges).
inline PureNewtonRun pure_newton_run(MechanicalSystem& sys, State& s, double t_end, double step,
                                     double t_first, bool pure_newton = true) {
  sys.start_loads(0, s.u, s.v);
  StaticNewton integrator;
  if (pure_newton) integrator.newton.reuse_tangent = false;
  auto solver = make_linear_solver(SolverKind::kAuto);
  TimeLoopSettings loop;
  loop.t0 = 0, loop.t_end = t_end, loop.step = step;
  PureNewtonRun out;
  const TimeLoopResult r =
      run_time_loop(sys, integrator, *solver, loop, s, [&](const AcceptedStep& st, const State& c) {
        sys.accept(st.t, c.u, c.v);
        out.last = st.report->residuals;
        if (std::abs(st.t - t_first) < 1e-9) out.first = out.last;
        return true;
      });
  out.completed = r.completed;
  if (!r.completed) std::cout << "not completed: " << r.reason << "\n";
  return out;
}

}  // namespace velum::test
