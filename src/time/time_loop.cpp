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
  explicit StepControl(const TimeLoopSettings& cfg) : cfg_(cfg) { m_.h = cfg.step; }
  double size() const { return m_.h; }
  const StepControlState& state() const { return m_; }
  void restore(const StepControlState& m) { m_ = m; }
  void failed(double tried) {
    if (m_.trying) m_.streak_needed = std::min(2 * m_.streak_needed, kMaxStreak);
    m_.trying = false;
    m_.h = tried * 0.5;
    m_.easy = m_.streak = 0;
  }
  void converged(int factorizations) {
    m_.trying = false;
    if (!cfg_.adaptive || m_.h >= cfg_.step) {
      m_.streak_needed = kFirstStreak;
      return;
    }
    ++m_.streak;
    if (factorizations <= cfg_.easy_iterations) ++m_.easy;
    if (m_.easy >= kEasySteps || m_.streak >= m_.streak_needed) {
      m_.trying = m_.easy < kEasySteps;  // a try on a hard streak
      m_.h = std::min(cfg_.step, 2 * m_.h);
      m_.easy = m_.streak = 0;
    }
  }

 private:
  static constexpr int kEasySteps = 3, kFirstStreak = 8, kMaxStreak = 256;
  const TimeLoopSettings& cfg_;
  StepControlState m_;
};

}  // namespace

TimeLoopResult run_time_loop(SecondOrderSystem& sys, TimeIntegrator& integrator,
                             LinearSolver& solver, const TimeLoopSettings& cfg, State& s,
                             const std::function<bool(const AcceptedStep&, const State&)>& observer,
                             const LoopResume* resume) {
  TimeLoopResult res;
  double t = resume ? resume->t : cfg.t0;
  res.t = t;
  const double eps = 1e-9 * cfg.step;
  StepControl control(cfg);
  if (resume) {
    res.steps = resume->steps, res.iterations = resume->iterations;
    res.factorizations = resume->factorizations, res.cutbacks = resume->cutbacks;
    control.restore(resume->control);
  } else if (const StepReport rep = integrator.start(sys, solver, t, s); !rep.converged) {
    res.reason = fmt::format("at t = {:g}: {}", t, rep.reason);
    return res;
  }
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
        .total_factorizations = res.factorizations,
        .output_time = hits_target && (cfg.output_interval > 0 || t >= cfg.t_end - eps),
        .report = &rep,
        .control = &control.state(),
        .cutbacks = res.cutbacks};
    control.converged(rep.factorizations);
    if (observer && !observer(info, s)) {
      res.stopped = true;
      return res;
    }
  }
  res.completed = true;
  return res;
}

}  // namespace velum
