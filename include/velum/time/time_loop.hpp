// Step-size control around a TimeIntegrator: marches from t0 to t_end, halving the step on a
// failed step down to min_step, regrowing it after easy steps, landing exactly on output
// times, and reporting each accepted step to an observer (which may stop the run).
#pragma once

#include <functional>
#include <string>

#include "velum/time/integrators.hpp"

namespace velum {

/// Explicit (central difference) runs check every this many steps, at every output time,
/// checkpoint and the end: an element turned inside out, the energies held and the run's
/// plausibility (energy created, blow-up), so that a failure shows at most this many steps
/// late; the loop asks whether it was interrupted as often (a collective vote on several
/// processes; the steps are short). The work of the loads is booked every step.
/// (docs/performance.md: their cost.)
inline constexpr int kExplicitCheckInterval = 50;

struct TimeLoopSettings {
  double t0 = 0, t_end = 1;
  double step = 1e-2;      ///< nominal (and largest) step
  double min_step = 1e-8;  ///< below this a failed step ends the run
  bool adaptive = true;
  double output_interval = 0;  ///< > 0: steps land on multiples of it
  int easy_iterations = 4;     ///< steps converged within this many factorisations may regrow
};

/// The step-size control's memory (time_loop.cpp): what a restart needs to step on as the run
/// would have.
struct StepControlState {
  double h = 0;  ///< the size of the next step
  int easy = 0, streak = 0, streak_needed = 8;
  bool trying = false;
};

/// Where a restarted loop picks up (from a checkpoint).
struct LoopResume {
  double t = 0, step = 0;  ///< the time reached; the nominal step in force (central difference)
  int steps = 0, iterations = 0, factorizations = 0, cutbacks = 0;
  StepControlState control;
};

struct AcceptedStep {
  double t = 0, h = 0;
  int step = 0;
  int iterations = 0;
  int total_iterations = 0;
  int factorizations = 0;
  int total_factorizations = 0;
  bool output_time = false;  ///< t is on an output interval (or the end)
  const StepReport* report = nullptr;
  const StepControlState* control = nullptr;  ///< after this step (for checkpoints)
  int cutbacks = 0;                           ///< of the run so far
  /// Loops without step control (adaptive false: central difference): the step for the
  /// steps after this one, which the observer may change (the stable step re-estimated from
  /// the current state); null otherwise.
  double* next_step = nullptr;
};

struct TimeLoopResult {
  bool completed = false;
  bool stopped = false;  ///< the observer asked to stop
  double t = 0;
  int steps = 0, iterations = 0, factorizations = 0, cutbacks = 0;
  std::string reason;  ///< when not completed: where and why
};

/// Runs the loop; `observer` returns false to stop early. With `resume`, from there (s is the
/// state then; the integrator's start, the initial acceleration, is not redone).
TimeLoopResult run_time_loop(SecondOrderSystem& sys, TimeIntegrator& integrator,
                             LinearSolver& solver, const TimeLoopSettings& settings, State& s,
                             const std::function<bool(const AcceptedStep&, const State&)>& observer,
                             const LoopResume* resume = nullptr);

}  // namespace velum
