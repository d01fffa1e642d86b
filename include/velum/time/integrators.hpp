// Time integrators on a SecondOrderSystem: the generalized-α family (Newmark β-γ, HHT-α and
// Chung-Hulbert generalized-α) with Newton-Raphson, explicit central difference with a
// lumped mass, and static load stepping. One step at a time; the step-size control lives in
// run_time_loop (time_loop.hpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "velum/solve/linear_solver.hpp"
#include "velum/time/low_rank_solver.hpp"
#include "velum/time/newton.hpp"
#include "velum/time/secant_updates.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum {

struct State {
  VecX u, v, a;  ///< over the system's equations
};

class TimeIntegrator {
 public:
  virtual ~TimeIntegrator() = default;
  virtual std::string name() const = 0;
  virtual bool implicit() const { return true; }
  /// Advances `s` from t to t + h in place; on failure `s` is left unchanged.
  virtual StepReport step(SecondOrderSystem& sys, LinearSolver& solver, double t, double h,
                          State& s) = 0;
  /// Initial acceleration consistent with the equation of motion at t (implicit schemes).
  virtual StepReport start(SecondOrderSystem& sys, LinearSolver& solver, double t, State& s);
  /// What the integrator keeps between steps (predictor history), for a checkpoint, and its
  /// restoration; nothing for the one-step schemes. Vectors in the global numbering
  /// (SecondOrderSystem::to_global: save is a collective call on several processes).
  virtual std::vector<double> save(const SecondOrderSystem& sys) const {
    (void)sys;
    return {};
  }
  virtual void restore(const SecondOrderSystem& sys, const std::vector<double>& memory) {
    (void)sys, (void)memory;
  }

  NewtonSettings newton;
};

/// Generalized-α: M a(n+1−αm) + C v(n+1−αf) + f_int(u(n+1−αf)) = f_ext(t(n+1−αf)).
class GeneralizedAlpha : public TimeIntegrator {
 public:
  GeneralizedAlpha(double alpha_m, double alpha_f, double beta, double gamma, std::string name);
  /// Chung-Hulbert with high-frequency spectral radius rho_inf in [0, 1].
  static std::unique_ptr<GeneralizedAlpha> chung_hulbert(double rho_inf);
  /// HHT-α with α in [0, 1/3] (αf = α; β = (1+α)²/4, γ = ½ + α).
  static std::unique_ptr<GeneralizedAlpha> hht(double alpha);
  static std::unique_ptr<GeneralizedAlpha> newmark(double beta = 0.25, double gamma = 0.5);

  std::string name() const override { return name_; }
  StepReport step(SecondOrderSystem& sys, LinearSolver& solver, double t, double h,
                  State& s) override;
  /// The Jacobian's coefficients (cu, cv, ca) of K, of the damping and of M for a step h.
  Vec3 shift(double h) const {
    return Vec3(1 - alpha_f, (1 - alpha_f) * gamma / (beta * h), (1 - alpha_m) / (beta * h * h));
  }

  double alpha_m, alpha_f, beta, gamma;

 private:
  std::string name_;
  VecX un_, vn_, an_, uf_, vf_, am_;
  NewtonWork work_;  ///< kept between steps: the Jacobian's pattern is allocated once
  /// The solver (with the low-rank part of the factorisation it holds) kept between steps,
  /// the wrapped solver's factorisation count after the last step (-1: none) and the shift
  /// coefficients (cu, cv, ca) of the Jacobian it factorised last.
  std::unique_ptr<LowRankCorrectedSolver> low_rank_;
  long carried_count_ = -1;
  Vec3 carried_shift_ = Vec3::Zero();
  int last_factorizations_ = 0;  ///< of the last step (carried only after an easy one)
};

/// Explicit central difference (velocity Verlet form) with the lumped mass.
class CentralDifference : public TimeIntegrator {
 public:
  std::string name() const override { return "central-difference"; }
  bool implicit() const override { return false; }
  StepReport step(SecondOrderSystem& sys, LinearSolver& solver, double t, double h,
                  State& s) override;
  StepReport start(SecondOrderSystem& sys, LinearSolver& solver, double t, State& s) override;

 private:
  VecX r_, zero_;
  VecX vhalf_, u_, a_, v_;  ///< the step's vectors, kept between steps
};

/// Static equilibrium f_int(u) = f_ext(t) at each load level t (no mass, no damping).
/// Load stepping with Newton. Each step starts from the last converged state extrapolated
/// along the last increment (scaled by the step ratio) or along the parabola through the last
/// three states, whichever would have predicted the last increment better (unless
/// `extrapolate` is off), and falls back to the plain start if Newton fails from there, or
/// converges on a state with more negative eigenvalues than the last (the predictor carried
/// the step over a limit point). A state that turns an element inside out is never accepted.
class StaticNewton : public TimeIntegrator {
 public:
  explicit StaticNewton(bool extrapolate = true) : extrapolate_(extrapolate) {}
  std::string name() const override { return "static"; }
  StepReport step(SecondOrderSystem& sys, LinearSolver& solver, double t, double h,
                  State& s) override;
  StepReport start(SecondOrderSystem&, LinearSolver&, double, State&) override {
    StepReport r;
    r.converged = true;
    return r;
  }
  std::vector<double> save(const SecondOrderSystem& sys) const override;
  void restore(const SecondOrderSystem& sys, const std::vector<double>& memory) override;

 private:
  // The start of Newton for the step from t to t + h into u; true when extrapolated.
  bool predict(const SecondOrderSystem& sys, double t, double h, const State& s, VecX& u);
  // The inertia of the tangent at the converged state u into rep.negative_pivots.
  void record_inertia(SecondOrderSystem& sys, LinearSolver& solver, double t, const VecX& u,
                      StepReport& rep);
  // The history the next predictor needs, after the step from u_start to u was accepted.
  void remember(const SecondOrderSystem& sys, double t, double h, const VecX& u_start,
                const VecX& u, const StepReport& rep);

  bool extrapolate_;
  SecantUpdates secant_;  ///< the chord steps' quasi-Newton pairs, their storage kept
  VecX zero_;
  NewtonWork work_;        ///< kept between steps: the Jacobian's pattern is allocated once
  VecX u_prev_, u_prev2_;  ///< converged states before the last two accepted steps
  double h_prev_ = 0, h_prev2_ = 0;       ///< their sizes (0: no such increment)
  double t_prev_ = -1;                    ///< the time the last accepted step ended at
  VecX linear_, parabolic_;               ///< this step's two predictors
  VecX left_by_line_, left_by_parabola_;  ///< the residuals they left, to first order
  bool continuous_ = false;               ///< this step starts where the last one ended
  bool second_ = false;                   ///< this step has the parabola
  bool prefer_parabola_ = false;          ///< the parabola predicted the last increment better
  /// Of the last accepted state (-1: unknown). The start counts as stable (0), as the
  /// analysis's stability watch takes it: a first step whose last tangent has no negative
  /// pivot then needs no factorisation at its converged state to say so.
  int negative_pivots_ = 0;
};

}  // namespace velum
