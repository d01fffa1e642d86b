// Static equilibrium by dynamic relaxation (Day; Barnes's kinetic damping): for sheets that
// start flat or slack, where Newton has no stiffness to start from. Each load level is
// relaxed by explicit steps of a fictitious dynamics whose masses come from the stiffness
// (Gershgorin row sums of the tangent, one mass per node, so the step Δτ = 1 is stable), with
// the velocities zeroed at every peak of the kinetic energy. Once the residual has fallen to
// `newton_switch` of the force scale, full Newton (with its line search) finishes on the
// static tolerances; if it fails, relaxation goes on to a tighter switch and tries again, and
// relaxation alone may reach the static tolerance. The integrator sees only the
// SecondOrderSystem.
#pragma once

#include "velum/time/integrators.hpp"

namespace velum {

struct RelaxationSettings {
  double newton_switch = 1e-3;   ///< residual / force scale at which Newton takes over
  long max_iterations = 200000;  ///< explicit iterations per load level
  /// Wall-clock seconds a load level may take (relaxation and its Newton finish; 0: no
  /// limit). Spent: the level fails and the run ends there (a smaller level would spend it
  /// again).
  double max_seconds = 0;
};

class DynamicRelaxation : public TimeIntegrator {
 public:
  std::string name() const override { return "relaxation"; }
  StepReport step(SecondOrderSystem& sys, LinearSolver& solver, double t, double h,
                  State& s) override;
  StepReport start(SecondOrderSystem&, LinearSolver&, double, State&) override {
    StepReport r;
    r.converged = true;
    return r;
  }

  RelaxationSettings relaxation;
  /// Explicit iterations and kinetic-energy peaks of the last step.
  long last_iterations() const { return iterations_; }
  long last_peaks() const { return peaks_; }

 private:
  /// Relaxes u at load level t until ‖r‖ <= target or the iteration budget is spent. Returns
  /// false with `why` on a non-finite state.
  bool relax(SecondOrderSystem& sys, double t, VecX& u, double target, long budget,
             std::string& why);
  /// Whether the level must end now (a signal, or max_seconds spent): `why` says which.
  bool out_of_time(const SecondOrderSystem& sys, double rn, std::string& why);
  /// Fictitious masses from the tangent at u: m = ½ max over the node's equations of the row
  /// sums of |K| (so Δτ = 1 is stable by Gershgorin with a margin of 2).
  void update_masses(SecondOrderSystem& sys, double t, const VecX& u);

  VecX r_, v_, m_, zero_, f_prev_;
  SparseMatrix J_;
  double ref_ = 0;  ///< force scale at the start of this level
  long iterations_ = 0, peaks_ = 0;
  double level_start_ = 0;  ///< steady clock, seconds, when this level began
  bool interrupted_ = false, spent_ = false;
};

}  // namespace velum
