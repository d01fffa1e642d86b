#include "velum/time/time_loop.hpp"

#include <fmt/format.h>

#include <algorithm>
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
  void set_size(double h) { m_.h = h; }
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

// The loop's time without drift: the last landing (the start, an output time, the end, or
// where the step size last changed) plus a count of equal steps, so that 20,000 steps of 0.005
// reach 100 to the last bit instead of 2.6e-11 short of it (a sliver step that could not
// converge). A step that would stop a sliver short of the next target (an output time or
// the end) is stretched to land on it: nothing below min_step, or a millionth of the step,
// is left over.
class StepClock {
 public:
  StepClock(const TimeLoopSettings& cfg, double t) : cfg_(cfg), anchor_(t) {}
  double t() const { return anchor_ + static_cast<double>(n_) * h_; }
  bool finished() const { return t() >= cfg_.t_end - eps(); }
  struct Next {
    double h = 0, t = 0;  ///< the step's size and where it ends
    bool on_target = false;
  };
  // The step of (at most) h from t(): on the next target when it reaches it or would stop a
  // sliver short of it.
  Next next(double h) const {
    const double now = t();
    double target = cfg_.t_end;
    if (cfg_.output_interval > 0) {
      const double k = std::floor((now + eps()) / cfg_.output_interval) + 1;
      target = std::min(target, k * cfg_.output_interval);
    }
    const double sliver = std::max({cfg_.min_step, 1e-6 * h, eps()});
    if (h >= target - now - sliver) return {target - now, target, true};
    const double t_next = h == h_ ? anchor_ + static_cast<double>(n_ + 1) * h_ : now + h;
    return {h, t_next, false};
  }
  void advance(const Next& step) {
    if (step.on_target || step.h != h_) {
      anchor_ = step.on_target ? step.t : t();
      n_ = 0;
      h_ = step.on_target ? 0 : step.h;
    }
    if (!step.on_target) ++n_;
  }

 private:
  double eps() const { return 1e-9 * cfg_.step; }
  const TimeLoopSettings& cfg_;
  double anchor_;
  long n_ = 0;
  double h_ = 0;
};

}  // namespace

TimeLoopResult run_time_loop(SecondOrderSystem& sys, TimeIntegrator& integrator,
                             LinearSolver& solver, const TimeLoopSettings& cfg, State& s,
                             const std::function<bool(const AcceptedStep&, const State&)>& observer,
                             const LoopResume* resume) {
  TimeLoopResult res;
  const double t0 = resume ? resume->t : cfg.t0;
  res.t = t0;
  StepClock clock(cfg, t0);
  StepControl control(cfg);
  if (!resume && !(cfg.t_end - cfg.t0 >= cfg.min_step)) {
    // No step can reach the end (shorter than min_step, or lost in the start's last digits):
    // nothing would be solved, and that is no converged run.
    res.reason = fmt::format(
        "the analysis spans {:.6g} (t = {:.17g} to {:.17g}), less than min_step {:.6g}: no "
        "step can be taken and nothing was solved (give a longer time.end)",
        cfg.t_end - cfg.t0, cfg.t0, cfg.t_end, cfg.min_step);
    return res;
  }
  if (resume) {
    res.steps = resume->steps, res.iterations = resume->iterations;
    res.factorizations = resume->factorizations, res.cutbacks = resume->cutbacks;
    control.restore(resume->control);
  } else if (const StepReport rep = integrator.start(sys, solver, t0, s); !rep.converged) {
    res.reason = fmt::format("at t = {:g}: {}", t0, rep.reason);
    return res;
  }
  while (!clock.finished()) {
    const double t = clock.t();
    // (A collective vote on several processes: an explicit run's steps are short, so it asks
    // every kExplicitCheckInterval steps.)
    if ((integrator.implicit() || res.steps % kExplicitCheckInterval == 0) &&
        integrator.newton.interrupt_requested()) {
      res.stopped = true;
      res.reason = fmt::format("interrupted at t = {:g}", t);
      return res;
    }
    const StepClock::Next next = clock.next(control.size());
    const double hs = next.h;
    const StepReport rep = integrator.step(sys, solver, t, hs, s);
    if (!rep.converged) {
      if (rep.interrupted || rep.ends_run || !cfg.adaptive || hs * 0.5 < cfg.min_step) {
        res.stopped = rep.interrupted;
        res.reason = rep.interrupted || rep.ends_run
                         ? fmt::format("at t = {:g}: {}", t, rep.reason)
                         : fmt::format("at t = {:g} with step {:g} (minimum {:g}): {}", t, hs,
                                       cfg.min_step, rep.reason);
        res.t = t;
        return res;
      }
      control.failed(hs);
      ++res.cutbacks;
      continue;
    }
    clock.advance(next);
    ++res.steps;
    res.iterations += rep.iterations;
    res.factorizations += rep.factorizations;
    res.t = next.t;
    AcceptedStep info{
        .t = next.t,
        .h = hs,
        .step = res.steps,
        .iterations = rep.iterations,
        .total_iterations = res.iterations,
        .factorizations = rep.factorizations,
        .total_factorizations = res.factorizations,
        .output_time = next.on_target && (cfg.output_interval > 0 || clock.finished()),
        .report = &rep,
        .control = &control.state(),
        .cutbacks = res.cutbacks};
    control.converged(rep.factorizations);
    double next_step = control.size();
    if (!cfg.adaptive) info.next_step = &next_step;
    if (observer && !observer(info, s)) {
      res.stopped = true;
      return res;
    }
    if (!cfg.adaptive && next_step > 0) control.set_size(next_step);
  }
  res.completed = true;
  return res;
}

}  // namespace velum
