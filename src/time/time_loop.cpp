#include "velum/time/time_loop.hpp"

#include <fmt/format.h>

#include <cmath>

namespace velum {

TimeLoopResult run_time_loop(
    SecondOrderSystem& sys, TimeIntegrator& integrator, LinearSolver& solver,
    const TimeLoopSettings& cfg, State& s,
    const std::function<bool(const AcceptedStep&, const State&)>& observer) {
  TimeLoopResult res;
  double t = cfg.t0;
  res.t = t;
  const double eps = 1e-9 * cfg.step;
  if (const StepReport rep = integrator.start(sys, solver, t, s); !rep.converged) {
    res.reason = fmt::format("at t = {:g}: {}", t, rep.reason);
    return res;
  }
  double h = cfg.step;
  int easy = 0;
  while (t < cfg.t_end - eps) {
    // Land on the next output time and on the end time.
    double target = cfg.t_end;
    if (cfg.output_interval > 0) {
      const double k = std::floor((t + eps) / cfg.output_interval) + 1;
      target = std::min(target, k * cfg.output_interval);
    }
    double hs = std::min(h, target - t);
    const bool hits_target = hs >= target - t - eps;
    const StepReport rep = integrator.step(sys, solver, t, hs, s);
    if (!rep.converged) {
      if (!cfg.adaptive || hs * 0.5 < cfg.min_step) {
        res.reason = fmt::format("at t = {:g} with step {:g} (minimum {:g}): {}", t, hs,
                                 cfg.min_step, rep.reason);
        res.t = t;
        return res;
      }
      h = hs * 0.5;
      easy = 0;
      ++res.cutbacks;
      continue;
    }
    t = hits_target ? target : t + hs;
    ++res.steps;
    res.iterations += rep.iterations;
    res.factorizations += rep.factorizations;
    res.t = t;
    AcceptedStep info{
        .t = t,
        .h = hs,
        .step = res.steps,
        .iterations = rep.iterations,
        .total_iterations = res.iterations,
        .factorizations = rep.factorizations,
        .output_time = hits_target && (cfg.output_interval > 0 || t >= cfg.t_end - eps),
        .report = &rep};
    if (observer && !observer(info, s)) {
      res.stopped = true;
      return res;
    }
    // Regrow after a few easy steps (counted in factorisations: chord steps are cheap).
    if (cfg.adaptive && h < cfg.step) {
      if (rep.factorizations <= cfg.easy_iterations && ++easy >= 3) {
        h = std::min(cfg.step, 2 * h);
        easy = 0;
      }
    }
  }
  res.completed = true;
  return res;
}

}  // namespace velum
