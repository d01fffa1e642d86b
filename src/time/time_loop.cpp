#include "velum/time/time_loop.hpp"

#include <fmt/format.h>

#include <cmath>

namespace velum {
namespace {

// The step size: halved on a failed step; after a cut-back it grows back, doubled after
// kEasySteps easy steps (converged within easy_iterations factorisations), and
// otherwise tried at double the size after a streak of converged steps, however hard (a step
// that needs many factorisations at every size would never look easy: on a blown-up airbag
// the step stayed cut for 13,674 steps). A try that fails doubles the streak asked before the
// next one (up to kMaxStreak), so a step that is really too long is not retried every few
// steps.
class StepControl {
 public:
  explicit StepControl(const TimeLoopSettings& cfg) : cfg_(cfg), h_(cfg.step) {}
  double size() const { return h_; }
  void failed(double tried) {
    if (trying_) streak_needed_ = std::min(2 * streak_needed_, kMaxStreak);
    trying_ = false;
    h_ = tried * 0.5;
    easy_ = streak_ = 0;
  }
  void converged(int factorizations) {
    trying_ = false;
    if (!cfg_.adaptive || h_ >= cfg_.step) {
      streak_needed_ = kFirstStreak;
      return;
    }
    ++streak_;
    if (factorizations <= cfg_.easy_iterations) ++easy_;
    if (easy_ >= kEasySteps || streak_ >= streak_needed_) {
      trying_ = easy_ < kEasySteps;  // a try on a hard streak
      h_ = std::min(cfg_.step, 2 * h_);
      easy_ = streak_ = 0;
    }
  }

 private:
  static constexpr int kEasySteps = 3, kFirstStreak = 8, kMaxStreak = 256;
  const TimeLoopSettings& cfg_;
  double h_;
  int easy_ = 0, streak_ = 0, streak_needed_ = kFirstStreak;
  bool trying_ = false;  ///< the current size is a try after a hard streak
};

}  // namespace

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
  StepControl control(cfg);
  while (t < cfg.t_end - eps) {
    // Land on the next output time and on the end time.
    double target = cfg.t_end;
    if (cfg.output_interval > 0) {
      const double k = std::floor((t + eps) / cfg.output_interval) + 1;
      target = std::min(target, k * cfg.output_interval);
    }
    double hs = std::min(control.size(), target - t);
    const bool hits_target = hs >= target - t - eps;
    const StepReport rep = integrator.step(sys, solver, t, hs, s);
    if (!rep.converged) {
      if (!cfg.adaptive || hs * 0.5 < cfg.min_step) {
        res.reason = fmt::format("at t = {:g} with step {:g} (minimum {:g}): {}", t, hs,
                                 cfg.min_step, rep.reason);
        res.t = t;
        return res;
      }
      control.failed(hs);
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
    control.converged(rep.factorizations);
  }
  res.completed = true;
  return res;
}

}  // namespace velum
